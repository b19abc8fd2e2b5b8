"""The bounds of option values that several commands share (plain numbers: importing this
module imports nothing else, so `cli.checks` and the settings models both take them from here)."""

from __future__ import annotations

MAX_SEED = 2**63 - 1  # torch and numpy take seeds in [0, 2**63)
MAX_STEPS = 100_000  # prior / diffusion steps: 100x faithful's 1000
MAX_COUNT = 1_000_000  # poses written by `zedo augment`
MAX_SIGMA_FRAMES = 1_000.0  # the temporal filter's width: a window of 6000 frames
MAX_FPS = 100_000.0
MAX_FOCAL_PX = 1e6
DEVICE_HELP = "cpu, cuda, cuda:N or auto (CUDA when torch sees a GPU, else cpu)."  # --device of every command
