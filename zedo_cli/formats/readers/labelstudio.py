"""Label Studio keypoint exports (the JSON and JSON_MIN exports), ``label-studio``.

The JSON export is a list of tasks (one image each; a single task object is read too)::

    [{"id": 7, "data": {"image": "/data/upload/1/frame_0001.jpg"},
      "annotations": [{"id": 21, "was_cancelled": false, "result": [
          {"id": "a1", "type": "keypointlabels", "from_name": "kp", "to_name": "image", "origin": "manual",
           "original_width": 1280, "original_height": 720, "image_rotation": 0,
           "value": {"x": 32.2, "y": 53.9, "width": 0.5, "keypointlabels": ["Knee_L"]}}, ...]}]}]

(``completions`` instead of ``annotations`` in exports of Label Studio before 1.0). Only
``keypointlabels`` results are read; ``x`` and ``y`` are percentages of the original image's width
and height (pixel = x / 100 * original_width), refused outside 0-100, and a rotated image
(``image_rotation`` other than 0) is refused. The first annotation of a task that was not
cancelled is read (a note says when a task has more; predictions are never read). The keypoints of
one ``parentID`` (the box they were drawn in) are one person; those without one are one person
together. The image id is the task's ``id``, the file name the last part of ``data.image``.

The JSON_MIN export is a list of one object per task, the results of each control under its
``from_name`` (``{"image": ..., "id": 7, "kp": [{"x": ..., "y": ..., "keypointlabels": [...],
"original_width": ..., "original_height": ...}], ...}``): read the same way, one person per task.
"""

from __future__ import annotations

from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import Skeleton
from .named_points import Instance, Labels, add_point, build_named, coordinate
from .validate import ImageId, as_dict, as_list, error, field, image_id, is_list, pixels

FORMAT = "label-studio"
TOOL = "Label Studio"
_KEYPOINTS = "keypointlabels"


def _is_task(entry: Any) -> bool:
    return isinstance(entry, dict) and "data" in entry and ("annotations" in entry or "completions" in entry)


def _min_keys(entry: Any) -> list[str]:
    """The keys of a JSON_MIN item that hold keypoint results."""
    if not isinstance(entry, dict):
        return []
    return [
        key
        for key, value in entry.items()
        if is_list(value) and value and isinstance(value[0], dict) and _KEYPOINTS in value[0]
    ]


def is_label_studio(data: Any) -> bool:
    """A Label Studio JSON export (a task, or a list of tasks) or a JSON_MIN export with keypoints."""
    if _is_task(data):
        return True
    return is_list(data) and bool(data) and (_is_task(data[0]) or bool(_min_keys(data[0])))


def _percent(value: dict[str, Any], key: str, size: float, path: str, where: str) -> float:
    where = field(where, key)
    p = coordinate(value.get(key), path, where)
    if not 0.0 <= p <= 100.0:
        raise error(
            path,
            where,
            f"expected a percentage of the image's {'width' if key == 'x' else 'height'} in [0, 100], got {p:g}",
        )
    return p / 100.0 * size


def _image_size(result: dict[str, Any], path: str, where: str) -> tuple[float, float]:
    for key in ("original_width", "original_height"):
        if result.get(key) is None:
            raise error(path, field(where, key), "missing: the percentages cannot be turned into pixels")
    rotation = result.get("image_rotation", 0) or 0
    if rotation != 0:
        raise error(
            path,
            field(where, "image_rotation"),
            f"the image was rotated by {rotation} degrees in Label "
            "Studio; zedo reads keypoints of unrotated images only",
        )
    return (
        pixels(result["original_width"], path, field(where, "original_width")),
        pixels(result["original_height"], path, field(where, "original_height")),
    )


def _label(value: dict[str, Any], path: str, where: str) -> str:
    where = field(where, _KEYPOINTS)
    names = as_list(value.get(_KEYPOINTS), path, where)
    if len(names) != 1 or not isinstance(names[0], str):
        raise error(path, where, f"expected one label, got {len(names)} values")
    return names[0]


def _file_name(data: Any) -> str | None:
    image = data.get("image") if isinstance(data, dict) else None
    if not isinstance(image, str) or not image:
        return None
    return image.split("?", 1)[0].rstrip("/").rsplit("/", 1)[-1] or None


def _task_id(task: dict[str, Any], k: int, path: str, where: str) -> ImageId:
    return image_id(task["id"], path, field(where, "id")) if task.get("id") is not None else k


def _read_results(
    results: Any, key: ImageId, file_name: str | None, labels: Labels, path: str, where: str, parents: bool
) -> list[Instance]:
    """The persons of one task's results: one per ``parentID`` (with `parents`), else one."""
    persons: dict[Any, Instance] = {}
    size: tuple[float, float] | None = None
    for r, result in enumerate(as_list(results, path, where)):
        at = f"{where}[{r}]"
        result = as_dict(result, path, at)
        if parents:  # the JSON export: {"type", "value": {...}, "original_width", ...}
            if result.get("type", _KEYPOINTS if _KEYPOINTS in (result.get("value") or {}) else None) != _KEYPOINTS:
                continue  # a box, a polygon, a choice: not a keypoint
            vat = field(at, "value")
            value = as_dict(result.get("value"), path, vat)
        else:  # JSON_MIN: the value's fields and the original size in one object
            if _KEYPOINTS not in result:
                continue
            vat, value = at, result
        this = _image_size(result, path, at)
        if size is not None and this != size:
            raise error(
                path,
                at,
                f"original size {this[0]:g} x {this[1]:g} differs from {size[0]:g} x {size[1]:g} "
                "of the task's other keypoints",
            )
        size = this
        xy = (_percent(value, "x", size[0], path, vat), _percent(value, "y", size[1], path, vat))
        parent = result.get("parentID")
        person = persons.setdefault(parent if isinstance(parent, str) else None, Instance(key, file_name, size, None))
        add_point(person, labels, _label(value, path, vat), xy, path, field(vat, _KEYPOINTS))
    return [p for p in persons.values() if p.points]


def _read_task(task: Any, k: int, labels: Labels, path: str, where: str) -> tuple[list[Instance], int]:
    """The persons of one task of the JSON export, and how many annotations it has."""
    task = as_dict(task, path, where)
    key = "annotations" if "annotations" in task else "completions"
    annotations = [
        (a, ann)
        for a, ann in enumerate(as_list(task.get(key), path, field(where, key)))
        if not (isinstance(ann, dict) and ann.get("was_cancelled"))
    ]
    if not annotations:
        return [], 0
    a, annotation = annotations[0]
    at = f"{field(where, key)}[{a}]"
    annotation = as_dict(annotation, path, at)
    results = annotation.get("result", [])
    return _read_results(
        results,
        _task_id(task, k, path, where),
        _file_name(task.get("data")),
        labels,
        path,
        field(at, "result"),
        parents=True,
    ), len(annotations)


def read_label_studio(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed Label Studio export (JSON: tasks; or JSON_MIN). ``--skeleton`` does not apply."""
    if skeleton is not None:
        raise error(path, "", f"--skeleton {skeleton.name} does not apply to {TOOL} exports: labels name the joints")
    labels = Labels()
    instances: list[Instance] = []
    several = 0
    if isinstance(data, dict):
        found, count = _read_task(data, 0, labels, path, "")
        instances, several = found, int(count > 1)
    else:
        tasks = as_list(data, path, "")
        json_min = not _is_task(tasks[0]) if tasks else False
        for k, task in enumerate(tasks):
            where = f"[{k}]"
            if json_min:
                task = as_dict(task, path, where)
                key, name = _task_id(task, k, path, where), _file_name(task)
                for control in _min_keys(task):
                    instances += _read_results(
                        task[control], key, name, labels, path, field(where, control), parents=False
                    )
                continue
            found, count = _read_task(task, k, labels, path, where)
            instances += found
            several += count > 1
    notes = (f"{path}: {several} tasks have several annotations; the first of each is read",) if several else ()
    return build_named(instances, labels, path, FORMAT, tool=TOOL, notes=notes)
