"""The SyRIP pose sets benchmarks ease into clips, by source name, including the one reserved for independent checks.

- `syrip-train`: the 600 training poses (the bundled prior was trained on them);
- `syrip-test`: Test100's poses (the final check);
- `syrip-synthetic`: HW-HuP's 3D poses of SyRIP's 1000 synthetic images (rendered infant body models), rows 300-1299
  of `poses3d_hwhup.npy`. No prior, calibration or setting of zedo was trained, tuned or validated on them: they are
  a pose source outside every fit, for independent checks only. Nothing may be chosen by what they show.

Each pose keeps the orientation of its own photo: eased one into the next, the body turns from one photo's view to
the next's (on `norms_false_alarms.py`'s typical 10 s clips the trunk's forward axis turns at a median 49 deg/s and
lies 77 degrees from the camera's direction). With the suffix `-supine` (`syrip-train-supine`, ...) each pose is first
turned to lie as an infant is filmed, chest to the camera and head up the image
(`zedo_cli.evaluation.clips.cameras.turned_supine`); `norms_false_alarms.py` then sways the body about one place as
the adult motion's clips do (its trunk turns at a median 0.9 deg/s and lies 7 degrees from the camera's direction).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from zedo_cli.data.datasets import load_npy, load_syrip_3d
from zedo_cli.data.skeleton import center_on_root, convert_points, get_skeleton
from zedo_cli.evaluation.clips.cameras import Sway, turned_supine

HWHUP_POSES = "poses3d_hwhup.npy"
SYNTHETIC_ROWS = slice(300, 1300)
EASED_SOURCES = ("syrip-train", "syrip-test", "syrip-synthetic")
SUPINE = "-supine"
SUPINE_SOURCES = tuple(s + SUPINE for s in EASED_SOURCES)


def synthetic_poses(syrip_dir: str | Path) -> np.ndarray:
    """SyRIP's synthetic rows as `syrip12` poses `(1000, 12, 3)`, metres, centred on the hip midpoint."""
    raw = load_npy(Path(syrip_dir) / HWHUP_POSES, "fiu").astype(np.float64)[SYNTHETIC_ROWS]
    if raw.shape[1:] != (14, 3) or not np.abs(raw).sum(axis=(1, 2)).all():
        raise ValueError(f"{Path(syrip_dir) / HWHUP_POSES}: rows 300-1299 are not 1000 non-zero LSP-14 poses")
    lsp, dst = get_skeleton("lsp14"), get_skeleton("syrip12")
    poses, _ = convert_points(raw, np.ones(raw.shape[:2]), lsp, dst)
    return center_on_root(poses, dst)


def eased_source_poses(syrip_dir: str | Path, source: str) -> np.ndarray:
    """The poses of one of EASED_SOURCES or SUPINE_SOURCES, `(P, 12, 3)`."""
    if source in SUPINE_SOURCES:
        return turned_supine(eased_source_poses(syrip_dir, source.removesuffix(SUPINE)), get_skeleton("syrip12").joints)
    if source == "syrip-synthetic":
        return synthetic_poses(syrip_dir)
    if source not in EASED_SOURCES:
        raise ValueError(f"unknown pose source {source!r}; choose one of {', '.join(EASED_SOURCES)}")
    return load_syrip_3d(syrip_dir, "test" if source == "syrip-test" else "train").poses


def source_sway(source: str) -> Sway | None:
    """How a source's eased clips place the body: swaying about one place for SUPINE_SOURCES (`make_sequences(sway=)`),
    else None (turning and drifting at constant rates)."""
    return Sway() if source in SUPINE_SOURCES else None


PLACINGS = ("photo", "supine")  # how a calibration's SyRIP clips place their key poses (`placed_poses`)


def placed_poses(poses: np.ndarray, placing: str) -> tuple[np.ndarray, Sway | None]:
    """Key poses `(P, 12, 3)` as a calibration's SyRIP clips place them, with the `make_sequences(sway=)` to ease them
    with: "photo", each in its photo's orientation, the body turning and drifting at constant rates (None);
    "supine", each turned chest to the camera, the body swaying about one place (`Sway()`)."""
    if placing == "photo":
        return poses, None
    if placing != "supine":
        raise ValueError(f"unknown placing {placing!r}; choose one of {', '.join(PLACINGS)}")
    return turned_supine(poses, get_skeleton("syrip12").joints), Sway()
