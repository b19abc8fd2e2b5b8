"""The share calibration's recipe (benchmarks/calibrate/share_calibration.py) leaves out together the sources that
share their poses: a source turned supine is scored with margins fitted on other poses only."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import benchmark_module

recipe = benchmark_module("calibrate.share_calibration")


def _cases(source: str, error: float, n: int = 40) -> list[dict]:
    """`n` 10 s cases of `source` at the default threshold, each share `error` above its truth, no bootstrap width."""
    return [{"source": source, "seconds": 10.0, "clip": i, "pair": pair, "threshold_deg": 28.0, "truth": 0.2,
             "estimate": 0.2 + error, "low": 0.2 + error, "high": 0.2 + error}
            for i in range(n) for pair in ("symmetry_thigh", "symmetry_shank")]  # fmt: skip


def test_sources_that_share_poses_are_left_out_together(capsys: pytest.CaptureFixture[str]) -> None:
    assert recipe.same_poses("syrip-train", "syrip-train-supine") and not recipe.same_poses("adult", "syrip-train")
    cases = _cases("adult", 0.01) + _cases("syrip-train", 0.3) + _cases("syrip-train-supine", 0.3)
    recipe.coverage_table(cases, ("adult", "syrip-train", "syrip-train-supine"))
    rows = {line.split(" | ")[0].strip("| "): line for line in capsys.readouterr().out.splitlines()}
    held = float(rows["syrip-train"].split(" | ")[6].rstrip(" %"))
    assert held == 0.0  # the adult margin (0.01) alone: the supine twin's 0.3 would have held every share
    assert np.isclose(float(rows["adult"].split(" | ")[6].rstrip(" %")), 100.0)
