"""Start-up of `zedo --help` and of a one-pose lift, as ratios to `python -c "import torch"` on the
same machine (docs/lifting.md, "Start-up and large batches").

Each round runs, one after the other in fresh interpreters: `import torch`, then for each source
tree given (its folder goes first on PYTHONPATH, so an older checkout can be compared in the same
run) `zedo --help` and `zedo lift one.json -o out.json --quiet`, where one.json is the first pose of
examples/prior_samples_coco.json, written to a temporary folder. It prints the median wall time
and the median CPU time (user + system of the process: what a machine shared with other work
disturbs least) of each, and each median's ratio to import torch's. Ratios, not seconds, so that
a busy machine still compares; the runs are interleaved so that a change in load hits every
command alike.

    .venv/bin/python benchmarks/speed/startup.py --rounds 7
    OMP_NUM_THREADS=1 .venv/bin/python benchmarks/speed/startup.py --rounds 7 . /path/to/older/checkout
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "examples" / "prior_samples_coco.json"


def one_pose_input(folder: Path) -> Path:
    """The example's first image and its one annotation, as a COCO file of one pose."""
    doc = json.loads(EXAMPLE.read_text())
    first = doc["images"][0]["id"]
    doc["images"] = doc["images"][:1]
    doc["annotations"] = [a for a in doc["annotations"] if a["image_id"] == first][:1]
    path = folder / "one.json"
    path.write_text(json.dumps(doc))
    return path


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(command: list[str], env: dict[str, str], cwd: Path) -> tuple[float, float]:
    """Wall and CPU seconds of one run of `command` (which must succeed)."""
    cpu, start = children_cpu(), time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=cwd)
    return time.perf_counter() - start, children_cpu() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", nargs="*", type=Path, default=[REPO], help="source trees to time (default: this one)")
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        # A folder of its own as the working directory: `python -m zedo_cli` would otherwise import
        # the zedo_cli of the current directory whatever PYTHONPATH says.
        work = Path(tmp)
        one = one_pose_input(work)
        cases: dict[str, tuple[list[str], dict[str, str]]] = {
            "import torch": ([sys.executable, "-c", "import torch"], dict(os.environ))
        }
        for i, tree in enumerate(args.trees):
            env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree.resolve()), os.environ.get("PYTHONPATH", "")]))
            zedo = [sys.executable, "-m", "zedo_cli"]
            cases[f"zedo --help [{i}]"] = ([*zedo, "--help"], env)
            cases[f"one-pose lift [{i}]"] = ([*zedo, "lift", str(one), "-o", str(work / "out.json"), "--overwrite",
                                              "--quiet"], env)  # fmt: skip
        wall: dict[str, list[float]] = {name: [] for name in cases}
        cpu: dict[str, list[float]] = {name: [] for name in cases}
        for _ in range(args.rounds):
            for name, (command, env) in cases.items():
                seconds, used = run(command, env, work)
                wall[name].append(seconds)
                cpu[name].append(used)
    for i, tree in enumerate(args.trees):
        print(f"[{i}] {tree.resolve()}")
    threads = os.environ.get("OMP_NUM_THREADS", "torch's default")
    print(f"{args.rounds} rounds, interleaved; OMP_NUM_THREADS={threads}; {os.cpu_count()} CPUs")
    for label, times in (("wall", wall), ("cpu", cpu)):
        base = statistics.median(times["import torch"])
        for name, values in times.items():
            median = statistics.median(values)
            print(f"{label:4s}  {name:20s}  median {median:6.3f} s  {median / base:5.2f}x import torch")


if __name__ == "__main__":
    main()
