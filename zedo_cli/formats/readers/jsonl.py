"""zedo JSON Lines 2D, ``zedo-jsonl``: one frame per line, for streaming from a detector.

Each non-blank line is one JSON object::

    {"frame": 0, "persons": [{"keypoints": [[x, y, c], [x, y], null, ...], "score": 0.93}]}

- ``frame`` (required): the 0-based frame index, an integer.
- ``persons`` (required): the people in the frame, possibly none. Per person ``keypoints`` has
  one point per joint in the zedo 2D syntax (``[x, y]`` = confidence 1, ``[x, y, c]`` with c in
  [0, 1], ``null`` or c == 0 = missing); ``score`` (optional) is the detection score.
- ``image_id`` (optional, default: the frame), ``file_name`` (optional),
  ``image_size`` (optional ``[W, H]`` pixels; a line without one has the size of the latest line
  that gave one: a stream states its video's size once, on its first line).
- ``skeleton`` (optional): a zedo skeleton name, given on the first line (later lines may repeat
  it); without it the joint count decides (17 coco17, 18 coco18, 25 body25, 26 halpe26).

Lines are read in order; blank lines are skipped; a ``.jsonl`` file or stdin (``-``) carries it.
Errors name the line, e.g. ``kp.jsonl: line 3: persons[0].keypoints[4]: expected a number``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import Skeleton
from ...errors import InputFormatError
from .source import blank, parse_document, parse_json
from .validate import (
    NAN_SIZE,
    Row,
    RowBuffer,
    as_dict,
    as_list,
    build,
    counted_skeleton,
    error,
    frame_number,
    image_id,
    is_list,
    joints,
    kind,
    optional_score,
    size_pair,
)
from .zedo2d import skeleton_name, zedo_point

FORMAT = "zedo-jsonl"


def _line_key(obj: dict[str, Any], key: str, path: str, line: str) -> Any:
    if key not in obj:
        raise error(path, f"{line}: {key}", "missing required key")
    return obj[key]


def _frame_rows(
    obj: Any,
    line: str,
    skeleton: Skeleton | None,
    path: str,
    rows: RowBuffer,
    forced: Skeleton | None = None,
    size: tuple[float, float] = NAN_SIZE,
) -> tuple[Skeleton | None, tuple[float, float]]:
    """Append the rows of one line (`line` = "line 3") to `rows`; `skeleton` and `size` are the
    ones fixed by earlier lines, and those returned the ones fixed after this line."""
    obj = as_dict(obj, path, line)
    frame = frame_number(_line_key(obj, "frame", path, line), path, f"{line}: frame")
    key = image_id(obj["image_id"], path, f"{line}: image_id") if obj.get("image_id") is not None else frame
    if obj.get("skeleton") is not None:
        named = skeleton_name(obj["skeleton"], path, f"{line}: skeleton")
        if skeleton is not None and named != skeleton:
            raise error(path, f"{line}: skeleton", f"expected {skeleton.name} like the earlier lines, got {named.name}")
        if forced is not None and named != forced:
            raise error(path, f"{line}: skeleton", f"the file says {named.name}, but --skeleton says {forced.name}")
        skeleton = named
    if obj.get("image_size") is not None:
        size = size_pair(obj["image_size"], path, f"{line}: image_size")
    file_name = obj.get("file_name")
    if file_name is not None and not isinstance(file_name, str):
        raise error(path, f"{line}: file_name", f"expected a string, got {kind(file_name)}")
    for i, person in enumerate(as_list(_line_key(obj, "persons", path, line), path, f"{line}: persons")):
        where = f"{line}: persons[{i}]"
        person = as_dict(person, path, where)
        if "keypoints" not in person:
            raise error(path, f"{where}.keypoints", "missing required key")
        points = as_list(person["keypoints"], path, f"{where}.keypoints")
        skeleton = counted_skeleton(len(points), skeleton, path, f"{where}.keypoints", forced)
        parsed = [zedo_point(p, path, f"{where}.keypoints[{j}]") for j, p in enumerate(points)]
        xy, conf = joints(parsed, skeleton, path, f"{where}.keypoints")
        rows.append(Row(key, xy, conf, file_name, size, optional_score(person, path, where), frame))
    return skeleton, size


def _read_records(records: Iterable[tuple[int, Any]], path: str, forced: Skeleton | None = None) -> Keypoints2D:
    """The rows of `records` ((line number, parsed line) pairs), read one line at a time."""
    skeleton: Skeleton | None = None
    named = False
    rows = RowBuffer()
    count = 0
    size = NAN_SIZE
    for number, obj in records:
        skeleton, size = _frame_rows(obj, f"line {number}", skeleton, path, rows, forced, size)
        named = named or (isinstance(obj, dict) and obj.get("skeleton") is not None)
        count += 1
    if skeleton is None:
        raise error(path, "", "no instances found" if count else "no frames found")
    reason = "skeleton field" if named else "--skeleton" if forced is not None else f"joint count {skeleton.num_joints}"
    return build(rows, skeleton, path, FORMAT, reason=reason, counted=not named and forced is None)


def read_zedo_jsonl(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read already parsed zedo JSONL: one frame object (one line) or a list of them (line k + 1)."""
    records = data if is_list(data) else [data]
    return _read_records(enumerate(records, start=1), path, skeleton)


def _lines(text: str) -> Iterator[tuple[int, str]]:
    """The non-blank lines of `text` with their numbers, split on "\\n" only, one at a time."""
    start, number = 0, 1
    while start <= len(text):
        end = text.find("\n", start)
        end = len(text) if end < 0 else end
        line = text[start:end]
        if not blank(line):
            yield number, line
        start, number = end + 1, number + 1


def read_zedo_jsonl_text(text: str, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read zedo JSONL text. Lines are split on "\\n" only: U+2028 may stand raw inside a JSON string.

    Every line is parsed once to check it (an invalid line is reported before any field of an
    earlier one), then again as it is read: one line's objects are held at a time.
    """
    count = 0
    for number, line in _lines(text):
        parse_json(line, path, f"line {number}")
        count += 1
    if not count:
        raise error(path, "", "file is empty")
    records = ((number, parse_json(line, path, f"line {number}")) for number, line in _lines(text))
    return _read_records(records, path, skeleton)


def looks_like_jsonl(text: str) -> bool:
    """Whether `text` is zedo JSONL rather than one JSON document: its first non-blank line
    parses alone as an object with ``persons`` (a pretty-printed document's first line is "{").
    The line is scanned as a document (`source.parse_document`): a one-line document of 100,000
    instances is checked element by element, never built whole."""
    for _, line in _lines(text):
        try:
            first = parse_document(line, "")
        except InputFormatError:  # not JSON on its own: the caller parses it whole and reports errors
            return False
        return isinstance(first, dict) and "persons" in first
    return False
