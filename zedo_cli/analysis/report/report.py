"""The HTML report of an analysis: one self-contained file a clinician can open offline.

Everything is inline (CSS in the page, figures as inline SVG drawn by matplotlib's Agg/SVG
backend, no script, no font or CDN link), so the file can be mailed or archived as it is.
The page is a list of sections (`report_sections`), each made by one small function of the
`Analysis`: the title and input, the research-use notice, the decisions (the calls, the rule
they follow in plain words, each case for a few images), the notes, the symmetry values and the
paper's bands, skeleton views of a few frames with the mirrored right limbs, for a video the
time series and the movement features, then the per-frame symmetry table (each value with the
interval that decides its call) and the joint-angle table. A new section is one more function
in that list.

Left and right are drawn in the colours of `zedo render` and the pose plots (`formats.colours`).
matplotlib is imported inside the functions: `zedo analyze` without `--report` never loads it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...files import write_text_atomic
from ...formats.colours import CENTRE_HEX, LEFT_HEX, RIGHT_HEX, side_hex
from ...version import __version__
from ..analyse import SYMMETRY_NAMES, Analysis, no_calibration_note, poses_counted, summary
from ..pose.geometry import joint, reflect, unit
from ..pose.joint_angles import ANGLE_BASES, ANGLE_NAMES, SIDES, angle_name
from ..pose.symmetry import BAND_EDGES_DEG, PAIRS
from .clip_report import MAX_POINTS, Review, review_picks, review_section, summary_section, time_series_section
from .epochs import Epochs, epochs_of
from .figures import figure, svg
from .markup import escape

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ...data.skeleton import Skeleton

MAX_TABLE_ROWS = 300  # per table; the CSV has every row
MAX_SKELETONS = 6
MIRROR = "#e377c2"  # dashed pink: the right limbs mirrored onto the left side
PAIR_COLOURS = ("#2ca02c", "#9467bd")  # the two pairs of a time-series panel: neither side's blue nor orange
_CALL_CLASS = {"symmetric": "sym", "asymmetric": "asym", "uncertain": "unc"}
_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:24px auto;max-width:1150px;color:#222}
h1{font-size:22px;margin-bottom:4px} h2{font-size:17px;margin-top:28px;border-bottom:1px solid #ddd}
table{border-collapse:collapse;font-size:12.5px;margin:6px 0}
td,th{border:1px solid #ddd;padding:3px 7px;text-align:right}
th{background:#f3f3f3} td.l,th.l{text-align:left} .meta{color:#555;font-size:13px}
.note{padding:8px 12px;border-radius:4px;margin:10px 0;font-size:13.5px}
.warn{background:#fff4d6;border:1px solid #e8c15a} .ok{background:#e9f6ec;border:1px solid #8cc79a}
.notice{background:#eef3fb;border:1px solid #9db4d8}
td.sym,li.sym{background:#e3f4e6} td.asym,li.asym{background:#fbe1df} td.unc,li.unc{background:#fff1c9}
.figs{display:flex;flex-wrap:wrap;gap:8px} .figs svg{height:auto;max-width:100%}
small{color:#666;white-space:nowrap} th small{font-weight:normal} p.rule{font-size:14.5px}
table.wide{font-size:11.5px} .scroll{overflow-x:auto}
.thumbs{display:flex;flex-wrap:wrap;gap:10px} figure.thumb{margin:0;width:270px;font-size:12.5px}
figure.thumb img{width:270px;border:1px solid #ccc} figure.thumb small{white-space:normal}
ul.far{font-size:14px;margin-top:2px}
"""


def _fmt(value: float, digits: int = 1) -> str:
    return f"{value:.{digits}f}" if np.isfinite(value) else "–"


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
        colour = side_hex(skel.joints[i], skel.joints[j])
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
        fig = figure(5.0, 3.0)
        axes = fig.subplots(1, 2)
        label = f"frame {res.frame_index[i]}" + (f" · {res.file_names[i]}" if res.file_names[i] else "")
        angles = "  ".join(f"{_short(n)} {_fmt(a.values[n][k], 0)}°" for n in SYMMETRY_NAMES)
        fig.suptitle(f"{label}, person {res.person[i]}\n{angles}", fontsize=10)
        _draw_pose(axes[0], pose, a, 0, 1, "camera view", half)
        _draw_pose(axes[1], pose, a, 2, 1, "side view (depth → right)", half)
        out.append(svg(fig))
    return out


def _short(name: str) -> str:
    return {"upper_arm": "UA", "forearm": "FA", "thigh": "TH", "shank": "SH"}[
        name.removeprefix("symmetry_").removesuffix("_deg")
    ]


def time_series(a: Analysis) -> str:
    """Inline SVG: the symmetry angles over time (threshold dashed), then each joint angle,
    left and right, per person track (a track over SUMMARY_OVER_S by its epochs' medians)."""
    res = a.result
    fig = figure(11.5, 9.0)
    axes = fig.subplots(4, 2).ravel()
    step = max(1, -(-len(a.index) // MAX_POINTS))  # a long clip drawn decimated: the figure stays small
    t_of = res.frame_index[a.index] / float(a.fps or 1.0)
    people = res.person[a.index]
    thin = np.zeros(len(a.index), bool)
    thin[::step] = True
    tracks = sorted(set(people.tolist()))
    for p, style in zip(tracks, ["-", "--", ":", "-."] * len(tracks), strict=False):
        sel = (people == p) & thin
        ep = epochs_of(a, p)
        suffix = (f" (person {p})" if len(tracks) > 1 else "") + (f", median of each {ep.seconds:g} s" if ep else "")

        def series(values: np.ndarray, sel: np.ndarray = sel, ep: Epochs | None = ep) -> tuple[np.ndarray, np.ndarray]:
            return (ep.t, ep.quartiles(values)[1]) if ep is not None else (t_of[sel], values[sel])

        for k, n in enumerate(SYMMETRY_NAMES):
            axes[k // 2].plot(*series(a.values[n]), color=PAIR_COLOURS[k % 2], ls=style, lw=1.3,
                              label=_short(n) + suffix)  # fmt: skip
        for ax, base in zip(axes[2:], ANGLE_BASES, strict=True):
            for side, colour in zip(SIDES, (LEFT_HEX, RIGHT_HEX), strict=True):
                ax.plot(*series(a.values[angle_name(side, base)]), color=colour, ls=style, lw=1.2,
                        label=side + suffix)  # fmt: skip
            ax.set_title(base.replace("_", " ") + " (deg)", fontsize=10)
    for ax, title in zip(axes[:2], ("symmetry angle, arms (deg)", "symmetry angle, legs (deg)"), strict=True):
        ax.axhline(a.settings.threshold_deg, color="0.4", ls="--", lw=1)
        ax.set_title(title + f"; dashed: threshold {a.settings.threshold_deg:g}", fontsize=10)
    for ax in axes:
        ax.legend(fontsize=8, loc="upper right")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_xlabel("time (s)", fontsize=9)
    return svg(fig)


def _pair_label(name: str) -> str:
    return name.removeprefix("symmetry_").removesuffix("_deg").replace("_", " ")


def _level(value: float) -> str:
    return f"{value:.0%}".replace("%", " %")


def _interval(low: float, high: float, level: float) -> str:
    """`80 % interval [3.1, 25.0]`, or "" where there is none."""
    if not (np.isfinite(low) and np.isfinite(high)):
        return ""
    return f"{_level(level)} interval [{_fmt(low)}, {_fmt(high)}]"


def _no_interval(how: str) -> str:
    """The `interval` column's reason, as a reader wants it: "no interval: joint filled by the prior ..."."""
    return "no interval: " + how.removeprefix("none: ")


# --- sections, in page order (report_sections) ----------------------------------------------------


def _title(a: Analysis) -> str:
    res = a.result
    fps = f"{a.fps:g} fps ({a.fps_source})" if a.fps else "none: frames analysed as separate images"
    counted = poses_counted(res.frame_index[a.index], res.person[a.index])
    return (f"<h1>Postural symmetry and joint angles: {escape(Path(res.source).name)}</h1>"
            f"<p class=meta>{escape(res.source)} · {res.format} · skeleton {res.skeleton.name} · {counted} analysed · "
            f"frame rate: {escape(fps)} · symmetric at ≤ {a.settings.threshold_deg:g}° · zedo {__version__} · "
            f"{datetime.now(UTC):%Y-%m-%d %H:%M} UTC</p>")  # fmt: skip


def research_notice() -> str:
    """The first thing read after the title: what these figures are and are not."""
    return ("<div class='note notice'><b>For research; not a diagnosis.</b> These measures come from 3D poses "
            "that zedo estimated from 2D keypoints of ordinary images; zedo is a research tool, not a medical "
            "device, and its calls are not a clinical assessment. Read them beside the footage and a "
            "clinician's judgement. The bundled pose priors are trained on SyRIP, whose terms allow research / "
            "non-commercial use only.</div>")  # fmt: skip


def call_rule(a: Analysis) -> str:
    """The rule behind symmetric, asymmetric and uncertain, in plain words, then how far it can be trusted."""
    thr = f"{a.settings.threshold_deg:g}°"
    level = _level(a.settings.call_level)
    miss = _level((1 - a.settings.call_level) / 2)
    return (f"<p class=rule><b>How zedo calls a pair.</b> zedo calls a pair <b>symmetric</b> only when the whole "
            f"{level} interval of its symmetry angle lies at or below {thr}, and <b>asymmetric</b> only when the "
            f"whole interval lies above {thr}. When the interval includes {thr}, the pair is <b>uncertain</b>: "
            "the image does not settle the question, usually because the limbs point towards or away from the "
            "camera and their depth is the prior's guess. Uncertain cases are for a person to look at (the "
            "footage, another view); they are not evidence either way.</p>"
            f"<p class=meta>The interval printed beside each call in this report is that {level} interval. Each of "
            f"its ends missed the true angle at most {miss} of the time on held-out poses like the calibration's, and "
            "such calls agreed with the true call 79-97 % of the time on held-out poses of the calibration's two "
            "sources (least on single images of SyRIP's poses) and 88-91 % on SyRIP Test100 "
            "(docs/clinical.md).</p>")  # fmt: skip


def _case_list(a: Analysis) -> str:
    """For a few images: each case spelled out, the decisive calls first, each with its deciding interval."""
    if len(a.index) > 12:
        return ""
    listed = []
    for k, i in enumerate(a.index):
        p = int(a.result.person[i])
        image = a.result.file_names[i] or a.result.image_ids[i]
        items = []
        for n in SYMMETRY_NAMES:
            call, value = a.calls[n][k], a.values[n][k]
            low, high = (x[k] if np.isfinite(value) else np.nan for x in a.call_intervals[n])
            what = _interval(low, high, a.settings.call_level) or escape(_no_interval(a.interval_how[n][k]))
            items.append(f"<li class={_CALL_CLASS.get(call, '')}><b>{_pair_label(n)}: {call}</b> "
                         f"{_fmt(value)}° <small>({what})</small></li>")  # fmt: skip
        items.sort(key=lambda t: "uncertain" in t)  # the decisive calls first
        listed.append(f"<p class=meta>{escape(image)}, person {p}</p><ul>{''.join(items)}</ul>")
    return "".join(listed)


def _decisions(a: Analysis) -> str:
    """The calls first: what can be acted on, the rule they follow, and what "uncertain" means here."""
    if not a.uncertainty_available:
        return ("<h2>Decisions</h2><div class='note warn'><b>No decisive calls.</b> No measure calibration holds "
                f"for this result ({escape(a.calibration_note)}), so no interval backs a call: every symmetry call is "
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
    return f"<h2>Decisions</h2><table>{head}{''.join(rows)}</table>{call_rule(a)}{_case_list(a)}"


def _notes(a: Analysis) -> str:
    shown = set() if a.uncertainty_available else {no_calibration_note(a.calibration_note)}  # in the decisions
    notes = "".join(f"<li>{escape(n)}</li>" for n in a.notes if n not in shown)
    return f"<ul class=meta>{notes}</ul>" if notes else ""


def _bands_label() -> tuple[str, str, str]:
    low, high = (f"{e:g}" for e in BAND_EDGES_DEG)  # the paper's edges: 30 and 60 degrees
    return f"&lt; {low}°", f"{low}–{high}°", f"≥ {high}°"


def _symmetry_section(a: Analysis) -> str:
    """The values per pair, then how many fall in each of the paper's bands: a description of the
    angle's size, not a call (the calls are the decisions above)."""
    stats = summary(a)
    head = ("<tr><th></th><th colspan=5>the symmetry angle</th><th colspan=3>poses per band of Huang et al. "
            "(not the call)</th></tr><tr><th class=l>pair</th><th>poses</th><th>mean</th><th>median</th>"
            "<th>min</th><th>max</th>" + "".join(f"<th>{b}</th>" for b in _bands_label()) + "</tr>")  # fmt: skip
    rows = []
    for n in SYMMETRY_NAMES:
        s = stats[n]
        values = "".join(f"<td>{_fmt(s.get(k, np.nan))}°</td>" for k in ("mean", "median", "min", "max"))
        bands = "".join(f"<td>{s[f'band_{b}']}</td>" for b in (1, 2, 3))
        rows.append(f"<tr><td class=l>{_pair_label(n)}</td><td>{s['count']}</td>{values}{bands}</tr>")
    thr = f"{a.settings.threshold_deg:g}°"
    return ("<h2>Symmetry</h2><p class=meta>Angle between the left segment and the right one mirrored through the "
            "body's mid-plane (shoulders for the arms, hips for the legs); 0° = mirror-symmetric (Huang et al. "
            "2022). The last three columns count the poses by the <b>bands of that paper</b> "
            f"({', '.join(_bands_label())}): they describe how large the angle is, they are <b>not the call</b>, "
            f"which zedo makes on the interval at {thr} (Decisions, above).</p>"
            f"<table>{head}{''.join(rows)}</table>")  # fmt: skip


def _skeleton_section(a: Analysis) -> str:
    which = "First, middle and last frames." if a.is_sequence else "The first frames and the most asymmetric ones."
    return ("<h2>Skeleton views</h2><p class=meta>Root-centred; "
            f"<b style='color:{LEFT_HEX}'>blue</b> = left, <b style='color:{RIGHT_HEX}'>orange</b> = right (the "
            f"colours of zedo render), <b style='color:{CENTRE_HEX}'>grey</b> = between the sides, "
            f"<b style='color:{MIRROR}'>dashed pink</b> = the right limbs mirrored onto the left side: where they "
            "differ from the blue limbs, the posture is asymmetric. UA upper arm, FA forearm, TH thigh, SH shank: "
            f"symmetry angles. {which}</p><div class=figs>{''.join(skeleton_views(a))}</div>")  # fmt: skip


def _time_series_section(a: Analysis) -> str:
    return f"<h2>Symmetry angles and joint angles over time</h2><div class=figs>{time_series(a)}</div>"


def _movement_section(a: Analysis) -> str:
    rows = {(r.person, r.measure): r.value for r in a.clip_rows}
    people = sorted({p for p, _ in rows})
    if not people:
        return "<h2>Movement features</h2><p class=meta>Too few lifted frames for movement features.</p>"
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
    return f"<h2>Movement features</h2><table>{''.join(out)}</table>"


def _cell(value: float, low: float = np.nan, high: float = np.nan, call: str = "") -> str:
    text = _fmt(value)
    if np.isfinite(low) and np.isfinite(high):
        text += f" <small>[{_fmt(low)}, {_fmt(high)}]</small>"
    if call:
        text += f" <small>{call}</small>"
    return f"<td class={_CALL_CLASS.get(call, '')}>{text}</td>"


def _frame_rows(a: Analysis, names: tuple[str, ...], cell: Any) -> tuple[str, str]:
    """`<tr>`s of the first MAX_TABLE_ROWS poses (frame, image, person, then `cell(name, k, frame, person)`
    per measure) and the line that says when rows were left out."""
    res = a.result
    rows = []
    for k, i in enumerate(a.index[:MAX_TABLE_ROWS]):
        f, p = int(res.frame_index[i]), int(res.person[i])
        image = res.file_names[i] or res.image_ids[i]
        rows.append(f"<tr><td>{f}</td><td class=l>{escape(image)}</td><td>{p}</td>"
                    + "".join(cell(n, k, f, p) for n in names) + "</tr>")  # fmt: skip
    more = ""
    if len(a.index) > MAX_TABLE_ROWS:
        more = f"<p class=meta>The first {MAX_TABLE_ROWS} of {len(a.index)} poses; the CSV has them all.</p>"
    return "".join(rows), more


_LEAD = "<th>frame</th><th class=l>image</th><th>person</th>"


def _symmetry_frames_section(a: Analysis) -> str:
    """Each symmetry value with the interval that decides its call (--call-level), and the call."""

    def cell(name: str, k: int, f: int, p: int) -> str:
        value = a.values[name][k]
        if not np.isfinite(value):
            return _cell(value, np.nan, np.nan, "")
        return _cell(value, *(x[k] for x in a.call_intervals[name]), a.calls[name][k])

    level = _level(a.settings.call_level)
    unit = f"deg [{level}] call" if a.uncertainty_available else "deg, call"
    head = f"<tr>{_LEAD}" + "".join(f"<th>{_pair_label(n)}<br><small>{unit}</small></th>" for n in SYMMETRY_NAMES)
    rows, more = _frame_rows(a, SYMMETRY_NAMES, cell)
    what = (f"degrees, the <b>{level} interval that decides the call</b> in brackets, then the call; the "
            f"{_level(a.settings.level)} intervals are in the CSV and JSON (low, high)"
            if a.uncertainty_available else "degrees and call (no interval: no calibration holds)")  # fmt: skip
    return f"<h2>Symmetry per frame</h2><p class=meta>{what}.</p><table>{head}</tr>{rows}</table>{more}"


def _angle_frames_section(a: Analysis) -> str:
    def cell(name: str, k: int, f: int, p: int) -> str:
        return _cell(a.values[name][k], *(x[k] for x in a.intervals[name]))

    level = _level(a.settings.level)
    head = f"<tr>{_LEAD}" + "".join(f"<th>{escape(n.removesuffix('_deg').replace('_', ' '))}</th>" for n in ANGLE_NAMES)
    rows, more = _frame_rows(a, ANGLE_NAMES, cell)
    interval = f", the {level} interval in brackets" if a.uncertainty_available else ""
    return (f"<h2>Joint angles per frame</h2><p class=meta>degrees{interval}. Knee / elbow flexion: 0 = straight. "
            "Hip / shoulder flexion: from straight down the trunk, positive forward; abduction: positive away from "
            "the midline (trunk frame from the hips and shoulders; docs/clinical.md).</p>"
            f"<div class=scroll><table class=wide>{head}</tr>{rows}</table></div>{more}")  # fmt: skip


@dataclass(frozen=True)
class Footage:
    """For a clip: the frames to review and their thumbnails (PNG bytes by frame number) cut from the
    footage by the CLI (footage.thumbnails), or why there are none."""

    picks: list[Review]
    thumbnails: dict[int, bytes] = field(default_factory=dict)
    note: str = ""


def report_sections(a: Analysis, footage: Footage | None = None) -> list[str]:
    """The page's sections in order, each the HTML of one small function of `a`. A clip (fps) leads with
    its summary, the time series and the frames to review (clip_report)."""
    if not a.is_sequence:
        return [_title(a), research_notice(), _decisions(a), _notes(a), _symmetry_section(a), _skeleton_section(a),
                _symmetry_frames_section(a), _angle_frames_section(a)]  # fmt: skip
    footage = footage or Footage(review_picks(a))
    return [_title(a), research_notice(), summary_section(a), time_series_section(a),
            review_section(a, footage.picks, footage.thumbnails, footage.note), _decisions(a), _notes(a),
            _symmetry_section(a), _time_series_section(a), _movement_section(a), _skeleton_section(a),
            _symmetry_frames_section(a), _angle_frames_section(a)]  # fmt: skip


def report_html(a: Analysis, footage: Footage | None = None) -> str:
    """The whole report as one HTML string."""
    head = (f"<!DOCTYPE html><html lang=en><head><meta charset=utf-8><title>zedo analyze: "
            f"{escape(Path(a.result.source).name)}</title><style>{_CSS}</style></head><body>")  # fmt: skip
    foot = (
        "<p class=meta>Self-contained page (no network): figures inline SVG, thumbnails inline PNG.</p></body></html>"
    )
    return "\n".join([head, *report_sections(a, footage), foot]) + "\n"


def write_report(a: Analysis, out: str | Path, *, overwrite: bool = False, footage: Footage | None = None) -> Path:
    """Write the report to `out` atomically; an existing file only with `overwrite`."""
    write_text_atomic(out, report_html(a, footage), overwrite=overwrite)
    return Path(out)
