"""The measure registry (analysis.measures) holds every measure `zedo analyze` writes, with the unit and scope the
rows carry, and docs/measures.md is its table."""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document

from zedo_cli.analysis.analyse import analyse
from zedo_cli.analysis.compare import compared, features_by_person
from zedo_cli.analysis.measures import MEASURES, measure_of, registry_markdown
from zedo_cli.analysis.norms.norms import build_norms
from zedo_cli.formats.readers.result import read_result

DOCS = Path(__file__).resolve().parents[2] / "docs" / "measures.md"


def test_every_row_of_a_compared_clip_is_in_the_registry_with_its_unit_and_scope(tmp_path: Path) -> None:
    a = analyse(read_result(write_document(tmp_path / "clip.zedo.json", result_document(kicking_poses(90),
                                                                                        fps=30.0))))  # fmt: skip
    clip = features_by_person(a)[0]
    rng = np.random.default_rng(0)
    typical = [
        replace(clip, source=f"typical{i}.zedo.json",
                values={k: np.nan_to_num(v, nan=0.5) + rng.normal(0.0, 0.05) for k, v in clip.values.items()})
        for i in range(20)
    ]  # fmt: skip
    a = compared(a, build_norms(typical, "test"), None)
    for name in {row.measure for row in a.rows}:  # one family each
        assert sum(re.fullmatch(m.regex, name) is not None for m in MEASURES) == 1, name
    seen = set()
    for row in a.rows:
        m = measure_of(row.measure)
        assert (row.unit, "frame" if row.frame_index is not None else "clip") == (m.unit, m.scope), row.measure
        seen.add(m.pattern)
    assert {"symmetry_<pair>_deg", "<side>_<angle>_deg", "3d_mean_angle_<L|R><part>", "<feature>_norm_z",
            "surprise_<published|extended|asymmetry>_p", "head_turn"} <= seen  # fmt: skip
    assert len(seen) >= 0.8 * len(MEASURES)


def test_an_unknown_name_is_refused_and_each_pattern_is_listed_once() -> None:
    with pytest.raises(KeyError, match="no family"):
        measure_of("symmetry_thigh_degrees")
    assert len({m.pattern for m in MEASURES}) == len(MEASURES)


def test_docs_measures_md_is_the_registry_table() -> None:
    assert registry_markdown() in DOCS.read_text(encoding="utf-8")


def test_every_published_statistic_of_the_registry_has_the_reports_words() -> None:
    from zedo_cli.analysis import measures

    stats = {*measures._ANGLE_STATS, *measures._POSITION_STATS, "mean_dispersion", "lrCorr_angle", "lrCorr_x"}
    assert stats == set(measures.STAT_WORDS)
