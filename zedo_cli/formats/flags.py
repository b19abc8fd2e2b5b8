"""The flags of a lifted person, as the JSON results list them per person and the CSV per joint row.

Per person (`person_flags`): `not_lifted_<reason>`, `joints_filled_by_prior: <joints>`, the camera sanity flags
(`implausible_distance`, `keypoints_outside_image`), `unstable_solution`, and `--temporal clip`'s
`left_right_swapped_in_2d`, `detection_outlier: <joints>` and `depth_ambiguous: <joints>`. Per joint
(`joint_flags`): what concerns that joint alone (`depth_ambiguous`, with the other side's flexion at an ankle or
wrist, and `detection_outlier`); `person_wide_flags` are the rest, which every row of the person carries.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..camera.sanity import CameraSanity
from ..data.keypoints import Keypoints2D

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ..lifting.solver import LiftResult

DEPTH_AMBIGUOUS = "depth_ambiguous"
DETECTION_OUTLIER = "detection_outlier"
SEPARATOR = "; "  # between a CSV row's flags


def ambiguous_joint(joints: tuple[str, ...], res: LiftResult, i: int, j: int) -> str:
    """Joint `j` of person `i`, depth-ambiguous: its name, an ankle's or wrist's with the flexion the other side
    would give its knee or elbow."""
    name = joints[j]
    angle = np.nan if res.other_flexion_deg is None else res.other_flexion_deg[i, j]
    hinge = name.replace("ankle", "knee").replace("wrist", "elbow")
    return name if not np.isfinite(angle) else f"{name} (other side: {hinge} flexion {angle:.0f} deg)"


def person_wide_flags(res: LiftResult, i: int, sanity: CameraSanity) -> list[str]:
    """The flags of person `i` that concern the whole person, not one joint."""
    flags = list(sanity.flags(i))  # implausible_distance, keypoints_outside_image (camera.sanity)
    unstable = res.unstable()
    if unstable is not None and unstable[i]:  # K > 1: hypotheses far apart (lifting.result.UNSTABLE_SPREAD_M)
        flags.append("unstable_solution")
    if res.detection_swapped is not None and res.detection_swapped[i]:  # --temporal clip: corrected before lifting
        flags.append("left_right_swapped_in_2d")
    return flags


def joint_flags(kp: Keypoints2D, res: LiftResult, i: int, j: int) -> list[str]:
    """The flags of joint `j` of person `i` alone (a CSV row's own)."""
    flags = []
    if res.detection_outliers is not None and res.detection_outliers[i, j]:
        flags.append(DETECTION_OUTLIER)
    if res.depth_ambiguous is not None and res.lifted[i] and res.depth_ambiguous[i, j]:
        detail = ambiguous_joint(kp.skeleton.joints, res, i, j).removeprefix(kp.skeleton.joints[j]).strip()
        flags.append(f"{DEPTH_AMBIGUOUS} {detail}".strip())
    return flags


def person_flags(kp: Keypoints2D, res: LiftResult, i: int, sanity: CameraSanity) -> list[str]:
    """Every flag of person `i`, as the JSON results list them."""
    flags = [] if res.lifted[i] else [f"not_lifted_{res.status[i]}"]  # reasons: lifting.solver.NOT_LIFTED
    missing = [kp.skeleton.joints[j] for j in np.flatnonzero(~res.observed[i])]
    if missing and res.lifted[i]:
        flags.append("joints_filled_by_prior: " + ", ".join(missing))
    flags += person_wide_flags(res, i, sanity)
    joints = kp.skeleton.joints
    if res.detection_outliers is not None and res.detection_outliers[i].any():
        flags.append(f"{DETECTION_OUTLIER}: " + ", ".join(joints[j] for j in np.flatnonzero(res.detection_outliers[i])))
    if res.depth_ambiguous is not None and res.lifted[i] and res.depth_ambiguous[i].any():  # --temporal clip
        names = [ambiguous_joint(joints, res, i, j) for j in np.flatnonzero(res.depth_ambiguous[i])]
        flags.append(f"{DEPTH_AMBIGUOUS}: " + ", ".join(names))
    return flags


def flags_from_rows(joints: tuple[str, ...], cells: dict[int, str]) -> list[str]:
    """A person's flags as the JSON lists them (those a CSV holds), from its joint rows' `flags` cells (joint index
    -> cell): the person-wide flags every row carries, then the joints' own gathered."""
    split = {j: [f for f in cell.split(SEPARATOR) if f] for j, cell in cells.items()}
    own = (DEPTH_AMBIGUOUS, DETECTION_OUTLIER)
    flags = [f for f in split[min(split)] if not f.startswith(own)] if split else []
    outliers = [joints[j] for j in sorted(split) if DETECTION_OUTLIER in split[j]]
    if outliers:
        flags.append(f"{DETECTION_OUTLIER}: " + ", ".join(outliers))
    ambiguous = [f"{joints[j]} {f.removeprefix(DEPTH_AMBIGUOUS).strip()}".strip()
                 for j in sorted(split) for f in split[j] if f.startswith(DEPTH_AMBIGUOUS)]  # fmt: skip
    if ambiguous:
        flags.append(f"{DEPTH_AMBIGUOUS}: " + ", ".join(ambiguous))
    return flags
