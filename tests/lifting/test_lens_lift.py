"""Lifting through a lens with distortion: undistorted 2D lifts as the pinhole projection does,
and reprojection errors are measured in the original (distorted) image."""

from __future__ import annotations

import numpy as np

from tests.helpers import K_TEST, synthetic_poses
from zedo_cli.camera.model import CameraModel
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

LENS = CameraModel(K_TEST[0, 0], K_TEST[1, 1], K_TEST[0, 2], K_TEST[1, 2], (-0.3, 0.1, 0.0, 0.0, 0.0),
                   image_size=(640, 480))  # fmt: skip
PINHOLE = CameraModel(LENS.fx, LENS.fy, LENS.cx, LENS.cy)


def test_lens_lift_matches_the_pinhole_lift(tiny_prior: Prior) -> None:
    points = synthetic_poses(6, seed=5) + [0.15, 0.05, 0.8]  # off-centre, where the lens bends most
    seen, ideal = LENS.project(points), PINHOLE.project(points)
    assert np.abs(seen - ideal).max() > 5
    k, conf, cfg = np.stack([K_TEST] * 6), np.ones((6, 12)), get_preset("fast")
    through = lift(seen, conf, k, tiny_prior, cfg, cameras=[LENS] * 6)
    reference = lift(ideal, conf, k, tiny_prior, cfg)
    ignored = lift(seen, conf, k, tiny_prior, cfg)
    assert through.lifted.all() and reference.lifted.all()
    np.testing.assert_allclose(through.poses_camera, reference.poses_camera, atol=1e-4)
    assert np.abs(ignored.poses_camera - reference.poses_camera).max() > 1e-2
    # errors in the distorted image: the lifted joints projected through the lens, against `seen`
    expected = np.linalg.norm(LENS.project(through.poses_camera) - seen, axis=-1)
    np.testing.assert_allclose(through.reprojection_error_px, expected, atol=1e-6)


def test_no_distortion_changes_nothing(tiny_prior: Prior) -> None:
    points = synthetic_poses(3, seed=6) + [0.0, 0.0, 1.0]
    xy = PINHOLE.project(points)
    k, conf, cfg = np.stack([K_TEST] * 3), np.ones((3, 12)), get_preset("fast")
    a = lift(xy, conf, k, tiny_prior, cfg, cameras=[PINHOLE, None, PINHOLE])
    b = lift(xy, conf, k, tiny_prior, cfg)
    np.testing.assert_array_equal(a.poses_camera, b.poses_camera)
    np.testing.assert_array_equal(a.reprojection_error_px, b.reprojection_error_px)
