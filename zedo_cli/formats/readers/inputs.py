"""The entry point of the 2D keypoint readers: format names, auto-detection, files, stdin and
directories, into one `Keypoints2D` (FORMATS.md 3.7).

Formats (``--format`` names) and the module that reads each:

- ``coco-annotations``, ``coco-results``: `coco.py` (SyRIP ground truth; FiDIP, HRNet output)
- ``alphapose``: `alphapose.py` (COCO-17 or Halpe-26 results with string image ids)
- ``openpose``: `openpose.py` (one per-frame file, or a directory of them)
- ``mmpose-image``, ``mmpose-video``, ``mmpose-demo``: `mmpose.py`; ``mmpose`` picks the layout
- ``zedo-2d``: `zedo2d.py`; ``zedo-jsonl``: `jsonl.py` (JSON Lines, from a file or stdin)
- ``labelme``: `labelme.py` (LabelMe point files, one image each, or a folder of them as one clip)
- ``label-studio``: `labelstudio.py` (Label Studio keypoint exports, JSON or JSON_MIN)
- ``deeplabcut``: `deeplabcut.py` (DeepLabCut's CSV and ``.h5`` tables, single- or multi-animal)

Coordinates are 0-indexed pixels from the image's top-left. Missing joints come out as NaN with
confidence 0, never as positions. Every malformed input raises `InputFormatError` whose message
starts with the file path and names the field, e.g.
``kp.json: annotations[3].keypoints: expected 51 numbers (17 joints x 3), got 50``. Readers
return every instance (person) of every frame; choosing one person is left to the caller.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from ...data.keypoints import Keypoints2D
from ...data.skeleton import Skeleton, get_skeleton
from ...errors import ConfigError
from .alphapose import is_alphapose_entry, read_alphapose
from .coco import OCCLUDED_CONFIDENCE, parse_images, read_coco_annotations, read_coco_results
from .deeplabcut import looks_like_deeplabcut, read_deeplabcut_h5, read_deeplabcut_text
from .jsonl import looks_like_jsonl, read_zedo_jsonl, read_zedo_jsonl_text
from .labelme import is_labelme, is_labelme_folder, read_labelme, read_labelme_dir
from .labelstudio import is_label_studio, read_label_studio
from .mmpose import mmpose_layout, read_mmpose, read_mmpose_demo, read_mmpose_image, read_mmpose_video
from .openpose import frame_files, read_openpose, read_openpose_dir
from .sniff import is_hdf5
from .source import STDIN, load_document, parse_document, read_head, read_text
from .validate import as_dict, error, is_list, kind
from .zedo2d import ZEDO_2D_SCHEMA, read_zedo_2d

__all__ = [
    "INPUT_FORMATS", "OCCLUDED_CONFIDENCE", "ZEDO_2D_SCHEMA", "detect_format", "read_coco_annotations",
    "read_coco_results", "read_keypoints", "read_keypoints_text", "read_parsed", "read_zedo_2d",
]  # fmt: skip

_READERS: dict[str, Callable[[Any, str, Skeleton | None], Keypoints2D]] = {
    "coco-annotations": read_coco_annotations,
    "coco-results": read_coco_results,
    "alphapose": read_alphapose,
    "openpose": read_openpose,
    "mmpose": read_mmpose,
    "mmpose-image": read_mmpose_image,
    "mmpose-video": read_mmpose_video,
    "mmpose-demo": read_mmpose_demo,
    "zedo-2d": read_zedo_2d,
    "zedo-jsonl": read_zedo_jsonl,
    "labelme": read_labelme,
    "label-studio": read_label_studio,
}
# Tables, not JSON: read from their text (CSV) or file (.h5), never from a parsed JSON document.
_TABLE_FORMATS = ("deeplabcut",)
INPUT_FORMATS = ("auto", *_READERS, *_TABLE_FORMATS)
_JSONL_SUFFIXES = (".jsonl", ".ndjson")
_EXPECTED = (
    "expected COCO annotations (images, annotations, categories), a COCO results or AlphaPose list "
    "(image_id, keypoints), OpenPose (people), MMPose (instance_info; or a list with frame_id and instances, "
    "or with keypoints and keypoint_scores), zedo 2D (instances), zedo JSONL (frame, persons), "
    "LabelMe (shapes) or Label Studio (tasks with annotations, or JSON_MIN keypointlabels)"
)


def _keys(obj: dict[str, Any]) -> str:
    keys = [k if k.isprintable() else repr(k) for k in map(str, obj)]
    shown = ", ".join(keys[:12])
    return shown + (f", ... ({len(keys)} keys)" if len(keys) > 12 else "")


def _is_results_entry(entry: Any) -> bool:
    """A dict with ``image_id`` and a flat ``keypoints`` list (not MMPose's nested [[x, y], ...])."""
    if not isinstance(entry, dict) or "image_id" not in entry:
        return False
    keypoints = entry.get("keypoints")
    return isinstance(keypoints, list) and not (keypoints and isinstance(keypoints[0], list))


def detect_format(data: Any, path: str = "<input>") -> str:
    """The format of a parsed JSON document, one of `INPUT_FORMATS` (FORMATS.md 3.7).

    A dict: with images, annotations and categories COCO annotations; with people OpenPose;
    with instance_info the MMPose demo layout; with persons one zedo JSONL line; with instances
    zedo 2D; with shapes LabelMe; a Label Studio task (data and annotations). A list: of dicts
    with image_id and flat keypoints COCO results (an empty list too: a detector that found
    nobody), AlphaPose when the image_id is a string or idx/box are there;
    of dicts with frame_id and instances MMPose video; of dicts with nested keypoints and
    keypoint_scores MMPose image; of Label Studio tasks, or of JSON_MIN items with keypointlabels,
    Label Studio.
    """
    if isinstance(data, dict):
        if all(key in data for key in ("images", "annotations", "categories")):
            return "coco-annotations"
        for key, fmt in (("people", "openpose"), ("instance_info", "mmpose-demo"), ("persons", "zedo-jsonl"),
                         ("instances", "zedo-2d")):  # fmt: skip
            if key in data:
                return fmt
        if is_labelme(data):
            return "labelme"
        if is_label_studio(data):
            return "label-studio"
        found = f"top-level JSON object has keys {_keys(data)}" if data else "top-level JSON object is empty"
    elif is_list(data):
        if not data or _is_results_entry(data[0]):
            return "alphapose" if data and is_alphapose_entry(data[0]) else "coco-results"
        if is_label_studio(data):
            return "label-studio"
        layout = mmpose_layout(data)
        if layout is not None:
            return layout
        if isinstance(data[0], dict):
            found = f"top-level JSON list of objects whose first has keys {_keys(data[0]) or '(none)'}"
            if isinstance(data[0].get("keypoints"), list):
                found += " and nested keypoints"
        else:
            found = f"top-level JSON list whose first element is {kind(data[0])}"
    else:
        found = f"top-level JSON value is {kind(data)}"
    raise error(path, "", f"{found}; {_EXPECTED}")


def _format_option(fmt: str | None) -> str | None:
    if fmt is None or fmt == "auto":
        return None
    if fmt not in INPUT_FORMATS:
        raise ConfigError(f"unknown input format {fmt!r}; expected one of {', '.join(INPUT_FORMATS)}")
    return fmt


def _skeleton_option(skeleton: str | Skeleton | None) -> Skeleton | None:
    """``--skeleton``: a zedo skeleton name (ConfigError, exit 2, for an unknown one)."""
    if skeleton is None or isinstance(skeleton, Skeleton):
        return skeleton
    return get_skeleton(skeleton)


def _size_option(image_size: tuple[float, float]) -> tuple[float, float]:
    try:
        width, height = (float(v) for v in image_size)
    except (TypeError, ValueError):
        raise ConfigError(f"--image-size: expected two numbers W H, got {image_size!r}") from None
    if not all(math.isfinite(v) and v > 0 for v in (width, height)):
        raise ConfigError(f"--image-size: expected two positive numbers of pixels, got {width:g} {height:g}")
    return width, height


def _join_images(kp: Keypoints2D, images: str) -> Keypoints2D:
    """Fill unknown sizes and file names from a companion COCO file's ``images[]``, joined on image_id.

    A string image_id (AlphaPose) that is not an id there is looked up as a ``file_name`` or an
    ``original_file_name``.
    """
    index = parse_images(as_dict(load_document(images), images, ""), images)
    by_name = {name: image for image in index.values() for name in image.names}
    sizes = kp.image_sizes.copy()
    file_names = list(kp.file_names)
    for n, image_id in enumerate(kp.image_ids):
        image = index.get(image_id) or (by_name.get(image_id) if isinstance(image_id, str) else None)
        if image is None:
            raise error(kp.path, "image_id", f"image id {image_id!r} is not among the images[] of {images}")
        if np.isnan(sizes[n]).any():
            sizes[n] = image.size
        file_names[n] = file_names[n] if file_names[n] is not None else image.file_name
    return dataclasses.replace(kp, image_sizes=sizes, file_names=file_names)


def read_parsed(
    data: Any, path: str = "<input>", *, format: str | None = None, skeleton: str | Skeleton | None = None
) -> Keypoints2D:
    """Read an already parsed JSON document; `path` only names it in messages.

    `format`: one of `INPUT_FORMATS`; None or "auto" detects it (`detect_format`). `skeleton`:
    the joint set of inputs whose names are unknown or absent (``--skeleton``); names a file
    does carry must agree with it.
    """
    fmt = _format_option(format)
    if fmt in _TABLE_FORMATS:
        raise error(path, "", f"--format {fmt} reads DeepLabCut's CSV or .h5 files, not a JSON document")
    return _READERS[fmt or detect_format(data, path)](data, path, _skeleton_option(skeleton))


def read_keypoints_text(
    text: str, path: str = "<input>", *, format: str | None = None, skeleton: str | Skeleton | None = None
) -> Keypoints2D:
    """Read the text of a keypoint file (JSON, zedo JSON Lines or a DeepLabCut CSV); `path` names
    it in messages.

    Auto-detection takes a DeepLabCut CSV when the first cell is ``scorer``, JSON Lines for a
    ``.jsonl``/``.ndjson`` name or when the first line is a frame object on its own, and otherwise
    parses one JSON document.
    """
    fmt = _format_option(format)
    forced = _skeleton_option(skeleton)
    if fmt == "deeplabcut" or (fmt is None and looks_like_deeplabcut(text)):
        return read_deeplabcut_text(text, path, forced)
    if fmt == "zedo-jsonl" or (fmt is None and (path.endswith(_JSONL_SUFFIXES) or looks_like_jsonl(text))):
        return read_zedo_jsonl_text(text, path, forced)
    return read_parsed(parse_document(text, path), path, format=fmt, skeleton=forced)


def read_keypoints(
    path: str | Path,
    *,
    format: str | None = None,
    image_size: tuple[float, float] | None = None,
    images: str | Path | None = None,
    skeleton: str | Skeleton | None = None,
) -> Keypoints2D:
    """Read a 2D keypoint file ("-" = stdin; a DeepLabCut ``.h5`` by its HDF5 signature), or a
    directory of OpenPose or LabelMe frame files, into `Keypoints2D` (xy (N, J, 2) pixels, float64).

    `format`: one of `INPUT_FORMATS`; None or "auto" detects it. `images`: a companion COCO
    annotation file whose ``images[]`` give sizes and file names (for a results file), joined
    on image_id. `image_size`: (W, H) pixels for the instances whose size is still unknown.
    `skeleton`: ``--skeleton`` (see `read_parsed`). The result's `source` says which joint set
    was assumed and why.
    """
    name = str(path)
    fmt = _format_option(format)
    forced = _skeleton_option(skeleton)
    size = _size_option(image_size) if image_size is not None else None
    if name != STDIN and Path(name).is_dir():
        if fmt not in (None, "openpose", "labelme"):
            raise error(
                name, "", f"is a directory; only OpenPose or LabelMe files are read from a directory, not {fmt}"
            )
        labelme = fmt == "labelme" or (fmt is None and is_labelme_folder(Path(name)))
        kp = read_labelme_dir(name, forced) if labelme else read_openpose_dir(name, forced)
    elif name != STDIN and fmt in (None, "deeplabcut") and is_hdf5(read_head(name)):
        kp = read_deeplabcut_h5(name, forced)
    else:
        # --format deeplabcut reads a file that does not look like a table, to say which row is wrong
        text = read_text(name, sniff=fmt != "deeplabcut")
        kp = read_keypoints_text(text, name, format=fmt, skeleton=forced)
    if images is not None:
        kp = _join_images(kp, str(images))
    return kp if size is None else fill_image_sizes(kp, size)[0]


def fill_image_sizes(kp: Keypoints2D, image_size: tuple[float, float]) -> tuple[Keypoints2D, int]:
    """`--image-size` (W, H) for the instances whose size is still unknown (neither the input nor
    `--images` states it), and how many it filled: 0 when every size was known, so the option
    was not used (`zedo lift` says so)."""
    size = _size_option(image_size)
    sizes = kp.image_sizes.copy()
    unknown = np.isnan(sizes).any(axis=1)
    sizes[unknown] = size
    return dataclasses.replace(kp, image_sizes=sizes), int(unknown.sum())


def input_sha256(path: str | Path) -> str | None:
    """SHA-256 (hex) of an input for the result's provenance: a file's bytes, or for a directory
    of OpenPose frames each frame file's name and bytes in frame order; None for stdin ("-"),
    which cannot be read twice. Unreadable inputs raise `InputFormatError`."""
    name = str(path)
    if name == STDIN:
        return None
    digest = hashlib.sha256()
    try:
        if Path(name).is_dir():
            for file, _ in frame_files(Path(name)):
                digest.update(file.name.encode() + b"\0" + hashlib.sha256(file.read_bytes()).digest())
        else:
            with open(name, "rb") as handle:  # a MiB at a time: the input is not held twice
                while chunk := handle.read(1 << 20):
                    digest.update(chunk)
    except OSError as exc:
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    return digest.hexdigest()
