"""DeepLabCut's pose tables, ``deeplabcut``: the CSV and ``.h5`` files of ``analyze_videos`` (a
likelihood per point) and the hand-labelled ``CollectedData_<scorer>`` files (x and y only),
single- or multi-animal.

DeepLabCut stores a pandas DataFrame whose columns are a MultiIndex; its CSV writes each level as
a header row, the first cell naming the level::

    scorer,DLC_resnet50_infantsJan1shuffle1_100000,DLC_resnet50_...,...
    individuals,infant,infant,infant,...,single,single,single    (multi-animal only)
    bodyparts,nose,nose,nose,LKnee,LKnee,LKnee,...
    coords,x,y,likelihood,x,y,likelihood,...
    0,312.5,140.2,0.98,...

The first column is the frame number (video analysis) or the image's path (labelled data:
``labeled-data/clip/img001.png``, which newer versions split over three columns, the header
rows then holding two empty cells after the level's name). An empty cell is a missing value: a
point without x or y (or with likelihood 0) is missing, confidence 0, never (0, 0). The likelihood
is the confidence (clipped to [0, 1]); without likelihood columns every placed point is sure.

Body parts are read as zedo's joints by name, through the annotation tools' alias table
(`data.labels`: ``LKnee``, ``left_knee``, ``knee_l``, ...). The record's joints are COCO-17's; every
other body part is kept by name as the input's other keypoints (2D only): those `data.labels`
knows under zedo's name (``neck``, ``head_top``, ``left_toe``, ...), the rest under DeepLabCut's own
name, listed once in the record's notes. Each individual is one person of every frame, in the
header's order (the person index is the individual's place); ``single`` (DeepLabCut's unique
body parts, which belong to no animal) is left out, with a note. A frame where no individual has
a point holds no person; in a frame where one has, every individual is an instance (a missing one
with all its joints missing), so the person index stays the individual's.

Frame numbers are DeepLabCut's frame index, which must count up; image paths are the image ids,
their file names' trailing numbers the frames where they count up. DeepLabCut stores no image
size. Malformed tables are one line naming the file and the row (``kp.csv: row 3: ...``).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...data.keypoints import Keypoints2D, OtherKeypoints
from ...data.labels import joint_name_of_label
from ...data.skeleton import SKELETONS, Skeleton, SkeletonSource
from ...errors import InputFormatError
from .named_points import shown
from .sniff import first_cell, is_hdf5
from .source import read_head
from .validate import MAX_FRAME_DIGITS, error, trailing_number

FORMAT = "deeplabcut"
SKELETON = SKELETONS["coco17"]
H5_KEY = "df_with_missing"  # the key DeepLabCut stores its DataFrame under
LEVELS = ("scorer", "individuals", "bodyparts", "coords")
COORDS = ("x", "y", "likelihood")
UNIQUE = "single"  # the multi-animal "individual" of unique body parts (no animal's)
INSTALL_H5 = "pip install 'zedo[deeplabcut]' (from a checkout: pip install -e '.[deeplabcut]')"
DOCS = 'docs/inputs.md, "DeepLabCut"'
TABLE_SUFFIXES = (".csv", ".h5", ".hdf5")


@dataclass
class Table:
    """A DeepLabCut table as stored: the column labels of each level, the row index, the values."""

    individuals: list[str] | None  # (C,) None for a single-animal table
    bodyparts: list[str]  # (C,)
    coords: list[str]  # (C,)
    header: dict[str, str]  # level -> where it is, for messages ("row 3")
    index: list[tuple[str, ...]]  # (F,) each row's index cells
    values: np.ndarray  # (F, C) float64, NaN = empty cell
    rows: list[str]  # (F,) where each row is, for messages ("row 7")


def looks_like_deeplabcut(text: str) -> bool:
    """A DeepLabCut CSV: its first cell is ``scorer``."""
    return first_cell(text) == "scorer"


# --- CSV ----------------------------------------------------------------------------------------


def _csv_rows(text: str, path: str) -> list[list[str]]:
    """The CSV's rows (CRLF or LF line ends, a byte-order mark dropped)."""
    reader = csv.reader(io.StringIO(text.lstrip("\ufeff"), newline=""))
    try:
        return list(reader)
    except csv.Error as exc:
        raise error(path, f"row {reader.line_num}", f"not a readable CSV row ({exc})") from None


def _header(rows: list[list[str]], path: str) -> tuple[dict[str, list[str]], int]:
    """The header rows by level (each row's cells after the index columns) and the number of index
    columns (1, or 3 for newer labelled data: the empty cells after ``coords``)."""
    found: dict[str, list[str]] = {}
    for want in LEVELS:
        n = len(found)
        got = rows[n][0].strip() if n < len(rows) and rows[n] else ""
        if want == "individuals" and got != want:
            continue
        if got != want:
            before = f" after the {list(found)[-1]} row" if found else ""
            said = f"got {got[:40]!r}" if n < len(rows) else "the file ends"
            raise error(path, f"row {n + 1}", f"expected DeepLabCut's {want} row{before} "
                        f"({want}, {_example(want)}), {said}")  # fmt: skip
        found[want] = rows[n]
    coords = found["coords"]
    width = len(coords)
    k = 1
    while k < width and not coords[k].strip():
        k += 1
    if k == width:
        raise error(path, f"row {len(found)}", "the coords row names no coordinate (x, y, likelihood)")
    for n, (level, cells) in enumerate(found.items(), 1):
        if len(cells) != width:
            raise error(path, f"row {n}", f"{len(cells)} cells, the coords row has {width}: ragged {level} row")
    return {level: [c.strip() for c in cells[k:]] for level, cells in found.items()}, k


def _example(level: str) -> str:
    return {"scorer": "<network or labeller>, ...", "individuals": "infant, infant, ...",
            "bodyparts": "nose, nose, nose, ...", "coords": "x, y, likelihood, ..."}[level]  # fmt: skip


def _numbers(cells: list[str], path: str, where: str, labels: tuple[list[str], list[str]]) -> list[float]:
    """A row's values: empty cells are NaN; anything else must be a number."""
    try:
        return [float(c) if c.strip() else math.nan for c in cells]
    except ValueError:
        pass
    for c, cell in enumerate(cells):
        try:
            float(cell) if cell.strip() else None
        except ValueError:
            part, coord = labels[0][c], labels[1][c]
            raise error(path, where, f"{part} {coord}: not a number: {cell[:40]!r}") from None
    raise AssertionError("unreachable: a cell failed and none fails again")


def read_table_csv(text: str, path: str) -> Table:
    """A DeepLabCut CSV's table; every data row as wide as the coords row, its values numbers."""
    rows = _csv_rows(text, path)
    levels, k = _header(rows, path)
    width = k + len(levels["coords"])
    start = len(levels)
    index: list[tuple[str, ...]] = []
    values: list[list[float]] = []
    wheres: list[str] = []
    labels = (levels["bodyparts"], levels["coords"])
    for r, cells in enumerate(rows[start:], start + 1):
        if not any(c.strip() for c in cells):  # a blank line (an Excel sheet's trailing rows)
            continue
        where = f"row {r}"
        if len(cells) != width:
            raise error(path, where, f"{len(cells)} cells, the coords row has {width}: ragged row")
        index.append(tuple(c.strip() for c in cells[:k]))
        values.append(_numbers(cells[k:], path, where, labels))
        wheres.append(where)
    header = {level: f"row {n}" for n, level in enumerate(levels, 1)}
    array = np.asarray(values, dtype=np.float64).reshape(len(values), width - k)  # (F, C)
    return Table(levels.get("individuals"), levels["bodyparts"], levels["coords"], header, index, array, wheres)


# --- H5 -----------------------------------------------------------------------------------------


def _pandas(path: str) -> Any:
    try:
        import pandas
        import tables  # noqa: F401 (pandas reads HDF5 through PyTables)
    except ImportError:
        raise error(path, "", f"reading DeepLabCut's .h5 files needs pandas and PyTables: {INSTALL_H5}; "
                    "or lift the CSV DeepLabCut writes beside it (save_as_csv=True)") from None  # fmt: skip
    return pandas


def _refuse_pickles(path: str) -> str:
    """The key of the DataFrame to read (``df_with_missing``, or the file's only one); a file holding
    pickled Python objects as data is refused (loading them could run code)."""
    import tables

    try:
        with tables.open_file(path, mode="r") as h5:
            for leaf in h5.walk_nodes("/", classname="Leaf"):
                atom = getattr(leaf, "atom", None)
                if atom is not None and atom.kind == "object":
                    raise error(path, leaf._v_pathname, "holds pickled Python objects, which zedo does not load")
            keys = [group._v_name for group in h5.root._f_iter_nodes(classname="Group")]
    except InputFormatError:
        raise
    except (OSError, tables.HDF5ExtError, ValueError) as exc:
        raise error(
            path, "", f"not a readable HDF5 file ({str(exc).splitlines()[0][:120] if str(exc) else exc})"
        ) from None
    if H5_KEY in keys:
        return H5_KEY
    if len(keys) == 1:
        return keys[0]
    raise error(path, "", f"no DeepLabCut table: expected the key {H5_KEY!r}, found {', '.join(keys) or 'none'}")


def _level_names(columns: Any, path: str, key: str) -> list[str]:
    names = [str(n) if n is not None else "" for n in getattr(columns, "names", [])]
    if getattr(columns, "nlevels", 1) not in (3, 4):
        raise error(path, key, f"columns: expected DeepLabCut's 3 or 4 column levels ({', '.join(LEVELS)}), "
                    f"got {getattr(columns, 'nlevels', 1)}")  # fmt: skip
    expected = [lv for lv in LEVELS if columns.nlevels == 4 or lv != "individuals"]
    if any(names) and names != expected:
        raise error(path, key, f"columns: expected the levels {', '.join(expected)}, got {', '.join(names)}")
    return expected


def read_table_h5(path: str) -> Table:
    """A DeepLabCut ``.h5`` file's table (pandas and PyTables needed: `INSTALL_H5` otherwise)."""
    pandas = _pandas(path)
    key = _refuse_pickles(path)
    try:
        frame = pandas.read_hdf(path, key)
    except Exception as exc:  # noqa: BLE001 (pandas and PyTables raise many kinds for a damaged file)
        raise error(path, key, f"not a readable pandas table ({type(exc).__name__})") from None
    if not isinstance(frame, pandas.DataFrame):
        raise error(path, key, f"expected a pandas DataFrame, got {type(frame).__name__}")
    levels = _level_names(frame.columns, path, key)
    labels = {lv: [str(v).strip() for v in frame.columns.get_level_values(n)] for n, lv in enumerate(levels)}
    try:
        values = frame.to_numpy(dtype=np.float64)
    except (TypeError, ValueError):
        raise error(path, key, "values: expected numbers (x, y, likelihood)") from None
    index = [tuple(str(v) for v in (i if isinstance(i, tuple) else (i,))) for i in frame.index]
    header = {lv: f"{key}: columns level {lv}" for lv in levels}
    rows = [f"{key}: row {n}" for n in range(len(index))]
    return Table(labels.get("individuals"), labels["bodyparts"], labels["coords"], header, index, values, rows)


# --- the record ---------------------------------------------------------------------------------


@dataclass
class Part:
    """One body part of one individual: its columns by coordinate."""

    individual: str | None  # None in a single-animal table
    name: str  # DeepLabCut's body part name
    columns: dict[str, int]  # "x", "y" and maybe "likelihood" -> the table's column


def _parts(table: Table, path: str) -> list[Part]:
    """The table's body parts, each with an x and a y column and at most one likelihood."""
    parts: dict[tuple[str | None, str], Part] = {}
    for c, (name, coord) in enumerate(zip(table.bodyparts, table.coords, strict=True)):
        individual = table.individuals[c] if table.individuals is not None else None
        if not name:
            raise error(path, table.header["bodyparts"], f"column {c + 1} of the coordinates has no body part name")
        if individual == "":
            raise error(path, table.header["individuals"], f"{name}: no individual named")
        if coord not in COORDS:
            raise error(path, table.header["coords"], f"{name}: coordinate {coord[:40]!r}: expected x, y or likelihood")
        part = parts.setdefault((individual, name), Part(individual, name, {}))
        if coord in part.columns:
            raise error(path, table.header["coords"], f"{_who(part)}: a second {coord} column")
        part.columns[coord] = c
    for part in parts.values():
        lacking = [coord for coord in ("x", "y") if coord not in part.columns]
        if lacking:
            raise error(path, table.header["coords"], f"{_who(part)}: no {' or '.join(lacking)} column")
    return list(parts.values())


def _who(part: Part) -> str:
    return part.name if part.individual is None else f"{part.individual}'s {part.name}"


def _names(parts: list[Part], path: str, where: str) -> tuple[dict[str, str], list[str]]:
    """DeepLabCut's body part -> the record's keypoint name (zedo's, by `data.labels`, else its
    own), and the body parts zedo does not know. Two body parts of one joint are refused."""
    names: dict[str, str] = {}
    part_of: dict[str, str] = {}
    unknown: list[str] = []
    for part in dict.fromkeys(p.name for p in parts):
        name = joint_name_of_label(part)
        if name is None:
            unknown.append(part)
            name = part
        if name in part_of:
            raise error(path, where, f"body parts {part_of[name]!r} and {part!r} both name {name}: one per joint")
        part_of[name] = part
        names[part] = name
    if not any(name in SKELETON.joints for name in names.values()):
        raise error(path, where, f"no body part names a body joint ({shown(list(names), 'body parts')}); {DOCS} "
                    "says which names zedo reads")  # fmt: skip
    return names, unknown


def _check_finite(table: Table, path: str) -> None:
    """Infinite values are no coordinates (an empty cell is a missing one)."""
    bad = np.argwhere(np.isinf(table.values))
    if len(bad):
        f, c = (int(v) for v in bad[0])
        raise error(path, table.rows[f], f"{table.bodyparts[c]} {table.coords[c]}: not a finite number")


def _points(
    table: Table, parts: list[Part], column: dict[str, int], k: int, tracked: list[str | None]
) -> tuple[np.ndarray, np.ndarray]:
    """(F, P, K, 2) pixels, NaN = missing, and (F, P, K) confidences of the tracked individuals
    (`column`: each body part's place among the K keypoints): the likelihood clipped to [0, 1], 1
    without one; a point without x or y, or of likelihood 0 (or empty), is missing."""
    f, p = len(table.index), len(tracked)
    xy = np.full((f, p, k, 2), np.nan)
    conf = np.zeros((f, p, k))
    for part in parts:
        x, y = table.values[:, part.columns["x"]], table.values[:, part.columns["y"]]  # (F,)
        c = table.values[:, part.columns["likelihood"]] if "likelihood" in part.columns else np.ones(f)
        present = np.isfinite(x) & np.isfinite(y) & (np.nan_to_num(c) > 0)
        i, j = tracked.index(part.individual), column[part.name]
        conf[:, i, j] = np.where(present, np.clip(np.nan_to_num(c), 0.0, 1.0), 0.0)
        xy[:, i, j] = np.where(present[:, None], np.stack([x, y], axis=-1), np.nan)
    return xy, conf


def _frame_rows(table: Table, path: str) -> list[int]:
    """The frame numbers of a video's rows: whole numbers that count up."""
    frames: list[int] = []
    for cells, where in zip(table.index, table.rows, strict=True):
        cell = cells[0]
        if len(cells) != 1 or not (cell.isascii() and cell.isdigit()) or len(cell.lstrip("0")) > MAX_FRAME_DIGITS:
            shown_cell = "/".join(cells)[:60]
            raise error(path, where, f"index {shown_cell!r}: expected a frame number (0, 1, 2, ...), "
                        f"as in {table.rows[0]}")  # fmt: skip
        frame = int(cell)
        if frames and frame <= frames[-1]:
            what = "repeats" if frame == frames[-1] else "does not count up"
            raise error(path, where, f"frame {frame} {what} (the row before is frame {frames[-1]}): "
                        "the frame index must count up")  # fmt: skip
        frames.append(frame)
    return frames


def _image_rows(table: Table, path: str) -> tuple[list[str], list[str], list[int | None]]:
    """Labelled images' rows: each image's path (its id), file name and frame (the file name's
    trailing number where every row has one and they count up, else None)."""
    ids: list[str] = []
    seen: dict[str, str] = {}
    for cells, where in zip(table.index, table.rows, strict=True):
        image = "/".join(c for c in cells if c)
        if not image:
            raise error(path, where, "empty index: expected a frame number or an image's path")
        if image in seen:
            raise error(path, where, f"image {image[:60]!r} repeats ({seen[image]})")
        seen[image] = where
        ids.append(image)
    files = [image.replace("\\", "/").rsplit("/", 1)[-1] for image in ids]
    numbers = [trailing_number(name.rsplit(".", 1)[0]) for name in files]
    known = [n for n in numbers if n is not None]
    counts_up = len(known) == len(numbers) and all(b > a for a, b in zip(known, known[1:], strict=False))
    return ids, files, numbers if counts_up else [None] * len(ids)


def _row_ids(table: Table, path: str) -> tuple[list[int | str], list[str | None], list[int | None]]:
    """Each row's image id, file name and frame: a video's frame numbers, or labelled images."""
    first = table.index[0] if table.index else ("",)
    if len(first) == 1 and first[0].isascii() and first[0].isdigit():
        frames = _frame_rows(table, path)
        return list(frames), [None] * len(frames), list(frames)
    ids, files, numbers = _image_rows(table, path)
    return list(ids), list(files), numbers


def _tracked(table: Table, path: str) -> list[str | None]:
    """The individuals lifted, in the header's order (None: the one of a single-animal table)."""
    if table.individuals is None:
        return [None]
    tracked = [i for i in dict.fromkeys(table.individuals) if i != UNIQUE]
    if not tracked:
        raise error(path, table.header["individuals"], f"no individual but {UNIQUE!r} (unique body parts, no "
                    "animal's): nothing to lift")  # fmt: skip
    return tracked


def _notes(table: Table, path: str, tracked: list[str | None], unknown: list[str], empty: int) -> tuple[str, ...]:
    notes = []
    unique = [] if table.individuals is None else [p for p, i in zip(table.bodyparts, table.individuals,
                                                                          strict=True) if i == UNIQUE]  # fmt: skip
    if unique:
        notes.append(f"{path}: DeepLabCut's unique body parts (individual {UNIQUE!r}: "
                     f"{shown(list(dict.fromkeys(unique)), 'body parts')}) belong to no infant, left out")  # fmt: skip
    if len(tracked) > 1:
        order = ", ".join(f"{name!r} {p}" for p, name in enumerate(tracked))
        notes.append(f"{path}: individuals read as the persons of each frame: {order}")
    if unknown:
        notes.append(f"{path}: body parts that name no zedo joint, kept by name as other keypoints (2D only, "
                     f"not lifted): {shown(unknown, 'body parts')} ({DOCS})")  # fmt: skip
    if empty:
        notes.append(f"{path}: {empty} of {len(table.index)} rows hold no point (frames without a person)")
    return tuple(notes)


def build_record(table: Table, path: str) -> Keypoints2D:
    """The table as a COCO-17 `Keypoints2D`: each tracked individual one person of every frame that
    holds a point, the body parts outside COCO-17 in `other` by name, what was left out in notes."""
    if not table.index:
        raise error(path, "", "no rows after the header: nothing to lift")
    _check_finite(table, path)
    tracked = _tracked(table, path)
    parts = [p for p in _parts(table, path) if p.individual in tracked]
    names, unknown = _names(parts, path, table.header["bodyparts"])
    others = [name for name in names.values() if name not in SKELETON.joints]
    slot = {name: k for k, name in enumerate((*SKELETON.joints, *others))}
    xy, conf = _points(
        table, parts, {part: slot[name] for part, name in names.items()}, len(slot), tracked
    )  # (F, P, K, .)
    kept = (conf > 0).any(axis=(1, 2))  # (F,) the rows that hold a point
    if not kept.any():
        raise error(path, "", "no row holds a point (every x and y is empty, or of likelihood 0)")
    ids, files, frames = _row_ids(table, path)
    rows = np.flatnonzero(kept)
    p, j = len(tracked), SKELETON.num_joints
    n = len(rows) * p
    xy, conf = xy[rows].reshape(n, -1, 2), conf[rows].reshape(n, -1)  # (N, K, 2), (N, K)
    each = [int(r) for r in rows for _ in range(p)]  # the row of each instance
    notes = _notes(table, path, tracked, unknown, int((~kept).sum()))
    return Keypoints2D(
        xy=xy[:, :j],
        confidence=conf[:, :j],
        skeleton=SKELETON,
        image_ids=[ids[r] for r in each],
        file_names=[files[r] for r in each],
        image_sizes=np.full((n, 2), np.nan),
        scores=[None] * n,
        path=path,
        format=FORMAT,
        frame_indices=None if all(f is None for f in frames) else [frames[r] for r in each],
        source=SkeletonSource(SKELETON.name, "DeepLabCut body parts, by name"),
        other=OtherKeypoints(tuple(others), xy[:, j:], conf[:, j:]) if others else None,
        notes=notes,
    )


def _no_skeleton_option(skeleton: Skeleton | None, path: str) -> None:
    if skeleton is not None:
        raise error(path, "", f"--skeleton {skeleton.name} does not apply to DeepLabCut files: their body "
                    "parts name the joints")  # fmt: skip


def read_deeplabcut_text(text: str, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read the text of a DeepLabCut CSV (a byte-order mark and CRLF line ends as Excel saves it
    are fine). ``--skeleton`` does not apply: the body parts name the joints."""
    _no_skeleton_option(skeleton, path)
    return build_record(read_table_csv(text, path), path)


def read_deeplabcut_h5(path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a DeepLabCut ``.h5`` file (pandas and PyTables needed: the ``deeplabcut`` extra)."""
    _no_skeleton_option(skeleton, path)
    return build_record(read_table_h5(path), path)


def is_deeplabcut_file(path: Path) -> bool:
    """A ``.csv`` whose first cell is ``scorer``, or an ``.h5`` HDF5 file: a DeepLabCut table that a
    folder of inputs stands for (a file that cannot be read is not one)."""
    if path.suffix.lower() not in TABLE_SUFFIXES or not path.is_file():
        return False
    try:
        head = read_head(str(path))
    except InputFormatError:
        return False
    if path.suffix.lower() == ".csv":
        return looks_like_deeplabcut(head.decode("utf-8", errors="replace"))
    return is_hdf5(head)
