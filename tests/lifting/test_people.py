"""Person selection per frame (`--person`)."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError
from zedo_cli.lifting.people import PERSON_MODES, group_by_frame, select_people

SKEL = get_skeleton("coco17")


def _person(cx: float, cy: float, half: float, joints: int = 17) -> np.ndarray:
    """A square of keypoints centred at (cx, cy), `half` pixels from centre to edge."""
    rng = np.random.default_rng(int(cx + cy + half))
    pts = rng.uniform(-half, half, (17, 2)) + [cx, cy]
    pts[0], pts[1] = [cx - half, cy - half], [cx + half, cy + half]  # pin the box
    pts[joints:] = np.nan
    return pts


def _kp(people: list[tuple[object, np.ndarray, float | None]], sizes: bool = True) -> Keypoints2D:
    xy = np.stack([p for _, p, _ in people])
    conf = np.where(np.isfinite(xy).all(-1), 0.9, 0.0)
    size = [640.0, 480.0] if sizes else [np.nan, np.nan]
    return Keypoints2D(
        xy, conf, SKEL, [f for f, _, _ in people], [None] * len(people), np.tile(size, (len(people), 1)),
        [s for _, _, s in people], "mem.json", "test",
    )  # fmt: skip


def test_groups_follow_first_appearance() -> None:
    kp = _kp([(3, _person(100, 100, 20), None), (1, _person(50, 50, 10), None), (3, _person(9, 9, 5), None)])
    assert group_by_frame(kp) == [[0, 2], [1]]


def test_each_mode_picks_its_person() -> None:
    small_centre = _person(320, 240, 20)
    big_corner = _person(100, 100, 80)
    kp = _kp([(0, small_centre, 0.3), (0, big_corner, 0.8)])
    assert select_people(kp, "largest").index.tolist() == [1]
    assert select_people(kp, "center").index.tolist() == [0]
    assert select_people(kp, "highest-score").index.tolist() == [1]
    both = select_people(kp, "all")
    assert both.index.tolist() == [0, 1] and both.person.tolist() == [0, 1]


def test_auto_prefers_complete_then_follows_the_same_person() -> None:
    infant = [_person(300 + 5 * t, 240, 60) for t in range(3)]
    parent_hands = _person(560, 80, 30, joints=6)  # few joints, high score
    parent = _person(500, 300, 70)
    people = [(0, infant[0], 0.7), (0, parent_hands, 0.99), (1, parent, 0.95), (1, infant[1], 0.7),
              (2, infant[2], 0.6)]  # fmt: skip
    sel = select_people(_kp(people), "auto")
    assert sel.index.tolist() == [0, 3, 4]  # the infant in every frame, not the higher-scoring parent
    assert sel.person.tolist() == [0, 1, 0]


def test_highest_score_falls_back_to_mean_confidence() -> None:
    kp = _kp([(0, _person(100, 100, 20), None), (0, _person(300, 300, 20), None)])
    kp.confidence[1] *= 0.5
    assert select_people(kp, "highest-score").index.tolist() == [0]


def test_center_without_image_sizes_is_a_clear_error() -> None:
    kp = _kp([(0, _person(100, 100, 20), None)], sizes=False)
    with pytest.raises(ConfigError, match="mem.json.*image sizes"):
        select_people(kp, "center")


def test_unknown_mode_and_all_missing_instances() -> None:
    with pytest.raises(ConfigError, match="--person"):
        select_people(_kp([(0, _person(1, 1, 1), None)]), "tallest")
    empty = np.full((17, 2), np.nan)
    kp = _kp([(0, empty, None), (0, _person(100, 100, 20), None)])
    for mode in PERSON_MODES:
        if mode != "all":
            assert select_people(kp, mode).index.tolist() == [1], mode
