"""The template of experiments/report_templates.py writes the same comparison block as the shipped f-strings, with
and without a comparison, so that its line count compares like with like."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from analysis_results import kicking_poses, result_document, write_document

from experiments.report_templates import comparison_block_from_template
from zedo_cli.analysis.analyse import analyse
from zedo_cli.analysis.compare import compared, features_by_person
from zedo_cli.analysis.norms.norms import build_norms
from zedo_cli.analysis.report.clip_report import comparison_block
from zedo_cli.formats.readers.result import read_result


def _analysed(path: Path, noise: float, seed: int) -> object:
    poses = kicking_poses(90) + np.random.default_rng(seed).normal(0.0, noise, (90, 12, 3))
    return analyse(read_result(write_document(path, result_document(poses, fps=30.0))))


def test_the_template_writes_what_the_f_strings_write(tmp_path: Path) -> None:
    reference = [features_by_person(_analysed(tmp_path / f"r{i}.zedo.json", 0.004, i))[0] for i in range(20)]
    norms = build_norms([replace(c, seconds=1.0) for c in reference], "x")  # the clip is 3 s: by its epochs
    a = _analysed(tmp_path / "clip<b>.zedo.json", 0.004, 99)
    assert comparison_block_from_template(a) == comparison_block(a)  # no comparison
    a = compared(a, norms, None)
    page = comparison_block(a)
    assert "3 epochs" in page and page.count("<tr>") == 4 and page.count("<li>") == 5
    assert comparison_block_from_template(a) == page
