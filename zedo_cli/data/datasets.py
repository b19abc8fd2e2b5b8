"""Loaders of 3D pose data into root-relative `(N, J, 3)` arrays in metres, plus the SyRIP split.

SyRIP (../shared/data/syrip/README.md): 3D rows of `poses3d_corrected.npy` are linked to SyRIP
image names through `poses3d_image_names.npy` and `image_name_map700.npy`. The benchmark split
is the paper's 600 / 100: test = the 100 images of `keypoints2d_gt_test100.json`, train = the
other 600 real images.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import DataError
from ..strict_json import loads
from .skeleton import Skeleton, center_on_root, convert_points, get_skeleton

SYRIP_POSES = "poses3d_corrected.npy"
SYRIP_ROW_NAMES = "poses3d_image_names.npy"
SYRIP_NAME_MAP = "image_name_map700.npy"
SYRIP_TEST100 = "keypoints2d_gt_test100.json"
SYRIP_REAL700 = "keypoints2d_gt_real700.json"
SYRIP_FIDIP = "keypoints2d_fidip_real700.json"
SYRIP_SPLITS = ("train", "test", "all")
# protocol -> joint set scored (`zedo evaluate --protocol`); both sides are converted to it and centred on its root
SCORING_PROTOCOLS: dict[str, str] = {"syrip12": "syrip12", "h36m17": "h36m17"}


@dataclass
class PoseSet:
    """Root-relative 3D poses in metres, camera-oriented axes (x right, y down, z forward)."""

    poses: np.ndarray  # (N, J, 3) float64
    skeleton: Skeleton
    names: list[str]  # one identifier per pose (SyRIP image name, or index)
    source: str  # human-readable description of where the poses came from

    def summary(self) -> dict[str, object]:
        return {"source": self.source, "count": len(self.names), "skeleton": self.skeleton.name}


def _require(path: Path) -> Path:
    if not path.is_file():
        raise DataError(f"{path}: file not found (is --syrip-dir the SyRIP data folder?)")
    return path


def load_npy(path: Path, kinds: str) -> np.ndarray:
    """A .npy array of a data set, its dtype of one of numpy's `kinds` ("f": numbers, "U": text);
    a truncated file, an object (pickled) array or another dtype is a DataError naming the file."""
    try:
        array = np.load(_require(path), allow_pickle=False)
    except (OSError, ValueError, EOFError) as exc:  # truncated, pickled objects, not an .npy at all
        raise DataError(f"{path}: not a readable .npy array ({' '.join(str(exc).split())})") from None
    if not isinstance(array, np.ndarray) or array.dtype.kind not in kinds:
        found = array.dtype if isinstance(array, np.ndarray) else type(array).__name__
        raise DataError(f"{path}: expected an array of {'numbers' if 'f' in kinds else 'text'}, got {found}")
    return array


def syrip_rows_by_name(syrip_dir: Path) -> dict[str, int]:
    """SyRIP image name (`train00001.jpg`, `test0.jpg`) -> row of the 3D pose arrays."""
    row_names = load_npy(syrip_dir / SYRIP_ROW_NAMES, "US")
    name_map = load_npy(syrip_dir / SYRIP_NAME_MAP, "US")
    if name_map.ndim != 2 or name_map.shape[1] != 2:
        raise DataError(f"{syrip_dir / SYRIP_NAME_MAP}: expected (N, 2) image name pairs, got shape {name_map.shape}")
    row_of = {str(n).split("/")[-1]: i for i, n in enumerate(row_names)}
    rows = {}
    for image_name, syrip_name in name_map:
        if str(image_name) not in row_of:
            raise DataError(f"{syrip_dir / SYRIP_NAME_MAP}: {image_name} has no 3D row")
        rows[str(syrip_name)] = row_of[str(image_name)]
    return rows


def syrip_test_names(syrip_dir: Path) -> list[str]:
    """SyRIP names of the Test100 images, in the order of their annotation file."""
    path = _require(syrip_dir / SYRIP_TEST100)
    try:
        data = loads(path.read_text())
        return [str(img["file_name"]) for img in data["images"]]
    except (ValueError, RecursionError, KeyError, TypeError) as exc:  # ValueError: JSON, digit limit, UTF-8
        raise DataError(f"{path}: not a COCO annotation file with images[].file_name") from exc


def load_syrip_3d(syrip_dir: str | Path, split: str = "train") -> PoseSet:
    """SyRIP weak-ground-truth 3D poses in the `syrip12` joint set, centred on the hip midpoint.

    `split`: "train" (600 poses), "test" (Test100, in its annotation file's order) or "all" (700).
    Train poses are ordered by their row in the 3D array.
    """
    syrip_dir = Path(syrip_dir)
    if split not in SYRIP_SPLITS:
        raise DataError(f"unknown SyRIP split {split!r}; choose one of {', '.join(SYRIP_SPLITS)}")
    if not syrip_dir.is_dir():
        raise DataError(f"{syrip_dir}: SyRIP data folder not found")
    raw = load_npy(syrip_dir / SYRIP_POSES, "fiu").astype(np.float64)
    if raw.ndim != 3 or raw.shape[1:] != (get_skeleton("lsp14").num_joints, 3):
        raise DataError(f"{syrip_dir / SYRIP_POSES}: expected (N, 14, 3) LSP-14 poses, got shape {raw.shape}")
    rows = syrip_rows_by_name(syrip_dir)
    test = syrip_test_names(syrip_dir)
    missing = [n for n in test if n not in rows]
    if missing:
        raise DataError(f"{syrip_dir / SYRIP_TEST100}: images without a 3D pose: {missing[:5]}")
    if split == "test":
        names = test
    else:
        test_set = set(test)
        by_row = sorted((row, name) for name, row in rows.items())
        names = [name for _, name in by_row if split == "all" or name not in test_set]
    lsp = get_skeleton("lsp14")
    dst = get_skeleton("syrip12")
    selected = raw[[rows[n] for n in names]]
    if not np.abs(selected).sum(axis=(1, 2)).all():
        raise DataError(f"{syrip_dir / SYRIP_POSES}: some selected rows are all zeros")
    poses, _ = convert_points(selected, np.ones(selected.shape[:2]), lsp, dst)
    return PoseSet(center_on_root(poses, dst), dst, names, f"SyRIP {split} ({syrip_dir})")


def npz_license(path: str | Path) -> str | None:
    """The data terms an npz of poses states in its optional `license` string (e.g. `zedo
    augment`'s output, derived from licensed data), or None when it states none."""
    try:
        with np.load(path, allow_pickle=False) as data:
            text = str(data["license"]) if "license" in data.files else ""
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise DataError(f"{path}: not a readable npz file ({exc})") from exc
    return text.strip() or None


def load_npz_poses(path: str | Path, skeleton: str | None = None) -> PoseSet:
    """3D poses from an npz file: `poses (N, J, 3)` in metres, optional `joint_names (J,)`,
    optional `names (N,)`. The skeleton is `skeleton`, else the one whose joint names match.
    Poses are centred on the skeleton's root point."""
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: file not found")
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise DataError(f"{path}: not a readable npz file ({exc})") from exc
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise DataError(f"{path}: not an npz archive (save poses with numpy.savez(path, poses=..., joint_names=...))")
    files = set(data.files)
    if "poses" not in files:
        raise DataError(f"{path}: no 'poses' array (found: {', '.join(sorted(files)) or 'none'})")
    try:
        poses = np.asarray(data["poses"], dtype=np.float64)
        names = [str(n) for n in data["names"]] if "names" in files else None
    except (ValueError, TypeError) as exc:
        raise DataError(f"{path}: unreadable 'poses' or 'names' ({exc})") from None
    if poses.ndim != 3 or poses.shape[-1] != 3 or poses.shape[0] == 0:
        raise DataError(f"{path}: 'poses' must have shape (N>0, J, 3), got {poses.shape}")
    if not np.isfinite(poses).all():
        raise DataError(f"{path}: 'poses' contains NaN or infinite values")
    if names is not None and len(names) != len(poses):
        raise DataError(f"{path}: 'names' has {len(names)} entries for {len(poses)} poses")
    skel = _npz_skeleton(path, data, skeleton, poses.shape[1])
    names = names if names is not None else [str(i) for i in range(len(poses))]
    return PoseSet(center_on_root(poses, skel), skel, names, str(path))


def _npz_skeleton(path: Path, data: np.lib.npyio.NpzFile, name: str | None, joints: int) -> Skeleton:
    from .skeleton import SKELETONS

    if name is not None:
        skel = get_skeleton(name)
    elif "joint_names" in data.files:
        try:
            joint_names = tuple(str(j) for j in data["joint_names"])
        except ValueError as exc:
            raise DataError(f"{path}: unreadable 'joint_names' ({exc})") from None
        matches = [s for s in SKELETONS.values() if s.joints == joint_names]
        if not matches:
            raise DataError(f"{path}: 'joint_names' match no known skeleton; pass --skeleton")
        skel = matches[0]
    else:
        raise DataError(f"{path}: no 'joint_names' array; pass --skeleton")
    if skel.num_joints != joints:
        raise DataError(f"{path}: 'poses' has {joints} joints but skeleton {skel.name} has {skel.num_joints}")
    return skel


def syrip_original_names(real700_path: str | Path) -> dict[str, str]:
    """image id (as str) -> true SyRIP name, from `keypoints2d_gt_real700.json`, which renumbers
    its images test0..test699 and keeps the true name in `original_file_name`."""
    path = _require(Path(real700_path))
    try:
        images = loads(path.read_text())["images"]
        return {str(img["id"]): str(img["original_file_name"]) for img in images}
    except (ValueError, RecursionError, KeyError, TypeError) as exc:  # ValueError: JSON, digit limit, UTF-8
        raise DataError(f"{path}: expected images[] with id and original_file_name ({exc})") from None
