"""Footage: lifted skeletons drawn over the video or images they were lifted from (`zedo
render`), and keypoints checked against their video (`zedo lift --video`).

Builds on `camera` (projection, video files), `data` and `formats` (the result reader).
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".render": ["RenderSettings", "RenderSummary", "render_images", "render_video"],
    },
)
