"""`zedo export`: a result written again in every format is what `zedo lift -o`
wrote from the same lift (the same input and seed), apart from the times (of writing, of lifting)
and, for the C3D's float32 and the NPZ's full-precision arrays, the digits the source file
rounded away; the same checks as lift."""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from export_fixtures import TWO_FRAMES as FRAMES
from export_fixtures import write_two_people
from typer.testing import CliRunner

from zedo_cli.cli import app

runner = CliRunner()
FORMATS = ("json", "jsonl", "csv", "npz", "trc", "c3d")


def lift(prior: Path, src: Path, out: Path, *extra: str) -> None:
    args = ["lift", str(src), "--prior", str(prior), "--steps", "10", "-q", "--person", "all", "--fps", "30",
            "-o", str(out), *extra]  # fmt: skip
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output


def export(*args: str, code: int = 0) -> str:
    result = runner.invoke(app, ["export", *args])
    assert result.exit_code == code, result.output
    return result.stderr


@pytest.fixture(scope="module")
def lifted(tiny_prior_path: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The clip lifted once into every format (`direct/x.<fmt>`); its JSON also as `clip.zedo.json`,
    the result exported."""
    root = tmp_path_factory.mktemp("export")
    src = write_two_people(root / "clip.jsonl")
    (root / "direct").mkdir()
    for fmt in FORMATS:
        lift(tiny_prior_path, src, root / "direct" / f"x.{fmt}")
    (root / "clip.zedo.json").write_bytes((root / "direct" / "x.json").read_bytes())
    return root


def _drop_created(doc: dict[str, Any]) -> dict[str, Any]:
    """A document (or JSON Lines line) without its times: when it was written, and how long its
    lift took (the outputs compared come from lifts run one after the other, same seed, same poses)."""
    out = {k: v for k, v in doc.items() if k not in ("created", "seconds")}
    if isinstance(out.get("summary"), dict):
        out["summary"] = _drop_created(out["summary"])
    return out


def _text_equal(a: Path, b: Path) -> None:
    assert a.read_text(encoding="utf-8") == b.read_text(encoding="utf-8"), a.name


def _same_file(fmt: str, direct: Path, exported: Path) -> None:
    """The two outputs of one format hold the same content, apart from the time of writing."""
    if fmt == "json":
        assert _drop_created(json.loads(exported.read_text())) == _drop_created(json.loads(direct.read_text()))
    elif fmt == "jsonl":
        a, b = ([json.loads(line) for line in p.read_text().splitlines()] for p in (direct, exported))
        assert [_drop_created(x) for x in a] == [_drop_created(x) for x in b]
    elif fmt == "csv":
        _text_equal(direct, exported)
        a, b = (json.loads(p.with_suffix(".meta.json").read_text()) for p in (direct, exported))
        assert _drop_created(a) == _drop_created(b)
    elif fmt == "trc":
        for track in ("x_P1.trc", "x_P2.trc"):
            _text_equal(direct.with_name(track), exported.with_name(track))
        assert not direct.exists() and not exported.exists()
    elif fmt == "c3d":
        for track in ("x_P1.c3d", "x_P2.c3d"):  # float32 mm; the JSON keeps 1 µm
            a, b = c3d_points(exported.with_name(track)), c3d_points(direct.with_name(track))
            np.testing.assert_allclose(a, b, atol=1e-3, rtol=0)
    else:
        with np.load(direct) as d, np.load(exported) as e:
            assert sorted(d.files) == sorted(e.files)
            for key in d.files:
                if key == "metadata":
                    assert _drop_created(json.loads(str(e[key]))) == _drop_created(json.loads(str(d[key])))
                elif d[key].dtype.kind == "f":  # the JSON's precision: 1 µm, 0.001 px, 1e-4 confidence
                    atol = 6e-4 if key in ("keypoints_2d", "reprojection_error_px") else 6e-5
                    np.testing.assert_allclose(e[key], d[key], atol=atol, rtol=0, equal_nan=True, err_msg=key)
                else:
                    np.testing.assert_array_equal(e[key], d[key], err_msg=key)


def c3d_points(path: Path) -> np.ndarray:
    """Every frame's points `(F, M, 5)` (x, y, z mm, residual, cameras) of a C3D file."""
    import c3d

    with path.open("rb") as fh:
        return np.array([points for _, points, _ in c3d.Reader(io.BytesIO(fh.read())).read_frames()])


@pytest.mark.filterwarnings("ignore:No analog data")  # the c3d reader's: markers only, as written
@pytest.mark.parametrize("fmt", FORMATS)
def test_export_writes_what_lift_wrote(lifted: Path, fmt: str) -> None:
    out = lifted / "exported" / f"x.{fmt}"  # a folder that does not exist yet: made
    stderr = export(str(lifted / "clip.zedo.json"), "-o", str(out))
    names = {"trc": ["x_P1.trc", "x_P2.trc"], "c3d": ["x_P1.c3d", "x_P2.c3d"], "csv": ["x.csv", "x.meta.json"]}
    wrote = ", ".join(str(out.with_name(n)) for n in names.get(fmt, [f"x.{fmt}"]))
    assert stderr.strip().endswith(f"wrote {wrote}"), stderr  # every file named exists
    assert all(Path(p).is_file() for p in wrote.split(", "))
    _same_file(fmt, lifted / "direct" / f"x.{fmt}", out)


@pytest.mark.parametrize("source", ["jsonl", "csv", "npz"])
def test_every_result_format_exports_alike(lifted: Path, source: str) -> None:
    """From the JSON Lines, the CSV (with its sidecar) and the NPZ: the same TRC as lift's."""
    out = lifted / f"from_{source}" / "x.trc"
    export(str(lifted / "direct" / f"x.{source}"), "-o", str(out), "-q")
    for track in ("x_P1.trc", "x_P2.trc"):
        _text_equal(lifted / "direct" / track, out.with_name(track))


def test_person_format_and_default_name(lifted: Path, tmp_path: Path) -> None:
    src = tmp_path / "clip.zedo.json"
    src.write_bytes((lifted / "clip.zedo.json").read_bytes())
    export(str(src), "--person", "largest", "--format", "trc", "-q")  # one track: clip.zedo.trc beside it
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.zedo.json", "clip.zedo.trc"]
    rows = (tmp_path / "clip.zedo.trc").read_text().splitlines()[5:]
    assert len(rows) == FRAMES  # one row per frame number, the empty frame included
    export(str(src), "-o", str(tmp_path / "mm.csv"), "--units", "mm", "--frame", "root", "-q")
    header = (tmp_path / "mm.csv").read_text().splitlines()[0]
    assert "x_root_mm" in header
    export(str(src), "-o", str(tmp_path / "overhead.trc"), "--marker-axes", "overhead", "-q")
    assert (tmp_path / "overhead_P1.trc").is_file()


def test_export_refuses_with_one_line(lifted: Path, tmp_path: Path) -> None:
    src = lifted / "clip.zedo.json"
    existing = tmp_path / "have.trc"
    export(str(src), "--person", "largest", "-o", str(existing), "-q")
    coco = tmp_path / "kp.json"
    coco.write_text(json.dumps([{"image_id": 1, "keypoints": [1.0] * 51, "score": 1.0}]))
    root_csv = tmp_path / "root.csv"
    export(str(src), "-o", str(root_csv), "--frame", "root", "-q")
    cases = [
        ([str(src)], 2, "give -o/--output"),
        ([str(src), "--person", "largest", "-o", str(existing)], 2, "already exists; pass --overwrite"),
        ([str(src), "-o", str(src), "--overwrite"], 2, "is an input of this run"),
        ([str(src), "-o", str(tmp_path / "x.txt")], 2, "cannot tell the output format"),
        ([str(src), "-o", "-", "--format", "trc"], 2, "cannot go to stdout"),
        ([str(src), "-o", str(tmp_path / "y.trc"), "--fps", "25"], 2, "was lifted at 30 fps"),
        ([str(src), "-o", str(tmp_path / "y.trc"), "--person", "tallest"], 2, "--person must be one of"),
        ([str(root_csv), "-o", str(tmp_path / "cam.json"), "--frame", "camera"], 2, "root translation"),
        ([str(coco), "-o", str(tmp_path / "k.trc")], 3, "2D keypoints (coco-results), not a zedo result"),
        ([str(tmp_path / "missing.zedo.json"), "-o", str(tmp_path / "m.trc")], 3, "file not found"),
    ]
    before = sorted(p.name for p in tmp_path.iterdir())
    for args, code, needle in cases:
        result = runner.invoke(app, ["export", *args])
        assert result.exit_code == code, (args, result.output)
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("zedo: error: ") and needle in lines[0], (args, lines)
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written


def test_the_hypotheses_spread_is_read_back_and_exported(tiny_prior_path: Path, tmp_path: Path) -> None:
    """`hypothesis_spread_mm` (--hypotheses K > 1) survives `read_result` and `zedo export` in every
    format that holds it, with the `unstable_solution` flag it sets."""
    from zedo_cli.formats.readers.result import read_result

    src = write_two_people(tmp_path / "clip.jsonl")
    lift(tiny_prior_path, src, tmp_path / "x.json", "--hypotheses", "3")
    source = read_result(str(tmp_path / "x.json"))
    assert source.hypothesis_spread_m is not None and np.isfinite(source.hypothesis_spread_m[source.lifted]).all()
    for fmt in ("jsonl", "csv", "npz", "json"):
        export(str(tmp_path / "x.json"), "-o", str(tmp_path / f"y.{fmt}"))
        again = read_result(str(tmp_path / f"y.{fmt}"))
        assert again.hypothesis_spread_m is not None, fmt
        np.testing.assert_allclose(again.hypothesis_spread_m, source.hypothesis_spread_m, atol=1e-4, err_msg=fmt)
    lifted_once = read_result(str(tmp_path / "x.json"))
    assert [("unstable_solution" in f) for f in read_result(str(tmp_path / "y.jsonl")).flags] == [
        ("unstable_solution" in f) for f in lifted_once.flags
    ]
    plain = tmp_path / "one.json"
    lift(tiny_prior_path, src, plain)
    assert read_result(str(plain)).hypothesis_spread_m is None  # one hypothesis: nothing measured
