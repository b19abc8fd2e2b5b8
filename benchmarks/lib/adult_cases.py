"""The adult motion made infant-like as calibration cases: clips in the arrays that
`zedo_cli.evaluation.clips.eased.make_sequences` returns, so that a calibration lifts them as it lifts its SyRIP
clips (the second clip source of the calibrations, next to the SyRIP training poses)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.lib.settings import CLIP_SETTINGS
from zedo_cli.data.adult import ADULT_FILES
from zedo_cli.data.skeleton import get_skeleton

ADULT_SOURCE = "adult"  # the name of the adult-motion cases (a motion, an input kind)
# The adult motion as two pose sources of its own, for a table with a source left out: the captures share no poses
# (ADULT_FILES: Bandai-Namco's, then CMU's and DeepMimic's).
ADULT_CAPTURES = {"bandai": ADULT_FILES[:1], "cmu": ADULT_FILES[1:]}
ADULT_SOURCE_NAMES = {ADULT_SOURCE: "adult motion", "bandai": "adult motion, Bandai-Namco",
                      "cmu": "adult motion, CMU and DeepMimic"}  # fmt: skip
ADULT_JITTER_PX = 3.0
ADULT_DROPOUT = 0.03  # the share of joints dropped (NaN), as the SyRIP calibration clips drop them


def adult_sources(by_capture: bool) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """The adult motion's case sources as (name, files): one, ADULT_SOURCE, of every file; or with `by_capture` one
    per capture (ADULT_CAPTURES)."""
    return tuple(ADULT_CAPTURES.items()) if by_capture else ((ADULT_SOURCE, ADULT_FILES),)


def adult_case_clips(syrip_dir: str | Path, seed: int, known_cameras: bool, count: int, seconds: float,
                     files: tuple[str, ...] = ADULT_FILES) -> dict[str, np.ndarray]:  # fmt: skip
    """`count` clips of `seconds` of the adult motion made infant-like (`zedo_cli.evaluation.clips`: bones of SyRIP's
    training infants, supine, 30 fps, 3 px jitter, 3 % of joints dropped: NaN), each one infant, as `make_sequences`'
    arrays (`rel`, `xy`, `conf`, `k`, `tracks`, and `cam`, the joints in the camera's frame): before the pseudo
    camera, or with `known_cameras` before the clinic set-ups and two 2.5-3.5 m away (`FAR_CAMERAS`: up to 3000 px).
    `files`: the adult files drawn from (default every one)."""
    from zedo_cli.evaluation.clips import ClipSettings, adult_infant_clips, infant_bodies_from_syrip, load_adult_library
    from zedo_cli.evaluation.clips.cameras import CLINIC_CAMERAS, FAR_CAMERAS, PSEUDO_CAMERA
    from zedo_cli.evaluation.clips.habits import DetectorHabits
    from zedo_cli.lifting.clip import root_relative

    skeleton = get_skeleton("syrip12")
    habits = DetectorHabits(jitter_px=ADULT_JITTER_PX, dropout=ADULT_DROPOUT, swaps_per_min=0, hand_jumps_per_min=0,
                            losses_per_min=0)  # fmt: skip
    cameras = (*CLINIC_CAMERAS, *FAR_CAMERAS) if known_cameras else (PSEUDO_CAMERA,)
    settings = ClipSettings(fps=float(CLIP_SETTINGS["fps"]), cameras=cameras, habits=habits)
    library = load_adult_library(Path(syrip_dir).parent / "adult", files)
    made = adult_infant_clips(library, infant_bodies_from_syrip(syrip_dir), seconds, count, seed, settings)
    parts: dict[str, list[np.ndarray]] = {"rel": [], "cam": [], "xy": [], "conf": [], "k": [], "tracks": []}
    for track, clip in enumerate(made):
        missing = ~np.isfinite(clip.xy).all(-1)  # NaN, as zedo's readers give a detector's missing joints
        rel, root = root_relative(clip.poses3d, skeleton)
        parts["rel"].append(rel)
        parts["cam"].append(clip.poses3d)
        parts["xy"].append(clip.xy)
        parts["conf"].append(np.where(missing, 0.0, clip.confidence))
        parts["k"].append(np.broadcast_to(clip.intrinsics.matrix(), (len(clip), 3, 3)))
        parts["tracks"].append(np.full(len(clip), track))
    return {key: np.concatenate(v) for key, v in parts.items()}
