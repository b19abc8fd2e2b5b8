"""The clip report's own sections (a result with fps): the recording's summary first, then decimated
time series with their bands and flagged frames shaded, then the frames a person should review.

`review_picks(a)` chooses the frames to review (undecided symmetry calls, frames flagged too fast),
spread over the clip, most undecided first; the CLI cuts their thumbnails from the footage
(`footage.thumbnails`) and hands them to `report.write_report` as PNG bytes by frame number.
Everything per frame is vectorised: an 18,000-frame clip's plots draw at most MAX_POINTS points
per series. matplotlib is imported inside the functions (through `figures.figure`).
"""

from __future__ import annotations

import base64
from dataclasses import dataclass

import numpy as np

from ...formats.colours import LEFT_HEX, RIGHT_HEX
from ..analyse import SYMMETRY_NAMES, Analysis, Row
from ..compare import furthest_from_typical
from ..norms.calibrated import NULL_DRAWS
from ..pose.head import TURN_CALLS
from ..pose.joint_angles import ANGLE_BASES, SIDES, angle_name
from .epochs import Epochs, epochs_of
from .figures import figure, svg
from .markup import escape
from .plain_words import describe, has_words

MAX_POINTS = 600  # per plotted series: the clip decimated to at most this many time steps (a panel is ~500 px wide)
MAX_REVIEW = 8
FLAG_SHADE = "#f4a6a6"  # frames flagged too fast
AMBIGUOUS_SHADE = "#b9c8f0"  # frames with a limb whose depth side the 2D cannot tell (`--temporal clip`)
_TURN_COLOURS = {"left": LEFT_HEX, "right": RIGHT_HEX, "midline": "#9e9e9e"}
EPOCH_S = 60.0  # the report's epochs of a long clip
SHADE_SHARE = 0.05  # a long track's epoch is shaded where over this share of its frames carry the flag


def _pct(value: float) -> str:
    return f"{100 * value:.0f} %" if np.isfinite(value) else "–"


def _clip_rows(a: Analysis) -> dict[tuple[int, str], Row]:
    return {(r.person, r.measure): r for r in a.clip_rows}


def _share_cell(r: Row | None, level: str) -> str:
    if r is None or not np.isfinite(r.value):
        why = r.how.removeprefix("none: ") if r is not None and r.how else "not measured"
        return f"<td>– <small>({escape(why)})</small></td>"
    if np.isfinite(r.low) and np.isfinite(r.high):
        return f"<td><b>{_pct(r.value)}</b> <small>{level} interval {_pct(r.low)} – {_pct(r.high)}</small></td>"
    return f"<td><b>{_pct(r.value)}</b> <small>(no interval)</small></td>"


def typical_shares_row(a: Analysis) -> str:
    """With a reference: a row of what is typical for it, per pair the median share asymmetric of its clips and the
    range of their middle 80 % (a moving infant's limbs are often asymmetric)."""
    if a.reference is None:
        return ""
    cells = []
    for n in SYMMETRY_NAMES:
        values = np.array(
            [c.values.get(n.removesuffix("_deg") + "_share_asymmetric", np.nan) for c in a.reference.clips]
        )
        values = values[np.isfinite(values)]
        if not len(values):
            cells.append("<td>– <small>(not in the reference)</small></td>")
            continue
        lo, mid, hi = np.quantile(values, [0.1, 0.5, 0.9])
        cells.append(f"<td>{_pct(mid)} <small>typical: {len(values)} reference clips, middle 80 % {_pct(lo)} – "
                     f"{_pct(hi)}</small></td>")  # fmt: skip
    return f"<tr>{''.join(cells)}</tr>"


def _pair(name: str) -> str:
    return name.removeprefix("symmetry_").removesuffix("_deg").replace("_", " ")


def uncertain(a: Analysis) -> np.ndarray:
    """`(M,)` how many of the four symmetry calls of each analysed pose are uncertain."""
    return sum((a.calls[n] == "uncertain").astype(int) for n in SYMMETRY_NAMES)


def too_fast(a: Analysis) -> np.ndarray:
    """`(M,)` whether any joint angle of the pose was flagged too fast."""
    m = len(a.index)
    return np.any(np.stack([np.asarray(v, bool) for v in a.too_fast.values()] or [np.zeros(m, bool)]), axis=0)


def depth_ambiguous(a: Analysis) -> np.ndarray:
    """`(M,)` whether the lift flagged a limb of the pose depth-ambiguous (`--temporal clip`'s flag)."""
    flags = a.result.flags
    if flags is None:
        return np.zeros(len(a.index), bool)
    return np.array([any(f.startswith("depth_ambiguous") for f in flags[i]) for i in a.index], dtype=bool)


def epoch_shares(a: Analysis, person: int, epoch_s: float = EPOCH_S) -> tuple[np.ndarray, np.ndarray]:
    """Per `epoch_s` of a person's track, the start (s) `(E,)` and each symmetry pair's share of frames asymmetric
    `(E, 4)` (the mean of the frames' calibrated probabilities; NaN where an epoch has none)."""
    mine = a.result.person[a.index] == person
    t = a.result.frame_index[a.index][mine] / float(a.fps or 1.0)
    epoch = ((t - t.min()) // epoch_s).astype(int)
    count = int(epoch.max()) + 1
    shares = np.full((count, len(SYMMETRY_NAMES)), np.nan)
    for k, name in enumerate(SYMMETRY_NAMES):
        p = a.probabilities[name][mine] if name in a.probabilities else np.full(len(t), np.nan)
        known = np.isfinite(p)
        frames = np.bincount(epoch[known], minlength=count)
        with np.errstate(invalid="ignore"):
            shares[:, k] = np.bincount(epoch[known], weights=p[known], minlength=count) / frames
    return t.min() + epoch_s * np.arange(count), shares


def epoch_shares_table(a: Analysis, person: int) -> str:
    """For a track of over two epochs: its shares of frames asymmetric epoch by epoch (estimates only)."""
    if not a.fps or not a.probabilities:
        return ""
    starts, shares = epoch_shares(a, person)
    if len(starts) <= 2:
        return ""
    head = "".join(f"<th>{_pair(n)}</th>" for n in SYMMETRY_NAMES)
    body = "".join(f"<tr><td class=l>{s // 60:.0f}:{s % 60:02.0f}</td>"
                   + "".join(f"<td>{_pct(v)}</td>" for v in row) + "</tr>"
                   for s, row in zip(starts, shares, strict=True))  # fmt: skip
    return (
        f"<p class=meta>The same shares minute by minute (estimates only: each is known to about ±0.3, so only "
        f"larger changes between minutes say something).</p><table><tr><th class=l>from (min:s)</th>{head}</tr>"
        f"{body}</table>"
    )


def summary_section(a: Analysis) -> str:
    """The recording in a few lines: shares asymmetric, head, and the comparison with typical infants."""
    rows = _clip_rows(a)
    level = f"{a.settings.level:.0%}".replace("%", " %")
    people = sorted({p for p, _ in rows}) or sorted(set(a.result.person[a.index].tolist()))
    out = ["<h2>Summary of the recording</h2>"]
    for p in people:
        who = f" (person {p})" if len(people) > 1 else ""
        shares = [rows.get((p, n.removesuffix("_deg") + "_share_asymmetric")) for n in SYMMETRY_NAMES]
        if all(r is None or not np.isfinite(r.value) for r in shares):
            why = next((r.how.removeprefix("none: ") for r in shares if r is not None), "not measured")
            out.append(f"<p class=meta><b>Share of the frames asymmetric{who}</b>: not estimated ({escape(why)}; "
                       "the shares need the calibrated intervals of the frames).</p>")  # fmt: skip
        head = "".join(f"<th>{_pair(n)}</th>" for n in SYMMETRY_NAMES)
        cells = "".join(_share_cell(rows.get((p, n.removesuffix("_deg") + "_share_asymmetric")), level)
                        for n in SYMMETRY_NAMES)  # fmt: skip
        if not all(r is None or not np.isfinite(r.value) for r in shares):
            out.append(f"<p class=meta><b>Share of the frames asymmetric{who}</b>: the estimated share of frames in "
                   f"which the pair's true symmetry angle is above {a.settings.threshold_deg:g}°, with its {level} "
                   "interval (a block bootstrap over correlated frames, widened to the share's error on whole clips "
                   "of other sources: about ±0.3 whatever the clip's length, so differences smaller than that are "
                   "not evidence).</p>"
                   f"<table><tr>{head}</tr><tr>{cells}</tr>{typical_shares_row(a)}</table>")  # fmt: skip
            out.append(epoch_shares_table(a, p))
        turn = "".join(f"<th>head turned {c}</th>" if c != "midline" else "<th>head at the midline</th>"
                       for c in TURN_CALLS)  # fmt: skip
        turn_cells = "".join(_share_cell(rows.get((p, f"head_turn_fraction_{c}")), level) for c in TURN_CALLS)
        tilt = rows.get((p, "head_tilt_median_deg"))
        turn_rows = [rows.get((p, f"head_turn_fraction_{c}")) for c in TURN_CALLS]
        if all(r is None or not np.isfinite(r.value) for r in [*turn_rows, tilt]):
            why = next((r.how.removeprefix("none: ") for r in [tilt, *turn_rows] if r is not None), "")
            out.append(f"<p class=meta><b>Head{who}</b>: not measured ({escape(why or 'no head rows')}).</p>")
            continue
        if tilt is not None and np.isfinite(tilt.value):
            band = (f" <small>{level} interval {tilt.low:.1f}° – {tilt.high:.1f}°</small>"
                    if np.isfinite(tilt.low) else "")  # fmt: skip
            tilt_cell = f"<td><b>{tilt.value:.1f}°</b>{band}</td>"
        else:
            why = tilt.how.removeprefix("none: ") if tilt is not None else "not measured"
            tilt_cell = f"<td>– <small>({escape(why)})</small></td>"
        out.append(f"<p class=meta><b>Head{who}</b>: the share of the frames with a turn call, and the median "
                   "tilt (from the input's 2D face points and shoulders).</p>"
                   f"<table><tr>{turn}<th>median head tilt</th></tr>"
                   f"<tr>{turn_cells}{tilt_cell}</tr></table>")  # fmt: skip
    out.append(comparison_block(a))
    return "".join(out)


def comparison_block(a: Analysis) -> str:
    """With --norms: the published and extended surprise, and the features furthest from typical in words."""
    if not a.comparisons:
        return ("<p class=meta>No comparison with typical infants: give a reference from <code>zedo norms</code> "
                "with <code>--norms</code>.</p>")  # fmt: skip
    mismatches = sorted({pc.lifting_mismatch for pc in a.comparisons if pc.lifting_mismatch is not None})
    out = [f"<div class='note warn'>{escape(n[0].upper() + n[1:])}.</div>" for n in mismatches]
    for pc in a.comparisons:
        c = pc.comparison
        who = f" (person {pc.person})" if len(a.comparisons) > 1 else ""
        pub, cal = c.published, c.asymmetry
        scores = f"<tr><td class=l>published features ({pub.features})</td><td>{pub.z:+.2f}</td><td>{pub.p:.3g}</td>"
        for kind, s in (("extended features", c.extended), ("left-right asymmetry", c.asymmetry)):
            scores += f"</tr><tr><td class=l>{kind}, calibrated ({s.features})</td><td>–</td><td>{s.p:.3g}</td>"
        scores += "</tr>"
        far = [describe(n, z) if has_words(n) else f"{n.replace('_', ' ')}: z = {z:+.1f}"
               for n, z in furthest_from_typical(c)]  # fmt: skip
        items = "".join(f"<li>{escape(t)}</li>" for t in far)
        smallest = (
            f"with {cal.reference_clips} reference clips the smallest p is {1 / (cal.reference_clips + 1):.3f}"
            if cal.epochs == 1
            else f"compared by its epochs: about 1 time in 20, 1-8 % of typical clips in docs/movement.md; the "
            f"smallest p is {1 / (NULL_DRAWS + 1):.1g}"
        )
        by_epochs = (f" This clip is longer than the reference's: its calibrated p and each feature's z are of its "
                     f"{cal.epochs} epochs as long as the reference's clips (the median epoch, against medians of as "
                     f"many typical clips as its epochs are worth independently: {c.extended.independent_epochs} over "
                     f"the extended features, {cal.independent_epochs} over the asymmetry), the published z and p of "
                     "the whole clip."
                     if cal.epochs > 1 else "")  # fmt: skip
        out.append(f"<p class=meta><b>Compared with typical infants{who}</b>: how surprising this clip is under the "
                   "reference. The published z compares the clip's summed log-likelihood under the reference with "
                   "the typical clips' own sums (negative: less typical), p is its two-sided normal p-value (its false "
                   "alarms depend on the features' tails and the clips' lengths: docs/movement.md). The calibrated p "
                   "of the extended features and of the left-right asymmetry ranks the clip's distance from the "
                   "reference among the reference clips' own (each from the others): a typical clip gets p &lt; 0.05 "
                   f"at most 1 time in 20 ({smallest}). "
                   f"A small p says the movements differ from the reference, not why.{by_epochs}</p>"
                   f"<table><tr><th class=l>surprise over</th><th>z</th><th>p</th></tr>{scores}</table>"
                   "<p class=meta>Furthest from typical (the largest |z| of single features):</p>"
                   f"<ul class=far>{items}</ul>")  # fmt: skip
    return "".join(out)


# --- time series ------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Decimated:
    """One person's poses on a coarser time grid: every `step`-th pose, the flag OR-ed over each step."""

    take: np.ndarray  # (T',) positions in a.index
    t: np.ndarray  # (T',) seconds
    flagged: np.ndarray  # (T',) bool: any too-fast frame in the step
    ambiguous: np.ndarray  # (T',) bool: any frame in the step with a limb's depth side flagged ambiguous


def decimate(a: Analysis, person: int, max_points: int = MAX_POINTS) -> Decimated:
    res = a.result
    pos = np.flatnonzero(res.person[a.index] == person)  # (T,)
    pos = pos[np.argsort(res.frame_index[a.index][pos], kind="stable")]
    step = max(1, -(-len(pos) // max_points))
    pad = (-len(pos)) % step

    def any_in_step(mask: np.ndarray) -> np.ndarray:
        return np.pad(mask[pos], (0, pad)).reshape(-1, step).any(axis=1)  # (T',)

    take = pos[::step]
    t = res.frame_index[a.index][take] / float(a.fps or 1.0)
    return Decimated(take, t, any_in_step(too_fast(a)), any_in_step(depth_ambiguous(a)))


def _shade(ax, t: np.ndarray, ambiguous: np.ndarray, flagged: np.ndarray) -> None:  # noqa: ANN001 (matplotlib Axes)
    """Shade the time steps `t (T,)` where a limb's depth side was ambiguous or an angle was flagged too fast."""
    for where, colour in ((ambiguous, AMBIGUOUS_SHADE), (flagged, FLAG_SHADE)):
        if where.any():
            ax.fill_between(t, 0, 1, where=where, step="mid", color=colour, alpha=0.6, lw=0,
                            transform=ax.get_xaxis_transform())  # fmt: skip


def _empty(ax, text: str) -> None:  # noqa: ANN001
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=9, color="0.4", transform=ax.transAxes, wrap=True)
    ax.set_yticks([])


def _panels():  # noqa: ANN202 (matplotlib Figure and Axes, imported lazily)
    """The time series' figure: six joint-angle panels, head tilt and turn, and the uncertain calls' strip."""
    fig = figure(11.5, 11.5)
    grid = fig.add_gridspec(5, 2, height_ratios=[1, 1, 1, 0.8, 0.45])
    axes = [fig.add_subplot(grid[r, c]) for r in range(4) for c in range(2)]
    axes.append(fig.add_subplot(grid[4, :]))
    return fig, axes


def _finish_panels(axes: list, t: np.ndarray, unit: str) -> None:
    axes[6].set_title("head tilt (deg)", fontsize=10)
    axes[7].set_title("head turn (white: no call)", fontsize=10)
    axes[8].set_ylim(0, 4)
    axes[8].set_yticks([0, 2, 4])
    axes[8].set_title("symmetry calls uncertain in the frame (of 4: upper arm, forearm, thigh, shank)", fontsize=10)
    for ax in axes:
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_xlim(t[0], t[-1]) if len(t) > 1 else None
    for ax in axes[6:]:
        ax.set_xlabel(f"time ({unit})", fontsize=9)


def epoch_summary_figure(a: Analysis, ep: Epochs) -> str:
    """Inline SVG of a long track by epochs: per joint angle and side the median of each epoch (line) and its
    middle half (band), the head's tilt (median) and turn (each call's share), the uncertain calls (mean); epochs
    with over SHADE_SHARE of their frames flagged too fast or depth-ambiguous shaded."""
    fig, axes = _panels()
    minutes = ep.t / 60.0
    ambiguous, flagged = (ep.mean(flags(a)) > SHADE_SHARE for flags in (depth_ambiguous, too_fast))
    for ax in axes[:7]:
        _shade(ax, minutes, ambiguous, flagged)
    for ax, base in zip(axes[:6], ANGLE_BASES, strict=True):
        for side, colour in zip(SIDES, (LEFT_HEX, RIGHT_HEX), strict=True):
            low, mid, high = ep.quartiles(a.values[angle_name(side, base)])
            ax.fill_between(minutes, low, high, color=colour, alpha=0.2, lw=0)
            ax.plot(minutes, mid, color=colour, lw=1.2, marker=".", ms=3, label=side)
        ax.set_title(base.replace("_", " ") + f" (deg; median of each {ep.seconds:g} s, band: middle half)",
                     fontsize=10)  # fmt: skip
        ax.legend(fontsize=8, loc="upper right")
    tilt = ep.quartiles(a.head.tilt_deg)[1] if a.head is not None else np.full(len(ep.t), np.nan)
    if np.isfinite(tilt).any():
        axes[6].plot(minutes, tilt, color="#444444", lw=1.1, marker=".", ms=3)
    else:
        _empty(axes[6], "no head tilt: the input has no usable face points")
    calls = a.head.turn_call.astype(str) if a.head is not None else np.full(len(a.index), "")
    if (calls != "").any():
        below = np.zeros(len(ep.t))
        for c in TURN_CALLS:
            share = np.nan_to_num(ep.mean(calls == c))
            axes[7].fill_between(minutes, below, below + share, step="mid", color=_TURN_COLOURS[c], lw=0, label=c)
            below = below + share
        axes[7].legend(fontsize=8, loc="upper right", ncol=3)
        axes[7].set_ylim(0, 1.35)
        axes[7].set_yticks([])
    else:
        _empty(axes[7], "no head turn: the input has no usable face points")
    axes[8].fill_between(minutes, 0, np.nan_to_num(ep.mean(uncertain(a))), step="mid", color="#e0b000", alpha=0.7,
                         lw=0)  # fmt: skip
    _finish_panels(axes, minutes, "min")
    return svg(fig)


def time_series_figure(a: Analysis, person: int) -> str:
    """Inline SVG: each joint angle left and right with its interval as a band, the head's tilt, the head
    turn as a strip of colours, and how many symmetry calls are uncertain; frames too fast shaded red (a track
    over SUMMARY_OVER_S is drawn by `epoch_summary_figure` instead: `time_series_section`)."""
    d = decimate(a, person)
    fig, axes = _panels()
    for ax, base in zip(axes[:6], ANGLE_BASES, strict=True):
        _shade(ax, d.t, d.ambiguous, d.flagged)
        for side, colour in zip(SIDES, (LEFT_HEX, RIGHT_HEX), strict=True):
            name = angle_name(side, base)
            low, high = (x[d.take] for x in a.intervals[name])
            ax.fill_between(d.t, low, high, color=colour, alpha=0.18, lw=0)
            ax.plot(d.t, a.values[name][d.take], color=colour, lw=1.1, label=side)
        ax.set_title(base.replace("_", " ") + " (deg; band: interval)", fontsize=10)
        ax.legend(fontsize=8, loc="upper right")
    tilt_ax, turn_ax, calls_ax = axes[6], axes[7], axes[8]
    _shade(tilt_ax, d.t, d.ambiguous, d.flagged)
    tilt = a.head.tilt_deg[d.take] if a.head is not None else np.full(len(d.t), np.nan)
    turn = a.head.turn_call[d.take].astype(str) if a.head is not None else np.full(len(d.t), "")
    if np.isfinite(tilt).any():
        tilt_ax.plot(d.t, tilt, color="#444444", lw=1.1)
    else:
        _empty(tilt_ax, "no head tilt: the input has no usable face points")
    if (turn != "").any():
        for c in TURN_CALLS:
            turn_ax.fill_between(d.t, 0, 1, where=turn == c, step="mid", color=_TURN_COLOURS[c], lw=0, label=c)
        turn_ax.legend(fontsize=8, loc="upper right", ncol=3)
        turn_ax.set_ylim(0, 1.35)
        turn_ax.set_yticks([])
    else:
        _empty(turn_ax, "no head turn: the input has no usable face points")
    calls_ax.fill_between(d.t, 0, uncertain(a)[d.take], step="mid", color="#e0b000", alpha=0.7, lw=0)
    _finish_panels(axes, d.t, "s")
    return svg(fig)


def time_series_section(a: Analysis) -> str:
    res = a.result
    people, counts = np.unique(res.person[a.index], return_counts=True)
    person = int(people[np.argmax(counts)])
    n = int(counts.max())
    step = max(1, -(-n // MAX_POINTS))
    which = f" Person {person}, the longest track." if len(people) > 1 else ""
    thin = f" Every {step}th frame is drawn (shading covers every frame)." if step > 1 else ""
    bound = a.settings.max_velocity_deg_s
    flagged = (f"frames <b style='background:{FLAG_SHADE}'>flagged too fast</b> (a joint angle changing faster "
               f"than {bound:g} deg/s, likely a detection error){_ambiguous_words(a)}")  # fmt: skip
    ep = epochs_of(a, person)
    if ep is not None:
        return ("<h2>Over time</h2><p class=meta>The track lasts "
                f"{(ep.t[-1] - ep.t[0] + ep.seconds) / 60:.0f} minutes, so it is drawn by epochs of {ep.seconds:g} s: "
                "per joint angle, left (blue) and right (orange), the median of each epoch (line) and the middle half "
                f"of its frames' values (band); shaded: epochs with over {SHADE_SHARE:.0%} of their {flagged}. The "
                "bottom strip is the mean number of uncertain symmetry calls per frame in each epoch; the minute-by-"
                f"minute shares above and the frames to review below go with it.{which}</p>"
                f"<div class=figs>{epoch_summary_figure(a, ep)}</div>")  # fmt: skip
    return ("<h2>Over time</h2><p class=meta>Joint angles left (blue) and right (orange), each with its interval "
            f"as a band; shaded: {flagged}. The bottom strip counts the frame's uncertain symmetry calls: where it is "
            f"high, the 2D view leaves the posture open (the frames to review, below).{which}{thin}</p>"
            f"<div class=figs>{time_series_figure(a, person)}</div>")  # fmt: skip


def _ambiguous_words(a: Analysis) -> str:
    if not depth_ambiguous(a).any():
        return ""
    return (f" and <b style='background:{AMBIGUOUS_SHADE}'>a limb's depth side ambiguous</b> (the 2D cannot tell "
            "whether it points towards or away from the camera; the lift kept one side)")  # fmt: skip


# --- frames to review -------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Review:
    position: int  # in a.index
    frame_index: int
    person: int
    time_s: float
    uncertain: int  # symmetry calls uncertain (of 4)
    flagged: bool  # a joint angle too fast
    score: float  # how undecided: higher first


def review_picks(a: Analysis, count: int = MAX_REVIEW) -> list[Review]:
    """Up to `count` poses to look at: those with an uncertain call or a too-fast angle, one from each of
    `count` equal stretches of the candidates (spread over the clip), most undecided first. Without a
    measure calibration only the flagged frames are candidates."""
    res = a.result
    fast = too_fast(a)
    # without a calibration every call is uncertain by default, not because the view leaves it open
    unc = uncertain(a) if a.uncertainty_available else np.zeros(len(a.index), int)
    closeness = np.zeros(len(a.index))  # how near each call's probability is to a coin toss, summed
    for n in SYMMETRY_NAMES:
        prob = a.probabilities.get(n)
        if prob is not None:
            closeness += np.nan_to_num(1.0 - 2.0 * np.abs(prob - 0.5), nan=0.0)
    score = unc + closeness / len(SYMMETRY_NAMES) + 0.5 * fast
    cand = np.flatnonzero((unc > 0) | fast)
    if not len(cand):
        return []
    cand = cand[np.argsort(res.frame_index[a.index][cand], kind="stable")]
    picks = [int(part[np.argmax(score[part])]) for part in np.array_split(cand, min(count, len(cand)))]
    picks.sort(key=lambda k: -score[k])
    fps = float(a.fps or 1.0)
    return [Review(k, int(res.frame_index[a.index[k]]), int(res.person[a.index[k]]),
                   float(res.frame_index[a.index[k]]) / fps, int(unc[k]), bool(fast[k]), float(score[k]))
            for k in picks]  # fmt: skip


def _why(r: Review) -> str:
    parts = []
    if r.uncertain:
        parts.append(f"{r.uncertain} of 4 symmetry calls uncertain")
    if r.flagged:
        parts.append("a joint angle flagged too fast")
    return "; ".join(parts)


def review_section(a: Analysis, picks: list[Review], thumbnails: dict[int, bytes] | None = None,
                   footage_note: str = "") -> str:  # fmt: skip
    """The frames to review: thumbnails cut from the footage where given, else a list of frames and times."""
    if not picks:
        return ("<h2>Frames to review</h2><p class=meta>None: every symmetry call is decided and no joint angle "
                "was flagged too fast.</p>")  # fmt: skip
    thumbnails = thumbnails or {}
    intro = (f"<h2>Frames to review</h2><p class=meta>{len(picks)} frames spread over the clip, the most "
             "undecided first: the footage settles what the 2D keypoints could not.")  # fmt: skip
    if thumbnails:
        cards = []
        for r in picks:
            png = thumbnails.get(r.frame_index)
            img = (f"<img alt='frame {r.frame_index}' src='data:image/png;base64,{base64.b64encode(png).decode()}'>"
                   if png else "<div class=meta>(not in the footage)</div>")  # fmt: skip
            cards.append(f"<figure class=thumb>{img}<figcaption>frame {r.frame_index} · {r.time_s:.2f} s · "
                         f"person {r.person}<br><small>{escape(_why(r))}</small></figcaption></figure>")  # fmt: skip
        return f"{intro}</p><div class=thumbs>{''.join(cards)}</div>"
    rows = "".join(f"<tr><td>{r.frame_index}</td><td>{r.time_s:.2f}</td><td>{r.person}</td>"
                   f"<td class=l>{escape(_why(r))}</td></tr>" for r in picks)  # fmt: skip
    hint = (
        footage_note or "Give the footage with <code>--video FILE</code> or <code>--images DIR</code> for thumbnails."
    )
    return (f"{intro} {hint}</p><table><tr><th>frame</th><th>time (s)</th><th>person</th>"
            f"<th class=l>why</th></tr>{rows}</table>")  # fmt: skip
