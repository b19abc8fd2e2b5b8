"""Peak memory of reading and writing 100,000 poses in one input, in a process of its
own: resident memory stays bounded (before the streaming readers and writers: 3.8 GB with the
lifting). Slow (about a minute): run with ``pytest -m slow``."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

# Reads the input, then writes a made-up result of the same size (no torch, no lifting: the
# memory of the formats alone) and prints the peak resident set size in MB.
_CHILD = """
import resource, sys, types
import numpy as np
from zedo_cli.formats import read_keypoints
from zedo_cli.formats.writers.outputs import write_result
kp = read_keypoints(sys.argv[1])
n, j = kp.xy.shape[:2]
poses = np.zeros((n, j, 3)) + [0.0, 0.0, 2.0]
res = types.SimpleNamespace(poses_camera=poses, poses_root_relative=poses - poses.mean(axis=1, keepdims=True),
    root_translation=poses.mean(axis=1), reprojection_error_px=np.ones((n, j)), observed=kp.confidence > 0,
    lifted=np.ones(n, dtype=bool), status=np.full(n, "lifted", dtype=object), seconds=1.0)
mats = np.tile(np.array([[2000.0, 0, 320], [0, 2000.0, 240], [0, 0, 1]]), (n, 1, 1))
write_result(sys.argv[2], kp, res, mats, ["pseudo"] * n, {"preset": "test"}, {"path": sys.argv[1]})
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""


def _coco(n: int) -> dict[str, object]:
    rng = np.random.default_rng(0)
    xy = rng.uniform(100, 500, (n, 17, 2)).round(3)
    keypoints = np.concatenate([xy, np.full((n, 17, 1), 2.0)], axis=2).reshape(n, -1)
    return {
        "images": [{"id": i, "width": 640, "height": 480, "file_name": f"{i}.png"} for i in range(n)],
        "annotations": [
            {"id": i, "image_id": i, "category_id": 1, "keypoints": k.tolist()} for i, k in enumerate(keypoints)
        ],  # fmt: skip
        "categories": [{"id": 1, "name": "person"}],
    }


@pytest.mark.slow
@pytest.mark.parametrize("fmt", ["json", "csv"])
def test_100000_poses_read_and_written_in_bounded_memory(tmp_path: Path, fmt: str) -> None:
    src = tmp_path / "big.json"
    src.write_text(json.dumps(_coco(100_000)))  # about 45 MB
    out = tmp_path / f"big.zedo.{fmt}"
    done = subprocess.run([sys.executable, "-c", _CHILD, str(src), str(out)], capture_output=True, text=True,
                          check=True)  # fmt: skip
    peak_mb = float(done.stdout.strip().splitlines()[-1])
    assert out.stat().st_size > src.stat().st_size  # written whole
    assert peak_mb < 600, f"peak resident memory {peak_mb:.0f} MB for 100,000 poses"
