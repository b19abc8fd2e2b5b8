"""What kind of file an input is, from its first bytes: so that an image, a video, a CSV table or
a NumPy file given to `zedo lift` is told what zedo reads, instead of a JSON parser's message
("invalid JSON at line 1", "not UTF-8 text"). DeepLabCut's tables are read: a CSV whose first cell
is ``scorer``, and an HDF5 file (its ``.h5``)."""

from __future__ import annotations

from .validate import error

WHAT_ZEDO_READS = (
    "zedo lift reads a 2D detector's keypoints (COCO, OpenPose, AlphaPose, MMPose, DeepLabCut, zedo JSON/JSONL): "
    "run a 2D pose detector on it first (see docs/inputs.md)"
)
HEAD_BYTES = 4096  # enough for every signature below and a CSV's first lines
_IMAGE = "an image"
_VIDEO = "a video"
# (offset, signature, what): the first bytes of the common image, video and array containers.
_SIGNATURES: tuple[tuple[int, bytes, str], ...] = (
    (0, b"\x89PNG\r\n\x1a\n", f"{_IMAGE} (PNG)"),
    (0, b"\xff\xd8\xff", f"{_IMAGE} (JPEG)"),
    (0, b"GIF87a", f"{_IMAGE} (GIF)"),
    (0, b"GIF89a", f"{_IMAGE} (GIF)"),
    (0, b"BM", f"{_IMAGE} (BMP)"),
    (0, b"II*\x00", f"{_IMAGE} (TIFF)"),
    (0, b"MM\x00*", f"{_IMAGE} (TIFF)"),
    (8, b"WEBP", f"{_IMAGE} (WebP)"),
    (4, b"ftyp", f"{_VIDEO} (MP4/MOV) or an HEIF image"),
    (8, b"AVI ", f"{_VIDEO} (AVI)"),
    (0, b"\x1a\x45\xdf\xa3", f"{_VIDEO} (Matroska/WebM)"),
    (0, b"\x00\x00\x01\xba", f"{_VIDEO} (MPEG)"),
    (0, b"\x93NUMPY", "a NumPy array (.npy)"),
    (0, b"PK\x03\x04", "a ZIP archive (e.g. a NumPy .npz)"),
    (0, b"%PDF", "a PDF document"),
    (0, b"\x89HDF", "an HDF5 file"),
)
_HDF5 = b"\x89HDF\r\n\x1a\n"  # DeepLabCut's .h5 tables are HDF5


def file_kind(head: bytes) -> str | None:
    """What the first bytes of a file say it is ("an image (PNG)", "a CSV table", ...), or None
    for text that may be JSON (the parser decides)."""
    for offset, signature, what in _SIGNATURES:
        if head[offset : offset + len(signature)] == signature:
            return what
    text = head.decode("utf-8", errors="replace").lstrip("\ufeff \t\r\n")
    if not text or text[0] in "{[":
        return None
    first = text.split("\n", 1)[0]
    if "," in first or "\t" in first or ";" in first:
        return "a CSV table (or other delimited text; a DeepLabCut CSV starts with its scorer row)"
    return None


def first_cell(text: str) -> str:
    """The first cell of a CSV text's first line, without a byte-order mark, quotes or spaces."""
    line = text.lstrip("\ufeff \t\r\n").split("\n", 1)[0]
    return line.split(",", 1)[0].strip().strip('"').strip()


def is_hdf5(head: bytes) -> bool:
    """The first bytes of an HDF5 file (DeepLabCut's ``.h5``)."""
    return head.startswith(_HDF5)


def is_table_zedo_reads(head: bytes) -> bool:
    """DeepLabCut's tables: a CSV whose first cell is ``scorer`` (after a byte-order mark), or an
    HDF5 file (the reader says whether it holds DeepLabCut's DataFrame)."""
    return is_hdf5(head) or first_cell(head.decode("utf-8", errors="replace")) == "scorer"


def not_keypoints(name: str, what: str) -> Exception:
    """The `InputFormatError` for an input that is `what` rather than 2D keypoints."""
    return error(name, "", f"this is {what}, not 2D keypoints; {WHAT_ZEDO_READS}")


def check_kind(name: str, head: bytes) -> None:
    """Refuse an input whose first bytes say it is an image, a video, a table or an array that zedo
    does not read."""
    what = file_kind(head)
    if what is not None and not is_table_zedo_reads(head):
        raise not_keypoints(name, what)
