"""Generated annotation-tool files shaped like the tools' own output: LabelMe 5.x point files and
Label Studio JSON / JSON_MIN exports, with known pixels (multiples of 1/4, exact through JSON)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from format_fixtures import BODY25_POSE

from zedo_cli.data.skeleton import SKELETONS

# A 22-point infant annotation in the style of NYCU's LabelMe files (names like `Shoulder_R`,
# `Knee_L`; the real list is not at hand, so this is a plausible set of 22: the 17 COCO points, the
# neck, and the big toes and heels): label -> zedo joint name, placed on a standing person.
NYCU_LABELS = {
    "Nose": "nose", "Eye_L": "left_eye", "Eye_R": "right_eye", "Ear_L": "left_ear", "Ear_R": "right_ear",
    "Shoulder_L": "left_shoulder", "Shoulder_R": "right_shoulder", "Elbow_L": "left_elbow",
    "Elbow_R": "right_elbow", "Wrist_L": "left_wrist", "Wrist_R": "right_wrist", "Hip_L": "left_hip",
    "Hip_R": "right_hip", "Knee_L": "left_knee", "Knee_R": "right_knee", "Ankle_L": "left_ankle",
    "Ankle_R": "right_ankle", "Neck": "neck", "BigToe_L": "left_big_toe", "BigToe_R": "right_big_toe",
    "Heel_L": "left_heel", "Heel_R": "right_heel",
}  # fmt: skip
_BODY25 = SKELETONS["body25"].joints
_PIXELS = {name: BODY25_POSE[_BODY25.index("thorax" if name == "neck" else name)] for name in NYCU_LABELS.values()}


def pose_pixels(offset: float = 0.0, scale: float = 2.0) -> dict[str, tuple[float, float]]:
    """zedo joint name -> (x, y) pixels of the person, moved by `offset` (exact quarters)."""
    return {name: (200.0 + scale * x + offset, 100.0 + scale * y + offset / 2) for name, (x, y) in _PIXELS.items()}


def labelme_shape(label: str, x: float, y: float, group_id: int | None = None) -> dict[str, Any]:
    return {"label": label, "points": [[x, y]], "group_id": group_id, "description": "", "shape_type": "point",
            "flags": {}, "mask": None}  # fmt: skip


def labelme_doc(shapes: list[dict[str, Any]], image: str = "frame.jpg", size: tuple[int, int] = (1280, 720),
                image_data: str | None = None) -> dict[str, Any]:  # fmt: skip
    """A LabelMe 5.x file as the tool writes it."""
    return {"version": "5.5.0", "flags": {}, "shapes": shapes, "imagePath": image, "imageData": image_data,
            "imageHeight": size[1], "imageWidth": size[0]}  # fmt: skip


def nycu_labelme(offset: float = 0.0, image: str = "frame.jpg", group_id: int | None = None) -> dict[str, Any]:
    pixels = pose_pixels(offset)
    shapes = [labelme_shape(label, *pixels[name], group_id) for label, name in NYCU_LABELS.items()]
    # a box around the infant, as annotators often draw one too: not a point, left alone
    shapes.append({"label": "infant", "points": [[150.0, 80.0], [600.0, 560.0]], "group_id": group_id,
                   "description": "", "shape_type": "rectangle", "flags": {}, "mask": None})  # fmt: skip
    return labelme_doc(shapes, image)


def labelme_folder(folder: Path, frames: list[int], offset_per_frame: float = 1.0) -> Path:
    """A clip: one LabelMe file per frame, named `img_<n>.json` (no zero padding, so name order
    and natural order differ)."""
    folder.mkdir(parents=True, exist_ok=True)
    for n in frames:
        write_json(folder / f"img_{n}.json", nycu_labelme(offset_per_frame * n, image=f"img_{n}.jpg"))
    return folder


def ls_result(label: str, x_px: float, y_px: float, size: tuple[int, int] = (1280, 720),
              parent: str | None = None, rid: str = "r") -> dict[str, Any]:  # fmt: skip
    """One Label Studio keypoint result (percentages of the original size)."""
    result: dict[str, Any] = {
        "original_width": size[0], "original_height": size[1], "image_rotation": 0,
        "value": {"x": 100.0 * x_px / size[0], "y": 100.0 * y_px / size[1], "width": 0.5, "keypointlabels": [label]},
        "id": rid, "from_name": "kp", "to_name": "image", "type": "keypointlabels", "origin": "manual",
    }  # fmt: skip
    if parent is not None:
        result["parentID"] = parent
    return result


def ls_task(task_id: int, results: list[dict[str, Any]], image: str = "/data/upload/1/frame.jpg",
            cancelled_first: bool = False) -> dict[str, Any]:  # fmt: skip
    annotation = {"id": 100 + task_id, "completed_by": 1, "result": results, "was_cancelled": False,
                  "ground_truth": False, "created_at": "2025-01-01T00:00:00Z", "lead_time": 12.5,
                  "task": task_id}  # fmt: skip
    annotations = [annotation]
    if cancelled_first:
        annotations.insert(0, {**annotation, "id": 99, "was_cancelled": True, "result": []})
    return {"id": task_id, "annotations": annotations, "file_upload": "frame.jpg", "drafts": [], "predictions": [],
            "data": {"image": image}, "meta": {}, "created_at": "2025-01-01T00:00:00Z", "project": 1}  # fmt: skip


def nycu_label_studio_results(offset: float = 0.0, parent: str | None = None) -> list[dict[str, Any]]:
    pixels = pose_pixels(offset)
    return [ls_result(label, *pixels[name], parent=parent, rid=f"{parent}{k}")
            for k, (label, name) in enumerate(NYCU_LABELS.items())]  # fmt: skip


def json_min_item(task_id: int, offset: float = 0.0) -> dict[str, Any]:
    """One item of Label Studio's JSON_MIN export."""
    points = []
    for result in nycu_label_studio_results(offset):
        points.append({**result["value"], "original_width": result["original_width"],
                       "original_height": result["original_height"]})  # fmt: skip
    return {"image": f"/data/upload/1/f{task_id}.jpg", "id": task_id, "kp": points, "annotator": 1,
            "annotation_id": 100 + task_id, "created_at": "2025-01-01T00:00:00Z", "lead_time": 3.0}  # fmt: skip


def write_json(path: Path, obj: Any) -> Path:
    path.write_text(json.dumps(obj, indent=2))
    return path
