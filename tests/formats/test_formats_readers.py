"""Tests of the 2D keypoint readers (zedo_cli.formats.readers.inputs) on small fixtures written to tmp_path."""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import key_paths
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import ConfigError, InputFormatError
from zedo_cli.formats import INPUT_FORMATS, detect_format, read_keypoints
from zedo_cli.formats.readers.inputs import read_coco_results

SYRIP = Path(__file__).resolve().parents[3] / "shared/data/syrip"
COCO_NAMES = list(SKELETONS["coco17"].joints)
H36M_NAMES = list(SKELETONS["h36m17"].joints)


# --- fixtures ------------------------------------------------------------------------------


def _flat(xy: list[tuple[float, float]], third: list[float]) -> list[float]:
    return [value for (x, y), c in zip(xy, third, strict=True) for value in (x, y, c)]


def _points(offset: float) -> list[tuple[float, float]]:
    """17 distinct, recognisable joint positions."""
    return [(offset + j, offset + 100 + j) for j in range(17)]


def coco_annotations() -> dict[str, Any]:
    """Two images; annotations out of image order; a v=0 placeholder and a v=1 joint."""
    vis_a = [2.0] * 17
    vis_a[3] = 0  # missing, placeholder coordinates
    vis_a[5] = 1  # occluded
    kp_a = _flat(_points(10.0), vis_a)
    kp_a[9:11] = [-45, -45]
    return {
        "info": {"description": "test"},
        "images": [
            {"id": 7, "width": 640, "height": 480, "file_name": "b.jpg", "original_file_name": "orig_b.jpg"},
            {"id": 3, "width": 1280, "height": 720, "file_name": "a.jpg", "posture": "Supine"},
        ],
        "annotations": [
            {"id": 1, "image_id": 3, "category_id": 1, "keypoints": _flat(_points(200.0), [2] * 17)},
            {"id": 2, "image_id": 7, "category_id": 1, "keypoints": kp_a, "score": 0.9},
        ],
        "categories": [{"id": 1, "name": "person", "keypoints": COCO_NAMES, "skeleton": []}],
    }


def coco_results() -> list[dict[str, Any]]:
    """Three detections, two on image 5, one with an AlphaPose confidence above 1 and a c = 0 joint."""
    conf = [0.8] * 17
    conf[0] = 1.7
    conf[2] = 0.0
    return [
        {"image_id": 5, "category_id": 1, "keypoints": _flat(_points(1.0), conf), "score": 0.95},
        {"image_id": 2, "keypoints": _flat(_points(2.0), [0.5] * 17), "score": 0.4},
        {"image_id": 5, "keypoints": _flat(_points(3.0), [0.6] * 17)},
    ]


def zedo_2d() -> dict[str, Any]:
    joints: list[Any] = [[float(j), float(j + 1)] for j in range(17)]
    joints[1] = None
    joints[2] = [5.0, 6.0, 0.0]
    joints[3] = [7.0, 8.0, 0.25]
    return {
        "schema": "zedo.keypoints2d/1",
        "skeleton": "h36m17",
        "image_size": [320, 240],
        "instances": [
            {"image_id": "f0", "file_name": "f0.png", "score": 0.5, "keypoints": joints},
            {"image_id": 1, "image_size": [100, 50], "keypoints": [[1.0, 2.0, 1.0]] * 17},
        ],
    }


def write(tmp_path: Path, obj: Any, name: str = "kp.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(obj))
    return path


def assert_error(path: Path, *parts: str, **kwargs: Any) -> str:
    """read_keypoints(path) raises InputFormatError starting with the path and naming each part."""
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path, **kwargs)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    for part in parts:
        assert part in message, message
    return message


# --- main paths ----------------------------------------------------------------------------


def test_coco_annotations_values_order_missing_and_sizes(tmp_path: Path) -> None:
    kp = read_keypoints(write(tmp_path, coco_annotations()))
    assert isinstance(kp, Keypoints2D) and len(kp) == 2
    assert kp.format == "coco-annotations" and kp.skeleton.name == "coco17"
    assert kp.xy.dtype == np.float64 and kp.confidence.dtype == np.float64 and kp.image_sizes.dtype == np.float64
    assert kp.xy.shape == (2, 17, 2) and kp.confidence.shape == (2, 17)
    # ordered by image position in images[] (7 first), not by annotation order
    assert kp.image_ids == [7, 3]
    assert kp.file_names == ["orig_b.jpg", "a.jpg"]  # original_file_name (SyRIP's true name) wins
    np.testing.assert_array_equal(kp.image_sizes, [[640, 480], [1280, 720]])
    assert kp.scores == [0.9, None]
    # v = 0: NaN and confidence 0 (the placeholder -45 is never a position)
    assert np.isnan(kp.xy[0, 3]).all() and kp.confidence[0, 3] == 0
    assert kp.confidence[0, 5] == 0.5  # v = 1
    assert kp.confidence[0, 0] == 1.0 and kp.confidence[1].tolist() == [1.0] * 17
    np.testing.assert_array_equal(kp.xy[0, 0], [10.0, 110.0])
    np.testing.assert_array_equal(kp.xy[1, 16], [216.0, 316.0])
    assert kp.path == str(tmp_path / "kp.json")


def test_coco_annotations_float_visibility_is_a_confidence(tmp_path: Path) -> None:
    doc = coco_annotations()
    doc["annotations"][0]["keypoints"][2] = 0.7
    kp = read_keypoints(write(tmp_path, doc))
    assert kp.confidence[1, 0] == pytest.approx(0.7)


@pytest.mark.parametrize(
    ("names", "skeleton"),
    [
        (H36M_NAMES, "h36m17"),
        (["root" if n == "pelvis" else n.replace("ankle", "foot") for n in H36M_NAMES], "h36m17"),  # MMPose
    ],
)
def test_coco_annotations_skeleton_from_category_names(tmp_path: Path, names: list[str], skeleton: str) -> None:
    doc = coco_annotations()
    doc["categories"][0]["keypoints"] = names
    kp = read_keypoints(write(tmp_path, doc))
    assert kp.skeleton.name == skeleton
    assert kp.source_skeleton == {"name": skeleton, "reason": "categories[0].keypoints names"}


def test_coco_results_values_order_and_confidence(tmp_path: Path) -> None:
    kp = read_keypoints(write(tmp_path, coco_results()))
    assert kp.format == "coco-results" and kp.skeleton.name == "coco17" and len(kp) == 3
    assert kp.image_ids == [5, 2, 5]  # file order, several instances per image
    assert kp.scores == [0.95, 0.4, None]
    assert kp.file_names == [None, None, None]
    assert np.isnan(kp.image_sizes).all()
    assert kp.confidence[0, 0] == 1.0  # AlphaPose-style 1.7 clipped
    assert kp.confidence[0, 2] == 0.0 and np.isnan(kp.xy[0, 2]).all()  # c == 0 is missing
    assert kp.confidence[1, 4] == 0.5
    np.testing.assert_array_equal(kp.xy[2, 1], [4.0, 104.0])


def test_read_coco_results_with_image_sizes_and_string_ids() -> None:
    data = coco_results()
    data[1]["image_id"] = "frame_2.jpg"
    kp = read_coco_results(data, "r.json", image_sizes={5: (64, 48)})
    assert kp.image_ids == [5, "frame_2.jpg", 5]
    np.testing.assert_array_equal(kp.image_sizes[[0, 2]], [[64, 48], [64, 48]])
    assert np.isnan(kp.image_sizes[1]).all()


def test_zedo_2d_values_sizes_and_missing(tmp_path: Path) -> None:
    kp = read_keypoints(write(tmp_path, zedo_2d()))
    assert kp.format == "zedo-2d" and kp.skeleton.name == "h36m17"
    assert kp.image_ids == ["f0", 1] and kp.file_names == ["f0.png", None] and kp.scores == [0.5, None]
    np.testing.assert_array_equal(kp.image_sizes, [[320, 240], [100, 50]])  # default, then override
    assert kp.confidence[0, 0] == 1.0  # [x, y]
    assert kp.confidence[0, 1] == 0.0 and np.isnan(kp.xy[0, 1]).all()  # null
    assert kp.confidence[0, 2] == 0.0 and np.isnan(kp.xy[0, 2]).all()  # c == 0
    assert kp.confidence[0, 3] == 0.25
    np.testing.assert_array_equal(kp.xy[0, 4], [4.0, 5.0])


def test_detect_format() -> None:
    assert detect_format(coco_annotations()) == "coco-annotations"
    assert detect_format(coco_results()) == "coco-results"
    assert detect_format([]) == "coco-results"
    assert detect_format(zedo_2d()) == "zedo-2d"


@pytest.mark.parametrize(
    ("data", "found"),
    [
        ({"a": 1, "b": 2, "c": 3}, "top-level JSON object has keys a, b, c"),
        ({"images": [], "annotations": []}, "keys images, annotations"),
        ([1, 2], "first element is a number"),
        ([{"keypoints": [[1, 2]], "scores": [1]}], "nested keypoints"),
        ("text", "top-level JSON value is a string"),
    ],
)
def test_detect_format_errors_name_file_and_what_was_found(data: Any, found: str) -> None:
    with pytest.raises(InputFormatError) as info:
        detect_format(data, "x.json")
    message = str(info.value)
    assert message.startswith("x.json: ") and found in message and "expected COCO annotations" in message


def test_image_size_fills_unknown_sizes_only(tmp_path: Path) -> None:
    doc = zedo_2d()
    del doc["image_size"]
    kp = read_keypoints(write(tmp_path, doc), image_size=(640, 480))
    np.testing.assert_array_equal(kp.image_sizes, [[640, 480], [100, 50]])
    kp = read_keypoints(write(tmp_path, coco_results()), image_size=(1920, 1080))
    np.testing.assert_array_equal(kp.image_sizes, [[1920, 1080]] * 3)


def test_companion_images_file_gives_sizes_and_file_names(tmp_path: Path) -> None:
    results = coco_results()
    companion = {"images": [{"id": 2, "width": 10, "height": 20, "file_name": "two.jpg"},
                            {"id": 5, "width": 30, "height": 40, "file_name": "five.jpg"}]}  # fmt: skip
    images = write(tmp_path, companion, "gt.json")
    kp = read_keypoints(write(tmp_path, results), images=images, image_size=(1, 1))
    np.testing.assert_array_equal(kp.image_sizes, [[30, 40], [10, 20], [30, 40]])
    assert kp.file_names == ["five.jpg", "two.jpg", "five.jpg"]
    # AlphaPose string ids are matched on file_name
    results[1]["image_id"] = "two.jpg"
    kp = read_keypoints(write(tmp_path, results), images=images)
    assert kp.image_ids[1] == "two.jpg" and kp.image_sizes[1].tolist() == [10, 20]


def test_companion_images_file_missing_id_is_an_error(tmp_path: Path) -> None:
    images = write(tmp_path, {"images": [{"id": 5, "width": 30, "height": 40}]}, "gt.json")
    assert_error(write(tmp_path, coco_results()), "image_id", "image id 2", "gt.json", images=images)


def test_explicit_format_and_bad_options(tmp_path: Path) -> None:
    path = write(tmp_path, coco_annotations())
    assert read_keypoints(path, format="auto").format == "coco-annotations"
    assert_error(path, "expected a list, got an object", format="coco-results")
    with pytest.raises(ConfigError):
        read_keypoints(path, format="openpose-ish")
    with pytest.raises(ConfigError):
        read_keypoints(path, image_size=(-1, 10))


# --- errors: one per class ----------------------------------------------------------------


Mutation = Callable[[Any], Any]


def _set(keys: tuple[Any, ...], value: Any) -> Mutation:
    def mutate(doc: Any) -> Any:
        target = doc
        for key in keys[:-1]:
            target = target[key]
        target[keys[-1]] = value
        return doc

    return mutate


def _drop(keys: tuple[Any, ...]) -> Mutation:
    def mutate(doc: Any) -> Any:
        target = doc
        for key in keys[:-1]:
            target = target[key]
        del target[keys[-1]]
        return doc

    return mutate


def _truncate(keys: tuple[Any, ...], length: int) -> Mutation:
    def mutate(doc: Any) -> Any:
        target = doc
        for key in keys[:-1]:
            target = target[key]
        target[keys[-1]] = target[keys[-1]][:length]
        return doc

    return mutate


ERROR_CASES: list[tuple[str, Callable[[], Any], Mutation, tuple[str, ...]]] = [
    ("ann-count", coco_annotations, _truncate(("annotations", 0, "keypoints"), 50),
     ("annotations[0].keypoints", "expected a flat list of 51 numbers (17 joints x 3), got 50 numbers")),
    ("res-not-triplets", coco_results, _truncate((0, "keypoints"), 50), ("[0].keypoints", "got 50 numbers")),
    ("res-joint-count", coco_results, _truncate((1, "keypoints"), 42),
     ("[1].keypoints", "unsupported joint count 14 (42 numbers; COCO results hold 17 joints")),
    ("zedo-joint-count", zedo_2d, _truncate(("instances", 1, "keypoints"), 12),
     ("instances[1].keypoints", "expected 17 joints for skeleton h36m17, got 12")),
    ("non-numeric", coco_annotations, _set(("annotations", 1, "keypoints", 4), "12"),
     ("annotations[1].keypoints[4]", "expected a number, got a string")),
    ("non-numeric-zedo", zedo_2d, _set(("instances", 0, "keypoints", 0), [1.0, None]),
     ("instances[0].keypoints[0][1]", "expected a number")),
    ("nan-coordinate", coco_annotations, _set(("annotations", 0, "keypoints", 0), math.nan),
     ("annotations[0].keypoints", "joint 0 (nose)", "not marked missing")),
    ("inf-coordinate", coco_results, _set((2, "keypoints", 4), math.inf),
     ("[2].keypoints", "joint 1 (left_eye)")),
    ("negative-width", coco_annotations, _set(("images", 1, "width"), -3), ("images[1].width", "positive")),
    ("non-numeric-height", coco_annotations, _set(("images", 0, "height"), "720"),
     ("images[0].height", "expected a number")),
    ("bad-zedo-size", zedo_2d, _set(("image_size",), [0, 10]), ("image_size[0]", "positive")),
    ("missing-image-id", coco_annotations, _drop(("annotations", 0, "image_id")),
     ("annotations[0].image_id", "missing required key")),
    ("missing-keypoints", coco_results, _drop((1, "keypoints")), ("[1].keypoints", "missing required key")),
    ("missing-zedo-instance-id", zedo_2d, _drop(("instances", 1, "image_id")),
     ("instances[1].image_id", "missing required key")),
    ("missing-image-entry-id", coco_annotations, _drop(("images", 0, "id")),
     ("images[0].id", "missing required key")),
    ("unknown-image-id", coco_annotations, _set(("annotations", 1, "image_id"), 99),
     ("annotations[1].image_id", "image id 99 is not in images")),
    ("empty-annotations", coco_annotations, _set(("annotations",), []), ("no instances found",)),
    ("empty-results", coco_results, lambda doc: [], ("no instances found",)),
    ("empty-zedo", zedo_2d, _set(("instances",), []), ("no instances found",)),
    ("duplicate-image-id", coco_annotations, _set(("images", 1, "id"), 7),
     ("images[1].id", "duplicate image id 7")),
    ("bad-visibility", coco_annotations, _set(("annotations", 0, "keypoints", 2), 3),
     ("annotations[0].keypoints[2]", "visibility 3")),
    ("bool-image-id", coco_results, _set((0, "image_id"), True), ("[0].image_id", "integer or string")),
    ("bad-zedo-confidence", zedo_2d, _set(("instances", 0, "keypoints", 0), [1, 2, 1.5]),
     ("instances[0].keypoints[0][2]", "confidence in [0, 1]")),
    ("bad-schema", zedo_2d, _set(("schema",), "other/2"), ("schema", "zedo.keypoints2d/1")),
    ("unknown-skeleton", zedo_2d, _set(("skeleton",), "body24"), ("skeleton", "unknown skeleton 'body24'")),
    ("unknown-names", coco_annotations, _set(("categories", 0, "keypoints"), ["a"] * 14),
     ("categories[0].keypoints", "unknown joint names ('a', 'a'", "(14 names)", "--skeleton NAME")),
    ("annotations-not-list", coco_annotations, _set(("annotations",), {}),
     ("annotations", "expected a list")),
    ("huge-number", coco_results, _set((0, "keypoints", 0), 10**400), ("[0].keypoints[0]", "too large")),
]  # fmt: skip


@pytest.mark.parametrize(("build", "mutate", "parts"), [c[1:] for c in ERROR_CASES], ids=[c[0] for c in ERROR_CASES])
def test_malformed_input_names_file_and_field(
    tmp_path: Path, build: Callable[[], Any], mutate: Mutation, parts: tuple[str, ...]
) -> None:
    assert_error(write(tmp_path, mutate(build())), *parts)


def test_missing_top_level_key_with_explicit_format(tmp_path: Path) -> None:
    doc = coco_annotations()
    del doc["images"]
    assert_error(write(tmp_path, doc), "images: missing required key", format="coco-annotations")


@pytest.mark.parametrize(
    ("content", "parts"),
    [
        (None, ("file not found",)),
        ("dir", ("is a directory",)),
        (b"\xff\xfe\x00{", ("not UTF-8",)),
        (b'{"images": [1,\n  2,,]}', ("invalid JSON at line 2, column 5",)),
        (b"  \n", ("file is empty",)),
    ],
    ids=["missing", "directory", "not-utf8", "invalid-json", "empty"],
)
def test_file_level_errors(tmp_path: Path, content: bytes | str | None, parts: tuple[str, ...]) -> None:
    path = tmp_path / "kp.json"
    if content == "dir":
        path.mkdir()
    elif isinstance(content, bytes):
        path.write_bytes(content)
    assert_error(path, *parts)


# --- property: malformed documents end as InputFormatError ---------------------------------

_KEYS = st.sampled_from(
    ["images", "annotations", "categories", "id", "image_id", "keypoints", "width", "height", "file_name",
     "instances", "skeleton", "schema", "score", "image_size", "people"]
) | st.text(max_size=3)  # fmt: skip
_LEAVES = st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=4)
_JSON = st.recursive(
    _LEAVES, lambda children: st.lists(children, max_size=4) | st.dictionaries(_KEYS, children, max_size=4),
    max_leaves=24,
)  # fmt: skip


@st.composite
def _mutated(draw: st.DrawFn) -> Any:
    """A valid document of one of the three formats with one to three mutations."""
    doc = copy.deepcopy(draw(st.sampled_from([coco_annotations, coco_results, zedo_2d]))())
    for _ in range(draw(st.integers(1, 3))):
        locations = key_paths(doc)
        if not locations:
            break
        where = draw(st.sampled_from(locations))
        value: Any = doc
        for key in where[:-1]:
            value = value[key]
        op = draw(st.sampled_from(["drop", "replace", "truncate"]))
        if op == "truncate" and isinstance(value[where[-1]], list | str):
            mutate = _truncate(where, draw(st.integers(0, len(value[where[-1]]))))
        elif op == "drop":
            mutate = _drop(where)
        else:
            mutate = _set(where, draw(st.floats() | st.integers(-3, 3) | _JSON))
        doc = mutate(doc)
    return doc


@given(doc=_JSON | _mutated(), fmt=st.just("auto") | st.sampled_from(INPUT_FORMATS), size=st.booleans())
@settings(max_examples=300, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])
def test_malformed_documents_give_keypoints_or_input_format_error(
    tmp_path_factory: pytest.TempPathFactory, doc: Any, fmt: str, size: bool
) -> None:
    path = tmp_path_factory.getbasetemp() / "property.json"
    path.write_text(json.dumps(doc))
    try:
        kp = read_keypoints(path, format=fmt, image_size=(64, 48) if size else None)
    except InputFormatError as exc:
        assert str(exc).startswith(f"{path}: ")
        return
    assert isinstance(kp, Keypoints2D) and len(kp) > 0
    n, j = len(kp), kp.skeleton.num_joints
    assert kp.xy.shape == (n, j, 2) and kp.confidence.shape == (n, j) and kp.image_sizes.shape == (n, 2)
    assert ((kp.confidence >= 0) & (kp.confidence <= 1)).all()
    assert np.isfinite(kp.xy[kp.confidence > 0]).all() and np.isnan(kp.xy[kp.confidence == 0]).all()


@given(raw=st.binary(max_size=40))
@settings(max_examples=50, deadline=None, database=None)
def test_random_bytes_give_keypoints_or_input_format_error(
    tmp_path_factory: pytest.TempPathFactory, raw: bytes
) -> None:
    path = tmp_path_factory.getbasetemp() / "bytes.json"
    path.write_bytes(raw)
    try:
        assert isinstance(read_keypoints(path), Keypoints2D)
    except InputFormatError as exc:
        assert str(exc).startswith(f"{path}: ")


# --- the real SyRIP files, when the shared data is there ----------------------------------


def test_syrip_files() -> None:
    if not SYRIP.is_dir():
        pytest.skip(f"SyRIP data not found at {SYRIP}")
    gt = read_keypoints(SYRIP / "keypoints2d_gt_test100.json")
    assert len(gt) == 100 and gt.skeleton.name == "coco17" and gt.format == "coco-annotations"
    assert (gt.confidence == 0).sum() <= 13
    assert np.isfinite(gt.image_sizes).all() and all(name is not None for name in gt.file_names)
    dt = read_keypoints(SYRIP / "keypoints2d_fidip_real700.json", images=SYRIP / "keypoints2d_gt_real700.json")
    assert len(dt) == 700 and dt.format == "coco-results" and dt.skeleton.name == "coco17"
    assert np.isfinite(dt.image_sizes).all() and all(name is not None for name in dt.file_names)
    assert dt.confidence.max() <= 1.0
