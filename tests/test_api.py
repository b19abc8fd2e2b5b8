"""The Python API exported by `zedo_cli` (docs/api.md): the same poses as `zedo lift`."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

import zedo_cli
from zedo_cli.cli import app

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "prior_samples_coco.json"


def test_api_lift_equals_the_command(tmp_path: Path) -> None:
    from zedo_cli import get_preset, lift, load_prior, read_keypoints, resolve_intrinsics, resolve_prior_path

    prior = load_prior(resolve_prior_path(None))  # the bundled default prior
    kp = read_keypoints(EXAMPLE).to_skeleton(prior.skeleton)
    intrinsics, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)  # 2000 px at the centre
    res = lift(kp.xy, kp.confidence, intrinsics, prior, get_preset("fast"))

    out = tmp_path / "cli.json"
    cli = CliRunner().invoke(app, ["lift", str(EXAMPLE), "-o", str(out), "--quiet"])
    assert cli.exit_code == 0, cli.output
    doc = json.loads(out.read_text())
    written = np.array([p["keypoints_3d"] for f in doc["frames"] for p in f["persons"]], dtype=float)
    assert written.shape == res.poses_camera.shape
    np.testing.assert_allclose(written, res.poses_camera, atol=1e-6)  # the file keeps micrometres


def test_api_names_resolve_to_their_subpackage_objects() -> None:
    from zedo_cli.formats import read_keypoints
    from zedo_cli.lifting import LiftConfig, lift

    assert zedo_cli.lift is lift and zedo_cli.LiftConfig is LiftConfig and zedo_cli.read_keypoints is read_keypoints
    assert "lift" in dir(zedo_cli) and "lift" in zedo_cli.__all__
