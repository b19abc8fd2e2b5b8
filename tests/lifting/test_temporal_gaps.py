"""The temporal filter on the input's time axis: missing frames are gaps,
and a gap longer than the filter's radius is never blended across."""

from __future__ import annotations

import numpy as np

from zedo_cli.lifting.temporal import smooth_on_frames, smooth_sequence, smooth_tracks


def test_a_long_gap_is_never_blended_across() -> None:
    frames = np.array([0, 1, 2, 3, 4, 20, 21, 22, 23, 24])
    values = np.where(frames < 10, 0.0, 10.0)[:, None]
    np.testing.assert_allclose(smooth_on_frames(values, frames, 2.0), values, atol=1e-12)
    assert smooth_sequence(values, 2.0)[4, 0] > 1.0  # as consecutive frames, the jump leaks


def test_a_short_gap_is_weighted_by_real_time() -> None:
    """Across a 2-frame gap the weights follow real time: the result is the filter on the time
    axis with the missing frames NaN, not the filter of the frames taken as consecutive."""
    frames = np.array([0, 1, 2, 3, 6, 7, 8, 9])
    values = (3.0 * frames)[:, None].astype(float)
    dense = np.full((10, 1), np.nan)
    dense[frames] = values
    got = smooth_on_frames(values, frames, 1.0)
    np.testing.assert_allclose(got, smooth_sequence(dense, 1.0)[frames])
    assert np.abs(got - smooth_sequence(values, 1.0)).max() > 1.0


def test_without_increasing_frame_numbers_the_values_are_consecutive() -> None:
    values = np.arange(6.0)[:, None] ** 2
    want = smooth_sequence(values, 1.0)
    np.testing.assert_array_equal(smooth_on_frames(values, None, 1.0), want)
    np.testing.assert_array_equal(smooth_on_frames(values, np.array([0, 1, 1, 2, 3, 4]), 1.0), want)


def test_tracks_use_their_own_frames() -> None:
    rel = np.zeros((6, 2, 3))
    trans = np.array([[0.0, 0, 1], [0, 0, 1], [0, 0, 1], [5, 0, 1], [5, 0, 1], [5, 0, 1]])
    frames = np.array([0, 1, 2, 40, 41, 42])
    _, smoothed = smooth_tracks(rel, trans, 2.0, None, frames)
    np.testing.assert_allclose(smoothed, trans, atol=1e-12)


def test_timestamps_are_counted_in_their_usual_step() -> None:
    """Millisecond timestamps (33-34 ms apart, one frame missing) smooth like frame numbers."""
    frames = np.array([0, 33, 67, 100, 133, 200, 233, 267])  # 167 is missing
    values = np.sin(np.arange(8.0))[:, None]
    positions = np.array([0, 1, 2, 3, 4, 6, 7, 8])
    np.testing.assert_allclose(smooth_on_frames(values, frames, 1.0), smooth_on_frames(values, positions, 1.0))
    assert np.abs(smooth_on_frames(values, frames, 1.0) - values).max() > 0.05  # it does smooth
