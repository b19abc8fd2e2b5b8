"""Writing output files safely: never over an existing file unless asked, never half-written.

Files are written atomically: a temporary file in the destination folder, renamed over the
destination only when complete, so a crash or Ctrl-C never leaves a truncated result. An
existing file is replaced only when the caller says so. A write the system refuses (a full
disk, a read-only folder) is an `OutputError` naming the output, and leaves nothing behind.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from .errors import ConfigError, OutputError

_NOT_A_FILE = {stat.S_ISDIR: "a folder", stat.S_ISCHR: "a character device", stat.S_ISBLK: "a block device",
               stat.S_ISFIFO: "a FIFO (named pipe)", stat.S_ISSOCK: "a socket"}  # fmt: skip


def check_output_kind(path: Path) -> bool:
    """Refuse an output path that exists and is not a regular file (a folder, /dev/null): a
    result is never written into a device or over a folder, not even with --overwrite. Returns
    whether a file exists there."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        return False
    if not stat.S_ISREG(mode):
        what = next((name for test, name in _NOT_A_FILE.items() if test(mode)), "not a regular file")
        raise ConfigError(f"{path}: is {what}; an output must be a file name (use - for stdout where it is offered)")
    return True


def check_writable(path: Path, overwrite: bool) -> None:
    """Refuse to replace an existing file unless `overwrite`, and anything that is not a
    regular file (a folder, /dev/null) even then; a missing folder is fine (it is made when
    the file is written) unless a file stands where a folder of it would be."""
    if (check_output_kind(path) or path.is_symlink()) and not overwrite:
        raise ConfigError(f"{path}: already exists; pass --overwrite to replace it")
    check_output_folder(path.parent)


def check_output_folder(folder: Path) -> None:
    """An output folder exists, or can be made: its nearest existing ancestor is a folder."""
    for ancestor in (folder, *folder.parents):
        if ancestor.exists():
            if not ancestor.is_dir():
                raise ConfigError(f"{ancestor}: is not a folder, so {folder} cannot be an output folder")
            return


def make_output_folder(folder: Path) -> None:
    """Make an output folder and its parents (as every zedo command does for -o and
    --output-dir); a folder the system will not make is an `OutputError`."""
    check_output_folder(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise output_failure(folder, exc) from None


def output_failure(path: str | Path, exc: OSError) -> OutputError:
    """The `OutputError` of a write of `path` the system refused (ENOSPC, EACCES, EROFS, ...)."""
    return OutputError(f"{path}: cannot write: {exc.strerror or exc}")


def _umask() -> int:
    # os.umask can only be read by setting it; mkstemp creates 0600 files, and a result file
    # should get the permissions any other new file of the user would get.
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def open_temporary(path: Path) -> tuple[int, Path]:
    """A temporary file (descriptor, path) beside `path`, so that os.replace is atomic (its
    folder made first if missing)."""
    make_output_folder(path.parent)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise output_failure(path, exc) from None
    try:
        os.chmod(tmp, 0o666 & ~_umask())
    except OSError as exc:
        os.close(fd)
        os.unlink(tmp)
        raise output_failure(path, exc) from None
    return fd, Path(tmp)


def replace_into(tmp: Path, path: Path, overwrite: bool) -> None:
    """Move the finished temporary file `tmp` to `path` (checked again: a file that appeared
    meanwhile is not clobbered)."""
    check_writable(path, overwrite)
    try:
        os.replace(tmp, path)
    except OSError as exc:
        raise output_failure(path, exc) from None


def check_can_create(path: Path) -> None:
    """Create and remove a temporary file beside `path`: a folder the system will not write
    (read-only, under /proc) is an `OutputError` before any work, not after it."""
    fd, tmp = open_temporary(path)
    os.close(fd)
    tmp.unlink()


@contextmanager
def atomic_path(path: str | Path, *, overwrite: bool = False) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces `path`, on error it is removed.

    The overwrite check runs before anything is written and again before the rename, so a file
    that appeared meanwhile is not clobbered either. An OSError of the writing (a full disk) is
    an `OutputError` naming `path`.
    """
    path = Path(path)
    check_writable(path, overwrite)
    fd, tmp = open_temporary(path)
    os.close(fd)
    try:
        try:
            yield tmp
        except OSError as exc:
            if isinstance(exc, BrokenPipeError):
                raise
            raise output_failure(path, exc) from None
        replace_into(tmp, path, overwrite)
    finally:
        tmp.unlink(missing_ok=True)


def write_text_atomic(path: str | Path, text: str, *, overwrite: bool = False) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    with atomic_path(path, overwrite=overwrite) as tmp:
        tmp.write_text(text, encoding="utf-8")
