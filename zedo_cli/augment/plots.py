"""Headless PNG plots that check the poses written by `zedo augment`.

`zedo augment` converts adult 3D poses into infant-like ones with a diffusion model. Three
figures compare the converted (augmented) poses with the reference infant poses and with the
adult poses they came from:

- `bone_lengths.png`: per bone, the distribution of its length as a fraction of the pose's total
  bone length (the sum over all bones), so body proportions are compared independent of size;
  the suptitle gives each set's median total bone length in metres, since size matters too.
- `bone_angles.png`: per joint where two bones meet, the distribution of the angle between them
  in degrees (0 = folded onto each other, 180 = straight), e.g. the knee between hip and ankle.
- `pairs.png`: a few adult/converted pairs side by side (evenly spaced rows of the input), each
  from the front (x right, y down) and the side (z forward, y down), each pose in its own axis
  limits, since an adult (~1.7 m of bones) and an infant (~0.6 m) differ a lot in size.

In the distributions the augmented set should look like the infant reference, not like the
adult sources. matplotlib is imported inside the function, and only its Agg canvas (no pyplot,
no GUI backend), so `zedo` starts fast and plotting works without a display.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..data.skeleton import Skeleton
from ..data.skeleton import bone_lengths as skeleton_bone_lengths
from ..errors import ConfigError
from ..files import atomic_path, check_writable
from ..formats.plots import CENTRE_COLOUR, LEFT_COLOUR, RIGHT_COLOUR, _side
from .conversion import skeleton_size

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

PLOT_NAMES = ("bone_lengths.png", "bone_angles.png", "pairs.png")
# (label, colour) of the three compared sets, in the order they are passed around below.
_SETS = (
    ("infant (reference)", "tab:green"),
    ("augmented", "tab:orange"),
    ("adult sources", "tab:purple"),
)
# (title, horizontal axis, vertical axis): y points down in the camera frame, so it is inverted.
_PAIR_VIEWS = (("front", 0, 1), ("side", 2, 1))
_AXIS_NAMES = ("x, right", "y, down", "z, forward")


def _check_shape(name: str, poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    try:
        arr = np.asarray(poses, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"{name}: not an array of numbers ({exc})") from exc
    if arr.ndim != 3 or arr.shape[1:] != (skeleton.num_joints, 3):
        raise ConfigError(
            f"{name}: expected poses of shape (N, {skeleton.num_joints}, 3) for skeleton {skeleton.name}, "
            f"got {arr.shape}"
        )
    return arr


def bone_lengths(poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Length of every bone of `skeleton.bones` per pose: `(N, J, 3)` -> `(N, B)`, input units."""
    return skeleton_bone_lengths(_check_shape("poses", poses, skeleton), skeleton)


def bone_fractions(poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Bone lengths divided by the pose's total bone length `(N, B)`; rows sum to 1 (NaN for a
    pose whose bones all have zero length)."""
    lengths = bone_lengths(poses, skeleton)
    total = lengths.sum(axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(total > 0, lengths / total, np.nan)


def angle_triples(skeleton: Skeleton) -> list[tuple[int, int, int]]:
    """(joint, neighbour a, neighbour b) for every pair of bones that share a joint, joints in
    skeleton order, neighbours in bone order."""
    triples = []
    for j in range(skeleton.num_joints):
        neighbours = [b if a == j else a for a, b in skeleton.bones if j in (a, b)]
        for p in range(len(neighbours)):
            for q in range(p + 1, len(neighbours)):
                triples.append((j, neighbours[p], neighbours[q]))
    return triples


def joint_angles(poses: np.ndarray, skeleton: Skeleton) -> tuple[list[str], np.ndarray]:
    """Angles in degrees (0-180) at every joint where two bones meet: names like
    "left_knee (left_hip, left_ankle)" and the angles `(N, A)` (NaN where a bone has zero length)."""
    arr = _check_shape("poses", poses, skeleton)
    triples = angle_triples(skeleton)
    names = [f"{skeleton.joints[j]} ({skeleton.joints[a]}, {skeleton.joints[b]})" for j, a, b in triples]
    if not triples:
        return names, np.zeros((len(arr), 0))
    j, a, b = np.array(triples, dtype=np.int64).T
    u, v = arr[:, a] - arr[:, j], arr[:, b] - arr[:, j]
    norms = np.linalg.norm(u, axis=-1) * np.linalg.norm(v, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = np.where(norms > 0, (u * v).sum(-1) / norms, np.nan)
    # clip: rounding can push the cosine of a straight or folded limb just past +-1
    return names, np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def evenly_spaced_rows(n: int, k: int) -> np.ndarray:
    """`min(k, n)` distinct row indices spread evenly over `range(n)`, first and last included."""
    k = min(k, n)
    if k <= 1:
        return np.zeros(k, dtype=np.int64)
    # integer floor keeps the indices distinct (np.round's half-to-even could repeat one)
    return np.arange(k, dtype=np.int64) * (n - 1) // (k - 1)


def _validate(skeleton: Skeleton, infant: np.ndarray, augmented: np.ndarray, sources: np.ndarray,
              pairs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    if not skeleton.bones:
        raise ConfigError(f"skeleton {skeleton.name} has no bones to plot")
    arrays = []
    for name, poses in (("infant", infant), ("augmented", augmented), ("sources", sources)):
        arr = _check_shape(name, poses, skeleton)
        if len(arr) == 0:
            raise ConfigError(f"{name}: no poses to plot")
        if not np.isfinite(arr).all():
            raise ConfigError(f"{name}: {int((~np.isfinite(arr)).any(axis=(1, 2)).sum())} poses have NaN or "
                              "infinite coordinates")  # fmt: skip
        arrays.append(arr)
    if arrays[2].shape != arrays[1].shape:
        raise ConfigError(f"sources: shape {arrays[2].shape} differs from augmented {arrays[1].shape}; "
                          "row i of sources must be the adult pose augmented row i came from")  # fmt: skip
    if pairs < 1:
        raise ConfigError(f"pairs: must be at least 1, got {pairs}")
    return arrays[0], arrays[1], arrays[2]


def _shared_bins(values: list[np.ndarray], bins: int, lo: float | None = None, hi: float | None = None) -> np.ndarray:
    finite = np.concatenate([v[np.isfinite(v)] for v in values])
    lo = float(finite.min()) if lo is None and finite.size else 0.0 if lo is None else lo
    hi = float(finite.max()) if hi is None and finite.size else 1.0 if hi is None else hi
    if hi - lo < 1e-9:  # one value everywhere: widen the range so it gets a visible bin
        pad = max(0.05 * abs(lo), 1e-3)
        lo, hi = lo - pad, hi + pad
    return np.linspace(lo, hi, bins + 1)


def _histogram_grid(titles: list[str], columns: list[list[np.ndarray]], xlabel: str, suptitle: str, dpi: int,
                    fixed_range: tuple[float, float] | None = None) -> Figure:  # fmt: skip
    """One panel per title; `columns[s][:, i]` are set s's values for panel i."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    ncols = max(1, min(4, len(titles)))
    nrows = max(1, -(-len(titles) // ncols))
    fig = Figure(figsize=(3.3 * ncols, 2.5 * nrows + 0.9), dpi=dpi, layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, ncols, squeeze=False)).ravel()
    for i, title in enumerate(titles):
        ax: Axes = axes[i]
        values = [col[:, i] for col in columns]
        lo, hi = fixed_range if fixed_range else (None, None)
        bins = _shared_bins(values, 30, lo, hi)
        for v, (_, colour) in zip(values, _SETS, strict=True):
            v = v[np.isfinite(v)]
            if v.size:
                ax.hist(v, bins=bins, density=True, histtype="step", color=colour, lw=1.5)
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.set_yticks([])  # densities of differently sized sets: the shapes matter, not the numbers
        ax.grid(True, lw=0.4, alpha=0.5)
    for ax in axes[len(titles) :]:
        ax.set_axis_off()
    if not titles:
        axes[0].text(0.5, 0.5, "nothing to show", ha="center", va="center", transform=axes[0].transAxes)
    handles = [Line2D([], [], color=colour, lw=1.5, label=label) for label, colour in _SETS]
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=9, frameon=False)
    fig.suptitle(suptitle, fontsize=10)
    return fig


def _draw_pose(ax: Axes, pose: np.ndarray, skeleton: Skeleton, h: int, v: int, half: float) -> None:
    for a, b in skeleton.bones:
        ax.plot(pose[[a, b], h], pose[[a, b], v], color=_side(skeleton, a, b), lw=2.0, solid_capstyle="round")
    ax.scatter(pose[:, h], pose[:, v], s=10, color="0.2", zorder=3)
    ax.set_xlim(-half, half)
    ax.set_ylim(half, -half)  # y points down: inverted to keep the head up
    ax.set_aspect("equal")
    ax.set_xlabel(f"{_AXIS_NAMES[h]} (m)", fontsize=8)
    ax.set_ylabel(f"{_AXIS_NAMES[v]} (m)", fontsize=8)
    ax.tick_params(labelsize=7)
    ax.grid(True, lw=0.4, alpha=0.5)


def _pairs_figure(skeleton: Skeleton, augmented: np.ndarray, sources: np.ndarray, pairs: int, dpi: int) -> Figure:
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    rows = evenly_spaced_rows(len(augmented), pairs)
    root = skeleton.root_indices
    fig = Figure(figsize=(13.0, 3.2 * len(rows) + 0.9), dpi=dpi, layout="constrained")
    axes = fig.subplots(len(rows), 2 * len(_PAIR_VIEWS), squeeze=False)
    for r, i in enumerate(rows):
        for p, (label, pose) in enumerate((("adult", sources[i]), ("converted", augmented[i]))):
            pose = pose - pose[root].mean(axis=0)  # drawn root-relative whatever the input frame
            half = 1.15 * max(float(np.abs(pose).max()), 1e-3)
            size = float(skeleton_size(pose[None], skeleton)[0])
            for c, (view, h, v) in enumerate(_PAIR_VIEWS):
                ax = axes[r, p * len(_PAIR_VIEWS) + c]
                _draw_pose(ax, pose, skeleton, h, v, half)
                ax.set_title(f"row {i} {label}, {view}: size {size:.2f} m", fontsize=9)
    legend = [Line2D([], [], color=LEFT_COLOUR, lw=2.0, label="left"),
              Line2D([], [], color=RIGHT_COLOUR, lw=2.0, label="right"),
              Line2D([], [], color=CENTRE_COLOUR, lw=2.0, label="centre")]  # fmt: skip
    fig.legend(handles=legend, loc="outside lower center", ncols=len(legend), fontsize=9, frameon=False)
    fig.suptitle(f"adult source vs converted pose, {len(rows)} of {len(augmented)} evenly spaced rows | "
                 f"{skeleton.name}, root-relative, each pose in its own scale; size = total bone length",
                 fontsize=10)  # fmt: skip
    return fig


def write_augmentation_plots(
    out_dir: str | Path,
    skeleton: Skeleton,
    infant: np.ndarray,
    augmented: np.ndarray,
    sources: np.ndarray,
    *,
    pairs: int = 4,
    overwrite: bool = False,
    dpi: int = 100,
) -> list[Path]:
    """Write `bone_lengths.png`, `bone_angles.png` and `pairs.png` into `out_dir` (created if
    needed) and return their paths.

    `infant` `(N1, J, 3)` are reference infant poses, `augmented` `(N2, J, 3)` the converted poses
    and `sources` `(N2, J, 3)` the adult pose each came from (row i -> `augmented[i]`), all in
    metres. `pairs` adult/converted pairs are drawn (at most N2). Existing files are replaced only
    with `overwrite`; each PNG is written atomically. Bad inputs raise `ConfigError`.
    """
    infant, augmented, sources = _validate(skeleton, infant, augmented, sources, pairs)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / name for name in PLOT_NAMES]
    for path in paths:  # all checked before any is drawn
        check_writable(path, overwrite)
    from matplotlib.backends.backend_agg import FigureCanvasAgg  # lazy: keeps `zedo` start-up fast

    sets = (infant, augmented, sources)
    medians = ", ".join(f"{label} {np.median(skeleton_size(poses, skeleton)):.3f} m (n={len(poses)})"
                        for (label, _), poses in zip(_SETS, sets, strict=True))  # fmt: skip
    bone_titles = [f"{skeleton.joints[a]}-{skeleton.joints[b]}" for a, b in skeleton.bones]
    lengths_fig = _histogram_grid(
        bone_titles, [bone_fractions(p, skeleton) for p in sets], "fraction of total bone length",
        f"bone length / total bone length per pose ({skeleton.name})\nmedian total bone length: {medians}", dpi,
    )  # fmt: skip
    angle_sets = [joint_angles(p, skeleton) for p in sets]
    angles_fig = _histogram_grid(
        angle_sets[0][0], [angles for _, angles in angle_sets], "angle (degrees)",
        f"angle between two bones meeting at a joint ({skeleton.name}; 180 = straight)", dpi, (0.0, 180.0),
    )  # fmt: skip
    pairs_fig = _pairs_figure(skeleton, augmented, sources, pairs, dpi)
    for path, fig in zip(paths, (lengths_fig, angles_fig, pairs_fig), strict=True):
        FigureCanvasAgg(fig)
        with atomic_path(path, overwrite=overwrite) as tmp:
            fig.savefig(tmp, format="png")
    return paths
