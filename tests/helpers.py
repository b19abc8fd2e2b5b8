"""Generated test data: infant-sized syrip12 poses and their exact projections."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import torch

from zedo_cli.data.skeleton import center_on_root, get_skeleton
from zedo_cli.lifting.camera import project

REPO = Path(__file__).resolve().parents[1]
SYRIP_DIR = REPO.parent / "shared" / "data" / "syrip"
ADULT_DIR = SYRIP_DIR.parent / "adult"  # the adult motion capture (../shared/data/adult)
SKELETON = get_skeleton("syrip12")
# An infant-sized syrip12 pose (metres): hips, knees, ankles, shoulders, elbows, wrists.
BASE_POSE = np.array([
    [-0.05, 0.0, 0.0], [-0.05, 0.1, 0.0], [-0.05, 0.2, 0.0],
    [0.05, 0.0, 0.0], [0.05, 0.1, 0.0], [0.05, 0.2, 0.0],
    [0.06, -0.2, 0.0], [0.14, -0.2, 0.0], [0.2, -0.2, 0.0],
    [-0.06, -0.2, 0.0], [-0.14, -0.2, 0.0], [-0.2, -0.2, 0.0],
])  # fmt: skip
K_TEST = np.array([[1000.0, 0.0, 320.0], [0.0, 1000.0, 240.0], [0.0, 0.0, 1.0]])


def tiny_recipe(epochs: int, batch_size: int, more: str = "") -> str:
    """A training recipe (TOML) of a tiny score network, for tests that train or time one; `more`:
    further lines (of its [training] table first)."""
    model = "[model]\nhidden = 64\nembed = 16\nnum_blocks = 1\ngroups = 8\ndropout = 0.0\n"
    return f"{model}[training]\nepochs = {epochs}\nbatch_size = {batch_size}\n{more}"


def synthetic_poses(n: int, seed: int) -> np.ndarray:
    """Root-relative poses `(n, 12, 3)`: BASE_POSE with 1 cm joint noise, turned about the
    vertical axis by up to +-0.6 rad, so depth is informative and learnable."""
    rng = np.random.default_rng(seed)
    pts = BASE_POSE[None] + rng.normal(0.0, 0.01, (n, 12, 3))
    ang = rng.uniform(-0.6, 0.6, n)
    c, s = np.cos(ang), np.sin(ang)
    rot = np.zeros((n, 3, 3))
    rot[:, 0, 0], rot[:, 0, 2], rot[:, 1, 1], rot[:, 2, 0], rot[:, 2, 2] = c, s, 1.0, -s, c
    return center_on_root(pts @ rot.transpose(0, 2, 1), SKELETON)


def project_poses(poses: np.ndarray, depth: float = 1.0) -> np.ndarray:
    """Pixels `(n, 12, 2)` of root-relative poses placed `depth` metres in front of K_TEST."""
    cam = poses + np.array([0.0, 0.0, depth])
    return project(torch.tensor(cam), torch.tensor(K_TEST)).numpy()


COCO_NAMES = list(get_skeleton("coco17").joints)
SYRIP_TO_COCO = [COCO_NAMES.index(j) for j in get_skeleton("syrip12").joints]


def write_coco(path: Path, n: int = 3, *, drop_joint: int | None = None) -> Path:
    """A COCO annotation file of `n` generated poses (COCO joints absent from syrip12 at v=0).
    Image size 640x480, so the default pseudo K is f=2000 at (320, 240)."""
    xy = project_poses(synthetic_poses(n, seed=3))
    images, anns = [], []
    for i in range(n):
        kp = np.zeros((17, 3))
        kp[SYRIP_TO_COCO, :2] = xy[i]
        kp[SYRIP_TO_COCO, 2] = 2
        if drop_joint is not None:
            kp[SYRIP_TO_COCO[drop_joint]] = 0
        images.append({"id": 10 + i, "width": 640, "height": 480, "file_name": f"img{i}.jpg"})
        anns.append({"id": i, "image_id": 10 + i, "category_id": 1, "keypoints": kp.ravel().tolist()})
    cats = [{"id": 1, "name": "person", "keypoints": COCO_NAMES, "skeleton": []}]
    path.write_text(json.dumps({"images": images, "annotations": anns, "categories": cats}))
    return path


def benchmark_module(name: str) -> ModuleType:
    """A module of benchmarks/ (`"lib.folds"`, `"calibrate.calibrate_measures"`, ...), imported as the scripts
    import the shared code: `benchmarks.<name>` with the repository root on sys.path (benchmarks/README.md).
    The default suite tests benchmarks/ only, never experiments/."""
    if str(REPO) not in sys.path:
        sys.path.insert(0, str(REPO))
    return importlib.import_module(f"benchmarks.{name}")
