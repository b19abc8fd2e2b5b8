"""Hostile JSON in the library: a JSON object naming a key twice is refused by every JSON
reader (keypoint inputs, results, calibration files, shipped calibrations, weights metadata)
naming the key; a ragged K matrix is a camera error; the result reader refuses deep nesting and
integers past Python's digit limit in one line as the keypoint readers do; an image id past
int64 is written to NPZ as text and read back whole."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from test_formats_fuzz import BUILDERS, LAYOUTS
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.camera.files import read_camera_file
from zedo_cli.errors import CameraInputError, InputFormatError, WeightsError
from zedo_cli.formats import read_keypoints_text
from zedo_cli.formats.readers.result import read_result, read_result_bytes
from zedo_cli.formats.writers.outputs import write_result
from zedo_cli.prior.weights import json_field
from zedo_cli.strict_json import DuplicateKeyError, loads
from zedo_cli.versioned_json import read_items

DUPLICATE = '"zedo_dup": 1, "zedo_dup": 2, '


def _with_duplicate(text: str, which: int) -> str:
    """`text` with a repeated key put into its `which`-th object (counted from the start; -1 the last)."""
    starts = [i for i, c in enumerate(text) if c == "{"]
    at = starts[which] + 1
    return text[:at] + DUPLICATE + text[at:]


def test_loads_refuses_a_repeated_key_at_any_depth_and_reads_the_rest_as_json_loads() -> None:
    for text in ('{"a": 1, "a": 1}', '[{"b": {"c": [1, {"d": 0, "d": 0}]}}]'):
        with pytest.raises(DuplicateKeyError, match="duplicate key '(a|d)'"):
            loads(text)
    text = '{"a": [1, 2.5, NaN, {"b": null}], "c": "\\u00e9"}'
    assert json.dumps(loads(text)) == json.dumps(json.loads(text))


@pytest.mark.parametrize("layout", LAYOUTS)
@pytest.mark.parametrize("which", [0, -1])  # the top-level object (jsondoc's own scan) and the last nested one
def test_every_keypoint_reader_refuses_a_repeated_key_naming_it(layout: str, which: int) -> None:
    text = json.dumps(BUILDERS[layout]())
    if "{" not in text:
        pytest.skip("no object in this layout")
    with pytest.raises(InputFormatError, match=r"^h\.json: .*duplicate key 'zedo_dup'"):
        read_keypoints_text(_with_duplicate(text, which), "h.json")


def _result_json(tmp_path: Path, fmt: str) -> Path:
    kp, res, mats, sources = make_case()
    out = tmp_path / f"r.zedo.{fmt}"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    return out


@pytest.mark.parametrize("fmt", ["json", "jsonl"])
@pytest.mark.parametrize("which", [0, 3, -1])
def test_the_result_reader_refuses_a_repeated_key_naming_it(tmp_path: Path, fmt: str, which: int) -> None:
    text = _result_json(tmp_path, fmt).read_text()
    with pytest.raises(InputFormatError, match=r"^r\.json: (line \d+: )?duplicate key 'zedo_dup'"):
        read_result_bytes(_with_duplicate(text, which).encode(), "r.json")


def test_a_csv_sidecar_and_npz_metadata_with_a_repeated_key_are_refused(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    csv_path = tmp_path / "r.csv"
    write_result(csv_path, kp, res, mats, sources, PARAMS, INPUT_INFO)
    sidecar = csv_path.with_suffix(".meta.json")
    sidecar.write_text(_with_duplicate(sidecar.read_text(), 0))
    with pytest.raises(InputFormatError, match="duplicate key 'zedo_dup'"):
        read_result(csv_path)
    npz_path = tmp_path / "r.npz"
    write_result(npz_path, kp, res, mats, sources, PARAMS, INPUT_INFO)
    arrays = dict(np.load(npz_path))
    arrays["metadata"] = np.asarray(_with_duplicate(str(arrays["metadata"]), 0))
    np.savez(npz_path, **arrays)
    with pytest.raises(InputFormatError, match="r.npz: metadata: duplicate key 'zedo_dup'"):
        read_result(npz_path)


@pytest.mark.parametrize("fmt", ["json", "jsonl"])
@pytest.mark.parametrize(
    ("hostile", "said"),
    [("[" * 100_000 + "]" * 100_000, "nested too deeply to read"), ("9" * 5000, "an integer of more than 4300 digits")],
)
def test_the_result_reader_refuses_deep_nesting_and_huge_integers_in_one_line(
    tmp_path: Path, fmt: str, hostile: str, said: str
) -> None:
    text = _result_json(tmp_path, fmt).read_text()
    at = re.search(r'"frame_index": ?', text).end()
    bad = text[:at] + hostile + text[at + 1 :]  # the first frame's index (one digit) replaced
    with pytest.raises(InputFormatError, match=f"^r.json: (line 2: )?invalid JSON: {said}$"):
        read_result_bytes(bad.encode(), "r.json")


@pytest.mark.parametrize(
    ("name", "text", "field"),
    [
        ("K.json", '{"K": [[2000, 0, 640], [0, 2000], [0, 0, 1]]}', "K"),
        ("K.json", '{"images": {"a.png": {"K": [[2000, 0], [0, 2000, 360], [0, 0, 1]]}}}', r"images\['a.png'\].K"),
        ("cv.json", '{"camera_matrix": [[2000, 0, 640], [0, 2000, 360], [0, 1]]}', "camera_matrix"),
        ("c.toml", "[cam]\nname = 'a'\nmatrix = [[2000, 0, 640], [0, 2000], [0, 0, 1]]\n", r"\[cam\].matrix"),
    ],
)
def test_a_ragged_camera_matrix_is_a_camera_error_naming_the_field(
    tmp_path: Path, name: str, text: str, field: str
) -> None:
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(CameraInputError, match=f"{name}: {field}: K must be a 3x3 matrix of numbers, got rows of"):
        read_camera_file(path)


def test_a_calibration_file_with_a_repeated_key_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "K.json"
    path.write_text('{"fx": 2000, "fy": 2000, "cx": 640, "cy": 360, "fx": 20}')
    with pytest.raises(CameraInputError, match="K.json: not a readable JSON file .*duplicate key 'fx'"):
        read_camera_file(path)
    shipped = tmp_path / "cal.json"
    shipped.write_text('{"format": "f", "format_version": 1, "items": [], "items": [{}]}')
    with pytest.raises(WeightsError, match="duplicate key 'items'"):
        read_items(shipped, "f", 1, "items", "calibration")
    with pytest.raises(WeightsError, match="metadata field 'joints' is not valid JSON"):
        json_field({"joints": '{"a": 1, "a": 2}'}, "joints", Path("w.safetensors"))


def test_an_image_id_past_int64_is_written_to_npz_as_text_and_read_back_whole(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    kp.image_ids = [10**30, 10**30, 11, 12]
    out = tmp_path / "r.npz"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert np.load(out)["image_ids"].tolist() == [str(10**30)] * 2 + ["11", "12"]
    back = read_result(out)
    assert [str(i) for i in back.image_ids] == [str(10**30)] * 2 + ["11", "12"]
    kp.image_ids = [10, 10, 11, 12]  # ids that fit stay integers
    write_result(tmp_path / "s.npz", kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert np.load(tmp_path / "s.npz")["image_ids"].dtype == np.int64
