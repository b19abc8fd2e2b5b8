"""`paused_collection()`: Python's cyclic garbage collector paused while a large file's objects are built.

Reading a 10-minute clip's result makes millions of lists and dicts that hold no reference cycles; each collection
pass while they are made scans them all again (over half the reading time). Reference counting still frees them."""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def paused_collection() -> Iterator[None]:
    """Within the block, no cyclic collection; afterwards as before (nested blocks keep it paused)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()
