"""The SyRIP benchmark with the bundled prior (slow: lifts 200 poses at the real size).

Run with `pytest -m slow`; skipped without ../shared/data/syrip.
"""

from __future__ import annotations

import pytest
from helpers import SYRIP_DIR

from zedo_cli.evaluation.syrip_benchmark import load_benchmark_inputs, load_throughput_inputs, run_syrip_benchmark
from zedo_cli.lifting.config import get_preset
from zedo_cli.prior.weights import bundled_prior_path, load_prior

needs_syrip = pytest.mark.skipif(not SYRIP_DIR.is_dir(), reason="SyRIP data not found at ../shared/data/syrip")


@needs_syrip
def test_benchmark_inputs_match_the_protocol() -> None:
    truth, inputs = load_benchmark_inputs(SYRIP_DIR)
    assert len(truth.names) == 100
    for kp in inputs.values():
        assert len(kp) == 100 and kp.skeleton.name == "coco17"
        assert list(kp.file_names) == truth.names


@needs_syrip
def test_throughput_inputs_are_every_real_image_once_per_2d_source() -> None:
    inputs = load_throughput_inputs(SYRIP_DIR)
    assert sorted(inputs) == ["detected", "gt"]
    for kp in inputs.values():
        assert len(kp) == 700 and len(set(kp.image_ids)) == 700


@pytest.mark.slow
@needs_syrip
def test_fast_preset_is_as_accurate_as_faithful() -> None:
    """The bar: fast within 1 mm of faithful on Test100 (both 2D inputs)."""
    prior = load_prior(bundled_prior_path(), skeleton="syrip12")
    fast, _ = run_syrip_benchmark(SYRIP_DIR, prior, get_preset("fast"))
    faithful, _ = run_syrip_benchmark(SYRIP_DIR, prior, get_preset("faithful"))
    for a, b in zip(fast, faithful, strict=True):
        assert a.input_2d == b.input_2d and a.mpjpe_mm <= b.mpjpe_mm + 1.0


@pytest.mark.slow
@needs_syrip
def test_bundled_prior_meets_the_paper_from_scratch_figure() -> None:
    prior = load_prior(bundled_prior_path(), skeleton="syrip12")
    scores, _ = run_syrip_benchmark(SYRIP_DIR, prior, get_preset("faithful"))
    by_input = {s.input_2d: s for s in scores}
    assert by_input["gt"].mpjpe_mm <= 54.0  # the paper's from-scratch figure
    assert by_input["detected"].mpjpe_mm <= 56.0
    assert by_input["gt"].pa_mpjpe_mm < by_input["gt"].mpjpe_mm
