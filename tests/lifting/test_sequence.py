"""The temporal mode lifts only what is one sequence: photos, frames out of
order and jumping poses are refused before smoothing; after smoothing, a pose pulled off its 2D
is poor_fit."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import K_TEST, project_poses, synthetic_poses

from zedo_cli.errors import ConfigError
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.sequence import MAX_MEDIAN_JUMP, check_sequence, median_jump, sequence_problem
from zedo_cli.lifting.temporal import lift_sequence
from zedo_cli.prior.weights import Prior

QUICK = LiftConfig(steps=20, init_steps=20, step_delta=None)


def _video(n: int) -> np.ndarray:
    """Pixels `(n, 12, 2)` of a generated pose turning slowly, frame after frame, 1 px noise."""
    base = synthetic_poses(1, seed=3)[0]
    ang = np.linspace(-0.3, 0.3, n)
    c, s = np.cos(ang), np.sin(ang)
    rot = np.zeros((n, 3, 3))
    rot[:, 0, 0], rot[:, 0, 2], rot[:, 1, 1], rot[:, 2, 0], rot[:, 2, 2] = c, s, 1.0, -s, c
    return project_poses(base @ rot.transpose(0, 2, 1)) + np.random.default_rng(0).normal(0.0, 1.0, (n, 12, 2))


def _photos(n: int) -> np.ndarray:
    """Pixels of `n` unrelated poses: each placed, sized and turned at random in the image."""
    rng = np.random.default_rng(1)
    xy = project_poses(synthetic_poses(n, seed=5), depth=1.0)
    centre = xy.mean(1, keepdims=True)
    scale = rng.uniform(0.5, 2.0, (n, 1, 1))
    return (xy - centre) * scale + rng.uniform([100, 100], [540, 380], (n, 1, 2))


def _observed(xy: np.ndarray) -> np.ndarray:
    return np.isfinite(xy).all(-1)


def test_a_video_is_one_sequence() -> None:
    xy = _video(30)
    jump, pairs = median_jump(xy, _observed(xy))
    assert pairs == 29 and jump < 0.1
    sizes = np.tile([640.0, 480.0], (30, 1))
    names = [f"clip_{i:04d}.jpg" for i in range(30)]
    assert sequence_problem(xy, _observed(xy), image_sizes=sizes, file_names=names) is None
    assert sequence_problem(xy, _observed(xy), frames=np.arange(0, 60, 2)) is None  # every 2nd frame kept


def test_photos_are_not_one_sequence_by_their_motion() -> None:
    xy = _photos(40)
    jump, _ = median_jump(xy, _observed(xy))
    assert jump > MAX_MEDIAN_JUMP
    problem = sequence_problem(xy, _observed(xy), image_sizes=np.tile([640.0, 480.0], (40, 1)))
    assert problem is not None and "the pose jumps from frame to frame" in problem


def test_several_image_sizes_are_not_one_video() -> None:
    xy = _video(6)
    sizes = np.array([[640, 480], [640, 480], [1280, 720], [640, 480], [960, 720], [np.nan, np.nan]])
    problem = sequence_problem(xy, _observed(xy), image_sizes=sizes)
    assert problem == "3 image sizes (640x480, 960x720, 1280x720), where a video has one"


def test_frame_numbers_and_file_names_must_count_up() -> None:
    xy = _video(4)
    obs = _observed(xy)
    assert sequence_problem(xy, obs, frames=np.array([0, 1, 5, 3])) == (
        "frame numbers do not count up (frame 3 after frame 5)"
    )
    assert sequence_problem(xy, obs, file_names=["img9.jpg", "img10.jpg", "img2.jpg", "img11.jpg"]) == (
        "file names do not count up (img2.jpg after img10.jpg)"
    )
    problem = sequence_problem(xy, obs, file_names=["a.jpg", "b.jpg", "c.jpg", "d.jpg"])
    assert problem is not None and problem.startswith("file names without a frame number (a.jpg, b.jpg, ...)")
    # Frame numbers win over names; names of a frame shared by its people (tracks) are fine.
    assert sequence_problem(xy, obs, frames=np.arange(4), file_names=["z.jpg"] * 4) is None
    tracks = np.array([0, 1, 0, 1])
    assert sequence_problem(xy, obs, tracks=tracks, file_names=["f1.png", "f1.png", "f2.png", "f2.png"]) is None


def test_each_track_is_judged_alone() -> None:
    """Two people far apart, interleaved as --person all gives them: each moves continuously."""
    a, b = _video(10), _video(10) + [300.0, 0.0]
    xy = np.stack([a, b], 1).reshape(20, 12, 2)
    tracks = np.tile([0, 1], 10)
    assert median_jump(xy, _observed(xy), tracks)[0] < 0.1
    assert median_jump(xy, _observed(xy))[0] > MAX_MEDIAN_JUMP  # as one track it jumps
    assert sequence_problem(xy, _observed(xy), tracks=tracks) is None


def test_check_sequence_is_one_line_naming_the_input() -> None:
    xy = _photos(10)
    with pytest.raises(ConfigError) as info:
        check_sequence(xy, _observed(xy), "smooth", source="photos.json")
    message = str(info.value)
    assert message.startswith("photos.json: --temporal smooth smooths one video's frames, and these 10 are not one: ")
    assert message.endswith("lift them frame by frame (without --temporal)") and "\n" not in message
    assert info.value.exit_code == 2


def test_lift_sequence_refuses_photos_before_any_work(tiny_prior: Prior) -> None:
    xy = _photos(8)
    conf, k = np.ones((8, 12)), np.repeat(K_TEST[None], 8, 0)
    steps = []
    for mode in ("smooth", "two-pass"):
        with pytest.raises(ConfigError, match="the pose jumps from frame to frame"):
            lift_sequence(xy, conf, k, tiny_prior, QUICK, mode=mode, callback=steps.append)
    assert not steps  # refused before lifting
    assert lift_sequence(xy, conf, k, tiny_prior, QUICK, mode="none").lifted.all()  # frame by frame: fine


@pytest.mark.parametrize("mode", ["smooth", "two-pass"])
def test_a_pose_smoothing_pulls_off_its_2d_is_poor_fit(tiny_prior: Prior, mode: str) -> None:
    """One frame of a video moved 150 px in the image (a cut, a bad detection): the filter pulls its
    pose towards its neighbours', away from its own 2D, so it is flagged, as lift flags a poor fit."""
    xy = _video(24)
    xy[12] += [150.0, 0.0]  # about twice the pose's radius
    conf, k = np.ones((24, 12)), np.repeat(K_TEST[None], 24, 0)
    alone = lift_sequence(xy, conf, k, tiny_prior, QUICK, mode="none")
    assert alone.lifted.all()  # frame by frame, the moved frame fits its own 2D
    res = lift_sequence(xy, conf, k, tiny_prior, QUICK, mode=mode)
    assert res.status[12] == "poor_fit" and not res.lifted[12]
    assert np.isnan(res.poses_camera[12]).all() and np.isnan(res.reprojection_error_px[12]).all()
    far = np.r_[0:9, 16:24]  # beyond the filter's reach of frame 12 (3 sigma = 6 frames), nothing changes
    assert res.lifted[far].all()
