"""The 61-frame clip of the export targets (docs/exports.md): 30 fps, frame 30 empty (no person),
frame 40 with a joint missing (filled by the prior), frame 50 with too few joints (not lifted);
lifted once to JSON, TRC and C3D with the tiny prior, and the JSON's poses in marker axes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
from helpers import project_poses, synthetic_poses
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.formats.writers.markers import MARKER_AXES

FRAMES, FPS, EMPTY, PARTIAL, UNLIFTED = 61, 30, 30, 40, 50


def write_clip(path: Path) -> Path:
    """The clip as zedo JSON Lines 2D (one line per frame, the empty frame included)."""
    xy = project_poses(synthetic_poses(FRAMES, seed=5))
    lines = []
    for f in range(FRAMES):
        points: list[Any] = [[float(x), float(y), 0.9] for x, y in xy[f]]
        if f == PARTIAL:
            points[2] = None
        if f == UNLIFTED:
            points[2:] = [None] * 10
        record = {"frame": f, "image_size": [640, 480], "persons": [] if f == EMPTY else [{"keypoints": points}]}
        lines.append(json.dumps({"skeleton": "syrip12", **record} if f == 0 else record))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


# A shorter clip of two people per frame (zedo export, the "wrote" lines of --person all).
TWO_FRAMES, TWO_EMPTY, TWO_PARTIAL, TWO_UNLIFTED = 16, 5, 8, 12


def write_two_people(path: Path) -> Path:
    """zedo JSON Lines 2D: two people per frame (the second 150 px to the right), frame TWO_EMPTY
    without people, the second person's ankle missing in TWO_PARTIAL, the first unliftable in TWO_UNLIFTED."""
    xy = project_poses(synthetic_poses(TWO_FRAMES, seed=5))
    lines = []
    for f in range(TWO_FRAMES):
        people = []
        for shift in (0.0, 150.0):
            points: list[Any] = [[float(x) + shift, float(y), 0.9] for x, y in xy[f]]
            if f == TWO_PARTIAL and shift:
                points[2] = None
            if f == TWO_UNLIFTED and not shift:
                points[2:] = [None] * 10
            people.append({"keypoints": points, "score": 0.8})
        record = {"frame": f, "image_size": [640, 480], "persons": [] if f == TWO_EMPTY else people}
        lines.append(json.dumps({"skeleton": "syrip12", **record} if f == 0 else record))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def lift_clip(prior: Path, folder: Path) -> dict[str, Path]:
    """The clip lifted (same seed) to clip.zedo.json, clip.trc and clip.c3d in `folder`."""
    src = write_clip(folder / "clip.jsonl")
    out = {"json": folder / "clip.zedo.json", "trc": folder / "clip.trc", "c3d": folder / "clip.c3d"}
    for path in out.values():
        args = ["lift", "--prior", str(prior), "--steps", "20", "-q", "--fps", str(FPS), str(src), "-o", str(path)]
        result = CliRunner().invoke(app, args)
        assert result.exit_code == 0, result.output
    return out


def json_markers(path: Path, axes: str = "level") -> np.ndarray:
    """The JSON's `keypoints_3d` as `(FRAMES, 12, 3)` metres in marker axes, NaN where it has no pose."""
    doc = json.loads(path.read_text(encoding="utf-8"))
    assert doc["units"] == "m" and doc["coordinate_frame"] == "camera"
    out = np.full((FRAMES, 12, 3), np.nan)
    for frame in doc["frames"]:
        (person,) = frame["persons"]
        if person["keypoints_3d"] is not None:
            out[frame["frame_index"]] = np.array(person["keypoints_3d"], dtype=float)
    return out @ MARKER_AXES[axes].T
