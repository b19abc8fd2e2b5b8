"""DeepLabCut's CSV and .h5 tables (`--format deeplabcut`): single- and multi-animal, hand-labelled
without likelihood, body parts by name, Excel's byte-order mark and CRLF, one-line errors."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from annotation_fixtures import pose_pixels
from typer.testing import CliRunner
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.cli import app
from zedo_cli.cli.lift_plan import expand_inputs
from zedo_cli.data.labels import joint_name_of_label
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import read_keypoints, read_parsed
from zedo_cli.formats.readers.result import read_result
from zedo_cli.formats.writers.outputs import write_result

# DeepLabCut body part -> zedo name: the spellings DeepLabCut projects use, an unknown one last.
PARTS = {
    "nose": "nose", "leftEye": "left_eye", "right_eye": "right_eye", "LEar": "left_ear", "ear_r": "right_ear",
    "LShoulder": "left_shoulder", "RShoulder": "right_shoulder", "l_elbow": "left_elbow",
    "r_elbow": "right_elbow", "LWrist": "left_wrist", "RWrist": "right_wrist", "hip_left": "left_hip",
    "hip_right": "right_hip", "LeftKnee": "left_knee", "kneeR": "right_knee", "ankle_l": "left_ankle",
    "RAnkle": "right_ankle", "Neck": "neck", "pacifier": "pacifier",
}  # fmt: skip
runner = CliRunner()
SCORER = "DLC_resnet50_infantsJan1shuffle1_100000"
FRAMES = (0, 1, 2, 5)  # a gap: frames 3 and 4 were not analysed


def pixels(frame: int) -> dict[str, tuple[float, float]]:
    """zedo name -> (x, y) of `frame` (exact quarters); the pacifier near the mouth."""
    found = pose_pixels(float(frame))
    found["pacifier"] = (found["nose"][0] + 2.5, found["nose"][1] + 4.0)
    return found


def likelihood(frame: int, k: int) -> float:
    return round(0.5 + 0.02 * k + 0.01 * frame, 4)


def header(parts: list[str], coords: tuple[str, ...], individuals: list[str] | None = None, k: int = 1) -> list[str]:
    """DeepLabCut's header rows: the level's name, k - 1 empty index cells, a label per column."""
    pad = [""] * (k - 1)
    rows = [["scorer", *pad, *[SCORER] * (len(individuals or [None]) * len(parts) * len(coords))]]
    if individuals is not None:
        rows.append(["individuals", *pad, *[i for i in individuals for _ in parts for _ in coords]])
    rows.append(["bodyparts", *pad, *[p for _ in (individuals or [None]) for p in parts for _ in coords]])
    rows.append(["coords", *pad, *[c for _ in (individuals or [None]) for _ in parts for c in coords]])
    return [",".join(row) for row in rows]


def video_csv(frames: tuple[int, ...] = FRAMES, parts: list[str] | None = None) -> str:
    """A single-animal analysis CSV: x, y, likelihood per body part, one row per frame."""
    parts = list(PARTS) if parts is None else parts
    lines = header(parts, ("x", "y", "likelihood"))
    for f in frames:
        cells = []
        for k, part in enumerate(parts):
            x, y = pixels(f).get(PARTS.get(part, "nose"), (1.0, 2.0))
            cells += [f"{x}", f"{y}", f"{likelihood(f, k)}"]
        lines.append(",".join([str(f), *cells]))
    return "\n".join(lines) + "\n"


def write(path: Path, text: str, *, bom: bool = False, crlf: bool = False) -> Path:
    text = text.replace("\n", "\r\n") if crlf else text
    path.write_bytes(text.encode("utf-8-sig" if bom else "utf-8"))
    return path


def test_a_single_animal_analysis_csv_reads_each_joint_by_name(tmp_path: Path) -> None:
    text = video_csv()
    lines = text.splitlines()
    cells = lines[3].split(",")  # frame 0: the nose empty (not found), the left knee of likelihood 0
    cells[1:4] = ["", "", ""]
    knee = 1 + 3 * list(PARTS).index("LeftKnee")
    cells[knee + 2] = "0.0"
    lines[3] = ",".join(cells)
    kp = read_keypoints(write(tmp_path / "kp.csv", "\n".join(lines) + "\n"))
    assert kp.format == "deeplabcut" and kp.skeleton.name == "coco17" and len(kp) == 4
    assert kp.frame_indices == list(FRAMES) and kp.image_ids == list(FRAMES)
    assert np.isnan(kp.image_sizes).all()
    joints = kp.skeleton.joints
    for i, f in enumerate(FRAMES):
        for k, (part, name) in enumerate(PARTS.items()):
            if name not in joints or (f == 0 and part in ("nose", "LeftKnee")):
                continue
            assert tuple(kp.xy[i, joints.index(name)]) == pixels(f)[name], (f, part)
            assert kp.confidence[i, joints.index(name)] == pytest.approx(likelihood(f, k)), (f, part)
    for name in ("nose", "left_knee"):  # missing: confidence 0, never (0, 0)
        assert kp.confidence[0, joints.index(name)] == 0 and np.isnan(kp.xy[0, joints.index(name)]).all()
    assert kp.other is not None and kp.other.names == ("neck", "pacifier")
    assert tuple(kp.other.xy[3, 1]) == pixels(5)["pacifier"]
    assert kp.other.confidence[3, 1] == pytest.approx(likelihood(5, len(PARTS) - 1))
    (note,) = kp.notes
    assert "'pacifier'" in note and "Neck" not in note and note.startswith(f"{tmp_path / 'kp.csv'}: ")
    assert kp.source_skeleton == {"name": "coco17", "reason": "DeepLabCut body parts, by name"}


@pytest.mark.parametrize("split", [False, True])
def test_hand_labelled_data_without_likelihood_is_sure_where_placed(tmp_path: Path, split: bool) -> None:
    """CollectedData: x and y only, the image's path as the index (one column, or three in newer
    DeepLabCut); a point not placed is empty."""
    parts = [p for p in PARTS if p != "pacifier"]
    lines = header(parts, ("x", "y"), k=3 if split else 1)
    for n in (1, 2, 10):
        cells = [f"{v}" for part in parts for v in pixels(n)[PARTS[part]]]
        if n == 2:
            cells[0:2] = ["", ""]  # the nose not placed in img002
        index = ["labeled-data", "infant01", f"img{n:03d}.png"]
        lines.append(",".join([*(index if split else ["/".join(index)]), *cells]))
    kp = read_keypoints(write(tmp_path / "CollectedData_ana.csv", "\n".join(lines) + "\n"))
    assert kp.image_ids == [f"labeled-data/infant01/img{n:03d}.png" for n in (1, 2, 10)]
    assert kp.file_names == ["img001.png", "img002.png", "img010.png"] and kp.frame_indices == [1, 2, 10]
    nose, knee = kp.skeleton.joints.index("nose"), kp.skeleton.joints.index("right_knee")
    assert kp.confidence[:, nose].tolist() == [1.0, 0.0, 1.0] and np.isnan(kp.xy[1, nose]).all()
    assert (kp.confidence[:, knee] == 1).all() and tuple(kp.xy[2, knee]) == pixels(10)["right_knee"]
    assert kp.notes == ()


def test_labelled_images_whose_numbers_do_not_count_up_have_no_frames(tmp_path: Path) -> None:
    lines = header(["nose", "LKnee"], ("x", "y"))
    lines += ["labeled-data/b/img005.png,1,2,3,4", "labeled-data/a/img001.png,5,6,7,8"]
    kp = read_keypoints(write(tmp_path / "c.csv", "\n".join(lines)))
    assert kp.frame_indices is None and kp.file_names == ["img005.png", "img001.png"]


def test_multi_animal_individuals_are_persons_and_single_is_left_out(tmp_path: Path) -> None:
    parts = ["nose", "LKnee", "RKnee"]
    lines = header(parts, ("x", "y", "likelihood"), ["infant", "parent"])
    single = header(["toy"], ("x", "y", "likelihood"), ["single"])
    lines = [a + b[b.index(",") :] for a, b in zip(lines, single, strict=True)]
    rows = {
        0: ["10,20,0.9", "11,21,0.8", "12,22,0.7", "50,60,0.9", "51,61,0.8", "52,62,0.7", "5,5,0.9"],
        1: [",,", ",,", ",,", "53,63,0.9", "54,64,0.8", "55,65,0.7", "5,5,0.9"],  # the infant not found
        2: [",,", ",,", ",,", ",,", ",,", ",,", "6,6,0.9"],  # only the toy: nobody
        3: ["13,23,0.9", "14,24,0.8", "15,25,0.7", ",,", ",,", ",,", ",,"],
    }
    lines += [",".join([str(f), *cells]) for f, cells in rows.items()]
    kp = read_keypoints(write(tmp_path / "ma.csv", "\n".join(lines)))
    assert kp.frame_indices == [0, 0, 1, 1, 3, 3]  # every individual in each frame that holds a point
    nose, knee = kp.skeleton.joints.index("nose"), kp.skeleton.joints.index("left_knee")
    np.testing.assert_array_equal(kp.xy[:, nose], [[10, 20], [50, 60], [np.nan] * 2, [53, 63], [13, 23], [np.nan] * 2])
    assert kp.confidence[:, knee].tolist() == [0.8, 0.8, 0.0, 0.8, 0.8, 0.0]
    assert kp.other is None  # the toy belongs to no infant
    assert any("'toy'" in note and "'single'" in note for note in kp.notes)
    assert any("'infant' 0, 'parent' 1" in note for note in kp.notes)
    assert any("1 of 4 rows hold no point" in note for note in kp.notes)


@pytest.mark.parametrize(
    ("part", "name"),
    [("left_knee", "left_knee"), ("LeftKnee", "left_knee"), ("l_knee", "left_knee"), ("kneeL", "left_knee"),
     ("LWrist", "left_wrist"), ("nose", "nose"), ("left_eye", "left_eye"), ("leftknee", "left_knee"),
     ("rightankle", "right_ankle"), ("Lshoulder", "left_shoulder"), ("elbowRight", "right_elbow"),
     ("mid_shoulder", "thorax"), ("MidShoulder", "thorax"), ("MidHip", "pelvis"), ("crown", "head_top")],
)  # fmt: skip
def test_deeplabcut_body_part_spellings_read_as_zedo_names(part: str, name: str) -> None:
    assert joint_name_of_label(part) == name


def test_unknown_body_parts_are_noted_once_and_kept_by_name(tmp_path: Path) -> None:
    text = video_csv(parts=["nose", "LKnee", "tail", "bottle", "RKnee"])
    kp = read_keypoints(write(tmp_path / "u.csv", text))
    assert kp.other is not None and kp.other.names == ("tail", "bottle")
    (note,) = kp.notes
    assert note.count("'tail'") == 1 and "'bottle'" in note


def test_an_excel_csv_with_a_byte_order_mark_and_crlf_reads_the_same(tmp_path: Path) -> None:
    plain = read_keypoints(write(tmp_path / "plain.csv", video_csv()))
    excel = read_keypoints(write(tmp_path / "excel.csv", video_csv(), bom=True, crlf=True))
    np.testing.assert_array_equal(excel.xy, plain.xy)
    np.testing.assert_array_equal(excel.confidence, plain.confidence)
    assert excel.frame_indices == plain.frame_indices and excel.other is not None and plain.other is not None
    np.testing.assert_array_equal(excel.other.xy, plain.other.xy)


def test_a_result_csv_saved_by_excel_reads_like_zedo_wrote_it(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    path = tmp_path / "r.csv"
    write_result(path, kp, res, mats, sources, PARAMS, INPUT_INFO)
    text = path.read_text()
    excel = tmp_path / "excel.csv"
    excel.write_bytes(text.replace("true", "TRUE").replace("false", "FALSE").replace("\n", "\r\n").encode("utf-8-sig"))
    excel.with_suffix(".meta.json").write_bytes(path.with_suffix(".meta.json").read_bytes())
    ours, theirs = read_result(path), read_result(excel)
    np.testing.assert_array_equal(theirs.poses, ours.poses)
    np.testing.assert_array_equal(theirs.observed, ours.observed)
    np.testing.assert_array_equal(theirs.lifted, ours.lifted)
    assert theirs.frame_index.tolist() == ours.frame_index.tolist() and theirs.fps == ours.fps
    assert not ours.observed.all() and ours.observed.any()  # the comparison can tell TRUE from FALSE


def _bad(lines: list[str]) -> str:
    return "\n".join(lines) + "\n"


_GOOD = header(["nose", "LKnee"], ("x", "y", "likelihood"))


@pytest.mark.parametrize(
    ("text", "said"),
    [
        (_bad([_GOOD[0], _GOOD[2], "0,1,2,0.9,3,4,0.9"]), "row 2: expected DeepLabCut's bodyparts row after the "
         "scorer row (bodyparts, nose, nose, nose, ...), got 'coords'"),
        (_bad([_GOOD[0], _GOOD[1], "0,1,2,0.9,3,4,0.9"]), "row 3: expected DeepLabCut's coords row after the "
         "bodyparts row (coords, x, y, likelihood, ...), got '0'"),
        (_bad([*_GOOD[:2], "coords,x,y,z,x,y,likelihood", "0,1,2,0.9,3,4,0.9"]),
         "row 3: nose: coordinate 'z': expected x, y or likelihood"),
        (_bad([*_GOOD[:2], "coords,x,x,likelihood,x,y,likelihood", "0,1,2,0.9,3,4,0.9"]),
         "row 3: nose: a second x column"),
        (_bad([*_GOOD, "0,1,2,0.9,3,4,0.9", "1,1,2,0.9,3,4"]), "row 5: 6 cells, the coords row has 7: ragged row"),
        (_bad([_GOOD[0], "bodyparts,nose,nose", _GOOD[2], "0,1,2,0.9,3,4,0.9"]),
         "row 2: 3 cells, the coords row has 7: ragged bodyparts row"),
        (_bad([*_GOOD, "0,1,2,0.9,3,4,0.9", "1,1,2,0.9,3,abc,0.9"]), "row 5: LKnee y: not a number: 'abc'"),
        (_bad([*_GOOD, "0,1,2,0.9,3,4,0.9", "1,1,2,0.9,3,inf,0.9"]), "row 5: LKnee y: not a finite number"),
        (_bad([*_GOOD, "0,1,2,0.9,3,4,0.9", "0,1,2,0.9,3,4,0.9"]),
         "row 5: frame 0 repeats (the row before is frame 0): the frame index must count up"),
        (_bad([*_GOOD, "4,1,2,0.9,3,4,0.9", "2,1,2,0.9,3,4,0.9"]),
         "row 5: frame 2 does not count up (the row before is frame 4)"),
        (_bad([*_GOOD, "0,1,2,0.9,3,4,0.9", "one,1,2,0.9,3,4,0.9"]), "row 5: index 'one': expected a frame number"),
        (_bad(header(["pacifier", "tail"], ("x", "y")) + ["0,1,2,3,4"]),
         "row 2: no body part names a body joint ('pacifier', 'tail')"),
        (_bad(header(["LKnee", "left_knee"], ("x", "y")) + ["0,1,2,3,4"]),
         "row 2: body parts 'LKnee' and 'left_knee' both name left_knee"),
        (_bad(_GOOD), "no rows after the header"),
        (_bad([*_GOOD, "0,,,,,,"]), "no row holds a point"),
        (_bad(["scorer", "bodyparts", "coords"]), "row 3: the coords row names no coordinate"),
    ],
)  # fmt: skip
def test_malformed_tables_are_one_line_naming_the_file_and_row(tmp_path: Path, text: str, said: str) -> None:
    path = write(tmp_path / "kp.csv", text)
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path)
    message = str(info.value)
    assert message.startswith(f"{path}: {said}") and "\n" not in message, message


def test_formats_and_detection(tmp_path: Path) -> None:
    path = write(tmp_path / "kp.txt", video_csv())  # the content decides, not the name
    assert read_keypoints(path).format == "deeplabcut"
    assert read_keypoints(path, format="deeplabcut").format == "deeplabcut"
    with pytest.raises(InputFormatError, match="not a JSON document"):
        read_parsed({"people": []}, "kp.json", format="deeplabcut")
    with pytest.raises(InputFormatError, match=r"kp.txt: --skeleton body25 does not apply"):
        read_keypoints(path, skeleton="body25")
    other = write(tmp_path / "table.csv", "frame,x,y\n0,1,2\n")
    with pytest.raises(InputFormatError, match="this is a CSV table .*DeepLabCut"):
        read_keypoints(other)
    with pytest.raises(InputFormatError, match=r"table.csv: row 1: expected DeepLabCut's scorer row"):
        read_keypoints(other, format="deeplabcut")


def test_a_folder_stands_for_its_deeplabcut_tables(tmp_path: Path) -> None:
    write(tmp_path / "a.csv", video_csv())
    write(tmp_path / "notes.csv", "frame,comment\n0,crying\n")
    (tmp_path / "b.zedo.csv").write_text("frame_index,x\n")
    assert expand_inputs([str(tmp_path)]) == [str(tmp_path / "a.csv")]


def _h5(path: Path, multi: bool) -> Path:
    pandas = pytest.importorskip("pandas")
    pytest.importorskip("tables")
    levels = ["scorer", "individuals", "bodyparts", "coords"] if multi else ["scorer", "bodyparts", "coords"]
    product = [[SCORER], ["infant"], ["nose", "LKnee"], ["x", "y", "likelihood"]]
    columns = pandas.MultiIndex.from_product(product if multi else [product[0], *product[2:]], names=levels)
    values = np.array([[1.0, 2.0, 0.9, 3.0, 4.0, 0.8], [5.0, 6.0, 0.7, np.nan, np.nan, np.nan]])
    pandas.DataFrame(values, columns=columns, index=[3, 4]).to_hdf(path, key="df_with_missing", mode="w")
    return path


@pytest.mark.parametrize("multi", [False, True])
def test_an_h5_file_reads_like_its_csv(tmp_path: Path, multi: bool) -> None:
    kp = read_keypoints(_h5(tmp_path / "kp.h5", multi))
    assert kp.format == "deeplabcut" and kp.frame_indices == [3, 4]
    nose, knee = kp.skeleton.joints.index("nose"), kp.skeleton.joints.index("left_knee")
    np.testing.assert_array_equal(kp.xy[:, nose], [[1, 2], [5, 6]])
    assert kp.confidence[:, knee].tolist() == [0.8, 0.0] and np.isnan(kp.xy[1, knee]).all()


def test_an_h5_file_without_pytables_is_one_line_saying_what_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "kp.h5"
    path.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(64))
    monkeypatch.setitem(sys.modules, "tables", None)  # import tables fails
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path)
    assert str(info.value).startswith(f"{path}: reading DeepLabCut's .h5 files needs pandas and PyTables: ")
    assert "pip install 'zedo[deeplabcut]'" in str(info.value)


def test_zedo_lift_of_a_deeplabcut_csv(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write(tmp_path / "kp.csv", video_csv(), bom=True, crlf=True)
    args = ["lift", str(src), "--prior", str(tiny_prior_path), "--steps", "10", "--image-size", "640", "480",
            "--fps", "30", "-o", "-"]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.stderr
    assert result.stderr.count("zedo: warning:") == 1 and "'pacifier'" in result.stderr
    doc = json.loads(result.stdout)
    assert doc["input"]["format"] == "deeplabcut" and doc["skeleton"]["name"] == "syrip12"
    assert [frame["frame_index"] for frame in doc["frames"]] == list(FRAMES)
    assert doc["params"]["fps"] == 30
    joints = doc["skeleton"]["joints"]
    assert "left_knee" in joints and "right_wrist" in joints
    for frame, f in zip(doc["frames"], FRAMES, strict=True):
        person = frame["persons"][0]
        for name in ("left_knee", "right_wrist", "left_ankle"):
            assert person["keypoints_2d"][joints.index(name)] == list(pixels(f)[name]), (f, name)
        assert all(math.isfinite(v) for point in person["keypoints_3d"] for v in point)
    assert set(doc["other_keypoints"]["joints"]) >= {"nose", "neck", "pacifier"}
