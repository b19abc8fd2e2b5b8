"""Reading large inputs element by element: `jsondoc.scan_document` gives what
json.loads gives, invalid text fails with json.loads' own message, and no reader parses a whole
document into Python objects or holds more than a few times the file's size."""

from __future__ import annotations

import functools
import json
import os
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import (
    alphapose,
    coco_annotations,
    coco_results,
    jsonl_records,
    jsonl_text,
    mmpose_demo,
    mmpose_instance,
    zedo_2d,
)
from hypothesis import given, settings
from hypothesis import strategies as st

from zedo_cli.errors import InputFormatError
from zedo_cli.formats import read_keypoints, read_keypoints_text, read_parsed
from zedo_cli.formats.readers.jsondoc import JsonArray, scan_document
from zedo_cli.formats.readers.source import parse_document, parse_json
from zedo_cli.strict_json import DuplicateKeyError


def _plain(value: Any) -> Any:
    """`value` with every `JsonArray` made a list (what json.loads gives)."""
    if isinstance(value, JsonArray):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


_JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False) | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=3), inner, max_size=4),
    max_leaves=20,
)


@settings(max_examples=200, deadline=None, database=None)
@given(value=_JSON, indent=st.sampled_from([None, 0, 1, 2]))
def test_scan_document_is_json_loads(value: Any, indent: int | None) -> None:
    text = json.dumps(value, indent=indent)
    assert _plain(scan_document(text)) == json.loads(text)
    assert _plain(scan_document(f" \n\t{text}\r\n ")) == json.loads(text)


def test_top_level_arrays_are_decoded_as_read() -> None:
    doc = scan_document('{"a": [1, {"b": [2]}], "c": {"d": [3]}, "a2": [], "e": "x"}')
    assert isinstance(doc["a"], JsonArray) and isinstance(doc["a2"], JsonArray)
    assert len(doc["a"]) == 2 and doc["a"][1] == {"b": [2]} and doc["a"][-1] == {"b": [2]} and doc["a"][:1] == [1]
    assert doc["c"] == {"d": [3]} and not doc["a2"]  # deeper values are plain, as json.loads makes them
    for text in ('{"a": [1], "a": [2]}', '{"a": [{"b": 1, "b": 2}]}'):  # a repeated key: refused, at any depth
        with pytest.raises(DuplicateKeyError, match="duplicate key '(a|b)'"):
            scan_document(text)


@pytest.mark.parametrize(
    "text",
    ["[1,]", "[1 2]", '{"a": [1 2]}', '{"a" 1}', '{"a": 1,}', '{"a": [1], }', "[1] x", '{"a": [1]} ]', "[", "{",
     '{"a": [1, {"b": }]}', '{1: 2}', '["\x01"]', "[NaN, Infinity, -Infinity, 1e999]", "[" * 100_000 + "]" * 100_000,
     "[" + "9" * 5000 + "]", '{"a": [1]}\n{"b": 2}', "[]", "{}", "  7  ", '{"a": 1, "a": 2}', '[{"a": 1, "a": 2}]'],
)  # fmt: skip
def test_invalid_text_fails_as_json_loads_says(text: str) -> None:
    try:
        expected = parse_json(text, "kp.json")
    except InputFormatError as exc:
        with pytest.raises(InputFormatError) as got:
            parse_document(text, "kp.json")
        assert str(got.value) == str(exc)
    else:
        assert json.dumps(_plain(parse_document(text, "kp.json"))) == json.dumps(expected)


@functools.lru_cache(maxsize=4)
def _documents(n: int) -> dict[str, tuple[str, str]]:
    """A document of each large single-document layout, `n` instances: name -> (file name, text)
    (made once per size for all the parametrized tests)."""
    coco = coco_annotations()
    image, annotation = coco["images"][0], coco["annotations"][0]
    coco["images"] = [{**image, "id": i, "file_name": f"{i}.jpg"} for i in range(n)]
    coco["annotations"] = [{**annotation, "id": i, "image_id": n - 1 - i} for i in range(n)]
    results = [{**coco_results()[0], "image_id": i} for i in range(n)]
    alpha = [{**entry, "image_id": f"{i}.jpg"} for i in range(n // 3) for entry in alphapose(17)]
    video = [{"frame_id": f, "instances": [mmpose_instance(f % 50)]} for f in range(n)]
    demo = mmpose_demo()
    demo["instance_info"] = [{"frame_id": f + 1, "instances": [mmpose_instance(f % 50)]} for f in range(n)]
    z2 = zedo_2d()
    z2["instances"] = [{**z2["instances"][0], "image_id": i} for i in range(n)]
    lines = [{**record, "frame": 3 * k + record["frame"]} for k in range(n // 3) for record in jsonl_records()]
    return {
        "coco-annotations": ("coco.json", json.dumps(coco)),
        "coco-results": ("results.json", json.dumps(results)),
        "alphapose": ("alphapose.json", json.dumps(alpha, indent=1)),
        "mmpose-image": ("image.json", json.dumps([mmpose_instance(k % 50) for k in range(n)])),
        "mmpose-video": ("video.json", json.dumps(video)),
        "mmpose-demo": ("results_clip.json", json.dumps(demo)),
        "zedo-2d": ("z2.json", json.dumps(z2)),
        "zedo-jsonl": ("frames.jsonl", jsonl_text(lines)),
    }


def _same(a: Any, b: Any) -> None:
    assert (a.format, a.skeleton, a.source, a.path) == (b.format, b.skeleton, b.source, b.path)
    assert (a.image_ids, a.file_names, a.scores, a.frame_indices) == (b.image_ids, b.file_names, b.scores,
                                                                      b.frame_indices)  # fmt: skip
    for name in ("xy", "confidence", "image_sizes"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


@pytest.mark.parametrize("layout", sorted(_documents(3)))
def test_readers_read_every_layout_as_from_json_loads(layout: str) -> None:
    name, text = _documents(300)[layout]
    kp = read_keypoints_text(text, name)
    assert kp.format == layout and len(kp) > 0
    if layout != "zedo-jsonl":
        _same(kp, read_parsed(json.loads(text), name))  # the whole document parsed at once


@pytest.mark.parametrize("layout", sorted(_documents(3)))
def test_no_reader_parses_the_whole_document(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, layout: str
) -> None:  # fmt: skip
    """json.loads of a whole large input is what took ten times its size in memory."""
    name, text = _documents(2100)[layout]
    path = tmp_path / name
    path.write_text(text)
    real_loads = json.loads

    def small_loads(s: Any, *args: Any, **kwargs: Any) -> Any:
        assert len(s) < 100_000, f"json.loads of {len(s)} characters: the whole document at once"
        return real_loads(s, *args, **kwargs)

    monkeypatch.setattr(json, "loads", small_loads)
    assert len(read_keypoints(path)) >= 2000


# The three costliest layouts to trace run with -m slow; the default suite keeps the others.
_TRACED_SLOW = ("mmpose-demo", "mmpose-image", "mmpose-video")


@pytest.mark.parametrize(
    "layout",
    [pytest.param(x, marks=pytest.mark.slow) if x in _TRACED_SLOW else x for x in sorted(_documents(3))],
)
def test_reading_holds_a_few_times_the_file(tmp_path: Path, layout: str) -> None:
    """Peak memory of a read (traced Python allocations) stays under 6x the file's size; a
    whole-document json.loads alone takes about 10x, reading into a 256 MiB buffer far more."""
    name, text = _documents(2100)[layout]
    path = tmp_path / name
    path.write_text(text)
    tracemalloc.start()
    try:
        kp = read_keypoints(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(kp) >= 2000
    assert peak < 6 * os.path.getsize(path), f"{peak / os.path.getsize(path):.1f} x the file's size"
