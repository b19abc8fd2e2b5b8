"""The bounds and help texts of options that several commands share (plain values: importing this
module imports nothing else, so `cli.checks` and the settings models both take them from here)."""

from __future__ import annotations

MAX_SEED = 2**63 - 1  # torch and numpy take seeds in [0, 2**63)
MAX_STEPS = 100_000  # prior / diffusion steps: 100x faithful's 1000
MAX_COUNT = 1_000_000  # poses written by `zedo augment`
MAX_SIGMA_FRAMES = 1_000.0  # the temporal filter's width: a window of 6000 frames
MAX_FPS = 100_000.0
MAX_FOCAL_PX = 1e6
MAX_SYMMETRY_THRESHOLD_DEG = 180.0  # --symmetry-threshold: the largest angle between two directions
DEVICE_HELP = "cpu, cuda, cuda:N or auto (CUDA when torch sees a GPU, else cpu)."  # --device of every command
# -o/--output of the commands that report figures (evaluate, the benchmarks)
REPORT_OUTPUT_HELP = "Also write the figures as JSON to this .json file (- : on stdout, as --json)."
