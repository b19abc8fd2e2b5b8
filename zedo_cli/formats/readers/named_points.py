"""Hand-annotated points by label (LabelMe, Label Studio) into one `Keypoints2D`.

An annotation tool stores each point with a label the annotator chose. `data.labels` reads a label
as zedo's joint name; the joints of COCO-17 (the body and face joints every lifted joint set is
made from) become the record's joints, every other known point (the neck, the head top, hands,
feet, toes, heels, ...) the input's other keypoints by name (`Keypoints2D.other`), and a label that
names no point is listed once in the record's notes, never guessed. An input whose labels name no
joint at all is refused, naming the file and the labels.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...data.keypoints import Keypoints2D, OtherKeypoints
from ...data.labels import joint_name_of_label
from ...data.skeleton import SKELETONS, SkeletonSource
from .validate import ImageId, error, number

SKELETON = SKELETONS["coco17"]
_SHOWN = 8  # labels shown in one message


@dataclass
class Instance:
    """One annotated person in one image: points by zedo joint name, in pixels."""

    image_id: ImageId
    file_name: str | None
    size: tuple[float, float]  # width, height in pixels; NaN = unknown
    frame: int | None
    points: dict[str, tuple[float, float]] = field(default_factory=dict)
    wheres: dict[str, str] = field(default_factory=dict)  # joint name -> the field it came from


@dataclass
class Labels:
    """Every label of an input: those read as a joint and those that name no known point."""

    mapped: dict[str, str] = field(default_factory=dict)  # label -> zedo joint name
    unknown: dict[str, None] = field(default_factory=dict)  # labels in order of first appearance

    def joint(self, label: str) -> str | None:
        if label in self.mapped:
            return self.mapped[label]
        if label in self.unknown:
            return None
        name = joint_name_of_label(label)
        if name is None:
            self.unknown[label] = None
        else:
            self.mapped[label] = name
        return name


def shown(items: list[str], noun: str = "labels") -> str:
    """Labels (or other names) for a one-line message: "'Foo', 'Bar', ... (12 labels)"."""
    text = ", ".join(repr(item[:40]) for item in items[:_SHOWN])
    return text + (f", ... ({len(items)} {noun})" if len(items) > _SHOWN else "")


def coordinate(value: object, path: str, where: str) -> float:
    """A point's x or y: a finite JSON number."""
    x = number(value, path, where)
    if not np.isfinite(x):
        raise error(path, where, f"expected a finite coordinate, got {x:g}")
    return x


def add_point(person: Instance, labels: Labels, label: str, xy: tuple[float, float], path: str, where: str) -> None:
    """The point `label` of `person` at `xy` pixels; a second point of the same joint is refused."""
    name = labels.joint(label)
    if name is None:
        return
    if name in person.points:
        raise error(
            path,
            where,
            f"label {label!r} is {name}, which {person.wheres[name]} already marks "
            "for this person: one point per joint and person",
        )
    person.points[name] = xy
    person.wheres[name] = where


def build_named(
    instances: list[Instance], labels: Labels, path: str, fmt: str, *, tool: str, notes: tuple[str, ...] = ()
) -> Keypoints2D:
    """The instances as a COCO-17 `Keypoints2D` with the other known points in `other` (by name,
    in order of first appearance) and the unknown labels in `notes`; refused when no label is a
    COCO-17 joint (nothing to lift)."""
    if not any(name in SKELETON.joints for name in labels.mapped.values()):
        every = list(labels.mapped) + list(labels.unknown)
        if not every:
            raise error(path, "", f"no labelled points found ({tool})")
        raise error(
            path,
            "",
            f"no label names a body joint ({shown(every)}); docs/inputs.md, "
            '"Annotation tools", lists the labels zedo reads',
        )
    if not instances:
        raise error(path, "", "no instances found")
    n, j = len(instances), SKELETON.num_joints
    others = list(dict.fromkeys(name for name in labels.mapped.values() if name not in SKELETON.joints))
    column = {name: k for k, name in enumerate((*SKELETON.joints, *others))}
    xy = np.full((n, j + len(others), 2), np.nan)  # (N, J + E, 2) pixels
    for i, person in enumerate(instances):
        for name, point in person.points.items():
            xy[i, column[name]] = point
    conf = np.isfinite(xy).all(axis=-1).astype(np.float64)  # (N, J + E): a hand-placed point is sure
    if labels.unknown:
        notes = (
            *notes,
            f"{path}: labels that name no joint, left out: {shown(list(labels.unknown))} "
            '(docs/inputs.md, "Annotation tools")',
        )
    frames = [p.frame for p in instances]
    return Keypoints2D(
        xy=xy[:, :j],
        confidence=conf[:, :j],
        skeleton=SKELETON,
        image_ids=[p.image_id for p in instances],
        file_names=[p.file_name for p in instances],
        image_sizes=np.array([p.size for p in instances], dtype=np.float64).reshape(n, 2),
        scores=[None] * n,
        path=path,
        format=fmt,
        frame_indices=None if all(f is None for f in frames) else frames,
        source=SkeletonSource(SKELETON.name, f"{tool} point labels, by name"),
        other=OtherKeypoints(tuple(others), xy[:, j:], conf[:, j:]) if others else None,
        notes=notes,
    )
