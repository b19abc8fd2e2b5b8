"""`Keypoints2D`: the one record every 2D reader produces, and `OtherKeypoints`: the input's
keypoints that a conversion to the lifted joint set leaves out (face, feet, ...), kept by name."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .skeleton import Skeleton, SkeletonSource, convert_points


@dataclass(frozen=True)
class OtherKeypoints:
    """The keypoints of N instances that are not joints of the record's skeleton: what
    `Keypoints2D.to_skeleton` leaves out (nose, eyes, ears, feet, the head top, ...), by name, as
    the input gave them (original image pixels, never undistorted; the input's confidences).

    They are carried through person selection and the lift into the result files (2D only: they
    are not lifted). Empty (E = 0) where the input had no joints beyond the lifted ones.
    """

    names: tuple[str, ...]  # (E,) joint names, in the input's joint-set order
    xy: np.ndarray  # (N, E, 2) float64 pixels; NaN = missing
    confidence: np.ndarray  # (N, E) float64 in [0, 1]; 0 = missing

    @classmethod
    def empty(cls, n: int) -> OtherKeypoints:
        """No other keypoints for `n` instances."""
        return cls((), np.zeros((n, 0, 2)), np.zeros((n, 0)))

    def subset(self, idx: list[int]) -> OtherKeypoints:
        return OtherKeypoints(self.names, self.xy[idx], self.confidence[idx])

    def extended(self, more: OtherKeypoints) -> OtherKeypoints:
        """These keypoints, then those of `more` whose names are not here yet."""
        new = [e for e, name in enumerate(more.names) if name not in self.names]
        return OtherKeypoints(
            (*self.names, *(more.names[e] for e in new)),
            np.concatenate([self.xy, more.xy[:, new]], axis=1),
            np.concatenate([self.confidence, more.confidence[:, new]], axis=1),
        )


@dataclass
class Keypoints2D:
    """2D keypoints of N instances (one person in one image each), in one joint set.

    Missing joints (COCO v = 0, confidence 0, below a threshold) have NaN coordinates and
    confidence 0: they are never positions.
    """

    xy: np.ndarray  # (N, J, 2) float64 pixels, 0-indexed from the image's top-left; NaN = missing
    confidence: np.ndarray  # (N, J) float64 in [0, 1]; 0 = missing
    skeleton: Skeleton
    image_ids: list[int | str]  # (N,) the input's image identifier of each instance
    file_names: list[str | None]  # (N,) image file name when the input has one
    image_sizes: np.ndarray  # (N, 2) float64 width, height in pixels; NaN = unknown
    scores: list[float | None]  # (N,) detection score of the instance when given
    path: str  # the file it was read from ("-" for stdin)
    format: str  # e.g. "coco-annotations", "coco-results", "zedo-2d", "openpose"
    # (N,) 0-based frame index of each instance where the input has frames (OpenPose file names,
    # MMPose frame_id, zedo JSONL), None where it has none; a default so positional callers work.
    frame_indices: list[int | None] | None = None
    # The joint set the input was read as and why (kept through `to_skeleton`); None where the
    # record was not made by a reader.
    source: SkeletonSource | None = None
    # The input's keypoints outside `skeleton` (set by `to_skeleton`: what the conversion left out,
    # by name, as read); None where the record is the input as read, or was made by a caller.
    other: OtherKeypoints | None = None
    # What the reader left out and the user should hear of (e.g. annotation labels that name no
    # joint), one line each; `zedo lift` prints them as warnings.
    notes: tuple[str, ...] = ()

    @property
    def source_skeleton(self) -> dict[str, str]:
        """``{"name", "reason"}`` of the joint set the input was read as (the output's
        ``input.source_skeleton``)."""
        if self.source is not None:
            return self.source.to_dict()
        return {"name": self.skeleton.name, "reason": "given by the caller"}

    def __len__(self) -> int:
        return int(self.xy.shape[0])

    def subset(self, index: list[int] | np.ndarray) -> Keypoints2D:
        idx = [int(i) for i in index]
        return Keypoints2D(
            self.xy[idx], self.confidence[idx], self.skeleton,
            [self.image_ids[i] for i in idx], [self.file_names[i] for i in idx],
            self.image_sizes[idx], [self.scores[i] for i in idx], self.path, self.format,
            None if self.frame_indices is None else [self.frame_indices[i] for i in idx], self.source,
            None if self.other is None else self.other.subset(idx), self.notes,
        )  # fmt: skip

    def to_skeleton(self, dst: Skeleton) -> Keypoints2D:
        """The same instances in joint set `dst`, converted by joint name. The joints of the
        record that `dst` lacks by name are kept, as they are, in `other` (after any kept before)."""
        left_out = [j for j, name in enumerate(self.skeleton.joints) if name not in dst.joints]
        present = self.confidence[:, left_out] > 0  # (N, E)
        other = OtherKeypoints(
            tuple(self.skeleton.joints[j] for j in left_out),
            np.where(present[..., None], self.xy[:, left_out], np.nan),
            np.where(present, self.confidence[:, left_out], 0.0),
        )  # fmt: skip
        other = other if self.other is None else self.other.extended(other)
        if dst.name == self.skeleton.name:
            return replace(self, other=other)
        xy, conf = convert_points(self.xy, self.confidence, self.skeleton, dst)
        return Keypoints2D(
            xy, conf, dst, self.image_ids, self.file_names, self.image_sizes, self.scores,
            self.path, self.format, self.frame_indices, self.source, other, self.notes,
        )  # fmt: skip
