"""CameraModel: undistortion inverts OpenCV's projection exactly, for both lens models."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.camera.model import CameraModel
from zedo_cli.errors import IntrinsicsError

WIDE = CameraModel(600.0, 600.0, 640.0, 360.0, (-0.3, 0.1, 0.0, 0.0, 0.0), image_size=(1280, 720))
FISHEYE = CameraModel(500.0, 500.0, 640.0, 360.0, (0.05, -0.01, 0.002, 0.0), "fisheye", (1280, 720))


@pytest.mark.parametrize("camera", [WIDE, FISHEYE])
def test_undistort_inverts_projection_to_the_corner(camera: CameraModel) -> None:
    rng = np.random.default_rng(0)
    points = np.c_[rng.uniform(-0.9, 0.9, (200, 1)), rng.uniform(-0.5, 0.5, (200, 1)), np.ones((200, 1))]
    seen = camera.project(points)
    ideal = points[:, :2] / points[:, 2:] * [camera.fx, camera.fy] + [camera.cx, camera.cy]
    assert np.abs(seen - ideal).max() > 10  # the lens matters here
    np.testing.assert_allclose(camera.undistort_pixels(seen), ideal, atol=1e-6)


def test_nan_and_points_behind_stay_nan() -> None:
    px = WIDE.project(np.array([[0.1, 0.0, 1.0], [0.0, 0.0, -1.0], [np.nan, 0, 1]]))
    assert np.isfinite(px[0]).all() and np.isnan(px[1:]).all()
    assert np.isnan(WIDE.undistort_pixels(np.array([[np.nan, 3.0]]))).all()


def test_json_round_trip_and_bad_coefficients() -> None:
    assert CameraModel.from_json(WIDE.to_json()) == WIDE
    assert CameraModel.from_json({"K": WIDE.matrix().tolist()}).dist == ()
    with pytest.raises(IntrinsicsError, match="distortion values"):
        CameraModel(600, 600, 0, 0, (0.1, 0.2, 0.3))
    with pytest.raises(IntrinsicsError, match="finite"):
        CameraModel(600, 600, 0, 0, (np.nan, 0, 0, 0))
