"""Typed errors with messages a user can act on.

Library code raises these; only the CLI turns them into one line on stderr and an exit code.
"""

from __future__ import annotations


class ZedoError(Exception):
    """Base class of every error zedo reports to a user."""

    exit_code: int = 1


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


class DataError(ZedoError):
    """A data set folder or 3D pose file is missing or inconsistent."""

    exit_code = 3
