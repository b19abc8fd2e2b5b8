"""Option values are checked before any work on every command: a bad
value is one line on stderr and exit 2, never a traceback or an exit 1 after a full run."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import torch
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app
from zedo_cli.cli.common import one_line

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--steps", "0"], "--steps"),
        (["--steps", "1000000000"], "--steps"),
        (["--seed", "-1"], "--seed"),
        (["--seed", str(2**64)], "--seed"),
        (["--fps", "inf"], "--fps"),
        (["--fps", "0"], "--fps"),
        (["--sigma", "inf"], "--sigma"),
        (["--sigma", "1e300", "--temporal", "smooth"], "--sigma"),
        (["--device", "bogus"], "--device"),
        (["--device", "cuda:99"], "--device"),
        # Cameras that can never work.
        (["--focal", "1e30"], "--focal"),
        (["--focal", "1e-30"], "--focal"),
        (["--principal-point", "1e9", "1e9"], "--principal-point"),
        (["--principal-point", "nan", "3"], "--principal-point"),
        (["--image-size", "1e300", "1e300"], "--image-size"),
        (["--image-size", "0", "480"], "--image-size"),
    ],
)
def test_lift_options_out_of_range_are_usage_errors(
    tiny_prior_path: Path, tmp_path: Path, extra: list[str], needle: str
) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), *extra))
    assert result.exit_code == 2, result.output
    assert result.output.startswith(f"zedo: error: {needle}") and len(result.output.strip().splitlines()) == 1
    assert not (tmp_path / "kp.zedo.json").exists()


@pytest.mark.skipif(torch.cuda.is_available(), reason="a GPU is present")
def test_cuda_without_a_gpu_is_a_usage_error(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--device", "cuda"))
    assert result.exit_code == 2 and "no CUDA GPU" in result.output, result.output


@pytest.mark.parametrize(
    "args",
    [
        ["fit-prior", "--syrip-dir", "nowhere", "--split", "bogus", "--out", "p.safetensors"],
        ["fit-prior", "--syrip-dir", "nowhere", "--seed", "-3", "--out", "p.safetensors"],
        ["fit-prior", "--syrip-dir", "nowhere", "--device", "tpu", "--out", "p.safetensors"],
        ["fit-prior", "--syrip-dir", "nowhere", "--lr", "inf", "--out", "p.safetensors"],  # trained to NaN weights
        ["adapt", "--syrip-dir", "nowhere", "--split", "bogus", "--out", "a.safetensors"],
        ["adapt", "--syrip-dir", "nowhere", "--seed", "-1", "--out", "a.safetensors"],
        ["fit-augmenter", "--syrip-dir", "nowhere", "--adult-dir", "nowhere", "--split", "bogus"],
        ["augment", "--adult-dir", "nowhere", "--count", "0"],
        ["augment", "--adult-dir", "nowhere", "--count", "1000000000"],
        ["augment", "--adult-dir", "nowhere", "--steps", "0"],
        ["augment", "--adult-dir", "nowhere", "--seed", "-1"],
        ["evaluate", "r.json", "--syrip-dir", "nowhere", "--split", "bogus"],
        ["benchmark", "--syrip-dir", "nowhere", "--device", "bogus"],
        ["benchmark-minirgbd", "--minirgbd-dir", "nowhere", "--prior", "x", "--steps", "0"],
        ["benchmark-minirgbd", "--minirgbd-dir", "nowhere", "--prior", "x", "--device", "bogus"],
    ],
)
def test_bad_options_of_every_command_are_usage_errors_before_any_data_is_read(tmp_path: Path, args: list[str]) -> None:
    result = runner.invoke(app, args)
    assert result.exit_code == 2, result.output
    assert result.output.startswith("zedo: error:") and len(result.output.strip().splitlines()) == 1


def test_messages_stay_on_one_line_with_control_characters_escaped(tiny_prior_path: Path, tmp_path: Path) -> None:
    assert one_line("a\nb\x1b[2Jc\td") == "a\\nb\\x1b[2Jc\\td"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(tmp_path / "evil\nname\x1b[31m.json")))
    assert result.exit_code == 3, result.output
    assert len(result.output.strip().splitlines()) == 1 and "evil\\nname\\x1b[31m.json" in result.output


def test_a_closed_stdout_pipe_exits_quietly(tiny_prior_path: Path, tmp_path: Path) -> None:
    """`zedo lift x.json -o - | head -1`: the reader goes away; no error message, no traceback."""
    src = write_coco(tmp_path / "kp.json", n=2)
    code = "import sys; from zedo_cli.cli import main; sys.argv[0] = 'zedo'; main()"
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    proc = subprocess.Popen([sys.executable, "-c", code, *lift_args(tiny_prior_path, str(src), "-o", "-")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)  # fmt: skip
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()  # before zedo writes: its write meets a pipe without a reader
    stderr = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141, stderr
    assert stderr == ""


def test_device_auto_picks_cuda_only_when_present(
    tiny_prior_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from zedo_cli.cli.checks import check_device

    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    assert check_device("auto") == "cpu"
    out = tmp_path / "out.json"
    src = write_coco(tmp_path / "kp.json", n=1)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--device", "auto", "-o", str(out)))
    assert result.exit_code == 0, result.output
    assert json.loads(out.read_text())["params"]["device"] == "cpu"  # what ran is recorded, not "auto"
    monkeypatch.setattr(torch.cuda, "is_available", lambda: True)
    assert check_device("auto") == "cuda"
