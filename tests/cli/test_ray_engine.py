"""`zedo lift --engine ray` gives exactly the local engine's outputs and exit codes (docs/lifting.md,
"The Ray engine"). Runs on a local Ray instance with 2 CPUs; skipped when the
`ray` extra is not installed (`.ci/run` installs it)."""

from __future__ import annotations

import json
import re
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from test_cli import lift_args, runner, write_coco

from zedo_cli.cli import app

# Timings differ between runs; everything else must be equal to the byte.
NUMBER = re.compile(r"-?\d+\.?\d*(?:e-?\d+)?")
TIMINGS = re.compile(r'"(created|seconds)": [^,\n]*')


@pytest.fixture(scope="module")
def local_ray() -> Iterator[None]:
    ray = pytest.importorskip("ray")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    yield
    ray.shutdown()


def batch(tmp_path: Path) -> list[str]:
    """Three inputs: one with a warning (a keypoint far outside its image), one broken, one plain."""
    bad = tmp_path / "in" / "bad.json"
    bad.parent.mkdir()
    bad.write_text('{"images": [], "annotations": []}')
    warned = write_coco(tmp_path / "in" / "a.json")
    doc = json.loads(warned.read_text())
    doc["annotations"][0]["keypoints"][3 * 5] += 10 * doc["images"][0]["width"]  # the left shoulder's x
    warned.write_text(json.dumps(doc))
    return [str(warned), str(bad), str(write_coco(tmp_path / "in" / "b.json", n=5))]


def assert_same_text(a: str, b: str, atol: float = 1e-5) -> None:
    """Output texts `a` and `b` are the same line by line, numbers to within `atol`."""
    left, right = a.splitlines(), b.splitlines()
    assert len(left) == len(right)
    for x, y in zip(left, right, strict=True):
        if x != y:
            nx, ny = NUMBER.findall(x), NUMBER.findall(y)
            assert NUMBER.sub("#", x) == NUMBER.sub("#", y) and len(nx) == len(ny), (x, y)
            assert all(abs(float(p) - float(q)) <= atol for p, q in zip(nx, ny, strict=True)), (x, y)


def run(prior: Path, inputs: list[str], out_dir: Path, *engine: str) -> tuple[int, dict[str, str], list[str]]:
    """Exit code, the outputs' texts (timings left out) and the warning lines on stderr."""
    out_dir.mkdir()
    result = runner.invoke(app, [*lift_args(prior, *inputs), "--output-dir", str(out_dir), *engine])
    warnings = [line for line in result.stderr.splitlines() if line.startswith("zedo: warning:")]
    return result.exit_code, {p.name: TIMINGS.sub("", p.read_text()) for p in sorted(out_dir.iterdir())}, warnings


@pytest.mark.usefixtures("local_ray")
def test_ray_engine_writes_what_the_local_engine_writes(tiny_prior_path: Path, tmp_path: Path) -> None:
    inputs = batch(tmp_path)
    local_code, local, local_warnings = run(tiny_prior_path, inputs, tmp_path / "local")
    ray_code, on_ray, ray_warnings = run(tiny_prior_path, inputs, tmp_path / "ray", "--engine", "ray", "--workers", "2")
    assert local_code == ray_code == 4  # the bad input is isolated and counted in both
    # a worker's warnings reach the driver's stderr, the same lines as the local engine's
    assert local_warnings == ray_warnings and "keypoints_outside_image" in ray_warnings[0]
    assert sorted(on_ray) == ["a.zedo.json", "b.zedo.json"]
    # Two workers on 2 CPUs run 1 torch thread each, the local engine 2: on some CPUs (an AMD
    # EPYC) that rounds a derived coordinate 1 micrometre apart, so numbers are compared to 10 um.
    for name in local:
        assert_same_text(on_ray[name], local[name])
    assert json.loads((tmp_path / "ray" / "b.zedo.json").read_text())["summary"]["instances_lifted"] == 5


@pytest.mark.usefixtures("local_ray")
def test_ray_engine_single_input_error_is_the_commands_error(tiny_prior_path: Path, tmp_path: Path) -> None:
    bad = batch(tmp_path)[1]
    result = runner.invoke(app, [*lift_args(tiny_prior_path, bad), "--engine", "ray"])
    assert result.exit_code == 3 and "bad.json" in result.output


@pytest.mark.usefixtures("local_ray")
def test_ray_engine_never_overwrites(tiny_prior_path: Path, tmp_path: Path) -> None:
    a = write_coco(tmp_path / "a.json")
    (tmp_path / "a.zedo.json").write_text("keep me")
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(a)), "--engine", "ray"])
    assert result.exit_code == 2 and (tmp_path / "a.zedo.json").read_text() == "keep me"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--engine", "bogus"], "--engine must be one of"),
        (["--engine", "ray", "-o", "-"], "stdin (-) and -o - need --engine local"),
        (["--engine", "ray", "--workers", "0"], "--workers must be an integer >= 1, got 0"),
    ],
)
def test_engine_usage_errors(tiny_prior_path: Path, tmp_path: Path, extra: list[str], message: str) -> None:
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(write_coco(tmp_path / "a.json"))), *extra])
    assert result.exit_code == 2 and message in result.output


def test_missing_ray_is_a_usage_error(tiny_prior_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray now raises ImportError
    result = runner.invoke(app, [*lift_args(tiny_prior_path, str(write_coco(tmp_path / "a.json"))), "--engine", "ray"])
    assert result.exit_code == 2 and "pip install 'zedo[ray]'" in result.output
