"""The clip report's comparison block from a Jinja2 template with autoescaping, beside today's f-strings: is it
shorter, and is it safer? (docs/decisions.md, "The HTML reports from templates".)

`comparison_block_from_template(a)` renders what `zedo_cli.analysis.report.clip_report.comparison_block(a)` writes,
from `TEMPLATE`; experiments/tests/test_report_templates.py checks that both give the same HTML. `main` prints the
lines of each way and how many interpolations each leaves to the author's care (an f-string interpolation that is
neither escaped nor a number; in the template: those marked `|safe`).

    python experiments/report_templates.py
"""

from __future__ import annotations

import ast
import inspect
import sys
from pathlib import Path
from typing import Any

import jinja2

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from zedo_cli.analysis.analyse import Analysis
from zedo_cli.analysis.compare import furthest_from_typical
from zedo_cli.analysis.norms.calibrated import NULL_DRAWS
from zedo_cli.analysis.report import clip_report
from zedo_cli.analysis.report.plain_words import describe, has_words

TEMPLATE = """\
{%- if not comparisons -%}
<p class=meta>No comparison with typical infants: give a reference from <code>zedo norms</code> with \
<code>--norms</code>.</p>
{%- else -%}
{%- for note in mismatches %}<div class='note warn'>{{ note }}.</div>{% endfor -%}
{%- for c in comparisons -%}
<p class=meta><b>Compared with typical infants{{ c.who }}</b>: how surprising this clip is under the reference. \
The published z compares the clip's summed log-likelihood under the reference with the typical clips' own sums \
(negative: less typical), p is its two-sided normal p-value (its false alarms depend on the features' tails and the \
clips' lengths: docs/movement.md). The calibrated p of the extended features and of the left-right asymmetry ranks \
the clip's distance from the reference among the reference clips' own (each from the others): a typical clip gets \
p &lt; 0.05 at most 1 time in 20 (\
{%- if c.epochs == 1 %}with {{ c.reference_clips }} reference clips the smallest p is \
{{ "%.3f"|format(1 / (c.reference_clips + 1)) }}\
{%- else %}compared by its epochs: about 1 time in 20, 1-8 % of typical clips in docs/movement.md; the smallest p \
is {{ "%.1g"|format(1 / (null_draws + 1)) }}{% endif %}). A small p says the movements differ from the reference, \
not why.\
{%- if c.epochs > 1 %} This clip is longer than the reference's: its calibrated p and each feature's z are of its \
{{ c.epochs }} epochs as long as the reference's clips (the median epoch, against medians of as many typical clips as \
its epochs are worth independently: {{ c.independent_extended }} over the extended features, \
{{ c.independent_asymmetry }} over the asymmetry), the published z and p of the whole clip.\
{%- endif %}</p><table><tr><th class=l>surprise over</th><th>z</th><th>p</th></tr>\
<tr><td class=l>published features ({{ c.published.features }})</td><td>{{ "%+.2f"|format(c.published.z) }}</td>\
<td>{{ "%.3g"|format(c.published.p) }}</td>\
{%- for kind, s in c.calibrated %}</tr><tr><td class=l>{{ kind }}, calibrated ({{ s.features }})</td><td>–</td>\
<td>{{ "%.3g"|format(s.p) }}</td>{% endfor %}</tr></table>\
<p class=meta>Furthest from typical (the largest |z| of single features):</p>\
<ul class=far>{% for t in c.far %}<li>{{ t }}</li>{% endfor %}</ul>
{%- endfor -%}
{%- endif -%}
"""
_ENV = jinja2.Environment(autoescape=True, keep_trailing_newline=False)


def comparison_block_from_template(a: Analysis) -> str:
    """`clip_report.comparison_block(a)` from TEMPLATE: the context in Python, the markup in the template."""
    mismatches = sorted({pc.lifting_mismatch for pc in a.comparisons if pc.lifting_mismatch is not None})
    comparisons: list[dict[str, Any]] = []
    for pc in a.comparisons:
        c = pc.comparison
        comparisons.append({
            "who": f" (person {pc.person})" if len(a.comparisons) > 1 else "",
            "published": c.published, "reference_clips": c.asymmetry.reference_clips, "epochs": c.asymmetry.epochs,
            "independent_extended": c.extended.independent_epochs,
            "independent_asymmetry": c.asymmetry.independent_epochs,
            "calibrated": (("extended features", c.extended), ("left-right asymmetry", c.asymmetry)),
            "far": [describe(n, z) if has_words(n) else f"{n.replace('_', ' ')}: z = {z:+.1f}"
                    for n, z in furthest_from_typical(c)],
        })  # fmt: skip
    return _ENV.from_string(TEMPLATE).render(comparisons=comparisons, null_draws=NULL_DRAWS,
                                             mismatches=[m[0].upper() + m[1:] for m in mismatches])  # fmt: skip


def unescaped_interpolations(source: str) -> int:
    """f-string interpolations into HTML (an f-string with a tag) that are neither `escape(...)` nor formatted
    numbers: each one a place where escaping is left to the author."""
    count = 0
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.JoinedStr):
            continue
        text = "".join(v.value for v in node.values if isinstance(v, ast.Constant) and isinstance(v.value, str))
        if "<" not in text:
            continue
        for v in node.values:
            if isinstance(v, ast.FormattedValue) and v.format_spec is None:
                func = getattr(v.value, "func", None)
                count += not (func is not None and getattr(func, "id", None) == "escape")
    return count


def main() -> int:
    fstrings = inspect.getsource(clip_report.comparison_block)
    template = inspect.getsource(comparison_block_from_template)
    assigned = next(n for n in ast.parse(Path(__file__).read_text()).body
                    if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "TEMPLATE")  # fmt: skip
    template_lines = assigned.end_lineno - assigned.lineno + 1
    print(f"f-strings: {len(fstrings.splitlines())} lines, {unescaped_interpolations(fstrings)} interpolations "
          "left to the author's escaping")  # fmt: skip
    print(f"template: {template_lines} template lines + {len(template.splitlines())} Python lines, "
          f"{TEMPLATE.count('|safe')} marked safe (every other interpolation escaped)")  # fmt: skip
    for name in ("report.py", "clip_report.py"):
        source = (Path(clip_report.__file__).parent / name).read_text()
        print(f"{name}: {len(source.splitlines())} lines, {unescaped_interpolations(source)} interpolations into HTML "
              "neither escaped nor numbers")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
