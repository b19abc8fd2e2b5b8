"""A test renderer: views of a checkerboard through a KNOWN lens, to check that calibration
recovers that lens.

A texture of the board (squares of `TEXTURE_PX` pixels, a white margin of one square) is warped
into the distorted image by `cv2.remap`: each image pixel is undistorted to its camera ray
(`CameraModel.undistort_pixels`, exact), the ray meets the board plane (the homography of the
board's pose), and the board point picks its texel. Then a Gaussian blur and sensor noise.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from zedo_cli.camera.calibration import Board
from zedo_cli.camera.model import CameraModel

TEXTURE_PX = 24  # texture pixels per square
BACKGROUND = 110  # grey around the board


def lens(width: int = 1280, height: int = 720, f: float = 600.0, k1: float = -0.3, k2: float = 0.1) -> CameraModel:
    """The task's wide lens (f 600 px at 1280x720), scaled with the image size."""
    s = width / 1280
    return CameraModel(
        f * s, f * s, width / 2 - 0.5, height / 2 - 0.5, (k1, k2, 0.0, 0.0, 0.0), image_size=(width, height)
    )


@lru_cache(maxsize=4)
def _rays(camera: CameraModel) -> np.ndarray:
    """`(H, W, 3)` the camera ray (z = 1) of every pixel of the distorted image."""
    width, height = camera.image_size
    u, v = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
    ideal = camera.undistort_pixels(np.stack([u, v], -1))
    x = (ideal[..., 0] - camera.cx) / camera.fx
    y = (ideal[..., 1] - camera.cy) / camera.fy
    return np.stack([x, y, np.ones_like(x)], -1)


def texture(board: Board) -> np.ndarray:
    """The board's texture: (cols+1) x (rows+1) squares and a white margin of one square."""
    nx, ny = board.cols + 3, board.rows + 3  # squares + margin on both sides
    ix, iy = np.meshgrid(np.arange(nx * TEXTURE_PX) // TEXTURE_PX, np.arange(ny * TEXTURE_PX) // TEXTURE_PX)
    black = ((ix + iy) % 2 == 0) & (ix >= 1) & (ix <= nx - 2) & (iy >= 1) & (iy <= ny - 2)
    return np.where(black, 20, 235).astype(np.uint8)


@dataclass(frozen=True)
class View:
    image: np.ndarray  # (H, W) uint8
    rvec: np.ndarray
    tvec: np.ndarray


def render_view(camera: CameraModel, board: Board, rvec: np.ndarray, tvec: np.ndarray, *, blur: float = 0.8,
                noise: float = 2.0, seed: int = 0) -> np.ndarray:  # fmt: skip
    """The distorted, blurred, noisy grey image of `board` at pose (rvec, tvec) (board -> camera)."""
    rot, _ = cv2.Rodrigues(np.asarray(rvec, dtype=np.float64))
    h = np.c_[rot[:, 0], rot[:, 1], np.asarray(tvec, dtype=np.float64).ravel()]  # board (X, Y, 1) -> ray
    rays = _rays(camera) @ np.linalg.inv(h).T  # (H, W, 3) ~ (X, Y, 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        bx, by = rays[..., 0] / rays[..., 2], rays[..., 1] / rays[..., 2]
    # board metres -> texel centres: corner (0, 0) of the object points is 2 squares in
    tx = (bx / board.square + 2) * TEXTURE_PX - 0.5
    ty = (by / board.square + 2) * TEXTURE_PX - 0.5
    behind = ~np.isfinite(tx) | ~np.isfinite(ty)
    tx[behind], ty[behind] = -1e6, -1e6
    image = cv2.remap(texture(board), tx.astype(np.float32), ty.astype(np.float32), cv2.INTER_LINEAR,
                      borderMode=cv2.BORDER_CONSTANT, borderValue=BACKGROUND)  # fmt: skip
    image = cv2.GaussianBlur(image.astype(np.float32), (0, 0), blur)
    image += np.random.default_rng(seed).normal(0, noise, image.shape).astype(np.float32)
    return np.clip(image, 0, 255).astype(np.uint8)


def board_poses(camera: CameraModel, board: Board, count: int, seed: int = 0) -> list[tuple[np.ndarray, np.ndarray]]:
    """`count` poses spread over the image (the lens shows at the edges), tilted up to ~35
    degrees, each with the whole board inside the image by a margin."""
    rng = np.random.default_rng(seed)
    width, height = camera.image_size
    centre = np.array([(board.cols - 1) / 2 * board.square, (board.rows - 1) / 2 * board.square, 0.0])
    corners = board.object_points().astype(np.float64)
    poses: list[tuple[np.ndarray, np.ndarray]] = []
    while len(poses) < count:
        angles = rng.uniform(-0.6, 0.6, 3) * [1, 1, 0.5]
        rot, _ = cv2.Rodrigues(angles)
        # aim the board's centre at a random pixel, at a depth where it fills a good part of the view
        target = rng.uniform([0.15 * width, 0.15 * height], [0.85 * width, 0.85 * height])
        ray = camera.undistort_pixels(target)
        depth = rng.uniform(0.35, 0.6) * board.cols * board.square / 0.3
        ray = np.array([(ray[0] - camera.cx) / camera.fx, (ray[1] - camera.cy) / camera.fy, 1.0])
        tvec = ray * depth - rot @ centre
        cam = corners @ rot.T + tvec
        px = camera.project(cam)
        margin = 1.5 * board.square / depth * camera.fx
        if (
            np.isfinite(px).all()
            and (px.min(0) > margin).all()
            and (px.max(0) < [width - margin, height - margin]).all()
        ):
            poses.append((angles, tvec))
    return poses


def render_views(camera: CameraModel, board: Board, count: int, seed: int = 0) -> list[View]:
    return [View(render_view(camera, board, r, t, seed=seed + i), r, t)
            for i, (r, t) in enumerate(board_poses(camera, board, count, seed))]  # fmt: skip
