"""Camera sanity of a lift: a person at a distance no recording of an infant has, or 2D keypoints
outside the image, say that the camera (focal length, image size, calibration file) does not fit
the input. Such instances are flagged in the result (and counted by `zedo lift` on stderr), not
refused: the 3D is what the camera given implies, and the flag says not to trust its scale.

The bounds:
- root depth (z of the root point in the camera frame) in [MIN_DEPTH_M, MAX_DEPTH_M]: an infant
  filmed in a clinic, a cot or from above is 0.3 to 3 m from the camera; 10 m is a distant
  wide shot, 0.1 m a camera touching the infant. The pseudo camera (f = 2000 px) puts an infant
  spanning 300 px about 2 m away.
- observed 2D keypoints within the image enlarged by OUTSIDE_MARGIN of its width and height on
  every side: detectors place occluded joints a little beyond the border, never far.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import plural

MIN_DEPTH_M = 0.1
MAX_DEPTH_M = 10.0
OUTSIDE_MARGIN = 0.1  # fraction of the image's width (x) and height (y)
IMPLAUSIBLE_DISTANCE = "implausible_distance"
KEYPOINTS_OUTSIDE_IMAGE = "keypoints_outside_image"


@dataclass(frozen=True)
class CameraSanity:
    """Per instance: the root depth and the two checks (False where not lifted or unknown)."""

    depth_m: np.ndarray  # (N,) z of the root point, metres; NaN where not lifted
    implausible_distance: np.ndarray  # (N,) bool: depth outside [MIN_DEPTH_M, MAX_DEPTH_M]
    outside: np.ndarray  # (N,) int: observed keypoints beyond the image and its margin (0 without a size)

    def flags(self, i: int) -> list[str]:
        """The result file's flags for instance `i` (`implausible_distance: 75.0 m`, ...)."""
        out = []
        if self.implausible_distance[i]:
            out.append(f"{IMPLAUSIBLE_DISTANCE}: {self.depth_m[i]:.1f} m")
        if self.outside[i]:
            out.append(f"{KEYPOINTS_OUTSIDE_IMAGE}: {int(self.outside[i])} joint(s)")
        return out

    def warnings(self) -> list[str]:
        """One line per check that fired somewhere, with its count and bound (for stderr)."""
        lines = []
        far = int(self.implausible_distance.sum())
        if far:
            depths = self.depth_m[self.implausible_distance]
            lines.append(
                f"{plural(far, 'lifted instance')} flagged {IMPLAUSIBLE_DISTANCE}: the person is {depths.min():.2g} to "
                f"{depths.max():.3g} m from the camera, outside [{MIN_DEPTH_M:g}, {MAX_DEPTH_M:g}] m "
                "(check --focal, --intrinsics and the image size)"
            )
        outside = int((self.outside > 0).sum())
        if outside:
            lines.append(
                f"{plural(outside, 'instance')} flagged {KEYPOINTS_OUTSIDE_IMAGE}: observed 2D keypoints more than "
                f"{OUTSIDE_MARGIN:.0%} of the image size beyond its border (check --image-size and the input)"
            )
        return lines


def check_camera_sanity(
    xy: np.ndarray, observed: np.ndarray, image_sizes: np.ndarray, root_translation: np.ndarray, lifted: np.ndarray
) -> CameraSanity:
    """The checks for pixels `xy (N, J, 2)` with `observed (N, J)`, image sizes `(N, 2)` (NaN:
    unknown), lifted root points `root_translation (N, 3)` (metres, camera frame) and `lifted (N,)`."""
    depth = np.where(lifted, np.asarray(root_translation, dtype=np.float64)[:, 2], np.nan)
    with np.errstate(invalid="ignore"):
        far = lifted & ~((depth >= MIN_DEPTH_M) & (depth <= MAX_DEPTH_M))
        size = np.asarray(image_sizes, dtype=np.float64)[:, None, :]  # (N, 1, 2)
        low, high = -OUTSIDE_MARGIN * size, (1 + OUTSIDE_MARGIN) * size
        beyond = ((xy < low) | (xy > high)).any(-1) & observed & np.isfinite(size).all(-1)
    return CameraSanity(depth, far, beyond.sum(1))
