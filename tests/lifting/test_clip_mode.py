"""`--temporal clip`: the two solutions of a bone on its ray, the side kept over a track, ambiguous stretches,
one skeleton per track with every limb bone at its length, and the fallback of a short track."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import K_TEST
from test_temporal import QUICK, _video

from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError
from zedo_cli.lifting.clip import (
    BONE_NAMES,
    LIMB_BONES,
    MIN_TRACK_FRAMES,
    ambiguous_stretches,
    choose_sides,
    ray_solutions,
    unit_rays,
)
from zedo_cli.lifting.temporal import lift_sequence
from zedo_cli.prior.weights import Prior

SYRIP12 = get_skeleton("syrip12")


def test_a_bone_on_its_ray_has_a_near_and_a_far_solution_at_its_length() -> None:
    parent = np.array([[0.05, 0.02, 1.0]])
    ray = unit_rays(np.array([[[400.0, 260.0]]]), K_TEST[None])[:, 0]
    near, far, reach = ray_solutions(parent, ray, 0.2)
    assert reach[0]
    for point in (near, far):
        assert np.linalg.norm(point - parent) == pytest.approx(0.2)
        assert np.linalg.norm(np.cross(point, ray)) == pytest.approx(0.0, abs=1e-12)  # on the ray
    assert near[0, 2] < far[0, 2]
    short_near, short_far, short = ray_solutions(parent, ray, 0.01)  # the ray passes further than 1 cm
    assert not short[0] and np.allclose(short_near, short_far)
    assert np.linalg.norm(short_near - parent) == pytest.approx(0.01)


def test_the_side_changes_only_near_the_image_plane() -> None:
    # frames 0-29 prefer the near side, 30-59 weakly prefer the far side while the solutions stay far apart
    cost = np.zeros((60, 2))
    cost[:30, 1] = 0.5
    cost[30:, 0] = 0.05
    apart = np.full(60, 1.5)
    assert (choose_sides(cost, apart) == 0).all()  # a flip mid-stretch would cost more than it gains
    close = apart.copy()
    close[29:31] = 0.02  # the limb passes the image plane at frame 30
    sides = choose_sides(cost, close)
    assert (sides[:30] == 0).all() and (sides[31:] == 1).all()
    margin = np.where(np.arange(60) < 30, 0.9, 0.1)
    flags = ambiguous_stretches(margin, close)
    assert not flags[:29].any() and flags[31:].all()  # the weakly preferred stretch is said to be ambiguous


def _clip_mode(prior: Prior, n: int, tracks: np.ndarray | None = None) -> tuple:
    poses, xy, conf, k = _video(n)
    res = lift_sequence(xy, conf, k, prior, QUICK, mode="clip", tracks=tracks, fps=30.0)
    return poses, res


def test_every_frame_holds_the_tracks_one_skeleton(tiny_prior: Prior) -> None:
    _, res = _clip_mode(tiny_prior, 40)
    assert res.lifted.all() and res.depth_ambiguous is not None and res.depth_ambiguous.shape == (40, 12)
    (skel,) = res.track_skeletons
    assert skel["frames"] == 40 and "fallback" not in skel
    for a, b in LIMB_BONES:
        lengths = np.linalg.norm(res.poses_camera[:, SYRIP12.index(a)] - res.poses_camera[:, SYRIP12.index(b)], axis=-1)
        bone = skel["bones"][BONE_NAMES[(a, b)]]
        np.testing.assert_allclose(lengths, bone["length_m"], rtol=1e-5)
        assert bone["share_low"] < bone["share"] < bone["share_high"]
    assert set(skel["torso"]) == {"hip_width", "shoulder_width", "trunk_length"}
    np.testing.assert_allclose(res.poses_root_relative, res.poses_camera - res.root_translation[:, None], atol=1e-12)
    assert np.nanmax(res.reprojection_error_px) < 40


def test_same_input_and_seed_same_output(tiny_prior: Prior) -> None:
    _, first = _clip_mode(tiny_prior, 30)
    _, again = _clip_mode(tiny_prior, 30)
    np.testing.assert_array_equal(first.poses_camera, again.poses_camera)
    assert first.track_skeletons == again.track_skeletons


def test_a_short_track_keeps_its_two_pass_poses_and_says_why(tiny_prior: Prior) -> None:
    n = 40 + MIN_TRACK_FRAMES - 1
    tracks = np.r_[np.zeros(40, int), np.ones(MIN_TRACK_FRAMES - 1, int)]
    _, res = _clip_mode(tiny_prior, n, tracks)
    long, short = res.track_skeletons
    assert long["track"] == 0 and "bones" in long
    assert short["track"] == 1 and short["fallback"].startswith("too few frames with every limb seen")
    assert not res.depth_ambiguous[40:].any()
    two_pass = lift_sequence(*_video(n)[1:], tiny_prior, QUICK, mode="two-pass", tracks=tracks)
    np.testing.assert_allclose(res.poses_camera[40:], two_pass.poses_camera[40:])


def test_clip_mode_needs_the_limbs_joints(tiny_prior: Prior) -> None:
    from dataclasses import replace

    from zedo_cli.lifting.temporal import lift_tracks_as_infants

    _, res = _clip_mode(tiny_prior, 20)
    h36m = get_skeleton("h36m17")
    with pytest.raises(ConfigError, match="--temporal clip needs the limbs' joints"):
        lift_tracks_as_infants(replace(res), np.zeros((20, 12, 2)), np.repeat(K_TEST[None], 20, 0),
                               replace(h36m, joints=h36m.joints[:12]), None, None, 2.0, 30.0)  # fmt: skip


def _keypoints(path, n: int):  # noqa: ANN001, ANN202
    import json

    _, xy, _, _ = _video(n)
    instances = [{"image_id": i, "frame": i, "keypoints": xy[i].tolist()} for i in range(n)]
    path.write_text(json.dumps({"skeleton": "syrip12", "image_size": [640, 480], "instances": instances}))
    return path


def test_zedo_lift_temporal_clip_records_the_skeleton_and_warns_of_a_fallback(tiny_prior_path, tmp_path) -> None:  # noqa: ANN001
    import json

    from typer.testing import CliRunner

    from zedo_cli.cli import app

    def run(n: int) -> tuple:
        src = _keypoints(tmp_path / f"kp{n}.json", n)
        out = tmp_path / f"kp{n}.zedo.json"
        args = ["lift", str(src), "--prior", str(tiny_prior_path), "--steps", "20", "--fps", "30", "--temporal", "clip",
                "--focal", "1000", "-o", str(out)]  # fmt: skip
        result = CliRunner().invoke(app, args)
        assert result.exit_code == 0, result.output
        return json.loads(out.read_text()), result.stderr

    from zedo_cli.formats.result_schema import ResultDocument

    doc, stderr = run(40)
    ResultDocument.model_validate(doc, context={"joints": 12})  # the skeletons typed by the published schema
    (skel,) = doc["params"]["temporal"]["skeletons"]
    assert doc["params"]["temporal"]["mode"] == "clip" and len(skel["bones"]) == 8 and "warning" not in stderr
    short, stderr = run(MIN_TRACK_FRAMES - 5)
    ResultDocument.model_validate(short, context={"joints": 12})
    assert short["params"]["temporal"]["skeletons"][0]["fallback"].startswith("too few frames")
    assert "1 of 1 tracks lifted as two-pass, not as one infant: too few frames" in " ".join(stderr.split())


def test_an_ambiguous_ankle_or_wrist_says_what_the_other_side_would_bend(tiny_prior: Prior) -> None:
    from dataclasses import replace

    from zedo_cli.formats.flags import ambiguous_joint
    from zedo_cli.lifting.clip import flexion_deg

    straight = flexion_deg(np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.1, 0.0]]), np.array([[0.0, 0.2, 0.0]]))
    bent = flexion_deg(np.array([[0.0, 0.0, 0.0]]), np.array([[0.0, 0.1, 0.0]]), np.array([[0.1, 0.1, 0.0]]))
    assert straight[0] == pytest.approx(0.0) and bent[0] == pytest.approx(90.0)
    _, res = _clip_mode(tiny_prior, 40)
    assert res.other_flexion_deg is not None and res.other_flexion_deg.shape == (40, 12)
    distal = [SYRIP12.index(n) for n in ("left_ankle", "right_ankle", "left_wrist", "right_wrist")]
    known = np.isfinite(res.other_flexion_deg)
    assert not known[:, [j for j in range(12) if j not in distal]].any()  # only at an ankle or a wrist
    assert (res.depth_ambiguous[known]).all()  # and only where the side was flagged
    flagged = np.zeros((40, 12), bool)
    flagged[3, SYRIP12.index("left_ankle")] = flagged[3, SYRIP12.index("right_knee")] = True
    other = np.full((40, 12), np.nan)
    other[3, SYRIP12.index("left_ankle")] = 41.6
    marked = replace(res, depth_ambiguous=flagged, other_flexion_deg=other)
    words = [ambiguous_joint(SYRIP12.joints, marked, 3, j) for j in np.flatnonzero(flagged[3])]
    assert words == ["right_knee", "left_ankle (other side: left_knee flexion 42 deg)"]


def test_a_csv_result_keeps_the_flags_per_joint_row_and_reads_them_back(tiny_prior: Prior, tmp_path) -> None:  # noqa: ANN001
    """The CSV's `flags` column: each joint row its own flags and the person's; read back, the person's flags are
    the JSON's (those not said by other columns: `status`, `observed`)."""
    import csv
    import io
    from dataclasses import replace

    from zedo_cli.camera.sanity import check_camera_sanity
    from zedo_cli.formats.flags import person_flags
    from zedo_cli.formats.readers.inputs import read_keypoints
    from zedo_cli.formats.readers.result_csv import read_csv
    from zedo_cli.formats.writers.result_csv import csv_text

    kp = read_keypoints(str(_keypoints(tmp_path / "kp.json", 40))).to_skeleton(SYRIP12)
    _, res = _clip_mode(tiny_prior, 40)
    ambiguous, outliers, swapped = (np.zeros((40, 12), bool) for _ in range(3))
    ambiguous[5, SYRIP12.index("left_ankle")] = ambiguous[5, SYRIP12.index("right_knee")] = True
    outliers[7, SYRIP12.index("right_wrist")] = True
    other = np.full((40, 12), np.nan)
    other[5, SYRIP12.index("left_ankle")] = 12.0
    res = replace(res, depth_ambiguous=ambiguous, other_flexion_deg=other, detection_outliers=outliers,
                  detection_swapped=swapped[:, 0] | (np.arange(40) == 7))  # fmt: skip
    k = np.repeat(K_TEST[None], 40, 0)
    text = csv_text(kp, res, k, ["cli"] * 40)
    rows = list(csv.DictReader(io.StringIO(text)))
    cell = {(int(r["frame_index"]), r["joint"]): r["flags"] for r in rows}
    assert cell[(5, "left_ankle")].endswith("depth_ambiguous (other side: left_knee flexion 12 deg)")
    assert cell[(7, "right_wrist")].endswith("left_right_swapped_in_2d; detection_outlier")
    hip = cell[(7, "left_hip")]
    assert hip.endswith("left_right_swapped_in_2d") and "detection_outlier" not in hip
    back = read_csv(text, "kp.zedo.csv", None)
    sanity = check_camera_sanity(kp.xy, res.observed, kp.image_sizes, res.root_translation, res.lifted)
    for i in range(40):
        expected = [f for f in person_flags(kp, res, i, sanity) if not f.startswith(("not_lifted_", "joints_filled"))]
        assert back.flags[i] == expected
    assert "depth_ambiguous: right_knee, left_ankle (other side: left_knee flexion 12 deg)" in back.flags[5]


@pytest.mark.parametrize("mode", ["two-pass", "clip"])
def test_a_joint_the_lift_does_not_use_never_moves_the_smoothed_2d(tiny_prior: Prior, mode: str) -> None:
    """A detector's placeholder (0, 0) or a joint under --min-confidence is not an observation: the poses are those
    of the same joint missing (NaN), not pulled towards it by the 2D smoothing of the second pass."""
    _, xy, conf, k = _video(40)
    junk_xy, junk_conf, missing_xy = xy.copy(), conf.copy(), xy.copy()
    junk_xy[::3, 8] = 0.0  # the left wrist at the image's corner every third frame
    junk_conf[::3, 8] = 0.05
    missing_xy[::3, 8] = np.nan
    got = lift_sequence(junk_xy, junk_conf, k, tiny_prior, QUICK, mode=mode, fps=30.0, min_confidence=0.3)
    want = lift_sequence(missing_xy, junk_conf, k, tiny_prior, QUICK, mode=mode, fps=30.0, min_confidence=0.3)
    np.testing.assert_allclose(got.poses_camera, want.poses_camera, atol=1e-9)
