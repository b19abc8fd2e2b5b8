"""What every 3D result writer shares: the units/frame options and frame grouping.

Options (FORMATS.md 3.8a), the same for every format:

- `units`: "m" (default; the lifting's internal unit) or "mm" (the H36M literature's unit).
- `frame`: "camera" (default; the absolute camera frame ZeDO optimises in, OpenCV axes x right,
  y down, z forward) or "root" (root-relative: each pose minus its skeleton's root point, e.g.
  the hip midpoint for syrip12, so the root sits at the origin; same axes). The root point's
  camera-frame position is always written as well, so a root-frame file loses nothing.

Files are written atomically (`zedo_cli.files`). The JSON documents (the result, the CSV's
sidecar, the NPZ's metadata) are written piece by piece (`json_pieces`): one frame at a time, never
the whole document as one string, so that memory does not grow with the text of the output.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from ...errors import ConfigError
from ...files import atomic_path

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...camera.model import CameraModel
    from ...lifting.solver import LiftResult

UNITS = ("m", "mm")
FRAMES = ("camera", "root")
AXES = {"x": "right", "y": "down", "z": "forward (away from the camera)"}
_SCALE = {"m": 1.0, "mm": 1000.0}
# Decimal places kept for 3D coordinates: a micrometre in either unit.
_DIGITS = {"m": 6, "mm": 3}
SIGNIFICANT = 6  # every number written keeps at least this many significant digits


def rounded(value: float, decimals: int) -> float:
    """`value` rounded to `decimals` decimals, or to more where those would keep fewer than SIGNIFICANT
    significant digits (0.03875 stays 0.03875 at 3 decimals); NaN and infinities unchanged."""
    magnitude = abs(value)
    if magnitude >= 10.0 ** (SIGNIFICANT - 1 - decimals) or magnitude == 0.0 or not math.isfinite(value):
        return round(value, decimals)
    return round(value, SIGNIFICANT - 1 - math.floor(math.log10(magnitude)))


def rounded_array(values: np.ndarray, decimals: int) -> np.ndarray:
    """`rounded` of every element of `values` (a float array): the same floats a JSON result holds, so that a
    file written from it and one exported from that JSON print alike."""
    values = np.asarray(values, dtype=float)
    out = np.round(values, decimals)
    with np.errstate(invalid="ignore"):
        small = np.flatnonzero((np.abs(values) < 10.0 ** (SIGNIFICANT - 1 - decimals)) & (values != 0))
    flat = out.reshape(-1)
    flat[small] = [rounded(v, decimals) for v in values.reshape(-1)[small].tolist()]
    return out


@dataclass(frozen=True)
class OutputOptions:
    """Units and coordinate frame of the written 3D coordinates."""

    units: str = "m"
    frame: str = "camera"

    def __post_init__(self) -> None:
        if self.units not in UNITS:
            raise ConfigError(f"unknown units {self.units!r}; choose one of: {', '.join(UNITS)}")
        if self.frame not in FRAMES:
            raise ConfigError(f"unknown coordinate frame {self.frame!r}; choose one of: {', '.join(FRAMES)}")

    @property
    def scale(self) -> float:
        """Factor from the lifting's metres to `units`."""
        return _SCALE[self.units]

    @property
    def digits(self) -> int:
        return _DIGITS[self.units]


def output_poses(res: LiftResult, options: OutputOptions) -> np.ndarray:
    """The poses `(N, J, 3)` in `options.frame` and `options.units`; NaN where not lifted."""
    poses = res.poses_camera if options.frame == "camera" else res.poses_root_relative
    return poses * options.scale


def frame_origin(frame: str, root_joints: Sequence[str]) -> str:
    """One line saying where the origin of `frame` is."""
    if frame == "camera":
        return "camera centre"
    root = " + ".join(root_joints) + (" (midpoint)" if len(root_joints) > 1 else "")
    return f"each person's root point ({root}); root_translation gives it in the camera frame"


@dataclass(frozen=True)
class FrameGroups:
    """Instances grouped into frames by image id, frames in order of first appearance."""

    frame_index: np.ndarray  # (N,) int, the frame number of each instance (`number` of its frame)
    person: np.ndarray  # (N,) int, the position of each instance within its frame
    members: list[list[int]]  # per frame, its instance indices in input order
    number: np.ndarray  # (F,) int, each frame's number: the input's where it has one, else its position
    numbered: bool = False  # True: `number` is the input's frame numbers (else positions)


def group_frames(image_ids: Sequence[int | str], frame_numbers: Sequence[int | None] | None = None) -> FrameGroups:
    """Group instances by image id (compared by repr, so 1 and "1" stay apart, as in the JSON).

    A frame's number is the input's frame number (`frame_numbers`, per instance: OpenPose file
    names, MMPose frame_id, JSONL frame, ...) when every instance has one, the instances of one
    image agree and different images differ; so frames the input left empty keep their gap.
    Otherwise it is the frame's position (0, 1, 2, ...).
    """
    index: dict[str, int] = {}
    members: list[list[int]] = []
    person = np.zeros(len(image_ids), dtype=np.int64)
    slot = np.zeros(len(image_ids), dtype=np.int64)
    for i, image_id in enumerate(image_ids):
        key = repr(image_id)
        if key not in index:
            index[key] = len(members)
            members.append([])
        f = index[key]
        slot[i], person[i] = f, len(members[f])
        members[f].append(i)
    number = np.arange(len(members), dtype=np.int64)
    numbered = False
    if frame_numbers is not None and len(frame_numbers) == len(image_ids):
        per_frame = [{frame_numbers[i] for i in m} for m in members]
        numbers = [next(iter(n)) for n in per_frame if len(n) == 1]
        if len(numbers) == len(members) and None not in numbers and len(set(numbers)) == len(numbers):
            number, numbered = np.asarray(numbers, dtype=np.int64), True
    return FrameGroups(number[slot], person, members, number, numbered)


class RawItems(tuple[str, ...]):
    """Several elements of an iterator member of `json_pieces`, each already the one-line JSON of its value."""


def _dumps(value: Any, indent: int | None, level: int) -> str:
    text = json.dumps(value, indent=indent, allow_nan=False)
    return text.replace("\n", "\n" + " " * level) if indent and level else text


def json_pieces(
    members: Iterable[tuple[str, Any]], *, indent: int | None = 1, one_line_items: bool = False
) -> Iterator[str]:
    """The text of ``json.dumps(dict(members), indent=indent, allow_nan=False)``, in pieces.

    A member whose value is an iterator is written as a list, one element at a time: the list
    (e.g. every frame of a result) is never held in memory, nor the whole text. Byte for byte
    what json.dumps writes (`tests/formats/test_writers_streaming.py`): ``indent=1`` puts a
    list's elements at two spaces and their own lines deeper (json.dumps escapes every newline
    inside strings, so indenting after each newline is safe); ``indent=None`` is json.dumps'
    one line with ", " and ": ". `one_line_items`: each element of an iterator member on one line of
    its own (json.dumps without indent: the same JSON, written by json's C encoder, several times faster); with
    it, the iterator may give `RawItems`, elements whose text is made already (a long table's rows, a part at a
    time).
    """
    sep, colon = (",\n" + " " * indent, ": ") if indent else (", ", ": ")
    inner = ",\n" + " " * (2 * indent) if indent else ", "
    opened, closed = ("\n" + " " * indent, "\n") if indent else ("", "")
    yield "{"
    first = True
    for key, value in members:
        yield (opened if first else sep) + json.dumps(key) + colon
        first = False
        if not isinstance(value, Iterator):
            yield _dumps(value, indent, indent or 0)
            continue
        empty = True
        for item in value:
            if isinstance(item, RawItems) and one_line_items:
                if not item:
                    continue
                text = inner.join(item)
            else:
                text = _dumps(item, None if one_line_items else indent, 2 * (indent or 0))
            yield ("[" + (opened + " " * (indent or 0) if indent else "") if empty else inner) + text
            empty = False
        yield "[]" if empty else (opened if indent else "") + "]"
    yield "}" if first else closed + "}"


def write_pieces(pieces: Iterable[str], fh: IO[str]) -> None:
    """Write text `pieces` to `fh`, a few hundred kB at a time (fewer, larger writes)."""
    buffer: list[str] = []
    size = 0
    for piece in pieces:
        buffer.append(piece)
        size += len(piece)
        if size > 1 << 18:
            fh.write("".join(buffer))
            buffer, size = [], 0
    fh.write("".join(buffer))


def write_text(out: str | Path, pieces: Iterable[str], *, overwrite: bool) -> None:
    """Write text `pieces` to `out` atomically (a temporary file beside it, renamed when
    complete; removed on an error), or to stdout when `out` is "-"."""
    if str(out) == "-":
        write_pieces(pieces, sys.stdout)
        sys.stdout.flush()
        return
    with atomic_path(out, overwrite=overwrite) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        write_pieces(pieces, fh)


def camera_block(k: np.ndarray, size: np.ndarray, source: str, lens: CameraModel | None) -> dict[str, Any]:
    """A frame's camera as every result states it: K `(3, 3)`, the image size `(2,)` (None when
    unknown), where K came from, and the lens model with its coefficients in OpenCV's order
    (`CameraModel.from_json` reads the block back)."""
    return {
        "K": [[rounded(float(v), 6) for v in row] for row in k],
        "image_size": size.round(1).tolist() if np.isfinite(size).all() else None,
        "source": source,
        "model": "pinhole" if lens is None else lens.model,
        "dist": [] if lens is None else [float(c) for c in lens.dist],
    }


def lens_at(lenses: Sequence[CameraModel | None] | None, i: int) -> CameraModel | None:
    """Instance `i`'s lens (None: a pinhole camera without distortion, also when none are given)."""
    return None if lenses is None else lenses[i]
