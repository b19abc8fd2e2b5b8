"""How far `zedo lift` answers differ between thread counts and between kinds of CPU.

Lifts SyRIP's 1400 real poses (700 images, ground-truth and FiDIP 2D, one instance per image each;
the bundled prior, `fast`) in a fresh process per setting, and compares each setting's
root-relative poses with the first's:

- thread counts: OMP_NUM_THREADS 1, 2 and 4 (torch's thread count; a lift's chunks run on them);
- kinds of CPU, as this machine can pose as them: torch's own kernels for AVX-512, AVX2 or no
  vector extension (`ATEN_CPU_CAPABILITY`), and MKL's matrix products for AVX2 or SSE4.2
  (`MKL_ENABLE_INSTRUCTIONS`; MKL picks its kernels by the CPU, as torch does).

    .venv/bin/python benchmarks/accuracy/agreement.py --syrip-dir ../shared/data/syrip

prints one row per setting: the largest and the 99th percentile joint difference (mm), and
whether every pose was lifted alike (the same status).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

SETTINGS: dict[str, dict[str, str]] = {
    "1 thread (reference)": {"OMP_NUM_THREADS": "1"},
    "2 threads": {"OMP_NUM_THREADS": "2"},
    "4 threads": {"OMP_NUM_THREADS": "4", "ZEDO_AGREEMENT_THREADS": "4"},
    "torch AVX2": {"OMP_NUM_THREADS": "1", "ATEN_CPU_CAPABILITY": "avx2"},
    "torch no vector extension": {"OMP_NUM_THREADS": "1", "ATEN_CPU_CAPABILITY": "default"},
    "MKL AVX2": {"OMP_NUM_THREADS": "1", "MKL_ENABLE_INSTRUCTIONS": "AVX2"},
    "MKL SSE4.2": {"OMP_NUM_THREADS": "1", "MKL_ENABLE_INSTRUCTIONS": "SSE4_2"},
    "torch and MKL AVX2 (an AVX2 CPU)": {
        "OMP_NUM_THREADS": "1",
        "ATEN_CPU_CAPABILITY": "avx2",
        "MKL_ENABLE_INSTRUCTIONS": "AVX2",
    },  # fmt: skip
    "torch none, MKL SSE4.2 (an older CPU)": {
        "OMP_NUM_THREADS": "1",
        "ATEN_CPU_CAPABILITY": "default",
        "MKL_ENABLE_INSTRUCTIONS": "SSE4_2",
    },  # fmt: skip
}


def child(syrip_dir: Path, out: Path) -> None:
    """Lift the 1400 poses in this process and save the root-relative poses and statuses."""
    import torch

    from zedo_cli.evaluation.syrip_benchmark import load_throughput_inputs
    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import get_preset
    from zedo_cli.lifting.solver import lift
    from zedo_cli.prior.weights import bundled_prior_path, load_prior

    prior = load_prior(bundled_prior_path())
    kps = [kp.to_skeleton(prior.skeleton) for kp in load_throughput_inputs(syrip_dir).values()]
    mats = np.concatenate([resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)[0] for kp in kps])
    xy, conf = np.concatenate([kp.xy for kp in kps]), np.concatenate([kp.confidence for kp in kps])
    threads = os.environ.get("ZEDO_AGREEMENT_THREADS")  # torch caps OMP_NUM_THREADS at the cores
    res = lift(xy, conf, mats, prior, get_preset("fast"), threads=int(threads) if threads else None)
    np.savez(out, poses=res.poses_root_relative, status=res.status.astype(str),
             capability=torch.backends.cpu.get_cpu_capability())  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--syrip-dir", type=Path, required=True)
    parser.add_argument("--child", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.syrip_dir, args.child)
        return
    repo = Path(__file__).resolve().parents[2]
    with tempfile.TemporaryDirectory() as tmp:
        results = {}
        for name, env in SETTINGS.items():
            out = Path(tmp) / f"{len(results)}.npz"
            full = {k: v for k, v in os.environ.items() if k not in ("ATEN_CPU_CAPABILITY", "MKL_ENABLE_INSTRUCTIONS")}
            full["PYTHONPATH"] = os.pathsep.join([str(repo), full.get("PYTHONPATH", "")])
            subprocess.run([sys.executable, __file__, "--syrip-dir", str(args.syrip_dir), "--child", str(out)],
                           env={**full, **env}, check=True)  # fmt: skip
            results[name] = np.load(out)
        ref = results["1 thread (reference)"]
        print("| setting | torch kernels | largest difference (mm) | 99th percentile (mm) | same status |")
        print("| --- | --- | --- | --- | --- |")
        for name, res in results.items():
            both = (ref["status"] == "lifted") & (res["status"] == "lifted")
            diff = np.linalg.norm(res["poses"][both] - ref["poses"][both], axis=-1) * 1000  # (n, J) mm
            same = "yes" if np.array_equal(ref["status"], res["status"]) else "no"
            bits = " (the same bits)" if np.array_equal(ref["poses"], res["poses"], equal_nan=True) else ""
            print(f"| {name} | {res['capability']} | {diff.max():.4f}{bits} | {np.percentile(diff, 99):.4f} | {same} |")
        print(f"\n{len(ref['status'])} poses, {int((ref['status'] == 'lifted').sum())} lifted in the reference")


if __name__ == "__main__":
    main()
