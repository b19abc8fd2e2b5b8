"""Headless PNG plots of lifted 3D skeletons, for a quick visual check of a result.

Three instances are drawn, each to its own PNG: the first lifted one, the one with the median
and the one with the worst mean reprojection error. Each PNG shows the pose root-relative (root
point at the origin; camera axes x right, y down, z forward) from three viewpoints: the camera's,
the side (from the camera's right) and the top (from above), with the skeleton's bones, left
and right limbs in different colours, and joints filled by the prior drawn hollow.

matplotlib is imported inside the function, and only its Agg canvas (no pyplot, no GUI
backend), so `zedo` starts fast and plotting works without a display.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..data.keypoints import Keypoints2D
from ..data.skeleton import Skeleton
from ..files import atomic_path, check_writable
from .colours import CENTRE_HEX, LEFT_HEX, RIGHT_HEX, side_hex
from .writers.common import OutputOptions, group_frames

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ..lifting.solver import LiftResult

if TYPE_CHECKING:
    from matplotlib.axes import Axes

PLOT_ROLES = ("first", "median", "worst")
# The sides in every figure zedo draws (formats.colours): zedo render's and the report's blue and orange.
LEFT_COLOUR, RIGHT_COLOUR, CENTRE_COLOUR = LEFT_HEX, RIGHT_HEX, CENTRE_HEX
# (title, horizontal axis, vertical axis, vertical axis inverted): y points down in the camera
# frame, so it is flipped to keep the head up; in the top view, farther (z) is up the page.
_VIEWS = (
    ("camera view", 0, 1, True),
    ("side view (from the right)", 2, 1, True),
    ("top view (from above)", 0, 2, False),
)
_AXIS_NAMES = ("x, right", "y, down", "z, forward")


def mean_reprojection_error_px(res: LiftResult) -> np.ndarray:
    """Per instance `(N,)`: the mean over observed joints; NaN for instances not lifted."""
    err = np.where(res.observed & res.lifted[:, None], res.reprojection_error_px, np.nan)
    counts = np.isfinite(err).sum(1)
    return np.where(counts > 0, np.nansum(err, 1) / np.maximum(counts, 1), np.nan)


def select_plot_instances(res: LiftResult) -> dict[str, int]:
    """Instance index per role: the first lifted, the median and the worst by mean
    reprojection error (the lower median for an even count). Empty when nothing was lifted."""
    err = mean_reprojection_error_px(res)
    ok = np.flatnonzero(res.lifted & np.isfinite(err))
    if len(ok) == 0:
        return {}
    ranked = ok[np.argsort(err[ok], kind="stable")]
    return {"first": int(ok[0]), "median": int(ranked[(len(ranked) - 1) // 2]), "worst": int(ranked[-1])}


def _side(skeleton: Skeleton, a: int, b: int) -> str:
    return side_hex(skeleton.joints[a], skeleton.joints[b])


def _joint_colour(name: str) -> str:
    return side_hex(name)


def _draw_view(ax: Axes, pose: np.ndarray, observed: np.ndarray, skeleton: Skeleton, view: tuple, units: str,
               half: float) -> None:  # fmt: skip
    title, h, v, invert = view
    for a, b in skeleton.bones:
        ax.plot(pose[[a, b], h], pose[[a, b], v], color=_side(skeleton, a, b), lw=2.2, solid_capstyle="round")
    for j, name in enumerate(skeleton.joints):
        colour = _joint_colour(name)
        ax.scatter(pose[j, h], pose[j, v], s=28, zorder=3, edgecolors=colour, linewidths=1.4,
                   facecolors=colour if observed[j] else "white")  # fmt: skip
    ax.set_xlim(-half, half)
    ax.set_ylim((half, -half) if invert else (-half, half))
    ax.set_aspect("equal")
    ax.set_xlabel(f"{_AXIS_NAMES[h]} ({units})")
    ax.set_ylabel(f"{_AXIS_NAMES[v]} ({units})")
    ax.set_title(title, fontsize=10)
    ax.grid(True, lw=0.4, alpha=0.5)


def write_pose_plots(
    out_prefix: str | Path,
    kp: Keypoints2D,
    res: LiftResult,
    *,
    units: str = "m",
    overwrite: bool = False,
    dpi: int = 100,
) -> list[Path]:
    """Write `<out_prefix>.first.png`, `.median.png` and `.worst.png` (the same instance may
    fill several roles) and return their paths; nothing when no instance was lifted.

    `kp` gives the skeleton, image ids and file names of the instances of `res`. Coordinates are
    drawn root-relative in `units` ("m" or "mm"). Existing files are replaced only with
    `overwrite`; each PNG is written atomically.
    """
    opts = OutputOptions(units, "root")
    chosen = select_plot_instances(res)
    prefix = Path(out_prefix)
    paths = {role: prefix.with_name(f"{prefix.name}.{role}.png") for role in chosen}
    for path in paths.values():  # all checked before any is drawn
        check_writable(path, overwrite)
    if not chosen:
        return []
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: keeps `zedo` start-up fast
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    err = mean_reprojection_error_px(res)
    groups = group_frames(kp.image_ids, kp.frame_indices)
    legend = [Line2D([], [], color=LEFT_COLOUR, lw=2.2, label="left"),
              Line2D([], [], color=RIGHT_COLOUR, lw=2.2, label="right"),
              Line2D([], [], color=CENTRE_COLOUR, lw=2.2, label="centre"),
              Line2D([], [], ls="", marker="o", color="0.3", label="observed joint"),
              Line2D([], [], ls="", marker="o", color="0.3", mfc="white", label="filled by the prior")]  # fmt: skip
    for role, i in chosen.items():
        pose = res.poses_root_relative[i] * opts.scale  # (J, 3)
        finite = np.abs(pose[np.isfinite(pose)])
        half = 1.15 * float(finite.max()) if finite.size and finite.max() > 0 else 1.0
        fig = Figure(figsize=(12.0, 4.6), dpi=dpi, layout="constrained")
        FigureCanvasAgg(fig)
        for ax, view in zip(fig.subplots(1, len(_VIEWS)), _VIEWS, strict=True):
            _draw_view(ax, pose, res.observed[i], kp.skeleton, view, opts.units, half)
        name = f" ({kp.file_names[i]})" if kp.file_names[i] else ""
        depth = f"{res.root_translation[i, 2] * opts.scale:.{3 if opts.units == 'm' else 0}f}"
        fig.suptitle(f"{role}: frame {groups.frame_index[i]}, image {kp.image_ids[i]}{name}, person "
                     f"{groups.person[i]} | mean reprojection error {err[i]:.2f} px | root depth {depth} "
                     f"{opts.units} | {kp.skeleton.name}, root-relative", fontsize=10)  # fmt: skip
        fig.legend(handles=legend, loc="outside lower center", ncols=len(legend), fontsize=9, frameon=False)
        with atomic_path(paths[role], overwrite=overwrite) as tmp:
            fig.savefig(tmp, format="png")
    return list(paths.values())
