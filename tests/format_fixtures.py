"""Generated 2D detector outputs in every input layout, with known pixel coordinates.

Coordinates are multiples of 1/4, so they survive a JSON round trip exactly. `expected_xy`
gives the pixels a reader must return; joints listed as missing must come back NaN.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from zedo_cli.data.skeleton import SKELETONS

MMPOSE_COCO_NAMES = list(SKELETONS["coco17"].joints)
MMPOSE_HALPE_NAMES = [*MMPOSE_COCO_NAMES, "head", "neck", "hip", "left_big_toe", "right_big_toe",
                      "left_small_toe", "right_small_toe", "left_heel", "right_heel"]  # fmt: skip


# A standing person in BODY_25's joint order (pixels, y down): the face (nose, eyes, ears) is
# small, the neck is the shoulders' midpoint and the mid-hip the hips', as OpenPose places them.
BODY25_POSE = [
    (100.0, 20.0), (100.0, 50.0), (80.0, 50.0), (75.0, 80.0), (72.0, 110.0), (120.0, 50.0), (125.0, 80.0),
    (128.0, 110.0), (100.0, 120.0), (90.0, 120.0), (88.0, 160.0), (87.0, 200.0), (110.0, 120.0), (112.0, 160.0),
    (113.0, 200.0), (96.0, 16.0), (104.0, 16.0), (92.0, 18.0), (108.0, 18.0), (118.0, 208.0), (121.0, 207.0),
    (112.0, 204.0), (82.0, 208.0), (79.0, 207.0), (88.0, 204.0),
]  # fmt: skip
# The same person in BODY_25B's order (OpenPose experimental models; Pose2Sim skeletons.py):
# COCO-17, upper neck, head top, left big toe, small toe, heel, right big toe, small toe, heel.
BODY25B_FROM_BODY25 = [0, 16, 15, 18, 17, 5, 2, 6, 3, 7, 4, 12, 9, 13, 10, 14, 11, -1, -2, 19, 20, 21, 22, 23, 24]
_BODY25B_EXTRA = {-1: (100.0, 42.0), -2: (100.0, 4.0)}  # upper neck, head top


def body25b_pose() -> list[tuple[float, float]]:
    return [BODY25_POSE[k] if k >= 0 else _BODY25B_EXTRA[k] for k in BODY25B_FROM_BODY25]


def expected_xy(count: int, offset: float) -> np.ndarray:
    """(count, 2) distinct pixels for person `offset`; 25 joints are a BODY_25 person."""
    if count == 25:
        return np.asarray(BODY25_POSE) + offset
    j = np.arange(count, dtype=np.float64)
    return np.stack([offset + 10.25 * j, offset + 200.5 + 3.75 * j], axis=1)


def confidences(count: int, missing: tuple[int, ...] = (), value: float = 0.75) -> list[float]:
    return [0.0 if j in missing else value for j in range(count)]


def flat(count: int, offset: float, missing: tuple[int, ...] = (), value: float = 0.75) -> list[float]:
    """``[x, y, c] * count``; a missing joint is 0, 0, 0 as OpenPose writes it."""
    out: list[float] = []
    for (x, y), c in zip(expected_xy(count, offset), confidences(count, missing, value), strict=True):
        out += [0.0, 0.0, 0.0] if c == 0 else [float(x), float(y), c]
    return out


def openpose_frame(*offsets: float, count: int = 25, missing: tuple[int, ...] = ()) -> dict[str, Any]:
    people = [
        {"person_id": [-1], "pose_keypoints_2d": flat(count, o, missing), "face_keypoints_2d": [],
         "hand_left_keypoints_2d": [], "hand_right_keypoints_2d": [], "pose_keypoints_3d": []}
        for o in offsets
    ]  # fmt: skip
    return {"version": 1.3, "people": people}


def mmpose_instance(
    offset: float, count: int = 17, missing: tuple[int, ...] = (), bbox_score: float = 0.875
) -> dict[str, Any]:
    xy = expected_xy(count, offset)
    return {
        "keypoints": [[float(x), float(y)] for x, y in xy],
        "keypoint_scores": confidences(count, missing, 0.5),
        "bbox": [[offset, offset, offset + 100.0, offset + 200.0]],  # MMPose's extra list
        "bbox_score": bbox_score,
    }


def mmpose_image() -> list[dict[str, Any]]:
    return [mmpose_instance(1.0, missing=(3,)), mmpose_instance(2.0, bbox_score=0.25)]


def mmpose_video(count: int = 17) -> list[dict[str, Any]]:
    return [
        {"frame_id": 0, "instances": [mmpose_instance(1.0, count), mmpose_instance(2.0, count)]},
        {"frame_id": 1, "instances": []},
        {"frame_id": 2, "instances": [mmpose_instance(3.0, count, missing=(0,))]},
    ]


def mmpose_demo(names: list[str] | None = None, dataset: str = "coco", start: int = 1) -> dict[str, Any]:
    names = MMPOSE_COCO_NAMES if names is None else names
    count = len(names)
    meta = {"dataset_name": dataset, "num_keypoints": count,
            "keypoint_id2name": {str(k): n for k, n in enumerate(names)}, "skeleton_links": [[0, 1]]}  # fmt: skip
    frames = [
        {"frame_id": start, "instances": [mmpose_instance(1.0, count)]},
        {"frame_id": start + 1, "instances": [mmpose_instance(2.0, count), mmpose_instance(3.0, count)]},
    ]
    return {"meta_info": meta, "instance_info": frames}


def alphapose(count: int = 26) -> list[dict[str, Any]]:
    """AlphaPose results out of frame order, two people on frame 2, an above-1 confidence."""
    first = flat(count, 1.0)
    first[2] = 1.5
    return [
        {"image_id": "10.jpg", "category_id": 1, "keypoints": first, "score": 2.875, "box": [1, 2, 3, 4], "idx": 1},
        {"image_id": "2.jpg", "category_id": 1, "keypoints": flat(count, 2.0, (4,)), "score": 1.5, "box": [1, 2, 3, 4],
         "idx": 1},
        {"image_id": "2.jpg", "category_id": 1, "keypoints": flat(count, 3.0), "score": 0.5, "box": [1, 2, 3, 4],
         "idx": 2},
    ]  # fmt: skip


def jsonl_records(count: int = 17) -> list[dict[str, Any]]:
    def person(offset: float, missing: tuple[int, ...] = (), score: float | None = None) -> dict[str, Any]:
        points: list[Any] = [[float(x), float(y), 0.5] for x, y in expected_xy(count, offset)]
        for j in missing:
            points[j] = None
        points[1] = points[1][:2] if points[1] is not None else None  # [x, y]: confidence 1
        return {"keypoints": points} | ({} if score is None else {"score": score})

    return [
        {"frame": 0, "image_size": [640, 480], "persons": [person(1.0, (2,), 0.75), person(2.0)]},
        {"frame": 1, "persons": []},
        {"frame": 2, "image_id": "f2.png", "file_name": "f2.png", "persons": [person(3.0)]},
    ]


def jsonl_text(records: list[Any]) -> str:
    return "".join(json.dumps(r) + "\n" for r in records)


def write_json(path: Path, obj: Any) -> Path:
    path.write_text(json.dumps(obj))
    return path


def coco_annotations() -> dict[str, Any]:
    names = list(SKELETONS["coco17"].joints)
    return {
        "images": [{"id": 1, "width": 640, "height": 480, "file_name": "a.jpg", "original_file_name": "orig_a.jpg"}],
        "annotations": [{"id": 1, "image_id": 1, "category_id": 1, "keypoints": [v if k % 3 < 2 else 2 for k, v in
                                                                                  enumerate(flat(17, 1.0))]}],
        "categories": [{"id": 1, "name": "person", "keypoints": names}],
    }  # fmt: skip


def coco_results() -> list[dict[str, Any]]:
    return [{"image_id": 5, "category_id": 1, "keypoints": flat(17, 1.0, (2,)), "score": 0.9}]


def zedo_2d() -> dict[str, Any]:
    return {"schema": "zedo.keypoints2d/1", "skeleton": "syrip12", "image_size": [64, 48],
            "instances": [{"image_id": 0, "keypoints": [[1.0, 2.0], None, *[[3.0, 4.0, 0.5]] * 10]}]}  # fmt: skip


def key_paths(doc: Any, prefix: tuple[Any, ...] = ()) -> list[tuple[Any, ...]]:
    """Every key path into `doc` (to a dict value or a list item), for tests that break a file
    at each place in turn."""
    items = doc.items() if isinstance(doc, dict) else enumerate(doc) if isinstance(doc, list) else []
    found = []
    for key, value in items:
        found.append((*prefix, key))
        found.extend(key_paths(value, (*prefix, key)))
    return found
