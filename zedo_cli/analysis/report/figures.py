"""matplotlib figures for the HTML report as inline SVG (matplotlib imported inside the functions)."""

from __future__ import annotations

import io
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def svg(fig: Figure) -> str:
    """`fig` drawn as an inline <svg> element (no XML prolog or doctype)."""
    buf = io.StringIO()
    fig.savefig(buf, format="svg")
    text = buf.getvalue()
    return text[text.index("<svg") :]  # drop the XML prolog and doctype: inline SVG


def figure(width: float, height: float) -> Figure:
    """A new figure of `width` x `height` inches on the SVG canvas, its text kept as text."""
    import matplotlib

    matplotlib.rcParams["svg.fonttype"] = "none"  # text as text: smaller files, crisp labels
    from matplotlib.backends.backend_svg import FigureCanvasSVG
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), dpi=72, layout="constrained")
    FigureCanvasSVG(fig)
    return fig
