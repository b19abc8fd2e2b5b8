"""A result document read a frame at a time (`result_json.read_streamed`, `jsondoc.stream_members`): the same
poses as the whole document read at once, and every other text left to the whole-document path."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.errors import InputFormatError
from zedo_cli.formats.readers.jsondoc import InvalidDocument, stream_members
from zedo_cli.formats.readers.result import read_result
from zedo_cli.formats.readers.result_json import read_document, read_streamed
from zedo_cli.formats.writers.outputs import write_result
from zedo_cli.strict_json import DuplicateKeyError, loads


def decoded(text: str) -> list[tuple[str, object]]:
    return [
        (k, list(v) if k == "frames" and not isinstance(v, int | dict) else v)
        for k, v in stream_members(text, "frames")
    ]


def test_members_decode_as_loads_does() -> None:
    for text in ["{}", ' {"a" : 1 , "frames": [1, 2, {"x": [3]}], "s": null} \n', '{"frames": []}', '{"frames": 3}']:
        assert dict(decoded(text)) == loads(text)
    key, frames = next(stream_members('{"frames": [1]}', "frames"))
    assert key == "frames" and not isinstance(frames, list) and list(frames) == [1]
    with pytest.raises(InvalidDocument):
        decoded("[1]")  # valid JSON, but not a document with members


@pytest.mark.parametrize("text", ['{"a":1,}', '{"a":1}x', '{"frames":[1,]}', '{"frames":[1 2]}', '{"a" 1}',
                                  '{"frames": [1, {"b": 1, "b": 2}]}', '{"a": [1}'])  # fmt: skip
def test_members_refuse_what_loads_refuses(text: str) -> None:
    with pytest.raises(ValueError):
        loads(text)
    with pytest.raises((ValueError, InvalidDocument)):
        decoded(text)


def test_members_name_a_repeated_key() -> None:
    with pytest.raises(DuplicateKeyError, match="'a'"):
        decoded('{"a": 1, "a": 2}')


def test_a_frame_left_half_read_is_refused() -> None:
    stream = stream_members('{"frames": [1, 2], "b": 0}', "frames")
    _, frames = next(stream)
    next(frames)
    with pytest.raises(InvalidDocument):
        next(stream)


@pytest.fixture()
def document(tmp_path: Path) -> str:
    kp, res, mats, sources = make_case()
    path = tmp_path / "kp.zedo.json"
    write_result(path, kp, res, mats, sources, {**PARAMS, "fps": 25.0}, INPUT_INFO)
    return path.read_text()


def same_result(a: object, b: object) -> None:
    for name in ("poses", "frame_index", "person", "observed", "lifted", "keypoints_2d", "root_translation"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    for name in ("image_ids", "file_names", "flags", "cameras", "params", "fps"):
        assert getattr(a, name) == getattr(b, name)
    np.testing.assert_array_equal(a.record.keypoints_2d, b.record.keypoints_2d)  # type: ignore[attr-defined]


def test_zedos_own_document_is_read_a_frame_at_a_time(document: str) -> None:
    streamed = read_streamed(document, "r.json")
    assert streamed is not None
    same_result(streamed, read_document(loads(document), "r.json", "json"))


@pytest.mark.parametrize("order", ["frames first", "a header member after the frames", "summary first"])
def test_another_key_order_reads_the_same(document: str, tmp_path: Path, order: str) -> None:
    doc = loads(document)
    keys = list(doc)
    if order == "frames first":
        keys = ["frames", *[k for k in keys if k != "frames"]]
    elif order == "summary first":
        keys = ["schema", "summary", *[k for k in keys if k not in ("schema", "summary")]]
    else:
        keys = [*[k for k in keys if k != "params"], "params"]
    text = json.dumps({k: doc[k] for k in keys}, indent=1)
    assert (read_streamed(text, "r.json") is None) == (order != "summary first")
    path = tmp_path / "r.zedo.json"
    path.write_text(text)
    same_result(read_result(path), read_document(doc, "r.json", "json"))


def test_a_bad_frame_is_named_as_before(document: str) -> None:
    doc = loads(document)
    doc["frames"][1]["persons"][0]["observed"] = [True]
    text = json.dumps(doc, indent=1)
    with pytest.raises(InputFormatError, match=r"^r\.json: frames\[1\]\.persons\[0\]\.observed: expected 12 entries"):
        read_streamed(text, "r.json")
    with pytest.raises(InputFormatError, match=r"^r\.json: frames\[1\]\.persons\[0\]\.observed: expected 12 entries"):
        read_document(doc, "r.json", "json")


def test_reading_pauses_the_collector_and_restores_it(document: str, tmp_path: Path) -> None:
    import gc

    from zedo_cli.collection import paused_collection

    path = tmp_path / "r.zedo.json"
    path.write_text(document)
    assert gc.isenabled()
    read_result(path)
    assert gc.isenabled()
    with paused_collection():
        assert not gc.isenabled()
        with paused_collection():
            assert not gc.isenabled()
        assert not gc.isenabled()
    assert gc.isenabled()
    gc.disable()
    try:
        with paused_collection():
            pass
        assert not gc.isenabled()  # left as it was found
    finally:
        gc.enable()
