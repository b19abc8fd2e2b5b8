"""Property-based fuzzing of every 2D reader: malformed input ends as `InputFormatError`, never a traceback.

Valid documents of each layout (tests/format_fixtures.py) are mutated (keys dropped, values
replaced by NaN, inf, huge integers, wrong types or random JSON, lists cut short, text cut and
spliced) and read through `read_parsed` (parsed JSON), `read_keypoints_text` (text, JSON Lines
included) and `read_keypoints` (files, stdin-like names, OpenPose directories, Pose2Sim-named
frame folders, files over a lowered size limit). The documents include the shapes of real files:
COCO and MMPose joint names in another order, H36M names in a COCO file, Human-Art's 21 names
over 17 joints, OpenPose BODY_25B; reads also draw a ``--skeleton``. Whatever is read either
fails with an `InputFormatError` naming the input on one line, or is a consistent `Keypoints2D`
that says which joint set it assumed.

Most examples parse from memory to keep the default run fast, and for those hypothesis draws
one seed that drives the layout, the format option and the mutations (drawing each choice from
hypothesis costs more than the read; a seed is still reproducible). 5,400 examples in all
(halved from 10,400 to keep the default suite under 3 minutes on 2 cores).
"""

from __future__ import annotations

import copy
import json
import math
import random
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from format_fixtures import (
    MMPOSE_COCO_NAMES,
    alphapose,
    body25b_pose,
    coco_annotations,
    coco_results,
    jsonl_records,
    jsonl_text,
    key_paths,
    mmpose_demo,
    mmpose_image,
    mmpose_video,
    openpose_frame,
    zedo_2d,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError, ZedoError
from zedo_cli.formats import INPUT_FORMATS, read_keypoints, read_keypoints_text, read_parsed
from zedo_cli.formats.readers import source

_PERM = [3, 0, 16, 5, 1, 2, 4, 6, 8, 7, 10, 9, 12, 11, 15, 14, 13]
_H36M_NAMES = ["root (pelvis)", "left_hip", "left_knee", "left_foot", "right_hip", "right_knee", "right_foot", "spine",
               "thorax", "neck_base", "head", "left_shoulder", "left_elbow", "left_wrist", "right_shoulder",
               "right_elbow", "right_wrist"]  # fmt: skip


def _coco_named(names: list[str]) -> dict[str, Any]:
    doc = coco_annotations()
    doc["categories"][0]["keypoints"] = names
    return doc


def _humanart() -> dict[str, Any]:
    doc = _coco_named([*MMPOSE_COCO_NAMES, "left_finger", "right_finger", "left_toe", "right_toe"])
    doc["annotations"][0]["keypoints_21"] = doc["annotations"][0]["keypoints"] + [1.0, 2.0, 2] * 4
    return doc


def _body25b() -> dict[str, Any]:
    values = [v for x, y in body25b_pose() for v in (x, y, 0.5)]
    return {"version": 1.3, "people": [{"person_id": [-1], "pose_keypoints_2d": values}]}


BUILDERS: dict[str, Callable[[], Any]] = {
    "coco-annotations": coco_annotations,
    "coco-results": coco_results,
    "zedo-2d": zedo_2d,
    "openpose": lambda: openpose_frame(1.0, 2.0, count=18, missing=(3,)),
    "mmpose-image": mmpose_image,
    "mmpose-video": mmpose_video,
    "mmpose-demo": mmpose_demo,
    "alphapose": lambda: alphapose(count=17),
    "zedo-jsonl": lambda: jsonl_records()[0],
}
LAYOUTS = sorted(BUILDERS)
# Documents in the shapes of real files, as (layout, builder).
VARIANTS: list[tuple[str, Callable[[], Any]]] = [
    ("coco-annotations", lambda: _coco_named([MMPOSE_COCO_NAMES[k] for k in _PERM])),
    ("coco-annotations", lambda: _coco_named(_H36M_NAMES)),
    ("coco-annotations", _humanart),
    ("coco-annotations", lambda: _coco_named([f"j{k}" for k in range(17)])),
    ("mmpose-demo", lambda: mmpose_demo([MMPOSE_COCO_NAMES[k] for k in _PERM])),
    ("openpose", _body25b),
    ("openpose", lambda: openpose_frame(1.0, 2.0)),
]
SKELETON_OPTIONS = [None, None, None, *sorted(SKELETONS)]


def pick_document(rng: random.Random) -> tuple[str, Any]:
    """A fresh document: a quarter of the time one of the real files' shapes."""
    if rng.random() < 0.25:
        layout, build = rng.choice(VARIANTS)
        return layout, build()
    layout = rng.choice(LAYOUTS)
    return layout, BUILDERS[layout]()


FORMATS = st.sampled_from(INPUT_FORMATS)
_ODD_VALUES: list[Any] = [
    math.nan, math.inf, -math.inf, 10**400, -1, 0, 1, 2, 3, 0.5, 1e308, -1e-300, True, False, None, "", "x",
    "12", [], {}, [[]], [1.0, 2.0], [[1.0, 2.0]], [1.0, 2.0, 0.5] * 17, {"a": 1}, [None], "coco17",
]  # fmt: skip
SETTINGS = {"deadline": None, "database": None, "suppress_health_check": [HealthCheck.too_slow]}


def mutate(doc: Any, rng: random.Random, count: int) -> Any:
    """`doc` (a fresh document: changed in place) with `count` random structural mutations."""
    for _ in range(count):
        locations = key_paths(doc)
        if not locations:
            return rng.choice(_ODD_VALUES)
        where = rng.choice(locations)
        parent = doc
        for key in where[:-1]:
            parent = parent[key]
        key, value = where[-1], parent[where[-1]]
        op = rng.randrange(5)
        if op == 0:
            del parent[key]
        elif op == 1 and isinstance(value, list | str):
            parent[key] = value[: rng.randrange(len(value) + 1)]
        elif op == 2 and isinstance(value, list) and value:
            parent[key] = [*value, copy.deepcopy(rng.choice(value))]
        elif op == 3 and isinstance(parent, dict):
            parent[rng.choice(["image_id", "keypoints", "frame_id", "people", "instances", "score", "skeleton"])] = (
                rng.choice(_ODD_VALUES)
            )
        else:
            parent[key] = copy.deepcopy(rng.choice(_ODD_VALUES))
    return doc


def mangle_text(text: str, rng: random.Random) -> str:
    """`text` cut, spliced or with a character replaced (often no longer JSON)."""
    if not text:
        return text
    a = rng.randrange(len(text))
    b = min(len(text), a + rng.randrange(1, 8))
    op = rng.randrange(4)
    if op == 0:
        return text[:a]
    if op == 1:
        return text[:a] + text[b:]
    if op == 2:
        return text[:a] + rng.choice(["\n", "]", "}", ",", '"', "NaN", "1e999", "\ufeff", "\x00", "\u2028"]) + text[a:]
    return text[:a] + chr(rng.randrange(32, 0x3000)) + text[a + 1 :]


def check(kp: Keypoints2D, path: str) -> None:
    """A `Keypoints2D` that a reader returned is consistent."""
    assert isinstance(kp, Keypoints2D) and len(kp) > 0 and kp.path == path
    n, j = len(kp), kp.skeleton.num_joints
    assert kp.xy.shape == (n, j, 2) and kp.confidence.shape == (n, j) and kp.image_sizes.shape == (n, 2)
    assert len(kp.image_ids) == len(kp.file_names) == len(kp.scores) == n
    assert kp.frame_indices is None or len(kp.frame_indices) == n
    assert ((kp.confidence >= 0) & (kp.confidence <= 1)).all()
    assert np.isfinite(kp.xy[kp.confidence > 0]).all() and np.isnan(kp.xy[kp.confidence == 0]).all()
    assert all(s is None or math.isfinite(s) for s in kp.scores)
    assert kp.source is not None and kp.source.name == kp.skeleton.name and kp.source.reason


def one_line(exc: Exception) -> bool:
    return str(exc).isprintable()


def read_or_error(read: Callable[[], Keypoints2D], path: str, shown: str | None = None) -> None:
    """Run one read: success must give a consistent record, failure an InputFormatError naming `path`
    (as `shown`: escaped where it holds control characters)."""
    try:
        kp = read()
    except InputFormatError as exc:
        assert isinstance(exc, ZedoError) and str(exc).startswith(f"{shown or path}: ") and one_line(exc), exc
        return
    check(kp, path)


def pick_format(layout: str, rng: random.Random) -> str:
    """Half "auto", a quarter the layout's own name, a quarter any name (mostly a mismatch)."""
    roll = rng.random()
    return "auto" if roll < 0.5 else layout if roll < 0.75 else rng.choice(INPUT_FORMATS)


SEEDS = st.integers(0, 2**64 - 1)


@given(seed=SEEDS)
@settings(max_examples=3000, **SETTINGS)
def test_mutated_documents_in_memory(seed: int) -> None:
    rng = random.Random(seed)
    layout, doc = pick_document(rng)
    fmt = pick_format(layout, rng)
    skeleton = rng.choice(SKELETON_OPTIONS)
    doc = mutate(doc, rng, rng.randint(0 if layout in ("coco-annotations", "openpose") else 1, 3))
    read_or_error(lambda: read_parsed(doc, "mem.json", format=fmt, skeleton=skeleton), "mem.json")


_KEYS = st.sampled_from(
    ["images", "annotations", "categories", "id", "image_id", "keypoints", "keypoint_scores", "people",
     "pose_keypoints_2d", "instances", "instance_info", "meta_info", "frame_id", "frame", "persons", "skeleton",
     "score", "bbox_score", "idx", "box", "keypoint_id2name", "dataset_name"]
) | st.text(max_size=3)  # fmt: skip
_LEAVES = st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=4)
_JSON = st.recursive(
    _LEAVES, lambda children: st.lists(children, max_size=4) | st.dictionaries(_KEYS, children, max_size=4),
    max_leaves=20,
)  # fmt: skip


@given(doc=_JSON, fmt=FORMATS)
@settings(max_examples=600, **SETTINGS)
def test_arbitrary_json_in_memory(doc: Any, fmt: str) -> None:
    read_or_error(lambda: read_parsed(doc, "any.json", format=fmt), "any.json")


@given(seed=SEEDS)
@settings(max_examples=1500, **SETTINGS)
def test_mangled_text_in_memory(seed: int) -> None:
    rng = random.Random(seed)
    layout, doc = pick_document(rng)
    fmt = pick_format(layout, rng)
    name = rng.choice(["mem.json", "mem.jsonl", "-", "m\nem\x1b[1m.json"])
    if layout == "zedo-jsonl":
        records = [mutate(r, rng, rng.randrange(2)) for r in jsonl_records()[: rng.randint(1, 3)]]
        text = jsonl_text(records)
    else:
        text = json.dumps(mutate(doc, rng, rng.randrange(2)), indent=rng.choice([None, 1]))
    text = mangle_text(text, rng) if rng.random() < 0.8 else text
    shown = name.replace("\n", "\\n").replace("\x1b", "\\x1b")  # names are shown escaped
    read_or_error(lambda: read_keypoints_text(text, name, format=fmt), name, shown)


@given(
    layout=st.sampled_from(LAYOUTS),
    fmt=FORMATS,
    suffix=st.sampled_from([".json", ".jsonl"]),
    size=st.booleans(),
    companion=st.booleans(),
    seed=st.integers(0, 2**32 - 1),
)
@settings(max_examples=300, **SETTINGS)
def test_mutated_files(
    tmp_path_factory: pytest.TempPathFactory, layout: str, fmt: str, suffix: str, size: bool, companion: bool, seed: int
) -> None:
    rng = random.Random(seed)
    base = tmp_path_factory.getbasetemp()
    path = base / f"fuzz{suffix}"
    if rng.random() < 0.25:
        layout, build = rng.choice(VARIANTS)
        doc = build()
    else:
        doc = BUILDERS[layout]()
    doc = mutate(doc, rng, rng.randrange(0, 3))
    raw = json.dumps(doc).encode()
    path.write_bytes(mangle_text(raw.decode(), rng).encode("utf-8", "replace") if rng.random() < 0.3 else raw)
    images = None
    if companion:  # a companion annotation file, itself sometimes broken
        images = base / "companion.json"
        images.write_text(json.dumps(mutate(coco_annotations(), rng, rng.randrange(2))))
    kwargs: dict[str, Any] = {"format": fmt, "image_size": (64, 48) if size else None, "images": images,
                              "skeleton": rng.choice(SKELETON_OPTIONS)}  # fmt: skip
    limit = source.MAX_INPUT_BYTES
    source.MAX_INPUT_BYTES = rng.choice([limit, limit, limit, rng.randrange(1, 2 * len(raw) + 2)])
    try:
        kp = read_keypoints(path, **kwargs)
    except InputFormatError as exc:
        assert str(exc).startswith((f"{path}: ", f"{images}: ")) and one_line(exc), exc
        return
    finally:
        source.MAX_INPUT_BYTES = limit
    check(kp, str(path))


@given(frames=st.integers(1, 3), fmt=st.sampled_from(["auto", "openpose"]), seed=st.integers(0, 2**32 - 1))
@settings(max_examples=100, **SETTINGS)
def test_mutated_openpose_directories(
    tmp_path_factory: pytest.TempPathFactory, frames: int, fmt: str, seed: int
) -> None:
    rng = random.Random(seed)
    directory = tmp_path_factory.mktemp("openpose")
    pattern = rng.choice(["c_{:012d}_keypoints.json", "cam01.{:04d}.json"])  # OpenPose's names, Pose2Sim's
    body25b = rng.random() < 0.3
    for frame in range(rng.choice([frames, frames + 3])):
        if frame >= frames:  # frames without people
            doc: Any = {"version": 1.3, "people": []}
        elif body25b:
            doc = _body25b()
        else:
            doc = openpose_frame(float(frame), count=rng.choice([18, 25]) if frame == 0 else 25)
        if rng.random() < 0.5:
            doc = mutate(doc, rng, 1)
        text = json.dumps(doc)
        name = pattern.format(2 * rng.randrange(4) if rng.random() < 0.3 else 2 * frame)
        (directory / name).write_text(mangle_text(text, rng) if rng.random() < 0.2 else text)
    try:
        kp = read_keypoints(directory, format=fmt, skeleton=rng.choice(SKELETON_OPTIONS))
    except InputFormatError as exc:
        assert str(exc).startswith(str(directory)) and one_line(exc), exc
        return
    check(kp, str(directory))
    assert kp.frame_indices is not None and all(f is not None and f % 2 == 0 for f in kp.frame_indices)
