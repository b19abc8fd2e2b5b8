"""The experiments' tests, run on demand (`python -m pytest experiments/tests -p no:cacheprovider`; the default
suite collects tests/ only). They import the experiments as the experiments import each other and the shared
benchmark code, with the repository root on sys.path, and share tests/helpers.py's generated poses."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
for path in (ROOT, ROOT / "tests"):
    if str(path) not in sys.path:
        sys.path.insert(0, str(path))
