"""The HTML report of an analysis: one self-contained file a clinician can open offline.

Everything is inline (CSS in the page, figures as inline SVG drawn by matplotlib's Agg/SVG
backend, no script, no font or CDN link), so the file can be mailed or archived as it is.
Sections: the input and settings (and, prominently, whether 90 % intervals were available),
the symmetry summary, skeleton views of a few frames with the mirrored right limbs, for a
video the time series of the symmetry and joint angles and the movement features, then the
per-frame symmetry table with its calls and the joint-angle table.

matplotlib is imported inside the functions: `zedo analyze` without `--report` never loads it.
"""

from __future__ import annotations

import html
import io
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..files import write_text_atomic
from ..version import __version__
from .analyse import SYMMETRY_NAMES, Analysis, poses_counted, summary
from .geometry import joint, reflect, unit
from .joint_angles import ANGLE_BASES, ANGLE_NAMES, SIDES, angle_name
from .symmetry import PAIRS

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..data.skeleton import Skeleton

MAX_TABLE_ROWS = 300  # per table; the CSV has every row
MAX_SKELETONS = 6
LEFT, RIGHT, MIRROR, CENTRE = "#1f77b4", "#d62728", "#e377c2", "#555555"
_CALL_CLASS = {"symmetric": "sym", "asymmetric": "asym", "uncertain": "unc"}
_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:24px auto;max-width:1150px;color:#222}
h1{font-size:22px;margin-bottom:4px} h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}
table{border-collapse:collapse;font-size:12.5px;margin:6px 0}
td,th{border:1px solid #ddd;padding:3px 7px;text-align:right}
th{background:#f3f3f3} td.l,th.l{text-align:left} .meta{color:#555;font-size:13px}
.note{padding:8px 12px;border-radius:4px;margin:10px 0;font-size:13.5px}
.warn{background:#fff4d6;border:1px solid #e8c15a} .ok{background:#e9f6ec;border:1px solid #8cc79a}
td.sym,li.sym{background:#e3f4e6} td.asym,li.asym{background:#fbe1df} td.unc,li.unc{background:#fff1c9}
.figs{display:flex;flex-wrap:wrap;gap:8px} .figs svg{height:auto;max-width:100%}
small{color:#666}
"""


def _esc(value: Any) -> str:
    return html.escape("" if value is None else str(value))


def _fmt(value: float, digits: int = 1) -> str:
    return f"{value:.{digits}f}" if np.isfinite(value) else "–"


def _svg(fig: Figure) -> str:
    buf = io.StringIO()
    fig.savefig(buf, format="svg")
    text = buf.getvalue()
    return text[text.index("<svg") :]  # drop the XML prolog and doctype: inline SVG


def _figure(width: float, height: float) -> Figure:
    import matplotlib

    matplotlib.rcParams["svg.fonttype"] = "none"  # text as text: smaller files, crisp labels
    from matplotlib.backends.backend_svg import FigureCanvasSVG
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=72, layout="constrained")
    FigureCanvasSVG(fig)
    return fig


def _skeleton_frames(a: Analysis) -> list[int]:
    """Positions (in a.index) of the persons drawn: for a video the first, middle and last
    frames; otherwise the first frames and the most asymmetric ones."""
    m = len(a.index)
    if a.is_sequence:
        picks = [0, m // 2, m - 1]
    else:
        worst = np.nanmax(np.stack([a.values[n] for n in SYMMETRY_NAMES]), axis=0)
        order = np.argsort(-np.nan_to_num(worst, nan=-1.0), kind="stable")
        picks = list(range(min(3, m))) + [int(i) for i in order[:MAX_SKELETONS]]
    return list(dict.fromkeys(picks))[:MAX_SKELETONS]


def _mirrored_segments(pose: np.ndarray, skel: Skeleton) -> np.ndarray:
    """`(pairs, 2, 3)`: each pair's right segment mirrored through the mid-plane (its two ends)."""
    segments = []
    for p, d, base in PAIRS.values():
        normal = unit(joint(pose, skel, f"left_{base}") - joint(pose, skel, f"right_{base}"))
        centre = (joint(pose, skel, f"left_{base}") + joint(pose, skel, f"right_{base}")) / 2
        segments.append([centre + reflect(joint(pose, skel, f"right_{x}") - centre, normal) for x in (p, d)])
    return np.asarray(segments)


def _view_half_width(pose: np.ndarray, skel: Skeleton) -> float:
    """Half the side of a root-centred view that holds the pose and its mirrored right limbs,
    which can reach further (a limb along the depth axis, mirrored through a tilted mid-plane,
    turns into the image plane), with a 10 % margin."""
    return 1.1 * float(np.nanmax(np.abs(np.concatenate([pose, *_mirrored_segments(pose, skel)]))))


def _draw_pose(ax: Axes, pose: np.ndarray, a: Analysis, h: int, v: int, title: str, half: float) -> None:
    skel = a.result.skeleton
    for i, j in skel.bones:
        names = skel.joints[i] + skel.joints[j]
        colour = LEFT if names.count("left_") == 2 else RIGHT if names.count("right_") == 2 else CENTRE
        ax.plot(pose[[i, j], h], pose[[i, j], v], color=colour, lw=2.2, solid_capstyle="round")
    for ends in _mirrored_segments(pose, skel):
        ax.plot(ends[:, h], ends[:, v], color=MIRROR, lw=2.0, ls=(0, (3, 2)))
    ax.set_xlim(-half, half)
    ax.set_ylim(half, -half)  # y (down) and z: drawn with the head / the camera side up
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)
    for spine in ax.spines.values():
        spine.set_color("#bbbbbb")


def skeleton_views(a: Analysis) -> list[str]:
    """Inline SVGs, one per chosen person: the camera view and the side view (root-centred)."""
    res = a.result
    out = []
    for k in _skeleton_frames(a):
        i = a.index[k]
        pose = res.poses[i] - np.nanmean(res.poses[i, res.skeleton.root_indices], axis=0)
        half = _view_half_width(pose, res.skeleton)
        fig = _figure(5.0, 3.0)
        axes = fig.subplots(1, 2)
        label = f"frame {res.frame_index[i]}" + (f" · {res.file_names[i]}" if res.file_names[i] else "")
        angles = "  ".join(f"{_short(n)} {_fmt(a.values[n][k], 0)}°" for n in SYMMETRY_NAMES)
        fig.suptitle(f"{label}, person {res.person[i]}\n{angles}", fontsize=10)
        _draw_pose(axes[0], pose, a, 0, 1, "camera view", half)
        _draw_pose(axes[1], pose, a, 2, 1, "side view (depth → right)", half)
        out.append(_svg(fig))
    return out


def _short(name: str) -> str:
    return {"upper_arm": "UA", "forearm": "FA", "thigh": "TH", "shank": "SH"}[
        name.removeprefix("symmetry_").removesuffix("_deg")
    ]


def time_series(a: Analysis) -> str:
    """Inline SVG: the symmetry angles over time (threshold dashed), then each joint angle,
    left and right, per person track."""
    res = a.result
    fig = _figure(11.5, 9.0)
    axes = fig.subplots(4, 2).ravel()
    t_of = res.frame_index[a.index] / float(a.fps or 1.0)
    people = res.person[a.index]
    for p in sorted(set(people.tolist())):
        sel = people == p
        suffix = f" (person {p})" if len(set(people.tolist())) > 1 else ""
        for n in SYMMETRY_NAMES:
            axes[0 if n in SYMMETRY_NAMES[:2] else 1].plot(
                t_of[sel], a.values[n][sel], lw=1.3, label=_short(n) + suffix
            )
        for ax, base in zip(axes[2:], ANGLE_BASES, strict=True):
            for side, colour in zip(SIDES, (LEFT, RIGHT), strict=True):
                ax.plot(t_of[sel], a.values[angle_name(side, base)][sel], color=colour, lw=1.2, label=side + suffix)
            ax.set_title(base.replace("_", " ") + " (deg)", fontsize=10)
    for ax, title in zip(axes[:2], ("symmetry angle, arms (deg)", "symmetry angle, legs (deg)"), strict=True):
        ax.axhline(a.settings.threshold_deg, color="0.4", ls="--", lw=1)
        ax.set_title(title + f"; dashed: threshold {a.settings.threshold_deg:g}", fontsize=10)
    for ax in axes:
        ax.legend(fontsize=8, loc="upper right")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_xlabel("time (s)", fontsize=9)
    return _svg(fig)


def _symmetry_summary(a: Analysis) -> str:
    stats = summary(a)
    head = "<tr><th class=l>pair</th><th>mean</th><th>median</th><th>symmetric</th><th>asymmetric</th>" \
           "<th>uncertain</th><th>band 1 (&lt;30)</th><th>band 2 (30–60)</th><th>band 3 (≥60)</th></tr>"  # fmt: skip
    rows = []
    for n in SYMMETRY_NAMES:
        s = stats[n]
        pair = n.removeprefix("symmetry_").removesuffix("_deg").replace("_", " ")
        rows.append(f"<tr><td class=l>{pair}</td><td>{_fmt(s.get('mean', np.nan))}°</td>"
                    f"<td>{_fmt(s.get('median', np.nan))}°</td><td>{s['symmetric']}</td><td>{s['asymmetric']}</td>"
                    f"<td>{s['uncertain']}</td>"
                    f"<td>{s['band_1']}</td><td>{s['band_2']}</td><td>{s['band_3']}</td></tr>")  # fmt: skip
    return f"<table>{head}{''.join(rows)}</table>"


def _cell(a: Analysis, name: str, k: int, call: str = "") -> str:
    v = a.values[name][k]
    text = _fmt(v)
    low, high = a.intervals[name][0][k], a.intervals[name][1][k]
    if np.isfinite(low) and np.isfinite(high):
        text += f" <small>[{_fmt(low)}, {_fmt(high)}]</small>"
    if call:
        text += f" <small>{call}</small>"
    return f"<td class={_CALL_CLASS.get(call, '')}>{text}</td>"


def _frame_tables(a: Analysis) -> tuple[str, str]:
    res = a.result
    calls = {(r.frame_index, r.person, r.measure): r.call for r in a.rows if r.measure in SYMMETRY_NAMES}
    head = "<th>frame</th><th class=l>image</th><th>person</th>"
    sym = [f"<tr>{head}" + "".join(f"<th>{_esc(n.removeprefix('symmetry_').removesuffix('_deg'))}</th>"
                                   for n in SYMMETRY_NAMES) + "</tr>"]  # fmt: skip
    ang = [f"<tr>{head}" + "".join(f"<th>{_esc(n.removesuffix('_deg').replace('_', ' '))}</th>" for n in ANGLE_NAMES)
           + "</tr>"]  # fmt: skip
    for k, i in enumerate(a.index[:MAX_TABLE_ROWS]):
        f, p = int(res.frame_index[i]), int(res.person[i])
        image = res.file_names[i] or res.image_ids[i]
        lead = f"<td>{f}</td><td class=l>{_esc(image)}</td><td>{p}</td>"
        sym.append(f"<tr>{lead}" + "".join(_cell(a, n, k, calls.get((f, p, n), "")) for n in SYMMETRY_NAMES) + "</tr>")
        ang.append(f"<tr>{lead}" + "".join(_cell(a, n, k) for n in ANGLE_NAMES) + "</tr>")
    more = ""
    if len(a.index) > MAX_TABLE_ROWS:
        more = f"<p class=meta>The first {MAX_TABLE_ROWS} of {len(a.index)} poses; the CSV has them all.</p>"
    return f"<table>{''.join(sym)}</table>{more}", f"<table>{''.join(ang)}</table>{more}"


def _movement_table(a: Analysis) -> str:
    rows = {(r.person, r.measure): r.value for r in a.rows if r.frame_index is None}
    people = sorted({p for p, _ in rows})
    if not people:
        return "<p class=meta>Too few lifted frames for movement features.</p>"
    out = ["<tr><th>person</th><th class=l>angle</th><th>median |velocity| L / R (deg/s)</th>"
           "<th>IQR |velocity| L / R (deg/s)</th><th>range L / R (deg)</th><th>left-right r</th></tr>"]  # fmt: skip
    for p in people:
        for base in ANGLE_BASES:

            def pair(kind: str, base: str = base, p: int = p) -> str:
                return " / ".join(_fmt(rows.get((p, f"{side}_{base}_{kind}"), np.nan)) for side in SIDES)

            r = rows.get((p, f"{base}_left_right_correlation"), np.nan)
            out.append(f"<tr><td>{p}</td><td class=l>{base.replace('_', ' ')}</td>"
                       f"<td>{pair('median_abs_velocity_deg_s')}</td><td>{pair('abs_velocity_iqr_deg_s')}</td>"
                       f"<td>{pair('range_deg')}</td><td>{_fmt(r, 2)}</td></tr>")  # fmt: skip
    return f"<table>{''.join(out)}</table>"


def _pair_label(name: str) -> str:
    return name.removeprefix("symmetry_").removesuffix("_deg").replace("_", " ")


def _decisions(a: Analysis) -> str:
    """The calls first: what can be acted on, and what "uncertain" means here."""
    thr = a.settings.threshold_deg
    level = f"{a.settings.level:.0%}"
    if not a.uncertainty_available:
        return ("<div class='note warn'><b>No decisive calls.</b> No measure calibration holds for this result ("
                f"{_esc(a.calibration_note)}), so no interval backs a call: every symmetry call is "
                "<b>uncertain</b>. The values below are the measures of the lifted pose, without "
                "intervals.</div>")  # fmt: skip
    summ = summary(a)
    head = ("<tr><th class=l>pair</th><th>symmetric</th><th>asymmetric</th><th>uncertain</th>"
            "<th>decisive</th></tr>")  # fmt: skip
    rows = []
    for n in SYMMETRY_NAMES:
        c = summ[n]
        total = c["symmetric"] + c["asymmetric"] + c["uncertain"]
        share = (c["symmetric"] + c["asymmetric"]) / total if total else np.nan
        rows.append(f"<tr><td class=l>{_pair_label(n)}</td><td class=sym>{c['symmetric']}</td>"
                    f"<td class=asym>{c['asymmetric']}</td><td class=unc>{c['uncertain']}</td>"
                    f"<td>{_fmt(100 * share)} %</td></tr>")  # fmt: skip
    call_level = f"{a.settings.call_level:.0%}"
    miss = f"{(1 - a.settings.call_level) / 2:.0%}"
    explain = (f"<p><b>Symmetric</b> / <b>asymmetric</b>: the {call_level} interval of the symmetry angle (the "
               f"one listed below) lies wholly below / above {thr:g}°; each of its ends missed the true angle at "
               f"most {miss} of the time on infants the calibration never saw, and such calls agreed with the "
               "reference call 88-95 % of the time on held-out infants and on SyRIP Test100 (docs/clinical.md). "
               f"<b>Uncertain</b>: that interval includes {thr:g}°, so the image does not "
               "settle the question, usually because the limbs point towards or away from the camera and their "
               "depth is guessed by the prior. Uncertain cases are for a person to look at (the footage, or "
               f"another view); they are not evidence either way. The tables and the CSV also give the {level} "
               "interval (low_90, high_90).</p>")  # fmt: skip
    listed = []
    if len(a.index) <= 12:  # a few images: spell each case out
        by_case = {(r.frame_index, r.person, r.measure): r for r in a.rows if r.measure in SYMMETRY_NAMES}
        for i in a.index:
            f, p = int(a.result.frame_index[i]), int(a.result.person[i])
            image = a.result.file_names[i] or a.result.image_ids[i]
            items = []
            for n in SYMMETRY_NAMES:
                r = by_case[(f, p, n)]
                what = (f"{_fmt(r.value)}° [{_fmt(r.call_low)}, {_fmt(r.call_high)}]" if np.isfinite(r.call_low)
                        else f"{_fmt(r.value)}° ({_esc(r.interval)})")  # fmt: skip
                items.append(f"<li class={_CALL_CLASS.get(r.call, '')}><b>{_pair_label(n)}: {r.call}</b> {what}</li>")
            items.sort(key=lambda t: "uncertain" in t)  # the decisive calls first
            listed.append(f"<p class=meta>{_esc(image)}, person {p}</p><ul>{''.join(items)}</ul>")
    return f"<h2>Decisions</h2><table>{head}{''.join(rows)}</table>{explain}{''.join(listed)}"


def report_html(a: Analysis) -> str:
    """The whole report as one HTML string."""
    res = a.result
    box = _decisions(a)
    notes = "".join(f"<li>{_esc(n)}</li>" for n in a.notes[1:])  # the first is the calibration note
    fps = f"{a.fps:g} fps ({a.fps_source})" if a.fps else "none: frames analysed as separate images"
    sym_table, angle_table = _frame_tables(a)
    counted = poses_counted(res.frame_index[a.index], res.person[a.index])
    parts = [
        "<!DOCTYPE html><html lang=en><head><meta charset=utf-8>",
        f"<title>zedo analyze: {_esc(Path(res.source).name)}</title><style>{_CSS}</style></head><body>",
        f"<h1>Postural symmetry and joint angles: {_esc(Path(res.source).name)}</h1>",
        f"<p class=meta>{_esc(res.source)} · {res.format} · skeleton {res.skeleton.name} · {counted} analysed · "
        f"frame rate: {_esc(fps)} · symmetric at ≤ {a.settings.threshold_deg:g}° · zedo {__version__} · "
        f"{datetime.now(UTC):%Y-%m-%d %H:%M} UTC</p>",
        box,
        f"<ul class=meta>{notes}</ul>" if notes else "",
        "<h2>Symmetry</h2><p class=meta>Angle between the left segment and the right one mirrored through the "
        "body's mid-plane (shoulders for the arms, hips for the legs); 0° = mirror-symmetric (Huang et al. 2022). "
        "Bands as in that paper.</p>",
        _symmetry_summary(a),
        "<h2>Skeleton views</h2><p class=meta>Root-centred; <b style='color:#1f77b4'>blue</b> = left, "
        "<b style='color:#d62728'>red</b> = right, <b style='color:#e377c2'>dashed pink</b> = the right limbs "
        "mirrored onto the left side: where they differ from the blue limbs, the posture is asymmetric. "
        "UA upper arm, FA forearm, TH thigh, SH shank: symmetry angles. "
        + ("First, middle and last frames." if a.is_sequence else "The first frames and the most asymmetric ones.")
        + "</p>",
        f"<div class=figs>{''.join(skeleton_views(a))}</div>",
    ]  # fmt: skip
    if a.is_sequence:
        parts += ["<h2>Time series</h2>", f"<div class=figs>{time_series(a)}</div>",
                  "<h2>Movement features</h2>", _movement_table(a)]  # fmt: skip
    parts += [
        "<h2>Symmetry per frame</h2><p class=meta>degrees"
        + (f" [{a.settings.level:.0%} interval]" if a.uncertainty_available else "") + " and call.</p>", sym_table,
        "<h2>Joint angles per frame</h2><p class=meta>degrees. Knee / elbow flexion: 0 = straight. Hip / "
        "shoulder flexion: from straight down the trunk, positive forward; abduction: positive away from the "
        "midline (trunk frame from the hips and shoulders; docs/clinical.md).</p>", angle_table,
        "<p class=meta>Self-contained page (no network): figures are inline SVG.</p></body></html>",
    ]  # fmt: skip
    return "\n".join(parts) + "\n"


def write_report(a: Analysis, out: str | Path, *, overwrite: bool = False) -> Path:
    """Write the report to `out` atomically; an existing file only with `overwrite`."""
    write_text_atomic(out, report_html(a), overwrite=overwrite)
    return Path(out)
