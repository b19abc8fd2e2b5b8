"""Typed errors with messages a user can act on.

Library code raises these; only the CLI turns them into one line on stderr and an exit code.
"""

from __future__ import annotations


def one_line(text: str) -> str:
    """`text` with every unprintable character (newline, tab, the ESC of a terminal sequence, ...)
    written as a Python escape, so that a message stays on one line and cannot drive a terminal."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def plural(count: int, word: str, many: str | None = None) -> str:
    """ "1 instance", "2 instances" (`many` for an irregular plural: "1 person", "3 people")."""
    return f"{count} {word if count == 1 else many or word + 's'}"


class ZedoError(Exception):
    """Base class of every error zedo reports to a user. Its message is kept on one line
    (`one_line`): file names and values with newlines or escape sequences are shown escaped."""

    exit_code: int = 1

    def __init__(self, *args: object) -> None:
        super().__init__(*(one_line(a) if isinstance(a, str) else a for a in args))


class InputFormatError(ZedoError):
    """An input file is missing, unreadable or not in a layout zedo understands."""

    exit_code = 3


class IntrinsicsError(ZedoError):
    """Camera intrinsics are missing, malformed or impossible (e.g. non-positive focal)."""

    exit_code = 2


class CameraInputError(IntrinsicsError):
    """The camera cannot be settled from an input file: a malformed intrinsics file, or an
    image size that is missing or out of range where the principal point needs it."""

    exit_code = 3


class WeightsError(ZedoError):
    """A weights file is missing, corrupt, of another format version or of another skeleton."""

    exit_code = 3


class ConfigError(ZedoError):
    """An option or recipe value is invalid."""

    exit_code = 2


class OutputError(ZedoError):
    """An output could not be written: a full disk, a read-only or vanished folder, a path the
    system refuses (e.g. under /proc). Whatever was being written is removed."""

    exit_code = 5


class DataError(ZedoError):
    """A data set folder or 3D pose file is missing or inconsistent."""

    exit_code = 3


class CalibrationError(ZedoError):
    """`zedo calibrate` refuses a camera it cannot trust: the board found in no view or in too
    few, an RMS reprojection error above the bound, or OpenCV's fit failing."""

    exit_code = 6
