"""MINI-RGBD: the reader of the data set's layout, both joint mappings, both splits, errors,
scoring, `zedo fit-prior --minirgbd-dir` and `zedo benchmark-minirgbd`.

The data set cannot be shipped, so every test writes a small one in its real layout: 12
sequences of 3 frames, infant-sized SMIL-25 poses 0.6-0.8 m in front of the depth camera,
with their exact projections through the Kinect depth intrinsics.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import torch
from helpers import tiny_recipe
from typer.testing import CliRunner

from zedo_cli.cli import app
from zedo_cli.data.minirgbd import (
    SEQUENCES,
    SMIL25_JOINTS,
    load_minirgbd,
    load_minirgbd_3d,
    smil_to_h36m17,
    split_sequences,
)
from zedo_cli.data.skeleton import center_on_root, get_skeleton
from zedo_cli.errors import ConfigError, DataError, InputFormatError, WeightsError
from zedo_cli.evaluation.minirgbd_benchmark import (
    DEPTH_INTRINSICS,
    protocol_joints,
    run_minirgbd_benchmark,
    score_minirgbd,
)
from zedo_cli.lifting.config import get_preset
from zedo_cli.prior.model import PriorConfig, ScoreNet
from zedo_cli.prior.sde import SubVPSDE
from zedo_cli.prior.weights import load_prior, save_prior

runner = CliRunner()
H36M = get_skeleton("h36m17")
FRAMES = 3  # per sequence
# An infant lying in front of the camera (metres, x right, y down, z away from the camera).
BASE_SMIL = {
    "global": (0.0, 0.0, 0.0), "leftThigh": (0.04, 0.02, 0.0), "rightThigh": (-0.04, 0.02, 0.0),
    "spine": (0.0, -0.05, 0.0), "leftCalf": (0.05, 0.13, -0.03), "rightCalf": (-0.05, 0.13, -0.03),
    "spine1": (0.0, -0.1, 0.0), "leftFoot": (0.05, 0.23, -0.01), "rightFoot": (-0.05, 0.23, -0.01),
    "spine2": (0.0, -0.15, 0.0), "leftToes": (0.055, 0.25, -0.05), "rightToes": (-0.055, 0.25, -0.05),
    "neck": (0.0, -0.22, 0.0), "leftShoulder": (0.03, -0.2, 0.0), "rightShoulder": (-0.03, -0.2, 0.0),
    "head": (0.0, -0.28, -0.01), "leftUpperArm": (0.07, -0.2, 0.0), "rightUpperArm": (-0.07, -0.2, 0.0),
    "leftForeArm": (0.13, -0.15, -0.03), "rightForeArm": (-0.13, -0.15, -0.03),
    "leftHand": (0.18, -0.1, -0.05), "rightHand": (-0.18, -0.1, -0.05),
    "leftFingers": (0.21, -0.08, -0.05), "rightFingers": (-0.21, -0.08, -0.05),
    "noseVertex": (0.0, -0.3, -0.05),
}  # fmt: skip
# ALGORITHM.md 1.2: the authors' MINI 25 -> H36M-17 table, and the anatomical variant
# (ankles 7/8 for the toes 10/11, upper arms 16/17 for the collars 13/14).
REFERENCE_TABLE = [0, 2, 5, 11, 1, 4, 10, 3, 9, 12, 15, 13, 18, 20, 14, 19, 21]
ANATOMICAL_TABLE = [0, 2, 5, 8, 1, 4, 7, 3, 9, 12, 15, 16, 18, 20, 17, 19, 21]
TINY_RECIPE = tiny_recipe(epochs=300, batch_size=32, more='lr = 1e-3\nwarmup_steps = 20\n[output]\ndtype = "float32"\n')


def random_smil_pose(rng: np.random.Generator) -> np.ndarray:
    """One SMIL-25 pose `(25, 3)` in the camera frame: the base pose with 1 cm joint noise,
    turned in the image plane by up to +-0.5 rad, 0.6-0.8 m from the camera."""
    pose = np.array([BASE_SMIL[j] for j in SMIL25_JOINTS]) + rng.normal(0.0, 0.01, (25, 3))
    a = rng.uniform(-0.5, 0.5)
    rot = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    shift = np.array([rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(0.6, 0.8)])
    return pose @ rot.T + shift


def write_minirgbd(root: Path, frames: int = FRAMES, seed: int = 0) -> Path:
    """A MINI-RGBD folder in the data set's layout: one line per joint, `x y z id` (metres)
    in joints_3D and `u v depth_mm id` in joints_2Ddep, the 2D projected exactly with K."""
    rng = np.random.default_rng(seed)
    k = DEPTH_INTRINSICS.matrix()
    for seq in SEQUENCES:
        (root / seq / "joints_3D").mkdir(parents=True)
        (root / seq / "joints_2Ddep").mkdir(parents=True)
        for f in range(frames):
            xyz = np.round(random_smil_pose(rng), 6)
            uv = (xyz @ k.T)[:, :2] / xyz[:, 2:]
            lines_3d = "".join(f"{x:.6f} {y:.6f} {z:.6f} {i}\n" for i, (x, y, z) in enumerate(xyz))
            uvz = np.c_[uv, 1000 * xyz[:, 2]]  # the third 2D column: depth in mm (not read)
            lines_2d = "".join(f"{u:.6f} {v:.6f} {d:.1f} {i}\n" for i, (u, v, d) in enumerate(uvz))
            (root / seq / "joints_3D" / f"syn_joints_3D_{f:05d}.txt").write_text(lines_3d)
            (root / seq / "joints_2Ddep" / f"syn_joints_2Ddep_{f:05d}.txt").write_text(lines_2d)
    return root


@pytest.fixture(scope="module")
def mini_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_minirgbd(tmp_path_factory.mktemp("minirgbd") / "MINI-RGBD")


@pytest.fixture(scope="module")
def mini_prior(mini_dir: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A tiny h36m17 prior trained by `zedo fit-prior` on the reference split's train side."""
    tmp = tmp_path_factory.mktemp("mini-prior")
    (tmp / "tiny.toml").write_text(TINY_RECIPE)
    out = tmp / "mini.safetensors"
    args = ["fit-prior", "--minirgbd-dir", str(mini_dir), "--minirgbd-split", "reference", "--split", "train",
            "--recipe", str(tmp / "tiny.toml"), "-q", "--out", str(out)]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    return out


# --- reading and mapping -------------------------------------------------------------------


def test_depth_intrinsics_are_the_kinect_depth_camera() -> None:
    k = DEPTH_INTRINSICS.matrix()
    assert k[0, 0] == pytest.approx(588.67905803875317) and k[1, 1] == pytest.approx(590.25690113005601)
    assert k[0, 2] == pytest.approx(322.22048191353628) and k[1, 2] == pytest.approx(237.46785983766890)


def test_reader_keeps_the_files_columns_in_joint_order(mini_dir: Path) -> None:
    frames = load_minirgbd(mini_dir, ("01", "12"), mapping="reference")
    assert frames.names == ["01/00000", "01/00001", "01/00002", "12/00000", "12/00001", "12/00002"]
    assert frames.poses_camera.shape == (6, 17, 3) and frames.keypoints_2d is not None
    raw = np.loadtxt(mini_dir / "12" / "joints_3D" / "syn_joints_3D_00001.txt")
    np.testing.assert_allclose(frames.poses_camera[4], raw[REFERENCE_TABLE, :3])
    raw2d = np.loadtxt(mini_dir / "12" / "joints_2Ddep" / "syn_joints_2Ddep_00001.txt")
    np.testing.assert_allclose(frames.keypoints_2d[4], raw2d[REFERENCE_TABLE, :2])
    # 3D in metres and 2D in depth-image pixels agree through the depth camera's K.
    uv = frames.poses_camera @ DEPTH_INTRINSICS.matrix().T
    np.testing.assert_allclose(uv[..., :2] / uv[..., 2:], frames.keypoints_2d, atol=1e-5)


@pytest.mark.parametrize(("mapping", "table"), [("reference", REFERENCE_TABLE), ("anatomical", ANATOMICAL_TABLE)])
def test_mappings_follow_the_documented_tables(mapping: str, table: list[int]) -> None:
    smil = np.arange(25 * 2, dtype=float).reshape(25, 2)
    np.testing.assert_array_equal(smil_to_h36m17(smil, mapping), smil[table])


def test_mappings_differ_only_in_ankles_and_shoulders(mini_dir: Path) -> None:
    ref = load_minirgbd(mini_dir, ("03",), mapping="reference").poses_camera
    ana = load_minirgbd(mini_dir, ("03",), mapping="anatomical").poses_camera
    differ = [j for j in H36M.joints if not np.allclose(ref[:, H36M.index(j)], ana[:, H36M.index(j)])]
    assert sorted(differ) == ["left_ankle", "left_shoulder", "right_ankle", "right_shoulder"]
    # The toes lie beyond the ankles: the reference's "shins" are longer on average.
    knee, ankle = H36M.index("left_knee"), H36M.index("left_ankle")
    assert (
        np.linalg.norm(ref[:, ankle] - ref[:, knee], axis=-1).mean()
        > np.linalg.norm(ana[:, ankle] - ana[:, knee], axis=-1).mean()
    )


@pytest.mark.parametrize(
    ("split", "side", "expected"),
    [
        ("paper", "train", SEQUENCES[:9]), ("paper", "test", ("10", "11", "12")),
        ("reference", "train", SEQUENCES[:10]), ("reference", "test", ("11", "12")),
        ("paper", "all", SEQUENCES), ("reference", "all", SEQUENCES),
    ],
)  # fmt: skip
def test_splits_by_name(mini_dir: Path, split: str, side: str, expected: tuple[str, ...]) -> None:
    assert split_sequences(split, side) == expected
    data = load_minirgbd_3d(mini_dir, split, side)
    assert len(data.names) == FRAMES * len(expected) and data.skeleton.name == "h36m17"
    assert {n.split("/")[0] for n in data.names} == set(expected)
    np.testing.assert_allclose(data.poses[:, H36M.index("pelvis")], 0.0)  # pelvis-centred


def test_train_and_test_sides_never_share_a_sequence() -> None:
    for split in ("paper", "reference"):
        assert not set(split_sequences(split, "train")) & set(split_sequences(split, "test"))
        assert set(split_sequences(split, "train")) | set(split_sequences(split, "test")) == set(SEQUENCES)


def test_stride_keeps_every_nth_frame_of_each_sequence(mini_dir: Path) -> None:
    frames = load_minirgbd(mini_dir, ("10", "11"), stride=2, with_2d=False)
    assert frames.names == ["10/00000", "10/00002", "11/00000", "11/00002"] and frames.keypoints_2d is None


# --- errors --------------------------------------------------------------------------------


def _break(root: Path, how: str) -> None:
    f3d = root / "05" / "joints_3D" / "syn_joints_3D_00001.txt"
    lines = f3d.read_text().splitlines(keepends=True)
    if how == "no-sequence":
        shutil.rmtree(root / "12")
    elif how == "no-3d-folder":
        shutil.rmtree(root / "05" / "joints_3D")
    elif how == "empty-3d-folder":
        for p in (root / "05" / "joints_3D").iterdir():
            p.unlink()
    elif how == "24-lines":
        f3d.write_text("".join(lines[:24]))
    elif how == "not-a-number":
        f3d.write_text("".join(lines[:4] + ["0.1 abc 0.7 4\n"] + lines[5:]))
    elif how == "two-columns":
        f3d.write_text("".join(lines[:2] + ["0.1 0.2\n"] + lines[3:]))
    elif how == "nan":
        f3d.write_text("".join(lines[:6] + ["0.1 nan 0.7 6\n"] + lines[7:]))
    elif how == "no-2d-file":
        (root / "05" / "joints_2Ddep" / "syn_joints_2Ddep_00001.txt").unlink()


@pytest.mark.parametrize(
    ("how", "error", "needles"),
    [
        ("no-sequence", DataError, ["12", "sequence 12 not found"]),
        ("no-3d-folder", DataError, ["05/joints_3D", "folder not found"]),
        ("empty-3d-folder", DataError, ["05/joints_3D", "no syn_joints_3D_XXXXX.txt files"]),
        ("24-lines", InputFormatError, ["syn_joints_3D_00001.txt", "expected 25 joint lines", "found 24"]),
        ("not-a-number", InputFormatError, ["syn_joints_3D_00001.txt: line 5:", "not a number"]),
        ("two-columns", InputFormatError, ["syn_joints_3D_00001.txt: line 3:", "at least 3 numbers"]),
        ("nan", InputFormatError, ["syn_joints_3D_00001.txt: line 7:", "NaN"]),
        ("no-2d-file", DataError, ["syn_joints_2Ddep_00001.txt: file not found", "05/00001"]),
    ],
)
def test_malformed_data_names_the_file_and_line(tmp_path: Path, how: str, error: type, needles: list[str]) -> None:
    root = write_minirgbd(tmp_path / "mini", frames=2)
    _break(root, how)
    with pytest.raises(error) as info:
        load_minirgbd(root, SEQUENCES)
    for needle in needles:
        assert needle in str(info.value)


@pytest.mark.parametrize(
    ("call", "needle"),
    [
        (lambda: split_sequences("ours", "train"), "unknown MINI-RGBD split 'ours'"),
        (lambda: split_sequences("paper", "val"), "unknown split side 'val'"),
        (lambda: smil_to_h36m17(np.zeros((25, 3)), "toes"), "unknown MINI-RGBD mapping 'toes'"),
        (lambda: protocol_joints("15"), "unknown protocol '15'"),
        (lambda: protocol_joints("16", "nose"), "'nose' is not an h36m17 joint"),
        (lambda: load_minirgbd("/nonexistent", ("01",), stride=0), "--stride must be >= 1"),
    ],
)
def test_bad_choices_are_config_errors(call: Callable[[], object], needle: str) -> None:
    with pytest.raises(ConfigError) as info:
        call()
    assert needle in str(info.value)


def test_missing_folder_is_a_data_error(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="MINI-RGBD folder not found"):
        load_minirgbd(tmp_path / "nope", SEQUENCES)


# --- scoring -------------------------------------------------------------------------------


def test_scoring_the_ground_truth_gives_zero(mini_dir: Path) -> None:
    truth = load_minirgbd(mini_dir, SEQUENCES).poses_camera
    for protocol in ("17", "16"):
        mpjpe, pa, per_joint = score_minirgbd(truth, truth, protocol_joints(protocol))
        assert mpjpe == pytest.approx(0.0, abs=1e-9) and pa == pytest.approx(0.0, abs=1e-6)
        assert len(per_joint) == int(protocol)


def test_scores_are_root_relative_and_the_16_joint_protocol_drops_one(mini_dir: Path) -> None:
    truth = load_minirgbd(mini_dir, SEQUENCES).poses_camera
    pred = truth + np.array([0.3, -0.2, 1.0])  # a translation only: no error once centred
    assert score_minirgbd(pred, truth, protocol_joints("17"))[0] == pytest.approx(0.0, abs=1e-9)
    pred = truth.copy()
    pred[:, 1:, 0] += 0.010  # every joint but the pelvis 10 mm off
    assert score_minirgbd(pred, truth, protocol_joints("17"))[0] == pytest.approx(10.0 * 16 / 17)
    assert score_minirgbd(pred, truth, protocol_joints("16"))[0] == pytest.approx(10.0)  # pelvis dropped
    assert "head" not in score_minirgbd(pred, truth, protocol_joints("16", "head"))[2]


# --- fit-prior and the benchmark -----------------------------------------------------------


def test_fit_prior_trains_an_h36m17_prior_from_the_folder(mini_prior: Path) -> None:
    prior = load_prior(mini_prior)
    assert prior.skeleton.name == "h36m17"
    assert prior.metadata["data"]["count"] == 10 * FRAMES  # reference split: sequences 01-10
    assert "MINI-RGBD reference split, train side" in prior.metadata["data"]["source"]
    assert "MINI-RGBD" in prior.metadata["license"]
    assert float(prior.template[H36M.index("pelvis")].abs().max()) == 0.0  # a pelvis-centred pose


@pytest.mark.parametrize(
    ("extra", "code", "needle"),
    [
        (["--syrip-dir", "{tmp}"], 2, "exactly one"),
        (["--skeleton", "syrip12"], 2, "h36m17 joint set"),
        (["--minirgbd-split", "ours"], 2, "--minirgbd-split must be one of paper, reference, got 'ours'"),
        (["--mapping", "toes"], 2, "--mapping must be one of reference, anatomical, got 'toes'"),
    ],
)
def test_fit_prior_errors_with_minirgbd(
    mini_dir: Path, tmp_path: Path, extra: list[str], code: int, needle: str
) -> None:
    out = str(tmp_path / "p.safetensors")
    args = ["fit-prior", "--minirgbd-dir", str(mini_dir), "--epochs", "1", "-q", "--out", out]
    result = runner.invoke(app, args + [a.replace("{tmp}", str(tmp_path)) for a in extra])
    assert result.exit_code == code, result.output
    assert needle in result.output and "Traceback" not in result.output


def test_fit_prior_from_a_missing_folder(tmp_path: Path) -> None:
    args = ["fit-prior", "--minirgbd-dir", str(tmp_path / "nope"), "-q", "--out", str(tmp_path / "p.safetensors")]
    result = runner.invoke(app, args)
    assert result.exit_code == 3 and "MINI-RGBD folder not found" in result.output


def test_benchmark_end_to_end(mini_dir: Path, mini_prior: Path) -> None:
    """The CLI lifts the paper split's test frames with the depth camera's K and scores them.

    Tolerances: a tiny prior trained on 30 poses cannot recover depth, so the depth (z) error
    is not bounded tightly. What lifting must get right regardless of the prior is what the 2D
    and K fix: the lifted joints reproject onto their 2D (mean < 1 px; about 0.2 px measured)
    and the image-plane (x, y) error of the root-relative pose stays small (mean < 20 mm;
    about 8 mm measured: only the depth of the root is guessed). MPJPE must beat the trivial
    'every joint at the pelvis' prediction, and the reported scores must equal a direct
    computation on the lifted poses.
    """
    args = ["benchmark-minirgbd", "--minirgbd-dir", str(mini_dir), "--prior", str(mini_prior), "--json", "-q"]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    doc = json.loads(result.stdout)
    assert doc["count"] == 3 * FRAMES and doc["split"] == "paper" and doc["side"] == "test"
    assert set(doc["per_sequence_mm"]) == {"10", "11", "12"} and len(doc["per_joint_mm"]) == 17
    assert doc["config"]["scale_min"] == 0.0 and doc["config"]["scale_max"] == 4.0  # the reference's MINI clamp
    assert doc["intrinsics"] == DEPTH_INTRINSICS.matrix().tolist()
    assert doc["mean_reprojection_error_px"] < 1.0

    run = run_minirgbd_benchmark(mini_dir, load_prior(mini_prior), get_preset("faithful"))
    pred = center_on_root(run.result.poses_camera, H36M)
    truth = center_on_root(run.frames.poses_camera, H36M)
    direct = 1000 * np.linalg.norm(pred - truth, axis=-1).mean()
    assert np.isfinite(direct) and doc["mpjpe_mm"] == pytest.approx(direct) == pytest.approx(run.score.mpjpe_mm)
    assert doc["pa_mpjpe_mm"] == pytest.approx(run.score.pa_mpjpe_mm) and doc["pa_mpjpe_mm"] < doc["mpjpe_mm"]
    assert 1000 * np.linalg.norm((pred - truth)[..., :2], axis=-1).mean() < 20.0
    assert doc["mpjpe_mm"] < 0.5 * 1000 * np.linalg.norm(truth, axis=-1).mean()


def test_benchmark_table_with_16_joints_reference_split_and_stride(mini_dir: Path, mini_prior: Path) -> None:
    args = ["benchmark-minirgbd", "--minirgbd-dir", str(mini_dir), "--prior", str(mini_prior), "-q",
            "--split", "reference", "--protocol", "16", "--mapping", "anatomical", "--stride", "2",
            "--preset", "fast"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())  # the table title wraps at the terminal's width
    assert "4 frames" in text and "16 joints (without pelvis)" in text
    assert "sequence 11" in text and "PA-MPJPE" in text


@pytest.fixture()
def syrip_prior(tmp_path: Path) -> Path:
    """An untrained syrip12 prior: the wrong joint set for MINI-RGBD."""
    cfg = PriorConfig(12, hidden=16, embed=8, groups=4, num_blocks=1, dropout=0.0)
    path = tmp_path / "syrip.safetensors"
    save_prior(path, ScoreNet(cfg).state_dict(), cfg, SubVPSDE(), get_skeleton("syrip12"), torch.zeros(12, 3),
               training={}, data={}, license_text="test only", dtype=torch.float32)  # fmt: skip
    return path


def test_benchmark_refuses_a_prior_of_another_joint_set(mini_dir: Path, syrip_prior: Path) -> None:
    with pytest.raises(WeightsError, match="needs an h36m17 prior, not syrip12"):
        run_minirgbd_benchmark(mini_dir, load_prior(syrip_prior), get_preset("fast"))
    result = runner.invoke(app, ["benchmark-minirgbd", "--minirgbd-dir", str(mini_dir), "--prior", str(syrip_prior)])
    assert result.exit_code == 3 and "zedo fit-prior --minirgbd-dir" in result.output


@pytest.mark.parametrize(
    ("extra", "code", "needle"),
    [
        (["--protocol", "15"], 2, "unknown protocol"),
        (["--protocol", "16", "--drop-joint", "nose"], 2, "not an h36m17 joint"),
        (["--stride", "0"], 2, "--stride must be >= 1"),
        (["--split", "ours"], 2, "unknown MINI-RGBD split"),
        (["--side", "val"], 2, "unknown split side"),
        (["--preset", "slow"], 2, "unknown preset"),
        (["--minirgbd-dir", "{tmp}/nope"], 3, "MINI-RGBD folder not found"),
    ],
)
def test_benchmark_errors(
    mini_dir: Path, mini_prior: Path, tmp_path: Path, extra: list[str], code: int, needle: str
) -> None:
    args = ["benchmark-minirgbd", "--minirgbd-dir", str(mini_dir), "--prior", str(mini_prior), "-q"]
    result = runner.invoke(app, args + [a.replace("{tmp}", str(tmp_path)) for a in extra])
    assert result.exit_code == code, result.output
    assert needle in result.output and result.output.strip().startswith("zedo: error:")


def test_help_teaches_with_examples() -> None:
    result = runner.invoke(app, ["benchmark-minirgbd", "--help"])
    assert result.exit_code == 0 and "Examples" in result.output and "--protocol" in result.output
    assert "benchmark-minirgbd" in runner.invoke(app, ["--help"]).output
