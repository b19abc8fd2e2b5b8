"""Hostile inputs in the library: hostile numbers (integers of thousands of digits, deep
nesting, booleans, non-ASCII digits, 1e30) in every reader, intrinsics file and weights metadata
end as typed one-line errors; the silent cases (a folder with a COCO file named like an OpenPose
frame, per-image intrinsics matching no image) are said; writes the system refuses are
`OutputError`s that leave nothing behind."""

from __future__ import annotations

import errno
import json
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import coco_annotations, key_paths, openpose_frame, write_json
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_formats_fuzz import BUILDERS, LAYOUTS

from zedo_cli.cli.lift_plan import expand_inputs
from zedo_cli.data.datasets import load_npy
from zedo_cli.errors import CameraInputError, DataError, InputFormatError, OutputError, WeightsError
from zedo_cli.files import atomic_path
from zedo_cli.formats import read_keypoints_text, read_parsed
from zedo_cli.formats.readers.openpose import is_openpose_folder
from zedo_cli.formats.readers.sniff import file_kind
from zedo_cli.formats.readers.validate import natural_key, trailing_number
from zedo_cli.formats.writers.result_jsonl import JsonlWriter
from zedo_cli.lifting.camera import resolve_intrinsics
from zedo_cli.prior.weights import _config_object, _member_count, json_field

SETTINGS = {"deadline": None, "database": None, "suppress_health_check": [HealthCheck.too_slow]}
# Every kind of number field a hostile file may hold: huge integers (past float's range and past
# Python's 4300-digit limit of int(str)), huge and tiny floats, booleans, digit strings in other scripts.
HOSTILE_NUMBERS = st.one_of(
    st.integers(min_value=300, max_value=5000).map(lambda digits: 10**digits - 1),
    st.integers(min_value=300, max_value=5000).map(lambda digits: 1 - 10**digits),
    st.sampled_from([1e30, -1e30, 1e308, 5e-324, True, False, "²", "٣", "1e30", "9" * 5000]),
    st.floats(allow_nan=True, allow_infinity=True),
)


@contextmanager
def _any_digits() -> Iterator[None]:
    """json.dumps of an integer past Python's digit limit (what a hostile file holds)."""
    old = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(old)


def _place(doc: Any, where: tuple[Any, ...], value: Any) -> Any:
    parent = doc
    for key in where[:-1]:
        parent = parent[key]
    parent[where[-1]] = value
    return doc


@given(layout=st.sampled_from(LAYOUTS), pick=st.integers(0, 10**6), value=HOSTILE_NUMBERS, as_text=st.booleans())
@settings(max_examples=400, **SETTINGS)
def test_every_reader_turns_every_hostile_number_into_an_input_error(
    layout: str, pick: int, value: Any, as_text: bool
) -> None:
    doc = BUILDERS[layout]()
    paths = key_paths(doc)
    doc = _place(doc, paths[pick % len(paths)], value)
    try:
        if as_text:
            with _any_digits():
                text = json.dumps(doc)
            read_keypoints_text(text, "h.json")
        else:
            read_parsed(doc, "h.json")
    except InputFormatError as exc:
        assert str(exc).startswith("h.json") and str(exc).isprintable()


@pytest.mark.parametrize("layout", LAYOUTS)
def test_deep_nesting_in_every_reader_is_an_input_error(layout: str) -> None:
    text = json.dumps(BUILDERS[layout]()).replace("1.0", "[" * 100_000 + "]" * 100_000, 1)
    with pytest.raises(InputFormatError, match="h.json"):
        read_keypoints_text(text if "[[[" in text else "[" * 100_000 + "]" * 100_000, "h.json")


@pytest.mark.parametrize("image_id", ["²", "٣.jpg", "x" + "1" * 5000, "1" * 5000 + ".jpg"])
def test_image_ids_with_odd_digits_are_read_not_crashed_on(image_id: str) -> None:
    entry = BUILDERS["alphapose"]()[0]
    entry["image_id"] = image_id
    kp = read_parsed([entry], "h.json")
    assert kp.image_ids == [image_id]


def test_natural_key_and_trailing_number_take_only_ascii_digits_of_a_frame_number_size() -> None:
    assert sorted(["f10", "f2", "²", "f" + "9" * 5000, "f1"], key=natural_key)[:3] == ["f1", "f2", "f10"]
    assert trailing_number("²") is None and trailing_number("a" + "1" * 19) is None
    assert trailing_number("clip_000000000012_keypoints") == 12


@given(key=st.sampled_from(["fx", "fy", "cx", "cy"]), value=HOSTILE_NUMBERS)
@settings(max_examples=150, **SETTINGS)
def test_intrinsics_number_fields_accept_only_finite_numbers_in_range(key: str, value: Any) -> None:
    entry: dict[str, Any] = {"fx": 1000, "fy": 1000, "cx": 320, "cy": 240, key: value}
    try:
        with warnings.catch_warnings():  # an overflow warning would reach the user's terminal
            warnings.simplefilter("error", RuntimeWarning)
            mats, _ = resolve_intrinsics(np.array([[640.0, 480.0]]), [1], ["a.png"], intrinsics_file=_intrinsics(entry))
    except CameraInputError as exc:
        assert str(exc).isprintable()
        return
    assert not isinstance(value, bool) and np.isfinite(mats).all()


_TMP = Path("/tmp") / f"zedo-hostile-{__name__}"


def _intrinsics(doc: Any, raw: str | None = None) -> str:
    _TMP.mkdir(exist_ok=True)
    path = _TMP / "K.json"
    with _any_digits():
        path.write_text(raw if raw is not None else json.dumps(doc))
    return str(path)


@pytest.mark.parametrize(
    ("doc", "raw", "said"),
    [
        ({"fx": True, "fy": 1000, "cx": 1, "cy": 1}, None, "fx: Input should be a valid number"),
        ({"K": [[True, 0, 1], [0, 1000, 1], [0, 0, 1]]}, None, r"K\[0\]\[0\]: Input should be a valid number"),
        (None, '{"fx": 1' + "0" * 500 + ', "fy": 1, "cx": 1, "cy": 1}', "fx: Input should be a valid number"),
        (None, '{"fx": 1' + "0" * 5000 + "}", "not valid JSON|not a readable"),
        (None, "[" * 100_000 + "]" * 100_000, "not valid JSON|not a readable|nested"),
        ({"images": {"other.png": {"fx": 900, "fy": 900, "cx": 1, "cy": 1}}}, None, "no key matches an input image"),
    ],
)
def test_hostile_or_unmatched_intrinsics_files_are_camera_errors(doc: Any, raw: str | None, said: str) -> None:
    with pytest.raises(CameraInputError, match=said):
        resolve_intrinsics(np.array([[640.0, 480.0]]), [1], ["a.png"], intrinsics_file=_intrinsics(doc, raw))


@pytest.mark.parametrize(
    "text", ["[" * 100_000 + "]" * 100_000, '{"hidden": 1' + "0" * 5000 + "}", '{"hidden": 1' + "0" * 400 + "}"]
)
def test_hostile_weights_metadata_is_a_weights_error(text: str) -> None:
    with pytest.raises(WeightsError, match="w.safetensors: metadata"):
        _config_object({"model_config": text}, "model_config", Path("w.safetensors"))
    if text.startswith("["):
        with pytest.raises(WeightsError, match="not valid JSON"):
            json_field({"joints": text}, "joints", Path("w.safetensors"))


@pytest.mark.parametrize("members", ["²", "9" * 5000, "0", "-3"])
def test_an_ensemble_member_count_is_ascii_digits_in_range(members: str) -> None:
    with pytest.raises(WeightsError, match="'members' must be an integer"):
        _member_count({"members": members}, Path("w.safetensors"))


def test_a_folder_is_one_openpose_sequence_only_when_every_file_is_a_frame(tmp_path: Path) -> None:
    frames = tmp_path / "frames"
    frames.mkdir()
    for k in range(3):
        write_json(frames / f"clip_{k:012d}_keypoints.json", openpose_frame(1.0))
    assert is_openpose_folder(frames) and expand_inputs([str(frames)]) == [str(frames)]
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    write_json(mixed / "coco_keypoints.json", coco_annotations())  # COCO, named like an OpenPose frame
    write_json(mixed / "other.json", coco_annotations())
    assert not is_openpose_folder(mixed)
    assert expand_inputs([str(mixed)]) == [str(mixed / "coco_keypoints.json"), str(mixed / "other.json")]
    alone = tmp_path / "alone"
    alone.mkdir()
    write_json(alone / "coco_keypoints.json", coco_annotations())
    assert not is_openpose_folder(alone)


def test_a_jsonl_stream_states_its_image_size_once() -> None:
    point = [[10.0 + j, 20.0 + j, 0.9] for j in range(17)]
    lines = [{"frame": 0, "image_size": [640, 480], "persons": [{"keypoints": point}]},
             {"frame": 1, "persons": [{"keypoints": point}]},
             {"frame": 2, "image_size": [320, 240], "persons": [{"keypoints": point}]},
             {"frame": 3, "persons": [{"keypoints": point}]}]  # fmt: skip
    kp = read_keypoints_text("\n".join(json.dumps(line) for line in lines), "s.jsonl")
    np.testing.assert_array_equal(kp.image_sizes, [[640, 480], [640, 480], [320, 240], [320, 240]])


@pytest.mark.parametrize(
    ("head", "kind"),
    [(b"\xff\xd8\xff\xe0", "an image (JPEG)"), (b"RIFF\x00\x00\x00\x00AVI ", "a video (AVI)"),
     (b"PK\x03\x04", "a ZIP archive"), (b"a;b\n1;2", "a CSV table"), (b' {"people": []}', None), (b"[1, 2]", None)],
)  # fmt: skip
def test_file_kind_from_the_first_bytes(head: bytes, kind: str | None) -> None:
    found = file_kind(head)
    assert found == kind if kind is None else (found is not None and found.startswith(kind))


def test_a_refused_write_is_an_output_error_and_leaves_nothing(tmp_path: Path) -> None:
    target = tmp_path / "r.zedo.json"
    with pytest.raises(OutputError, match=r"r.zedo.json: cannot write: No space left on device") as info:
        with atomic_path(target) as tmp:
            tmp.write_text("partial")
            raise OSError(errno.ENOSPC, "No space left on device")
    assert info.value.exit_code == 5 and not list(tmp_path.iterdir())
    with pytest.raises(OutputError, match="No space left"):
        with JsonlWriter(tmp_path / "s.zedo.jsonl") as writer:
            writer.write_header({"schema": "x"})

            def full(text: str) -> int:
                raise OSError(errno.ENOSPC, "No space left on device")

            writer._fh.write = full  # type: ignore[method-assign]
            writer.write_frame({"frame": 0})
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    ("content", "said"),
    [(b"\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False, 'shape': (100, 14, 3), }", "not a readable"),
     ("OBJECT", "not a readable"), ("TEXT", "expected an array of numbers")],
)  # fmt: skip
def test_truncated_or_object_npy_files_are_data_errors(tmp_path: Path, content: bytes | str, said: str) -> None:
    path = tmp_path / "poses3d_corrected.npy"
    if content == "OBJECT":
        np.save(path, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    elif content == "TEXT":
        np.save(path, np.array(["a", "b"]))
    else:
        path.write_bytes(content)
    with pytest.raises(DataError, match=said):
        load_npy(path, "fiu")


@pytest.mark.parametrize("value", [1 - 10**4301, -(10**18) - 1, -3], ids=["4301 digits", "19 digits", "-3"])
def test_a_negative_frame_number_of_any_size_is_one_line(value: int) -> None:
    """Found by the test above: a frame number below -10**4300 could not be printed in its message."""
    from zedo_cli.formats.readers.validate import frame_number

    with pytest.raises(InputFormatError, match=r"^h.json: line 1: frame: expected a frame number >= 0, got ") as exc:
        frame_number(value, "h.json", "line 1: frame")
    assert str(exc.value).isprintable() and len(str(exc.value)) < 200
