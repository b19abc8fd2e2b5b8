"""`Keypoints2D`: the one record every 2D reader produces."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .skeleton import Skeleton, SkeletonSource, convert_points


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
        )  # fmt: skip

    def to_skeleton(self, dst: Skeleton) -> Keypoints2D:
        """The same instances in joint set `dst`, converted by joint name."""
        if dst.name == self.skeleton.name:
            return self
        xy, conf = convert_points(self.xy, self.confidence, self.skeleton, dst)
        return Keypoints2D(
            xy, conf, dst, self.image_ids, self.file_names, self.image_sizes, self.scores,
            self.path, self.format, self.frame_indices, self.source,
        )  # fmt: skip
