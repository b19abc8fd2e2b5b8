"""Writing output files safely: never over an existing file unless asked, never half-written.

Files are written atomically: a temporary file in the destination folder, renamed over the
destination only when complete, so a crash or Ctrl-C never leaves a truncated result. An
existing file is replaced only when the caller says so.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import ConfigError


def check_writable(path: Path, overwrite: bool) -> None:
    """Refuse to replace an existing file unless `overwrite`; fail early on a missing folder."""
    if path.exists() and not overwrite:
        raise ConfigError(f"{path}: already exists; pass --overwrite (overwrite=True) to replace it")
    if not path.parent.is_dir():
        raise ConfigError(f"{path.parent}: output folder does not exist")


def _umask() -> int:
    # os.umask can only be read by setting it; mkstemp creates 0600 files, and a result file
    # should get the permissions any other new file of the user would get.
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def open_temporary(path: Path) -> tuple[int, Path]:
    """A temporary file (descriptor, path) beside `path`, so that os.replace is atomic."""
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.chmod(tmp, 0o666 & ~_umask())
    return fd, Path(tmp)


@contextmanager
def atomic_path(path: str | Path, *, overwrite: bool = False) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces `path`, on error it is removed.

    The overwrite check runs before anything is written and again before the rename, so a file
    that appeared meanwhile is not clobbered either.
    """
    path = Path(path)
    check_writable(path, overwrite)
    fd, tmp = open_temporary(path)
    os.close(fd)
    try:
        yield tmp
        check_writable(path, overwrite)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def write_text_atomic(path: str | Path, text: str, *, overwrite: bool = False) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    with atomic_path(path, overwrite=overwrite) as tmp:
        tmp.write_text(text, encoding="utf-8")
