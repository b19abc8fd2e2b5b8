"""The Python API exported by `zedo_cli` (docs/api.md): the same poses as `zedo lift`."""

from __future__ import annotations

import importlib.util
import io
import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import write_coco
from typer.testing import CliRunner

import zedo_cli
from zedo_cli.cli import app

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "prior_samples_coco.json"


def test_api_lift_equals_the_command(tmp_path: Path) -> None:
    from zedo_cli import get_preset, lift, load_prior, read_keypoints, resolve_intrinsics, resolve_prior_path

    prior = load_prior(resolve_prior_path(None))  # the bundled default prior
    kp = read_keypoints(EXAMPLE).to_skeleton(prior.skeleton)
    intrinsics, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)  # 2000 px at the centre
    res = lift(kp.xy, kp.confidence, intrinsics, prior, get_preset("fast"))

    out = tmp_path / "cli.json"
    cli = CliRunner().invoke(app, ["lift", str(EXAMPLE), "-o", str(out), "--quiet"])
    assert cli.exit_code == 0, cli.output
    doc = json.loads(out.read_text())
    written = np.array([p["keypoints_3d"] for f in doc["frames"] for p in f["persons"]], dtype=float)
    assert written.shape == res.poses_camera.shape
    np.testing.assert_allclose(written, res.poses_camera, atol=1e-6)  # the file keeps micrometres


def test_api_names_resolve_to_their_subpackage_objects() -> None:
    from zedo_cli.formats import read_keypoints
    from zedo_cli.lifting import LiftConfig, lift

    assert zedo_cli.lift is lift and zedo_cli.LiftConfig is LiftConfig and zedo_cli.read_keypoints is read_keypoints
    assert "lift" in dir(zedo_cli) and "lift" in zedo_cli.__all__


# The two-line API: zedo_cli.lift_file and zedo_cli.analyze take the commands'
# settings by their option names, with their defaults, and give what the commands give.

ROOT = EXAMPLE.parents[1]
_BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def _doc_blocks() -> list[str]:
    return _BLOCK.findall((ROOT / "docs" / "api.md").read_text())


def _run_doc_blocks(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, blocks: list[str]) -> dict:
    (tmp_path / "examples").symlink_to(ROOT / "examples")  # the page's relative paths, outputs in tmp_path
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "docs/api.md", "exec"), namespace)  # noqa: S102  (the page's own code)
    return namespace


def test_the_api_page_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocks = _doc_blocks()
    assert len(blocks) >= 4 and "zedo_cli.lift_file(" in blocks[0] and "zedo_cli.analyze(" in blocks[0]
    with_pandas = importlib.util.find_spec("pandas") is not None
    ns = _run_doc_blocks(tmp_path, monkeypatch, [b for b in blocks if with_pandas or "to_pandas" not in b])
    assert ns["lifted"].result.poses_camera.shape == (6, 12, 3) and ns["result"].poses_camera.shape == (6, 12, 3)
    if with_pandas:
        assert len(ns["table"]) == len(ns["analysis"].rows) and len(ns["thighs"]) == 6


def test_lift_file_and_analyze_give_what_the_commands_give(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=4)
    settings = {"prior": str(tiny_prior_path), "steps": 5, "focal": 1500, "seed": 2, "hypotheses": 2}
    lifted = zedo_cli.lift_file(src, **settings)
    out = tmp_path / "cli.zedo.json"
    cli = CliRunner().invoke(app, ["lift", str(src), "--prior", str(tiny_prior_path), "--steps", "5", "--focal",
                                   "1500", "--seed", "2", "--hypotheses", "2", "-o", str(out), "-q"])  # fmt: skip
    assert cli.exit_code == 0, cli.output
    doc = json.loads(out.read_text())
    written = np.array([p["keypoints_3d"] for f in doc["frames"] for p in f["persons"]], dtype=float)
    np.testing.assert_allclose(written, lifted.result.poses_camera, atol=1e-6)
    assert doc["params"]["options"] == lifted.params["options"] and lifted.params["options"]["focal"] == 1500.0
    # analyze: the rows of `zedo analyze` on the command's file
    from zedo_cli.analysis.outputs import csv_text

    csv_out = tmp_path / "cli.analysis.csv"
    cli = CliRunner().invoke(app, ["analyze", str(out), "-o", str(csv_out), "-q", "--symmetry-threshold", "30"])
    assert cli.exit_code == 0, cli.output
    assert csv_text(zedo_cli.analyze(out, symmetry_threshold=30)) == csv_out.read_text()
    assert csv_text(zedo_cli.analyze(lifted, symmetry_threshold=30)) == csv_out.read_text()


def test_lift_file_defaults_are_the_commands(tmp_path: Path) -> None:
    import inspect

    from zedo_cli.cli.lift import lift_command
    from zedo_cli.settings import LiftOptions

    defaults = LiftOptions().values()
    for name, param in inspect.signature(lift_command).parameters.items():
        if param.default is not inspect.Parameter.empty and name not in ("config", "print_config"):
            key = {"input_format": "format", "prior_spec": "prior", "out": "output"}.get(name, name)
            assert defaults[key] == param.default, key


def test_an_unknown_or_bad_setting_is_refused(tiny_prior_path: Path, tmp_path: Path) -> None:
    from zedo_cli.errors import ConfigError

    with pytest.raises(TypeError, match="unexpected setting 'stpes'; did you mean 'steps'"):
        zedo_cli.lift_file(EXAMPLE, stpes=3)
    with pytest.raises(ConfigError, match=r"--steps must be an integer in \[1, 100000\], got 0"):
        zedo_cli.lift_file(EXAMPLE, steps=0)
    with pytest.raises(ConfigError, match="--engine is for batches of zedo lift"):
        zedo_cli.lift_file(EXAMPLE, engine="ray")
    with pytest.raises(TypeError, match="did you mean 'symmetry_threshold'"):
        zedo_cli.analyze(EXAMPLE, symetry_threshold=3)


def test_to_pandas_without_pandas_says_how_to_get_it(monkeypatch: pytest.MonkeyPatch) -> None:
    from zedo_cli.analysis.analyse import Analysis

    monkeypatch.setitem(sys.modules, "pandas", None)  # as if pandas were not installed
    with pytest.raises(ImportError, match=r"pip install -e '\.\[pandas\]' in a zedo checkout"):
        Analysis.to_pandas(Analysis.__new__(Analysis))


def test_to_pandas_is_the_csv_table(tiny_prior_path: Path, tmp_path: Path) -> None:
    pd = pytest.importorskip("pandas")
    a = zedo_cli.analyze(zedo_cli.lift_file(write_coco(tmp_path / "kp.json"), prior=str(tiny_prior_path), steps=3))
    table = a.to_pandas()
    assert list(table.columns) == list(zedo_cli.analysis.COLUMNS) and len(table) == len(a.rows)
    from zedo_cli.analysis.outputs import csv_text

    from_csv = pd.read_csv(io.StringIO(csv_text(a)))
    np.testing.assert_allclose(table["value"].to_numpy(float), from_csv["value"].to_numpy(float), atol=1e-3)
