"""LabelMe annotation files, one image each, or a folder of them as one clip, ``labelme``.

LabelMe (5.x) writes one JSON file per image::

    {"version": "5.5.0", "flags": {}, "shapes": [{"label": "Knee_L", "points": [[412.0, 388.5]],
      "group_id": null, "description": "", "shape_type": "point", "flags": {}, "mask": null}, ...],
     "imagePath": "frame_0001.jpg", "imageData": null, "imageHeight": 720, "imageWidth": 1280}

Only ``shape_type: "point"`` shapes are read (one ``[x, y]`` in pixels each; boxes, polygons and
the rest are left alone; a shape without ``shape_type`` is a polygon, as in LabelMe). Labels are
read as joints by name (`data.labels`: ``Knee_L``, ``left_knee``, ``LKnee``, ...). Each
``group_id`` is one person; the points without one are one person together. The image size comes
from ``imageWidth`` / ``imageHeight``, the image id from the file name (its stem), the frame from
the trailing number of that name (0 without one); ``imageData`` is never decoded.

A folder of LabelMe files is one clip, in file-name order (natural order: ``f2`` before ``f10``):
each file's frame is the trailing number of its name where every name has a distinct one, else its
position (`openpose.frame_files`), so the frames count up and ``--temporal`` can read them as one
video. A file of the folder without point shapes is a frame without a person (a note says how
many); a single file without any is refused.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import Skeleton
from ...errors import InputFormatError
from .named_points import Instance, Labels, add_point, build_named, coordinate, shown
from .openpose import frame_files, sequence_files
from .source import load_json
from .validate import as_dict, as_list, error, field, is_list, kind, pixels, trailing_number

FORMAT = "labelme"
TOOL = "LabelMe"


def is_labelme(data: Any) -> bool:
    """A LabelMe document: an object with a ``shapes`` list."""
    return isinstance(data, dict) and is_list(data.get("shapes"))


def _size(doc: dict[str, Any], path: str) -> tuple[float, float]:
    if doc.get("imageWidth") is None or doc.get("imageHeight") is None:
        return math.nan, math.nan
    return pixels(doc["imageWidth"], path, "imageWidth"), pixels(doc["imageHeight"], path, "imageHeight")


def _label(shape: dict[str, Any], path: str, where: str) -> str:
    label = shape.get("label")
    if not isinstance(label, str):
        raise error(path, field(where, "label"), f"expected a string, got {kind(label)}")
    return label


def _point(shape: dict[str, Any], path: str, where: str) -> tuple[float, float]:
    where = field(where, "points")
    points = as_list(shape.get("points"), path, where)
    if len(points) != 1:
        raise error(path, where, f"a point shape holds one [x, y], got {len(points)} points")
    xy = as_list(points[0], path, f"{where}[0]")
    if len(xy) != 2:
        raise error(path, f"{where}[0]", f"expected [x, y], got {len(xy)} values")
    return coordinate(xy[0], path, f"{where}[0][0]"), coordinate(xy[1], path, f"{where}[0][1]")


def _group(shape: dict[str, Any], path: str, where: str) -> int | str | None:
    group = shape.get("group_id")
    if group is None or isinstance(group, str) or (isinstance(group, int) and not isinstance(group, bool)):
        return group
    raise error(path, field(where, "group_id"), f"expected an integer or null, got {kind(group)}")


def _file_instances(data: Any, path: str, frame: int, labels: Labels) -> tuple[list[Instance], int]:
    """The persons of one LabelMe file, and how many point shapes it holds."""
    doc = as_dict(data, path, "")
    if not is_labelme(doc):
        raise error(path, "shapes", f"expected a LabelMe file with a shapes list, got {kind(doc.get('shapes'))}")
    size, image_id = _size(doc, path), Path(path).stem
    image_path = doc.get("imagePath")
    file_name = image_path if isinstance(image_path, str) and image_path else None
    persons: dict[int | str | None, Instance] = {}
    count = 0
    for k, shape in enumerate(doc["shapes"]):
        where = f"shapes[{k}]"
        shape = as_dict(shape, path, where)
        if shape.get("shape_type", "polygon") != "point":
            continue
        count += 1
        label, xy = _label(shape, path, where), _point(shape, path, where)
        group = _group(shape, path, where)
        person = persons.setdefault(group, Instance(image_id, file_name, size, frame))
        add_point(person, labels, label, xy, path, field(where, "label"))
    return [p for p in persons.values() if p.points], count


def _no_points(path: str, doc: Any) -> InputFormatError:
    types = sorted({str(s.get("shape_type", "polygon")) for s in doc["shapes"] if isinstance(s, dict)})
    found = f"its shapes are {', '.join(types)}" if types else "its shapes list is empty"
    return error(path, "shapes", f'no point shapes (shape_type "point"): {found}; nothing to lift')


def read_labelme(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read one parsed LabelMe file (every person in it). ``--skeleton`` does not apply: labels
    name the joints."""
    _no_skeleton_option(skeleton, path)
    labels = Labels()
    stem = Path(path).stem
    instances, count = _file_instances(data, path, trailing_number(stem) or 0, labels)
    if count == 0:
        raise _no_points(path, data)
    return build_named(instances, labels, path, FORMAT, tool=TOOL)


def _no_skeleton_option(skeleton: Skeleton | None, path: str) -> None:
    if skeleton is not None:
        raise error(
            path, "", f"--skeleton {skeleton.name} does not apply to {TOOL} files: their labels name the joints"
        )


def is_labelme_folder(directory: Path) -> bool:
    """Whether `directory` is one clip of LabelMe files (`zedo lift DIR` reads it as one input):
    it holds ``*.json`` files and no JSON Lines, and its first and last files are LabelMe files."""
    files = sequence_files(directory)
    return bool(files) and all(_is_labelme_file(p) for p in (files[0], files[-1]))


def _is_labelme_file(path: Path) -> bool:
    try:
        return is_labelme(load_json(str(path)))
    except InputFormatError:
        return False


def read_labelme_dir(directory: str | Path, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a folder of LabelMe files as one clip (frames in file-name order; `frame_files`)."""
    name = str(directory)
    _no_skeleton_option(skeleton, name)
    labels = Labels()
    instances: list[Instance] = []
    empty: list[str] = []
    files = frame_files(Path(directory))
    for file, frame in files:
        found, count = _file_instances(load_json(str(file)), str(file), frame, labels)
        instances += found
        if count == 0:
            empty.append(file.name)
    if len(empty) == len(files):
        raise error(name, "", 'no point shapes (shape_type "point") in any of its LabelMe files; nothing to lift')
    notes = (
        (
            f"{name}: {len(empty)} of {len(files)} files hold no point shapes (frames without a person): "
            f"{shown(empty, 'files')}",
        )
        if empty
        else ()
    )
    return build_named(instances, labels, name, FORMAT, tool=TOOL, notes=notes)
