"""The SyRIP benchmark with the bundled prior (slow: lifts 200 poses at the real size).

Run with `pytest -m slow`; skipped without ../shared/data/syrip.
"""

from __future__ import annotations

import pytest
from helpers import SYRIP_DIR

from zedo_cli.benchmark import load_benchmark_inputs, run_syrip_benchmark
from zedo_cli.lifting import get_preset
from zedo_cli.weights import bundled_prior_path, load_prior

needs_syrip = pytest.mark.skipif(not SYRIP_DIR.is_dir(), reason="SyRIP data not found at ../shared/data/syrip")


@needs_syrip
def test_benchmark_inputs_match_the_protocol() -> None:
    truth, inputs = load_benchmark_inputs(SYRIP_DIR)
    assert len(truth.names) == 100
    for kp in inputs.values():
        assert len(kp) == 100 and kp.skeleton.name == "coco17"
        assert list(kp.file_names) == truth.names


@pytest.mark.slow
@needs_syrip
def test_bundled_prior_meets_the_paper_from_scratch_figure() -> None:
    prior = load_prior(bundled_prior_path(), skeleton="syrip12")
    scores, _ = run_syrip_benchmark(SYRIP_DIR, prior, get_preset("faithful"))
    by_input = {s.input_2d: s for s in scores}
    assert by_input["gt"].mpjpe_mm <= 54.0  # the paper's from-scratch figure
    assert by_input["detected"].mpjpe_mm <= 56.0
    assert by_input["gt"].pa_mpjpe_mm < by_input["gt"].mpjpe_mm
