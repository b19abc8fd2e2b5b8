"""zedo: lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i)."""

from .version import __version__

__all__ = ["__version__"]
