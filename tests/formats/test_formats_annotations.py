"""Hand annotations of annotation tools (LabelMe point files and folders, Label Studio exports):
labels read as joints by name, other points kept, unknown labels listed, bad files refused."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from annotation_fixtures import (
    NYCU_LABELS,
    json_min_item,
    labelme_doc,
    labelme_folder,
    labelme_shape,
    ls_result,
    ls_task,
    nycu_label_studio_results,
    nycu_labelme,
    pose_pixels,
    write_json,
)

from zedo_cli.data.labels import alias_table, joint_name_of_label
from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import detect_format, input_sha256, read_keypoints, read_parsed

COCO17 = SKELETONS["coco17"]
DOCS = Path(__file__).resolve().parents[2] / "docs" / "inputs.md"


@pytest.mark.parametrize(
    ("label", "name"),
    [
        ("Knee_L", "left_knee"), ("left_knee", "left_knee"), ("LKnee", "left_knee"), ("l_knee", "left_knee"),
        ("knee-left", "left_knee"), ("Left Knee", "left_knee"), ("leftKnee", "left_knee"), ("lknee", "left_knee"),
        ("KNEE_L", "left_knee"), ("Shoulder_R", "right_shoulder"), ("RShoulder", "right_shoulder"),
        ("r.wrist", "right_wrist"), ("Rt Elbow", "right_elbow"), ("Big_Toe_R", "right_big_toe"),
        ("LBigToe", "left_big_toe"), ("left_small_toe", "left_small_toe"), ("Heel_L", "left_heel"),
        ("Hand_R", "right_hand"), ("Nose", "nose"), ("Neck", "neck"), ("HeadTop", "head_top"),
        ("head_top", "head_top"), ("MidHip", "pelvis"), ("Eye_L", "left_eye"), ("REar", "right_ear"),
    ],
)  # fmt: skip
def test_labels_are_read_as_zedo_joint_names(label: str, name: str) -> None:
    assert joint_name_of_label(label) == name


@pytest.mark.parametrize("label", ["Knee", "Hip", "Nose_L", "kneel", "joint7", "", "Left", "L_R_Knee", "Knee_X"])
def test_labels_that_name_no_joint_are_not_guessed(label: str) -> None:
    assert joint_name_of_label(label) is None


def test_the_alias_table_is_documented() -> None:
    text = DOCS.read_text()
    for name, spellings in alias_table():
        assert f"`{name}`" in text and spellings in text, name


def _assert_on_names(kp, names: dict[str, str], pixels: dict[str, tuple[float, float]], i: int = 0) -> None:
    """Each labelled joint of instance `i` sits where the label put it, by name."""
    for name in names.values():
        if name in COCO17.joints:
            assert tuple(kp.xy[i, COCO17.index(name)]) == pixels[name], name
            assert kp.confidence[i, COCO17.index(name)] == 1.0
        else:
            e = kp.other.names.index(name)
            assert tuple(kp.other.xy[i, e]) == pixels[name], name
            assert kp.other.confidence[i, e] == 1.0


def test_a_labelme_file_puts_each_joint_on_its_name(tmp_path: Path) -> None:
    path = write_json(tmp_path / "infant_0007.json", nycu_labelme(image="infant_0007.jpg"))
    kp = read_keypoints(path)
    assert kp.format == "labelme" and kp.skeleton.name == "coco17" and len(kp) == 1
    _assert_on_names(kp, NYCU_LABELS, pose_pixels())
    assert kp.other.names == ("neck", "left_big_toe", "right_big_toe", "left_heel", "right_heel")
    assert kp.image_ids == ["infant_0007"] and kp.file_names == ["infant_0007.jpg"] and kp.frame_indices == [7]
    assert kp.image_sizes.tolist() == [[1280.0, 720.0]] and kp.notes == ()
    assert kp.source_skeleton["reason"] == "LabelMe point labels, by name"


def test_the_other_points_survive_the_conversion_to_the_lifted_joints(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "f.json", nycu_labelme())).to_skeleton(SKELETONS["syrip12"])
    pixels = pose_pixels()
    assert set(kp.other.names) == {"neck", "left_big_toe", "right_big_toe", "left_heel", "right_heel", "nose",
                                   "left_eye", "right_eye", "left_ear", "right_ear"}  # fmt: skip
    for name in kp.other.names:
        assert tuple(kp.other.xy[0, kp.other.names.index(name)]) == pixels[name]
    for j, name in enumerate(kp.skeleton.joints):
        assert tuple(kp.xy[0, j]) == pixels[name]


def test_labelme_groups_are_persons_and_missing_joints_stay_missing(tmp_path: Path) -> None:
    shapes = [labelme_shape("Knee_L", 10.0, 20.0, 1), labelme_shape("Knee_L", 110.0, 120.0, 2),
              labelme_shape("Hip_L", 12.0, 5.0, 1)]  # fmt: skip
    kp = read_parsed(labelme_doc(shapes), "two.json")
    assert len(kp) == 2 and kp.image_ids == ["two", "two"]
    knee, hip = COCO17.index("left_knee"), COCO17.index("left_hip")
    assert kp.xy[:, knee].tolist() == [[10.0, 20.0], [110.0, 120.0]]
    assert kp.confidence[:, hip].tolist() == [1.0, 0.0] and np.isnan(kp.xy[1, hip]).all()


def test_unknown_labels_are_listed_once_and_left_out(tmp_path: Path) -> None:
    folder = labelme_folder(tmp_path / "clip", [1, 2, 3])
    for file in folder.glob("*.json"):
        doc = json.loads(file.read_text())
        doc["shapes"] += [labelme_shape("Pacifier", 1.0, 2.0), labelme_shape("Knee", 3.0, 4.0)]
        write_json(file, doc)
    kp = read_keypoints(folder)
    assert len(kp.notes) == 1 and kp.notes[0].count("'Pacifier'") == 1 and "'Knee'" in kp.notes[0]
    assert kp.notes[0].startswith(str(folder)) and "Pacifier" not in kp.other.names


def test_a_labelme_folder_is_one_clip_in_file_name_order(tmp_path: Path) -> None:
    folder = labelme_folder(tmp_path / "clip", [10, 2, 1, 3])
    (folder / "clip.zedo.json").write_text("{}")  # zedo's own output beside the frames is not a frame
    kp = read_keypoints(folder)
    assert kp.format == "labelme" and kp.path == str(folder)
    assert kp.image_ids == ["img_1", "img_2", "img_3", "img_10"] and kp.frame_indices == [1, 2, 3, 10]
    assert kp.xy[:, COCO17.index("left_knee"), 0].tolist() == [pose_pixels(n)["left_knee"][0] for n in (1, 2, 3, 10)]
    assert input_sha256(folder) is not None


def test_a_folder_without_frame_numbers_counts_frames_by_position(tmp_path: Path) -> None:
    folder = tmp_path / "named"
    folder.mkdir()
    for name in ("b", "a", "c"):
        write_json(folder / f"{name}.json", nycu_labelme())
    kp = read_keypoints(folder, format="labelme")
    assert kp.image_ids == ["a", "b", "c"] and kp.frame_indices == [0, 1, 2]


def test_a_folder_frame_without_points_is_a_gap_with_a_note(tmp_path: Path) -> None:
    folder = labelme_folder(tmp_path / "clip", [1, 3])
    write_json(folder / "img_2.json", labelme_doc([]))
    kp = read_keypoints(folder)
    assert kp.frame_indices == [1, 3] and "1 of 3 files hold no point shapes" in kp.notes[0]


@pytest.mark.parametrize(
    ("doc", "fmt"),
    [
        (labelme_doc([labelme_shape("Knee_L", 1.0, 2.0)]), "labelme"),
        ([ls_task(1, nycu_label_studio_results())], "label-studio"),
        (ls_task(1, nycu_label_studio_results()), "label-studio"),
        ([json_min_item(1)], "label-studio"),
    ],
)
def test_annotation_files_are_detected(doc: object, fmt: str) -> None:
    assert detect_format(doc) == fmt


def test_a_label_studio_export_turns_percentages_into_pixels() -> None:
    results = nycu_label_studio_results(0.0, parent="baby1") + nycu_label_studio_results(40.0, parent="baby2")
    results.append({"id": "box", "type": "rectanglelabels", "from_name": "box", "to_name": "image",
                    "original_width": 1280, "original_height": 720, "image_rotation": 0,
                    "value": {"x": 1.0, "y": 2.0, "width": 50.0, "height": 60.0, "rotation": 0,
                              "rectanglelabels": ["infant"]}})  # fmt: skip
    tasks = [ls_task(5, results, image="/data/upload/1/5f2a-frame_0005.jpg?d=x", cancelled_first=True)]
    kp = read_parsed(tasks, "export.json")
    assert kp.format == "label-studio" and len(kp) == 2 and kp.image_ids == [5, 5]
    assert kp.file_names == ["5f2a-frame_0005.jpg"] * 2 and kp.image_sizes.tolist() == [[1280.0, 720.0]] * 2
    for i, offset in enumerate((0.0, 40.0)):
        pixels = pose_pixels(offset)
        for name in ("left_knee", "right_shoulder", "nose"):
            np.testing.assert_allclose(kp.xy[i, COCO17.index(name)], pixels[name], rtol=0, atol=1e-9)
        np.testing.assert_allclose(kp.other.xy[i, kp.other.names.index("neck")], pixels["neck"], atol=1e-9)


def test_a_label_studio_json_min_export_reads_the_same() -> None:
    kp = read_parsed([json_min_item(1), json_min_item(2, 8.0)], "min.json")
    assert kp.image_ids == [1, 2] and kp.file_names == ["f1.jpg", "f2.jpg"]
    np.testing.assert_allclose(kp.xy[1, COCO17.index("left_ankle")], pose_pixels(8.0)["left_ankle"], atol=1e-9)


@pytest.mark.parametrize(
    ("change", "said"),
    [
        (lambda r: r["value"].update(x=100.5),
         "value.x: expected a percentage of the image's width in [0, 100], got 100.5"),
        (lambda r: r["value"].update(y=-0.25), "value.y: expected a percentage of the image's height in [0, 100]"),
        (lambda r: r.update(image_rotation=90), "image_rotation: the image was rotated by 90 degrees"),
        (lambda r: r.pop("original_width"), "original_width: missing"),
        (lambda r: r["value"].update(keypointlabels=["Knee_L", "Knee_R"]), "keypointlabels: expected one label"),
    ],
)  # fmt: skip
def test_bad_label_studio_values_are_refused_naming_the_field(change, said: str) -> None:
    results = [ls_result("Knee_L", 100.0, 200.0), ls_result("Hip_L", 110.0, 150.0)]
    change(results[0])
    with pytest.raises(InputFormatError, match="^ls.json: \\[0\\]\\.annotations\\[0\\]\\.result\\[0\\]") as err:
        read_parsed([ls_task(1, results)], "ls.json")
    assert said in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize(
    ("shapes", "said"),
    [
        ([{**labelme_shape("x", 1.0, 2.0), "shape_type": "polygon", "points": [[1, 2], [3, 4], [5, 6]]}],
         'f.json: shapes: no point shapes (shape_type "point"): its shapes are polygon; nothing to lift'),
        ([], "f.json: shapes: no point shapes"),
        ([labelme_shape("Pacifier", 1.0, 2.0), labelme_shape("Toy_L", 3.0, 4.0), labelme_shape("Hand_L", 3.0, 4.0)],
         "f.json: no label names a body joint ('Hand_L', 'Pacifier', 'Toy_L')"),
        ([labelme_shape("Knee_L", 1.0, 2.0), labelme_shape("LKnee", 3.0, 4.0)],
         "f.json: shapes[1].label: label 'LKnee' is left_knee, which shapes[0].label already marks"),
        ([{**labelme_shape("Knee_L", 1.0, 2.0), "points": [[1.0, 2.0], [3.0, 4.0]]}],
         "f.json: shapes[0].points: a point shape holds one [x, y], got 2 points"),
    ],
)  # fmt: skip
def test_bad_labelme_files_are_refused_in_one_line(shapes: list, said: str) -> None:
    with pytest.raises(InputFormatError) as err:
        read_parsed(labelme_doc(shapes), "f.json")
    assert str(err.value).startswith(said) and "\n" not in str(err.value)


def test_skeleton_option_does_not_apply_to_labels() -> None:
    with pytest.raises(InputFormatError, match="--skeleton syrip12 does not apply to LabelMe files"):
        read_parsed(nycu_labelme(), "f.json", skeleton="syrip12")
