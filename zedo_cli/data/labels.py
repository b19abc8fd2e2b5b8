"""Point labels of annotation tools (LabelMe, Label Studio) read as zedo's joint names.

People label keypoints by hand with names of their own: ``Knee_L``, ``left_knee``, ``LKnee``,
``l_knee``, ``knee-left``, ``Left Knee``. A label is normalised (camelCase split, case, ``_``, ``-``,
``.`` and spaces alike) into a side (``l``, ``left``, ``lt`` / ``r``, ``right``, ``rt``, first or
last) and a body part, and the part's synonyms (`PART_SYNONYMS`) give zedo's joint name: sided
parts as ``left_<part>`` / ``right_<part>``, the others as themselves. A label that names no known
part, a sided part without a side (``Knee``) or a side on an unsided part (``Nose_L``) maps to
nothing: zedo never guesses (docs/inputs.md, "Annotation tools").

The names are zedo's: the joints of the named joint sets (`skeleton.SKELETONS`) and, for points no
joint set has, a few more (``head_top``, ``left_hand``, ``left_toe``, ``chin``, ...) that a reader
keeps as the input's other keypoints.
"""

from __future__ import annotations

import re

# Body parts that come in a left and a right one: zedo's part name -> the spellings read as it
# (after normalisation: lower case, words joined by "_"; a spelling without "_" also matches the
# joined words, so "bigtoe" and "big_toe" are the same).
SIDED_PARTS: dict[str, tuple[str, ...]] = {
    "shoulder": ("shoulder", "shoulders", "shldr", "sho"),
    "elbow": ("elbow", "elb"),
    "wrist": ("wrist", "wri", "wrst"),
    "hip": ("hip", "hips"),
    "knee": ("knee", "kne"),
    "ankle": ("ankle", "ank"),
    "eye": ("eye", "eyes"),
    "ear": ("ear", "ears"),
    "heel": ("heel",),
    "big_toe": ("big_toe", "bigtoe", "great_toe", "hallux"),
    "small_toe": ("small_toe", "smalltoe", "little_toe", "pinky_toe"),
    "toe": ("toe", "toes", "toe_tip", "foot_tip"),
    "hand": ("hand", "hand_tip", "palm"),
    "foot": ("foot", "feet"),
    "thumb": ("thumb",),
    "finger": ("finger", "index_finger", "middle_finger", "fingertip", "finger_tip"),
}
# Points without a side: zedo's name -> spellings.
UNSIDED_PARTS: dict[str, tuple[str, ...]] = {
    "nose": ("nose", "nose_tip"),
    "neck": ("neck",),
    "head": ("head", "head_center", "head_centre"),
    "head_top": ("head_top", "headtop", "top_head", "top_of_head", "crown", "vertex"),
    "chin": ("chin",),
    "mouth": ("mouth", "lips"),
    "thorax": ("thorax", "chest", "sternum", "upper_chest", "mid_shoulder", "shoulder_center", "shoulder_centre"),
    "pelvis": ("pelvis", "mid_hip", "midhip", "hip_center", "hip_centre", "root", "sacrum"),
    "spine": ("spine", "mid_spine", "belly", "navel", "umbilicus"),
}
_LEFT = ("left", "l", "lt")
_RIGHT = ("right", "r", "rt")
# camelCase and glued capitals: "LKnee" -> "L Knee", "leftBigToe" -> "left Big Toe"
_CAMEL = re.compile(r"(?<=[a-z0-9])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])")


def _lookup(table: dict[str, tuple[str, ...]]) -> dict[str, str]:
    found: dict[str, str] = {}
    for name, spellings in table.items():
        for spelling in (name, *spellings):
            found[spelling] = found[spelling.replace("_", "")] = name
    return found


_SIDED = _lookup(SIDED_PARTS)
_UNSIDED = _lookup(UNSIDED_PARTS)


def label_words(label: str) -> list[str]:
    """A label's words, lower case: "Knee_L" -> ["knee", "l"], "LBigToe" -> ["l", "big", "toe"]."""
    spaced = _CAMEL.sub(" ", label.strip())
    return [w for w in re.split(r"[\s_\-.:/]+", spaced.lower()) if w]


def _part(words: list[str], table: dict[str, str]) -> str | None:
    return table.get("_".join(words)) if words else None


def joint_name_of_label(label: str) -> str | None:
    """zedo's joint name for an annotation label, or None when it names no known point.

    "Knee_L", "left_knee", "LKnee", "l_knee", "knee-left", "Left Knee" -> "left_knee";
    "Nose" -> "nose"; "Big_Toe_R" -> "right_big_toe"; "HeadTop" -> "head_top"; "Knee" -> None.
    """
    words = label_words(label)
    if not words:
        return None
    if (part := _part(words, _UNSIDED)) is not None:
        return part
    for side, first, rest in (
        ("left", words[0], words[1:]),
        ("left", words[-1], words[:-1]),
        ("right", words[0], words[1:]),
        ("right", words[-1], words[:-1]),
    ):
        if first in (_LEFT if side == "left" else _RIGHT) and (part := _part(rest, _SIDED)) is not None:
            return f"{side}_{part}"
    # a side glued to the part in lower case: "lknee", "rshoulder", "kneel" is not read (knee + l?)
    word = "".join(words)
    for side, letters in (("left", _LEFT), ("right", _RIGHT)):
        for prefix in letters:
            if word.startswith(prefix) and (part := _SIDED.get(word[len(prefix) :])) is not None:
                return f"{side}_{part}"
    return None


def alias_table() -> list[tuple[str, str]]:
    """(zedo name, accepted spellings) for docs and messages, sided parts as left_/right_<part>."""
    rows = [(f"left_{name} / right_{name}", ", ".join(spellings)) for name, spellings in SIDED_PARTS.items()]
    return rows + [(name, ", ".join(spellings)) for name, spellings in UNSIDED_PARTS.items()]
