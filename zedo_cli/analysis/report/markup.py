"""HTML helpers the report's pages share (`report`, `clip_report`)."""

from __future__ import annotations

import html
from typing import Any


def escape(value: Any) -> str:
    """`value` as HTML text: its str() escaped, and None as the empty string."""
    return html.escape("" if value is None else str(value))
