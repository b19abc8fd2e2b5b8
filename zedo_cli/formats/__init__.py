"""Files in and out, readers apart from writers:

- `readers/`: every 2D detector layout into `data.Keypoints2D` (`readers.inputs` is the entry point:
  detection, files, stdin, folders) and zedo's own 3D results back (`readers.result`);
- `writers/`: the 3D result in every output format (`writers.outputs` is the entry point);
- `result_schema`: the result's pydantic models, shared by the result writers' tests, the result
  reader and `zedo schema result`;
- `export`: a stored result read and written again (`zedo export`), the one module that uses both;
- `plots`, `colours`: the pose plots (not imported here, so that matplotlib loads only when a plot is
  asked for) and the sides' colours every figure uses.

No module under `readers/` imports one under `writers/`, nor the other way round
(tests/test_architecture.py). Builds on `lifting` (the `LiftResult` a writer writes) and `data`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        "..data.keypoints": ["Keypoints2D"],
        ".readers.inputs": [
            "INPUT_FORMATS",
            "detect_format",
            "input_sha256",
            "read_keypoints",
            "read_keypoints_text",
            "read_parsed",
        ],
        ".readers.result": ["ResultPoses", "read_result"],
        ".writers.outputs": ["OUTPUT_FORMATS", "default_output_name", "write_result"],
    },
)
