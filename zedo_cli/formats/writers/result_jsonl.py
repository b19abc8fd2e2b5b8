"""The 3D result as JSON Lines (FORMATS.md 3.8b), written frame by frame.

One compact JSON object per line, each with a `type`:

    {"type": "header", "schema": "zedo.pose3d/1", "units": "m", "coordinate_frame": "camera", "axes": ..., ...}
    {"type": "frame", "frame_index": 0, "image_id": 27, "camera": {"K": ..., "source": "pseudo"}, "persons": [...]}
    {"type": "summary", "instances_total": 3, "instances_lifted": 2, ...}

The header is the JSON document's header (`result_json.build_header`), each frame line one of its
frames, the summary its summary: joining them gives the JSON document back. Missing values are
`null`. On stdout (`-`) each line is flushed as it is written, for pipelines; a file is written
to a temporary file beside it and renamed into place by `close`, so a reader never sees a
half-written result (and an aborted run leaves no file at all).
"""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Iterable
from pathlib import Path
from types import TracebackType
from typing import IO, Any

from ...files import check_writable, open_temporary, output_failure, replace_into


def _line(obj: dict[str, Any]) -> str:
    return json.dumps(obj, separators=(",", ":"), allow_nan=False) + "\n"


class JsonlWriter:
    """Incremental writer: `write_header` once, `write_frame` per frame, then `close(summary)`.

    Use it as a context manager: leaving the block normally closes it (with an empty summary
    when `close` was not called), leaving it by an exception discards the temporary file.
    """

    def __init__(self, out: str | Path, *, overwrite: bool = False) -> None:
        self._stdout = str(out) == "-"
        self._path = None if self._stdout else Path(out)
        self._overwrite = overwrite
        self._tmp: Path | None = None
        self._fh: IO[str]
        if self._path is None:
            self._fh = sys.stdout
        else:
            check_writable(self._path, overwrite)
            fd, self._tmp = open_temporary(self._path)
            self._fh = os.fdopen(fd, "w", encoding="utf-8")
        self._state = "new"  # new -> header -> closed
        self.frames_written = 0

    def _write(self, obj: dict[str, Any]) -> None:
        try:
            self._fh.write(_line(obj))
        except OSError as exc:  # a full disk: an OutputError (the caller's `with` discards the file)
            if self._stdout or self._path is None:
                raise
            raise output_failure(self._path, exc) from None
        if self._stdout:
            self._fh.flush()  # a consumer downstream sees each frame as soon as it is lifted

    def write_header(self, header: dict[str, Any]) -> None:
        if self._state != "new":
            raise RuntimeError("JsonlWriter: the header is written once, before any frame")
        self._write({"type": "header", **header})
        self._state = "header"

    def write_frame(self, frame: dict[str, Any]) -> None:
        if self._state != "header":
            raise RuntimeError("JsonlWriter: write_header first; no frame after close")
        self._write({"type": "frame", **frame})
        self.frames_written += 1

    def close(self, summary: dict[str, Any] | None = None) -> None:
        """Write the summary line and, for a file, move it into place."""
        if self._state == "closed":
            return
        if self._state != "header":
            self.abort()
            raise RuntimeError("JsonlWriter: closed before the header was written")
        self._write({"type": "summary", **(summary if summary is not None else {"frames_total": self.frames_written})})
        self._state = "closed"
        if self._tmp is not None and self._path is not None:
            try:
                try:
                    self._fh.close()  # flushes: a full disk shows here
                except OSError as exc:
                    raise output_failure(self._path, exc) from None
                replace_into(self._tmp, self._path, self._overwrite)  # a file that appeared meanwhile is kept
            finally:
                self._tmp.unlink(missing_ok=True)
        else:
            self._fh.flush()

    def abort(self) -> None:
        """Discard a file being written (stdout lines already written stay written)."""
        self._state = "closed"
        if self._tmp is not None:
            try:
                self._fh.close()
            except OSError:  # a full disk again: the file is discarded all the same
                pass
            self._tmp.unlink(missing_ok=True)

    def __enter__(self) -> JsonlWriter:
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        if exc_type is not None:
            self.abort()
        elif self._state != "closed":
            self.close()


def write_jsonl(
    out: str | Path,
    header: dict[str, Any],
    frames: Iterable[dict[str, Any]],
    summary: dict[str, Any] | None = None,
    *,
    overwrite: bool = False,
) -> None:
    """Write a header, the frames as the iterable yields them (e.g. `result_json.iter_frames`)
    and a summary to `out` (a path or "-")."""
    with JsonlWriter(out, overwrite=overwrite) as writer:
        writer.write_header(header)
        for frame in frames:
            writer.write_frame(frame)
        writer.close(summary)
