"""Temporal mode: the smoothing filter, the warm start of `lift`, and `lift_sequence` on a generated video."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from helpers import K_TEST, project_poses, synthetic_poses

from zedo_cli.errors import ConfigError
from zedo_cli.lifting.config import TEMPORAL_MODES, LiftConfig, get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.lifting.temporal import lift_sequence, smooth_sequence, smooth_tracks
from zedo_cli.prior.weights import Prior

QUICK = LiftConfig(steps=20, init_steps=20, step_delta=None)


def _video(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A slowly turning generated pose, frame after frame, with 1 px noise on its projections."""
    base = synthetic_poses(1, seed=3)[0]
    ang = np.linspace(-0.3, 0.3, n)
    c, s = np.cos(ang), np.sin(ang)
    rot = np.zeros((n, 3, 3))
    rot[:, 0, 0], rot[:, 0, 2], rot[:, 1, 1], rot[:, 2, 0], rot[:, 2, 2] = c, s, 1.0, -s, c
    poses = base @ rot.transpose(0, 2, 1)
    xy = project_poses(poses) + np.random.default_rng(0).normal(0.0, 1.0, (n, 12, 2))
    return poses, xy, np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)


def test_filter_keeps_a_constant_and_a_straight_line() -> None:
    const = np.full((20, 4, 3), 0.7)
    np.testing.assert_allclose(smooth_sequence(const, 2.0), const)
    line = np.linspace(0.0, 1.0, 30)[:, None]
    inner = slice(7, 23)  # beyond 3 sigma from the edges: symmetric window, no lag
    np.testing.assert_allclose(smooth_sequence(line, 2.0)[inner], line[inner], atol=1e-12)
    np.testing.assert_array_equal(smooth_sequence(line, 0.0), line)
    with pytest.raises(ConfigError):
        smooth_sequence(line, -1.0)


def test_filter_reduces_the_jitter_of_a_noisy_line() -> None:
    truth = np.linspace(0.0, 1.0, 200)
    noisy = truth + np.random.default_rng(0).normal(0.0, 0.05, 200)
    smooth = smooth_sequence(noisy, 2.0)
    assert np.abs(np.diff(smooth, 2)).mean() < 0.1 * np.abs(np.diff(noisy, 2)).mean()
    assert np.abs(smooth - truth).mean() < 0.5 * np.abs(noisy - truth).mean()


def test_filter_nan_gaps_stay_nan_and_do_not_poison_neighbours() -> None:
    values = np.full((30, 2), 3.0)
    values[10:13] = np.nan
    values[20, 1] = np.nan  # one element only
    out = smooth_sequence(values, 2.0)
    assert np.isnan(out[10:13]).all() and np.isnan(out[20, 1]) and out[20, 0] == pytest.approx(3.0)
    finite = np.isfinite(values)
    np.testing.assert_allclose(out[finite], 3.0)
    all_nan = smooth_sequence(np.full((5, 3), np.nan), 1.0)
    assert np.isnan(all_nan).all()


def test_tracks_are_smoothed_apart() -> None:
    rel = np.concatenate([np.zeros((10, 12, 3)), np.ones((10, 12, 3))])
    trans = np.concatenate([np.zeros((10, 3)), np.ones((10, 3))])
    tracks = np.repeat([5, 2], 10)
    r, t = smooth_tracks(rel, trans, 3.0, tracks)
    np.testing.assert_allclose(r, rel)
    np.testing.assert_allclose(t, trans)
    r_mixed, _ = smooth_tracks(rel, trans, 3.0)  # one track: the step is blurred
    assert not np.allclose(r_mixed, rel)


def test_warm_start_changes_nothing_when_unused(tiny_prior: Prior) -> None:
    _, xy, conf, k = _video(4)
    for name in ("fast",):
        cfg = replace(get_preset(name), init_steps=10)
        plain = lift(xy, conf, k, tiny_prior, cfg)
        none = lift(xy, conf, k, tiny_prior, cfg, start_poses=None, start_translation=None)
        nan = lift(xy, conf, k, tiny_prior, cfg, start_poses=np.full((4, 12, 3), np.nan),
                   start_translation=np.full((4, 3), np.nan))  # fmt: skip
        np.testing.assert_array_equal(plain.poses_camera, none.poses_camera)
        np.testing.assert_array_equal(plain.poses_camera, nan.poses_camera)
    for name in ("faithful", "fast", "fast-bf16"):  # the new fields' defaults leave the presets as they were
        preset = get_preset(name)
        assert replace(preset, warm_steps=7, warm_t_start=0.05).steps == preset.steps


def test_warm_start_from_the_truth_stays_close(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _video(6)
    cold = lift(xy, conf, k, tiny_prior, QUICK)
    warm = lift(xy, conf, k, tiny_prior, QUICK, start_poses=poses, start_translation=np.tile([0.0, 0.0, 1.0], (6, 1)))
    err = np.linalg.norm(warm.poses_root_relative - poses, axis=-1).mean() * 1000
    assert err < np.linalg.norm(cold.poses_root_relative - poses, axis=-1).mean() * 1000
    assert err < 25.0, err  # the tiny prior moves it a little in 3 steps
    assert np.isfinite(warm.poses_camera).all() and warm.config.warm_steps == 3
    with pytest.raises(ConfigError):
        lift(xy, conf, k, tiny_prior, QUICK, start_poses=poses)
    with pytest.raises(ConfigError):
        lift(xy, conf, k, tiny_prior, QUICK, start_poses=poses[:2], start_translation=np.zeros((2, 3)))


@pytest.mark.parametrize("bad", [{"warm_steps": 0}, {"warm_t_start": 0.001}, {"warm_release_fraction": 2.0},
                                 {"warm_step_delta": 0.0}])  # fmt: skip
def test_invalid_warm_settings_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        LiftConfig(**bad)


def test_temporal_modes_shapes_gaps_and_jitter(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _video(24)
    conf[8:10, 2:] = 0.0  # two frames with two joints: not lifted
    tracks = np.repeat([0, 1], 12)
    results = {}
    for mode in TEMPORAL_MODES:
        seen = []
        res = lift_sequence(xy, conf, k, tiny_prior, QUICK, mode=mode, tracks=tracks, callback=seen.append)
        assert res.poses_camera.shape == (24, 12, 3) and res.root_translation.shape == (24, 3)
        assert res.poses_root_relative.shape == (24, 12, 3) and res.reprojection_error_px.shape == (24, 12)
        assert res.lifted.tolist() == [i not in (8, 9) for i in range(24)]
        assert np.isnan(res.poses_camera[8:10]).all()
        assert np.isfinite(res.poses_camera[res.lifted]).all()
        assert seen[-1].done == seen[-1].total
        results[mode] = res

    def jitter(res: object) -> float:
        p = res.poses_root_relative[12:]  # type: ignore[attr-defined]
        return float(np.linalg.norm(np.diff(p, 2, axis=0), axis=-1).mean())

    assert jitter(results["smooth"]) < jitter(results["none"])
    with pytest.raises(ConfigError):
        lift_sequence(xy, conf, k, tiny_prior, QUICK, mode="nope")
    with pytest.raises(ConfigError):
        lift_sequence(xy, conf, k, tiny_prior, QUICK, tracks=np.zeros(3))
