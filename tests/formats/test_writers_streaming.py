"""The result writers stream: the JSON text is json.dumps' to the byte, yet neither the frames
nor the text of a document is ever held whole (peak memory of large inputs)."""

from __future__ import annotations

import json
import re
import weakref
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.formats.writers import outputs, result_csv, result_json
from zedo_cli.formats.writers.common import json_pieces
from zedo_cli.formats.writers.outputs import write_result
from zedo_cli.formats.writers.result_json import build_result_document

CREATED = re.compile(r'"created": "[^"]*"')


@pytest.mark.parametrize("indent", [1, None, 2])
@pytest.mark.parametrize(
    "doc",
    [{}, {"a": 1}, {"a": [], "b": {"c": [1, {"d": "x\ny \u00e9"}]}, "e": []}, {"a": [{"b": [1, 2]}, {}], "z": None}],
)
def test_json_pieces_are_json_dumps(doc: dict[str, Any], indent: int | None) -> None:
    expected = json.dumps(doc, indent=indent)
    assert "".join(json_pieces(doc.items(), indent=indent)) == expected
    streamed = [(k, iter(v) if isinstance(v, list) else v) for k, v in doc.items()]  # lists as iterators
    assert "".join(json_pieces(streamed, indent=indent)) == expected


def test_json_pieces_can_put_each_streamed_item_on_one_line() -> None:
    doc = {"a": {"b": 1}, "rows": [{"x": [1, 2], "y": "z\nw"}, {}, {"x": None}]}
    text = "".join(json_pieces([("a", doc["a"]), ("rows", iter(doc["rows"]))], one_line_items=True))
    assert json.loads(text) == doc
    assert text.splitlines()[-6:-1] == [' "rows": [', '  {"x": [1, 2], "y": "z\\nw"},', "  {},", '  {"x": null}', " ]"]
    with pytest.raises(ValueError):
        "".join(json_pieces([("rows", iter([{"x": float("nan")}]))], one_line_items=True))


def test_json_pieces_refuse_nan() -> None:
    with pytest.raises(ValueError):
        "".join(json_pieces([("frames", iter([{"x": float("nan")}]))]))


def _big_case(copies: int = 50) -> tuple[Keypoints2D, Any, np.ndarray, list[str]]:
    """The writer fixture's four instances repeated, every copy in frames of its own."""
    import dataclasses

    kp, res, mats, sources = make_case()
    idx = np.tile(np.arange(len(kp)), copies)
    ids = [image_id + 100 * (n // len(kp)) for n, image_id in enumerate(kp.image_ids * copies)]
    big = dataclasses.replace(kp.subset(idx), image_ids=ids)
    fields = {f.name: getattr(res, f.name) for f in dataclasses.fields(res)}
    arrays = {k: v[idx] for k, v in fields.items() if isinstance(v, np.ndarray) and v.shape[:1] == (len(kp),)}
    return big, dataclasses.replace(res, **arrays), mats[idx], [sources[i] for i in idx]


def test_json_file_is_the_document_json_dumps_writes(tmp_path: Path) -> None:
    kp, res, mats, sources = _big_case()
    out = tmp_path / "r.json"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    doc = build_result_document(kp, res, mats, sources, params=PARAMS, input_info=INPUT_INFO)
    expected = json.dumps(doc, indent=1, allow_nan=False) + "\n"
    assert CREATED.sub("", out.read_text(encoding="utf-8")) == CREATED.sub("", expected)


class _Frame(dict):  # type: ignore[type-arg]
    """A frame dict that a weak reference can watch (json.dumps writes it as any dict)."""

    __slots__ = ("__weakref__",)


class _Row(list):  # type: ignore[type-arg]
    __slots__ = ("__weakref__",)


def _watched(items: Iterator[Any], kind: type, keep: int = 2) -> Iterator[Any]:
    """`items` as `kind`, checking at each one that the writer let go of those yielded `keep`
    items before: a writer that collects them (a list of frames, one document) fails here."""
    refs: list[weakref.ref[Any]] = []
    for item in items:
        if len(refs) > keep:
            assert refs[-keep - 1]() is None, "the writer holds every item: not streamed"
        obj = kind(item)
        refs.append(weakref.ref(obj))
        yield obj
        del obj
    assert len(refs) > keep + 1


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
def test_writers_never_hold_every_frame(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmt: str) -> None:
    kp, res, mats, sources = _big_case()
    frames, cameras, rows = result_json.iter_frames, outputs._frame_cameras, result_csv.csv_rows
    watched_frames = lambda *a, **k: _watched(frames(*a, **k), _Frame)  # noqa: E731
    monkeypatch.setattr(result_json, "iter_frames", watched_frames)
    monkeypatch.setattr(outputs, "iter_frames", watched_frames)
    monkeypatch.setattr(outputs, "_frame_cameras", lambda *a, **k: _watched(cameras(*a, **k), _Frame))
    monkeypatch.setattr(result_csv, "csv_rows", lambda *a, **k: _watched(rows(*a, **k), _Row))
    write_result(tmp_path / f"r.{fmt}", kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert (tmp_path / f"r.{fmt}").stat().st_size > 0
