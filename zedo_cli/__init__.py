"""zedo: lift 2D infant body keypoints to 3D with a diffusion pose prior (ZeDO-i)."""

__version__ = "0.1.0"
