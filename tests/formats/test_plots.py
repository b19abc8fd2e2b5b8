"""Skeleton plots: which instances are drawn, valid PNGs of a sensible size, no clobbering."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
from writer_fixtures import make_case

from zedo_cli.errors import ConfigError
from zedo_cli.formats.plots import mean_reprojection_error_px, select_plot_instances, write_pose_plots

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def test_selection_first_median_worst() -> None:
    _, res, _, _ = make_case()
    np.testing.assert_allclose(mean_reprojection_error_px(res), [1.0, 2.0, 3.0, np.nan])
    assert select_plot_instances(res) == {"first": 0, "median": 1, "worst": 2}
    res.lifted[:] = False
    assert select_plot_instances(res) == {}


def test_writes_three_valid_pngs(tmp_path: Path) -> None:
    kp, res, _, _ = make_case()
    paths = write_pose_plots(tmp_path / "kp.zedo", kp, res, units="mm")
    assert [p.name for p in paths] == ["kp.zedo.first.png", "kp.zedo.median.png", "kp.zedo.worst.png"]
    for path in paths:
        assert png_size(path) == (1200, 460)
        assert path.stat().st_size > 20_000  # three drawn views, not a blank canvas
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in paths)  # no temp files
    with pytest.raises(ConfigError, match="already exists"):
        write_pose_plots(tmp_path / "kp.zedo", kp, res)
    assert write_pose_plots(tmp_path / "kp.zedo", kp, res, overwrite=True) == paths


def test_nothing_lifted_writes_nothing(tmp_path: Path) -> None:
    kp, res, _, _ = make_case()
    res.lifted[:] = False
    assert write_pose_plots(tmp_path / "x", kp, res) == []
    assert list(tmp_path.iterdir()) == []
