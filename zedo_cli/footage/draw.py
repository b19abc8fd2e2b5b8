"""Drawing lifted skeletons onto frames with OpenCV: bones and joints coloured by side, joints the
prior filled as hollow rings, flagged persons boxed and labelled, a side-view panel (depth
against height) and a frame / time stamp. Frames are BGR `uint8 (H, W, 3)`, drawn in place.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..data.skeleton import Skeleton
from ..formats.colours import CENTRE_ON_FOOTAGE_RGB, LEFT_RGB, RIGHT_RGB, bgr

# BGR; left and right are the person's own (joint names left_* / right_*), coloured as in every
# figure zedo draws (formats.colours: the report's and the plots' blue and orange).
LEFT = bgr(LEFT_RGB)  # blue
RIGHT = bgr(RIGHT_RGB)  # orange
CENTRE = bgr(CENTRE_ON_FOOTAGE_RGB)  # yellow: bones between the sides (hip to hip, shoulder to shoulder)
FLAG = (220, 40, 220)  # magenta: the box and label of a flagged person
TEXT = (255, 255, 255)
PANEL = (40, 40, 40)


@dataclass(frozen=True)
class Style:
    """Line and marker sizes in pixels, scaled with the frame: `Style.for_height(h)`."""

    thickness: int = 2
    radius: int = 4
    font_scale: float = 0.6

    @classmethod
    def for_height(cls, height: int) -> Style:
        s = max(height / 720, 0.5)
        return cls(max(1, round(2 * s)), max(2, round(4 * s)), max(0.6 * s, 0.4))


def side_colour(name: str) -> tuple[int, int, int]:
    if name.startswith("left_"):
        return LEFT
    if name.startswith("right_"):
        return RIGHT
    return CENTRE


def bone_colours(skeleton: Skeleton) -> list[tuple[int, int, int]]:
    """A bone is left or right when both its joints are, else centre."""
    out = []
    for a, b in skeleton.bones:
        ca, cb = side_colour(skeleton.joints[a]), side_colour(skeleton.joints[b])
        out.append(ca if ca == cb else CENTRE)
    return out


def _inside(px: np.ndarray, width: int, height: int, slack: float = 2.0) -> np.ndarray:
    """Finite pixels not absurdly far out (OpenCV's int coordinates; lines are clipped anyway)."""
    lim = slack * max(width, height)
    return np.isfinite(px).all(-1) & (np.abs(px) < lim).all(-1)


def draw_skeleton(frame: np.ndarray, px: np.ndarray, observed: np.ndarray, skeleton: Skeleton, style: Style) -> None:
    """Bones, then joints: observed joints filled, joints the prior filled in as hollow rings."""
    import cv2

    h, w = frame.shape[:2]
    ok = _inside(px, w, h)
    pts = np.where(ok[:, None], np.round(px * 16), 0).astype(np.int64)  # 4 fractional bits: sub-pixel
    for (a, b), colour in zip(skeleton.bones, bone_colours(skeleton), strict=True):
        if ok[a] and ok[b]:
            cv2.line(frame, tuple(pts[a]), tuple(pts[b]), colour, style.thickness, cv2.LINE_AA, 4)
    for j, name in enumerate(skeleton.joints):
        if not ok[j]:
            continue
        colour = side_colour(name)
        if observed[j]:
            cv2.circle(frame, tuple(pts[j]), style.radius * 16, colour, -1, cv2.LINE_AA, 4)
            cv2.circle(frame, tuple(pts[j]), style.radius * 16, (0, 0, 0), 1, cv2.LINE_AA, 4)
        else:  # filled by the prior: a ring, its centre showing the frame
            cv2.circle(frame, tuple(pts[j]), (style.radius + 1) * 16, colour, style.thickness, cv2.LINE_AA, 4)


def label(frame: np.ndarray, text: str, origin: tuple[int, int], colour: tuple[int, int, int], style: Style) -> None:
    """`text` on a dark box whose top-left corner is `origin` (kept inside the frame)."""
    import cv2

    font = cv2.FONT_HERSHEY_SIMPLEX
    (tw, th), base = cv2.getTextSize(text, font, style.font_scale, 1)
    h, w = frame.shape[:2]
    x = int(np.clip(origin[0], 0, max(w - tw - 6, 0)))
    y = int(np.clip(origin[1], 0, max(h - th - base - 6, 0)))
    cv2.rectangle(frame, (x, y), (x + tw + 6, y + th + base + 6), (0, 0, 0), -1)
    cv2.putText(frame, text, (x + 3, y + th + 3), font, style.font_scale, colour, 1, cv2.LINE_AA)


def flag_names(flags: list[str]) -> str:
    """`joints_filled_by_prior: a, b` -> `joints_filled_by_prior`; several joined by commas."""
    return ", ".join(f.split(":")[0] for f in flags)


def draw_flag(frame: np.ndarray, px: np.ndarray, flags: list[str], style: Style) -> None:
    """A magenta box around the person's joints and the flags' names above it."""
    import cv2

    h, w = frame.shape[:2]
    ok = _inside(px, w, h)
    if not ok.any():
        return
    lo = np.floor(px[ok].min(0)).astype(int) - 3 * style.radius
    hi = np.ceil(px[ok].max(0)).astype(int) + 3 * style.radius
    cv2.rectangle(frame, (int(lo[0]), int(lo[1])), (int(hi[0]), int(hi[1])), FLAG, 2 * style.thickness)
    text_height = int(30 * style.font_scale) + 8
    label(frame, "flag: " + flag_names(flags), (int(lo[0]), int(lo[1]) - text_height), FLAG, style)


def stamp(frame_index: int, fps: float | None) -> str:
    """`frame 12` or `frame 12  0.400 s`."""
    return f"frame {frame_index}" + ("" if fps is None else f"  {frame_index / fps:.3f} s")


@dataclass(frozen=True)
class SideView:
    """The side panel's scale: `metres_per_px`, the same for the whole clip (poses do not jump)."""

    width: int
    height: int
    metres_per_px: float

    @classmethod
    def fit(cls, rel_poses: np.ndarray, height: int) -> SideView:
        """A panel `height` tall, 0.6 of that wide, scaled so every root-relative pose `(N, J, 3)`
        fits with a margin (at least 0.5 m of height, for a lone or tiny pose)."""
        width = max(int(0.6 * height), 80)
        finite = rel_poses[np.isfinite(rel_poses).all(-1)]
        extent_z = 2 * np.abs(finite[:, 2]).max() if len(finite) else 0.0
        extent_y = 2 * np.abs(finite[:, 1]).max() if len(finite) else 0.0
        mpp = max(extent_z / (0.8 * width), extent_y / (0.8 * height), 0.5 / height)
        return cls(width, height, float(mpp))

    def draw(self, panel: np.ndarray, rel: list[tuple[np.ndarray, np.ndarray]], skeleton: Skeleton,
             style: Style) -> None:  # fmt: skip
        """Fill `panel (height, width, 3)` for one frame: each person's root-relative pose `(J, 3)`
        with its observed mask, depth (z, away from the camera) to the right, height (y, down)
        down, root at the centre."""
        import cv2

        panel[:] = PANEL
        cx, cy = self.width // 2, self.height // 2
        cv2.line(panel, (cx, 0), (cx, self.height), (80, 80, 80), 1)
        cv2.line(panel, (0, cy), (self.width, cy), (80, 80, 80), 1)
        bar = int(round(0.1 / self.metres_per_px))  # a 10 cm scale bar
        cv2.line(panel, (10, self.height - 12), (10 + bar, self.height - 12), TEXT, 2)
        label(panel, "10 cm", (14 + bar, self.height - 30), TEXT, style)
        label(panel, "side view: depth ->", (4, 4), TEXT, style)
        for pose, observed in rel:
            px = np.c_[cx + pose[:, 2] / self.metres_per_px, cy + pose[:, 1] / self.metres_per_px]
            draw_skeleton(panel, px, observed, skeleton, style)
