"""A JSON document whose large arrays are decoded one element at a time.

``json.loads`` of a 50 MB detector output builds about ten times its size in Python objects,
all alive while the reader walks them. `scan_document` instead checks the whole text once with
the json module's own decoder and returns the document with every array of its top level (a
top-level list, or the lists that are values of a top-level object: COCO ``annotations`` and
``images``, MMPose ``instance_info``, zedo 2D ``instances``, ...) as a `JsonArray`: a read-only
sequence that decodes an element from the text each time it is read. A reader that walks it
holds one element's objects at a time; the text itself (one byte per character for ASCII JSON,
within the input limit of `source.MAX_INPUT_BYTES`) is the rest.

Why not a streaming parser such as ijson: every value here is decoded by the same decoder as
the whole-document parse, `strict_json.DECODER` (numbers, NaN and Infinity, the refusal of a
repeated key, the digit limit of integers alike), and the scan is a few lines on top of it; an
invalid document is left to the whole-document parse (`source.parse_json`), so its error message
and position are exactly those of that parse. The cost is decoding each element twice (once to
check, once to read): about a second for 50 MB, small beside the readers' checks.
"""

from __future__ import annotations

import re
from array import array
from collections.abc import Iterator, Sequence
from json.decoder import scanstring
from typing import Any, overload

from ...strict_json import DECODER as _DECODER
from ...strict_json import DuplicateKeyError

_WHITESPACE = re.compile(r"[ \t\n\r]*")  # JSON's whitespace, as the json module skips it


class InvalidDocument(Exception):
    """The text is not valid JSON (the caller lets json.loads say where and why)."""


class JsonArray(Sequence[Any]):
    """A JSON array in a document's text; its elements are decoded when read, each time.

    Equal in content to the list json.loads makes, without holding it: `len`, indexing (also
    negative and slices, which give lists) and iteration in order.
    """

    __slots__ = ("_starts", "_text")

    def __init__(self, text: str, starts: array[int]) -> None:
        self._text = text
        self._starts = starts  # the offset of each element in the text

    def __len__(self) -> int:
        return len(self._starts)

    @overload
    def __getitem__(self, index: int) -> Any: ...
    @overload
    def __getitem__(self, index: slice) -> list[Any]: ...
    def __getitem__(self, index: int | slice) -> Any:
        if isinstance(index, slice):
            return [_DECODER.raw_decode(self._text, start)[0] for start in self._starts[index]]
        return _DECODER.raw_decode(self._text, self._starts[index])[0]

    def __iter__(self) -> Iterator[Any]:
        for start in self._starts:
            yield _DECODER.raw_decode(self._text, start)[0]

    def __repr__(self) -> str:
        return f"JsonArray({len(self)} elements)"


def _skip(text: str, pos: int) -> int:
    match = _WHITESPACE.match(text, pos)
    return match.end() if match else pos


def _elements(text: str, pos: int, end: list[int]) -> Iterator[tuple[int, Any]]:
    """The offset and value of each element of the array at text[pos] == "[", decoded in order; `end` gets the
    offset after the array once the last is read."""
    pos = _skip(text, pos + 1)
    closed = text.startswith("]", pos)
    while not closed:
        start = pos
        value, pos = _DECODER.raw_decode(text, pos)
        yield start, value
        pos, closed = _separator(text, pos, "]")
    end.append(pos + 1)


def _separator(text: str, pos: int, close: str) -> tuple[int, bool]:
    """After an item ending at `pos`: the next item's offset and False, or the offset of `close` and True."""
    pos = _skip(text, pos)
    if text.startswith(close, pos):
        return pos, True
    if not text.startswith(",", pos):
        raise InvalidDocument
    return _skip(text, pos + 1), False


def _array(text: str, pos: int) -> tuple[JsonArray, int]:
    """The array starting at text[pos] == "[", every element decoded once to check it."""
    end: list[int] = []
    starts = array("q", (start for start, _ in _elements(text, pos, end)))
    return JsonArray(text, starts), end[0]


def _value(text: str, pos: int) -> tuple[Any, int]:
    if text.startswith("[", pos):
        return _array(text, pos)
    return _DECODER.raw_decode(text, pos)


def _members(text: str, pos: int, end: list[int], streamed: str | None = None) -> Iterator[tuple[str, Any]]:
    """The members of the object starting at text[pos] == "{", in order; `end` gets the offset after it. Without
    `streamed`, its array values as `JsonArray`s; with it, every value decoded once as it comes, and the value of
    the key `streamed`, where an array, an iterator of its elements to be used up before the next member."""
    seen: set[str] = set()
    pos = _skip(text, pos + 1)
    closed = text.startswith("}", pos)
    while not closed:
        if not text.startswith('"', pos):
            raise InvalidDocument
        key, pos = scanstring(text, pos + 1)
        pos = _skip(text, pos)
        if not text.startswith(":", pos):
            raise InvalidDocument
        if key in seen:
            raise DuplicateKeyError(key)
        seen.add(key)
        pos = _skip(text, pos + 1)
        if streamed is not None and key == streamed and text.startswith("[", pos):
            after: list[int] = []
            yield key, (value for _, value in _elements(text, pos, after))
            if not after:
                raise InvalidDocument  # the elements were not read to the end
            pos = after[0]
        else:
            value, pos = _value(text, pos) if streamed is None else _DECODER.raw_decode(text, pos)
            yield key, value
        pos, closed = _separator(text, pos, "}")
    end.append(pos + 1)


def _object(text: str, pos: int) -> tuple[dict[str, Any], int]:
    """The object starting at text[pos] == "{", its array values as `JsonArray`s."""
    end: list[int] = []
    obj = dict(_members(text, pos, end))
    return obj, end[0]


def stream_members(text: str, streamed: str) -> Iterator[tuple[str, Any]]:
    """The members of the JSON object that is the whole of `text`, in one pass: each value decoded once as it
    comes, the value of the key `streamed` (where an array) an iterator of its elements, decoded as they are
    read, to be used up before the next member (a result's frames, one at a time). Raises what `scan_document`
    raises where the text is not one such object (the caller lets json.loads say where and why)."""
    pos = _skip(text, 0)
    if not text.startswith("{", pos):
        raise InvalidDocument
    end: list[int] = []
    yield from _members(text, pos, end, streamed)
    if _skip(text, end[0]) != len(text):
        raise InvalidDocument


def scan_document(text: str) -> Any:
    """The JSON document `text` with its top-level arrays as `JsonArray`s (module docstring).

    Raises `InvalidDocument`, `strict_json.DuplicateKeyError` (an object naming a key twice), or
    the json module's `JSONDecodeError`, `ValueError` or `RecursionError`, for text that is not
    one valid JSON value.
    """
    pos = _skip(text, 0)
    value, pos = _object(text, pos) if text.startswith("{", pos) else _value(text, pos)
    if _skip(text, pos) != len(text):
        raise InvalidDocument
    return value
