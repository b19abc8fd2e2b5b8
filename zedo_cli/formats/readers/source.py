"""Reading input text from a file or stdin and parsing it as JSON, with file-level errors.

Kept apart from the readers so that every reader (and a directory of OpenPose files) turns a
missing, unreadable, non-UTF-8, empty or invalid file into the same `InputFormatError`.
"""

from __future__ import annotations

import errno
import json
import os
import stat
import sys
from typing import Any

from ...errors import InputFormatError
from ...strict_json import DuplicateKeyError, loads
from .jsondoc import InvalidDocument, scan_document
from .sniff import HEAD_BYTES, check_kind
from .validate import error

STDIN = "-"
# The largest input zedo reads, in bytes. The text is held while it is read (`parse_document`
# decodes its arrays an element at a time); the largest real detector outputs seen (hours of
# AlphaPose frames) are tens of MB.
MAX_INPUT_BYTES = 256 * 1024 * 1024
_KINDS = {stat.S_ISFIFO: "a FIFO (named pipe)", stat.S_ISCHR: "a character device", stat.S_ISBLK: "a block device",
          stat.S_ISSOCK: "a socket", stat.S_ISDIR: "a directory, expected a JSON file"}  # fmt: skip


def _too_large(size: int) -> str:
    return f"larger than the input limit of {MAX_INPUT_BYTES / 2**20:.4g} MiB ({size / 2**20:.4g} MiB or more)"


def open_regular(name: str) -> int:
    """Open `name` for reading after checking it is a regular file within `MAX_INPUT_BYTES`;
    nothing is read from a FIFO, a device (``/dev/zero``) or a socket, and a symlink loop or a
    broken link is named as such. Returns the file descriptor."""
    try:
        info = os.stat(name)
    except FileNotFoundError:
        raise error(name, "", "broken symbolic link (its target does not exist)" if os.path.islink(name)
                    else "file not found") from None  # fmt: skip
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise error(name, "", "symbolic link loop (too many levels of symbolic links)") from None
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    for test, what in _KINDS.items():
        if test(info.st_mode):
            raise error(name, "", f"is {what}")
    if not stat.S_ISREG(info.st_mode):
        raise error(name, "", "not a regular file")
    if info.st_size > MAX_INPUT_BYTES:
        raise error(name, "", _too_large(info.st_size))
    try:
        return os.open(name, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None


def read_head(name: str) -> bytes:
    """The first `HEAD_BYTES` of file `name`, after the checks of `open_regular`."""
    fd = open_regular(name)
    try:
        return os.read(fd, HEAD_BYTES)
    except OSError as exc:
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    finally:
        os.close(fd)


def check_input_file(name: str) -> None:
    """An input file, checked before any work: a regular file that can be read, within the size
    limit (`open_regular`), and not an image, video, table or array that zedo does not read
    (`sniff.check_kind`)."""
    check_kind(name, read_head(name))


_CHUNK_BYTES = 1 << 20


def _read_bounded(stream: Any, name: str) -> bytearray:
    """At most `MAX_INPUT_BYTES` of `stream`; more is an error (a file that grew, or stdin).

    Read a MiB at a time into one growing buffer: ``read(MAX_INPUT_BYTES + 1)`` would reserve
    the whole limit (256 MiB) for any input, and joining chunks would hold the input twice.
    """
    raw = bytearray()
    while chunk := stream.read(min(_CHUNK_BYTES, MAX_INPUT_BYTES + 1 - len(raw))):
        raw += chunk
        if len(raw) > MAX_INPUT_BYTES:
            raise error(name, "", _too_large(len(raw)))
    return raw


def read_text(name: str, *, sniff: bool = True) -> str:
    """The UTF-8 text of file `name` ("-" = stdin); a byte-order mark (Excel's UTF-8 CSV) is
    dropped. Inputs that are not regular files, or larger than `MAX_INPUT_BYTES`, are refused
    before reading; with `sniff`, so is an image, a video or another kind of file zedo does not
    read (`sniff.check_kind`)."""
    try:
        if name == STDIN:
            raw = _read_bounded(sys.stdin.buffer, name)
        else:
            with os.fdopen(open_regular(name), "rb") as handle:
                raw = _read_bounded(handle, name)
    except OSError as exc:
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    if sniff:  # an image or a video: say what zedo reads, not "not UTF-8"
        check_kind(name, bytes(raw[:HEAD_BYTES]))
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(name, "", f"not UTF-8 text (invalid byte at offset {exc.start})") from None


def blank(text: str) -> bool:
    """Empty or only whitespace (``not text.strip()`` without copying a large text)."""
    return not text or text.isspace()


def json_error(name: str, where: str, exc: ValueError | RecursionError) -> InputFormatError:
    """The one-line error of text that `strict_json.loads` refused: a repeated key, invalid JSON
    (where and why), an integer past Python's digit limit or nesting too deep to decode."""
    if isinstance(exc, DuplicateKeyError):
        return error(name, where, str(exc))
    if isinstance(exc, json.JSONDecodeError):
        at = f"line {exc.lineno}, column {exc.colno}" if not where else f"column {exc.colno}"
        return error(name, where, f"invalid JSON at {at}: {exc.msg}")
    if isinstance(exc, RecursionError):
        return error(name, where, "invalid JSON: nested too deeply to read")
    if "integer string conversion" in str(exc):  # Python's own message names its setting, not the file
        return error(name, where, f"invalid JSON: an integer of more than {sys.get_int_max_str_digits()} digits")
    return error(name, where, f"invalid JSON: {exc}")


def parse_json(text: str, name: str, where: str = "") -> Any:
    """`text` parsed as one JSON value; `where` prefixes the position (e.g. "line 3" of a JSONL file).
    An object that names a key twice is refused (`strict_json`)."""
    if blank(text):
        raise error(name, where, "file is empty" if not where else "empty line")
    try:
        return loads(text)
    except (ValueError, RecursionError) as exc:  # JSONDecodeError is a ValueError
        raise json_error(name, where, exc) from None


def load_json(name: str) -> Any:
    """The parsed JSON of file `name` ("-" = stdin)."""
    return parse_json(read_text(name), name)


def parse_document(text: str, name: str) -> Any:
    """`parse_json` for a whole input file, its top-level arrays left in the text and decoded
    one element at a time as a reader walks them (`jsondoc.JsonArray`)."""
    if blank(text):
        return parse_json(text, name)  # "file is empty"
    try:
        return scan_document(text)
    except DuplicateKeyError as exc:
        raise json_error(name, "", exc) from None
    except (InvalidDocument, ValueError, RecursionError):  # JSONDecodeError is a ValueError
        return parse_json(text, name)  # json.loads says where and why (its document, should it not fail)


def load_document(name: str) -> Any:
    """The JSON document of file `name` ("-" = stdin), as `parse_document` returns it."""
    return parse_document(read_text(name), name)
