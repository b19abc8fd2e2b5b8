"""Tests of intrinsics, projection, rays and translation recovery (zedo_cli.lifting.camera)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import torch

from zedo_cli.errors import IntrinsicsError
from zedo_cli.lifting.camera import (
    PSEUDO_FOCAL_PX,
    Intrinsics,
    pixel_rays,
    project,
    project_onto_rays,
    resolve_intrinsics,
    solve_root_translation,
)

F64 = torch.float64


def _k(fx: float = 1500.0, fy: float = 1400.0, cx: float = 320.0, cy: float = 240.0) -> torch.Tensor:
    return torch.tensor([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]], dtype=F64)


def _gen(seed: int) -> torch.Generator:
    return torch.Generator().manual_seed(seed)


def _write_json(path: Path, doc: Any) -> str:
    path.write_text(json.dumps(doc))
    return str(path)


# --- projection and rays -------------------------------------------------------------------


def test_project_of_pixel_rays_times_depth_returns_the_pixels() -> None:
    g = _gen(0)
    k = _k()
    xy = torch.rand(4, 12, 2, generator=g, dtype=F64) * torch.tensor([640.0, 480.0], dtype=F64)
    depth = 0.5 + 3.0 * torch.rand(4, 12, 1, generator=g, dtype=F64)
    rays = pixel_rays(xy, k)
    np.testing.assert_allclose(rays[..., 2].numpy(), 1.0)
    np.testing.assert_allclose(project(rays * depth, k).numpy(), xy.numpy(), atol=1e-9)


def test_pixel_rays_and_project_batch_over_intrinsics() -> None:
    g = _gen(1)
    ks = torch.stack([_k(), _k(900.0, 950.0, 100.0, 80.0)])  # (2, 3, 3)
    xy = 200.0 * torch.rand(2, 5, 2, generator=g, dtype=F64)
    rays = pixel_rays(xy, ks)
    np.testing.assert_allclose(project(2.0 * rays, ks).numpy(), xy.numpy(), atol=1e-9)
    # The principal point maps to the optical axis.
    centre = torch.tensor([[[320.0, 240.0]]], dtype=F64)
    np.testing.assert_allclose(pixel_rays(centre, _k()).numpy(), [[[0.0, 0.0, 1.0]]])


def test_project_onto_rays_is_idempotent_and_keeps_points_on_the_ray() -> None:
    g = _gen(2)
    rays = torch.randn(3, 12, 3, generator=g, dtype=F64)
    unit = rays / rays.norm(dim=-1, keepdim=True)
    points = torch.randn(3, 12, 3, generator=g, dtype=F64)
    once = project_onto_rays(points, unit)
    twice = project_onto_rays(once, unit)
    np.testing.assert_allclose(twice.numpy(), once.numpy(), atol=1e-12)
    # The projection lies on the ray and the residual is orthogonal to it.
    np.testing.assert_allclose(torch.linalg.cross(once, unit).numpy(), 0.0, atol=1e-12)
    np.testing.assert_allclose(((points - once) * unit).sum(-1).numpy(), 0.0, atol=1e-12)
    on_ray = unit * torch.rand(3, 12, 1, generator=g, dtype=F64) * 4.0
    np.testing.assert_allclose(project_onto_rays(on_ray, unit).numpy(), on_ray.numpy(), atol=1e-12)


def _noise_free_scene(seed: int, batch: int = 4, joints: int = 12) -> tuple[torch.Tensor, ...]:
    g = _gen(seed)
    pose = 0.2 * torch.randn(batch, joints, 3, generator=g, dtype=F64)
    pose = pose - pose.mean(dim=-2, keepdim=True)
    t_xy = 0.4 * (torch.rand(batch, 2, generator=g, dtype=F64) - 0.5)
    t_z = 1.0 + 2.0 * torch.rand(batch, 1, generator=g, dtype=F64)
    t = torch.cat([t_xy, t_z], dim=-1)
    points = pose + t[:, None, :]
    rays = points / points[..., 2:3]
    return pose, rays, t


def test_solve_root_translation_recovers_t_exactly() -> None:
    pose, rays, t = _noise_free_scene(3)
    solved = solve_root_translation(pose, rays, torch.ones(pose.shape[:2], dtype=F64))
    np.testing.assert_allclose(solved.numpy(), t.numpy(), atol=1e-5)
    assert (solved[:, 2] > 0).all()


def test_solve_root_translation_ignores_zero_weight_joints() -> None:
    pose, rays, t = _noise_free_scene(4)
    weights = torch.ones(pose.shape[:2], dtype=F64)
    weights[:, [0, 3, 7]] = 0.0
    # Corrupt the rays of the zero-weight joints: they must not matter.
    rays = rays.clone()
    rays[:, [0, 3, 7], :2] += 5.0
    solved = solve_root_translation(pose, rays, weights)
    np.testing.assert_allclose(solved.numpy(), t.numpy(), atol=1e-5)
    assert (solved[:, 2] > 0).all()


def test_solve_root_translation_with_uneven_weights_is_exact_on_noise_free_data() -> None:
    pose, rays, t = _noise_free_scene(5, batch=2, joints=17)
    weights = 0.1 + torch.rand(pose.shape[:2], generator=_gen(6), dtype=F64)
    solved = solve_root_translation(pose, rays, weights)
    np.testing.assert_allclose(solved.numpy(), t.numpy(), atol=1e-5)


# --- Intrinsics ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "values",
    [(0.0, 100.0, 1.0, 1.0), (100.0, -5.0, 1.0, 1.0), (math.nan, 100.0, 1.0, 1.0),
     (100.0, 100.0, math.inf, 1.0), (100.0, 100.0, 1.0, math.nan)],
)  # fmt: skip
def test_intrinsics_rejects_bad_values(values: tuple[float, float, float, float]) -> None:
    with pytest.raises(IntrinsicsError):
        Intrinsics(*values)


def test_pseudo_intrinsics() -> None:
    k = Intrinsics.pseudo(960, 720)
    assert (k.fx, k.fy, k.cx, k.cy, k.source) == (2000.0, 2000.0, 480.0, 360.0, "pseudo")
    assert PSEUDO_FOCAL_PX == 2000.0
    np.testing.assert_array_equal(k.matrix(), [[2000, 0, 480], [0, 2000, 360], [0, 0, 1]])


def test_from_matrix_round_trip_and_skew_rejected() -> None:
    k = Intrinsics(1200.0, 1300.0, 300.0, 200.0)
    assert Intrinsics.from_matrix(k.matrix(), "file") == Intrinsics(1200.0, 1300.0, 300.0, 200.0, "file")
    skewed = k.matrix()
    skewed[0, 1] = 1.0
    with pytest.raises(IntrinsicsError, match="skew"):
        Intrinsics.from_matrix(skewed, "file")
    with pytest.raises(IntrinsicsError):
        Intrinsics.from_matrix(np.eye(2), "file")


# --- resolve_intrinsics --------------------------------------------------------------------

SIZES = np.array([[640.0, 480.0], [1280.0, 720.0], [800.0, 600.0]])
IDS: list[int | str] = [1, 2, 3]
NAMES: list[str | None] = ["a.jpg", "b.jpg", "c.jpg"]


def _entry(f: float, cx: float = 10.0, cy: float = 20.0) -> dict[str, Any]:
    return {"K": [[f, 0, cx], [0, f, cy], [0, 0, 1]]}


def test_resolve_pseudo_by_default() -> None:
    mats, sources = resolve_intrinsics(SIZES, IDS, NAMES)
    assert mats.shape == (3, 3, 3)
    assert sources == ["pseudo"] * 3
    np.testing.assert_array_equal(mats[1], Intrinsics.pseudo(1280, 720).matrix())


def test_resolve_cli_focal_and_principal_point() -> None:
    mats, sources = resolve_intrinsics(SIZES, IDS, NAMES, focal=1000.0)
    assert sources == ["cli"] * 3
    np.testing.assert_array_equal(mats[0], [[1000, 0, 320], [0, 1000, 240], [0, 0, 1]])
    mats, sources = resolve_intrinsics(SIZES, IDS, NAMES, principal_point=(5.0, 6.0))
    assert sources == ["cli"] * 3
    np.testing.assert_array_equal(mats[2], [[2000, 0, 5], [0, 2000, 6], [0, 0, 1]])


def test_resolve_precedence(tmp_path: Path) -> None:
    doc = {
        **_entry(700.0),  # global
        "images": {"1": _entry(100.0), "b.jpg": _entry(200.0), "2": {"fx": 300, "fy": 310, "cx": 1, "cy": 2}},
    }
    path = _write_json(tmp_path / "K.json", doc)
    sizes = np.array([[640.0, 480.0], [1280.0, 720.0], [800.0, 600.0], [100.0, 100.0]])
    mats, sources = resolve_intrinsics(
        sizes, [1, 2, 3, 4], ["a.jpg", "b.jpg", "c.jpg", None],
        focal=999.0, principal_point=(1.0, 1.0), intrinsics_file=path,
    )  # fmt: skip
    assert sources == ["file"] * 4
    assert mats[0, 0, 0] == 100.0  # by image id
    assert (mats[1, 0, 0], mats[1, 1, 1]) == (300.0, 310.0)  # image id beats file name
    assert mats[2, 0, 0] == 700.0  # global entry beats --focal
    assert mats[3, 0, 0] == 700.0


def test_resolve_per_image_by_file_name_then_cli(tmp_path: Path) -> None:
    path = _write_json(tmp_path / "K.json", {"images": {"b.jpg": _entry(200.0, 7.0, 8.0)}})
    mats, sources = resolve_intrinsics(SIZES, IDS, NAMES, focal=1000.0, intrinsics_file=path)
    assert sources == ["cli", "file", "cli"]
    np.testing.assert_array_equal(mats[1], [[200, 0, 7], [0, 200, 8], [0, 0, 1]])
    np.testing.assert_array_equal(mats[0], [[1000, 0, 320], [0, 1000, 240], [0, 0, 1]])
    # Without CLI values, the others fall back to pseudo.
    _, sources = resolve_intrinsics(SIZES, IDS, NAMES, intrinsics_file=path)
    assert sources == ["pseudo", "file", "pseudo"]


def test_resolve_missing_image_size_names_the_instance() -> None:
    sizes = np.array([[640.0, 480.0], [math.nan, math.nan]])
    with pytest.raises(IntrinsicsError, match=r"instance 1 \(image_id 'x7'\)"):
        resolve_intrinsics(sizes, [1, "x7"], [None, None])
    # A principal point makes the size unnecessary.
    mats, _ = resolve_intrinsics(sizes, [1, "x7"], [None, None], principal_point=(3.0, 4.0))
    np.testing.assert_array_equal(mats[1, :2, 2], [3.0, 4.0])


@pytest.mark.parametrize("focal", [0.0, -1.0, math.nan, math.inf])
def test_resolve_rejects_bad_focal(focal: float) -> None:
    with pytest.raises(IntrinsicsError, match="focal"):
        resolve_intrinsics(SIZES, IDS, NAMES, focal=focal)


@pytest.mark.parametrize(
    ("content", "needle"),
    [
        ("{not json", "JSON"),
        (json.dumps({"K": [[1000, 1, 10], [0, 1000, 10], [0, 0, 1]]}), "skew"),
        (json.dumps({"fx": 1000, "cx": 10, "cy": 10}), "fy"),
        (json.dumps({"images": {"a.jpg": {"fx": 1000, "cx": 10, "cy": 10}}}), "fy"),
        (json.dumps([1, 2, 3]), "object"),
        (json.dumps({"other": 1}), "no intrinsics"),
        (json.dumps({"fx": -5, "fy": 1000, "cx": 10, "cy": 10}), "focal"),
    ],
)
def test_resolve_malformed_file_names_the_file(tmp_path: Path, content: str, needle: str) -> None:
    path = tmp_path / "bad_K.json"
    path.write_text(content)
    with pytest.raises(IntrinsicsError) as info:
        resolve_intrinsics(SIZES, IDS, NAMES, intrinsics_file=str(path))
    assert str(path) in str(info.value)
    assert needle in str(info.value)


def test_resolve_missing_file(tmp_path: Path) -> None:
    path = str(tmp_path / "absent.json")
    with pytest.raises(IntrinsicsError, match="absent.json"):
        resolve_intrinsics(SIZES, IDS, NAMES, intrinsics_file=path)


def test_a_missing_image_size_names_every_option_that_gives_one() -> None:
    from zedo_cli.errors import CameraInputError

    sizes = np.array([[np.nan, np.nan]])
    with pytest.raises(CameraInputError, match="instance 0 .* has no image size") as err:
        resolve_intrinsics(sizes, [7], [None])
    for option in ("--image-size W H", "--video FILE", "--images COCO.json", "--principal-point", "--intrinsics"):
        assert option in str(err.value)
