"""A `fast` result written by an older zedo (`params.config.bf16` false, no `params.options`) is still a
--config that lifts again: bf16 does not change the poses beyond noise (CALIBRATION_IRRELEVANT)."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from zedo_cli.errors import ConfigError
from zedo_cli.lifting.config import get_preset
from zedo_cli.settings.from_result import result_config
from zedo_cli.settings.lift import LiftOptions


def _result(path: Path, config: dict) -> str:
    doc = {"schema": "zedo.pose3d/1", "params": {"preset": "fast", "config": config}}
    path.write_text(json.dumps(doc))
    return str(path)


def test_an_older_fast_result_with_bf16_false_lifts_again(tmp_path: Path) -> None:
    older = replace(get_preset("fast"), bf16=False).to_dict()
    config = result_config(_result(tmp_path / "old.zedo.json", older), LiftOptions)
    assert config.values["preset"] == "fast"


def test_a_setting_no_option_sets_is_still_refused(tmp_path: Path) -> None:
    other = replace(get_preset("fast"), init_steps=7).to_dict()
    with pytest.raises(ConfigError, match="params.config.init_steps"):
        result_config(_result(tmp_path / "odd.zedo.json", other), LiftOptions)
