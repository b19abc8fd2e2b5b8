"""What a lift is asked to do: `LiftConfig`, the named presets and the temporal modes.

Kept apart from the solver (and free of torch) so that option parsing and `--help` can show
the presets and defaults without loading the network code.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace
from typing import Any

from ..errors import ConfigError

MAX_HYPOTHESES = 64
# The largest step size a `step_delta = None` preset takes (1 / steps otherwise). Larger steps
# from t = 0.2 blow poses up: on held-out SyRIP poses, 10 steps of 1/10 left 141 of 150 lifted
# poses with a bone over 3 times its template length (MPJPE 199 mm; from t = 0.1: 57 poses,
# 98 mm); 10 steps of 0.03 lifted 43.5 mm, 20 of 0.03 41.9 mm (50 of 1/50: 42.5).
MAX_AUTO_DELTA = 0.03
AGGREGATES = ("mean", "median", "first")
MAX_LENGTH_ITERATIONS = 10


@dataclass(frozen=True)
class LiftConfig:
    """Lifting settings. The defaults are the reference's numbers (`faithful` preset)."""

    preset: str = "faithful"
    init_steps: int = 500  # Adam steps of the rotation/depth fit
    init_lr: float = 0.1
    init_depth_m: float = 1.0  # base distance along the root ray (the reference's IPO_T)
    scale_min: float = 0.5  # clamp of the depth scale (SyRIP values)
    scale_max: float = 8.0
    steps: int = 1000  # prior iterations
    t_start: float = 0.1
    t_end: float = 0.01
    release_fraction: float = 0.05  # root translation re-solved in the last 5 % of iterations
    step_delta: float | None = 1e-3  # the reference's fixed delta; None: 1 / steps
    flow: float = 1.0  # the reference's probability-flow factor (textbook: 0.5)
    min_observed: int = 3  # fewer observed joints: the instance is not lifted
    chunk_size: int = 4096  # poses lifted together
    # The network in bfloat16 (lifting/precision.py): True, False, or None = where the
    # device computes bfloat16 natively (a CPU with AMX or AVX512-BF16, a CUDA GPU), float32 elsewhere.
    bf16: bool | None = False
    # Warm start only (`lift(start_poses=...)`); unused otherwise.
    warm_steps: int = 3  # prior iterations from a start pose (measured: 3 beat 10)
    warm_t_start: float = 0.01  # a start pose is nearly right: the lowest noise level of the presets
    warm_release_fraction: float = 0.0  # keep the start's translation (a smoothed one: re-solving adds jitter)
    warm_step_delta: float | None = None  # None: the main loop's delta
    # Fraction of the way each observed joint is moved onto its camera ray before every prior step;
    # 1 = the reference (all the way: the 2D is trusted exactly), below 1 the prior may hold a joint
    # a little off its ray where the 2D and the prior disagree.
    ray_weight: float = 1.0
    # Joints whose confidence is below this fraction of the median confidence of their pose's observed
    # joints move onto their rays only in proportion (ray_weight x confidence / (ratio x median));
    # relative, so a detector's confidence scale does not matter. 0 = off (every observed joint alike).
    ray_confidence_ratio: float = 0.0
    # Hip joints (left_hip, right_hip) move this factor of their pull: a 2D hip is a landmark on
    # the body's surface, a prior's hip the body model's joint inside the pelvis (SyRIP's 2D hips
    # are about 0.8 times as far apart as its 3D hips, projected). 1 = like every other joint.
    hip_ray_factor: float = 1.0
    # Anatomical consistency (twin_limbs.py): fraction of each left/right limb-length mismatch
    # removed per prior iteration; 0 = off (the reference).
    twin_rate: float = 0.0
    # Bone proportions (proportions.py): fraction of each bone's log mismatch with its share of the
    # pose's size in the prior's template removed per step; 0 = off (the reference).
    proportion_rate: float = 0.0
    # Steps of the bone-length terms (twin limbs, then proportions) per prior iteration: fewer, larger
    # prior steps need more.
    length_iterations: int = 1
    # After the loop, limbs more than this many times as long as their twin are brought to this
    # ratio along the rays (twin_limbs.cap_twin_ratios); 0 = off (the reference).
    twin_ratio_cap: float = 0.0
    # Multiple hypotheses: `hypotheses` solutions per instance, lifted together. Hypothesis 0 is
    # the deterministic lift; the others start with their observed joints' depths jittered by
    # `start_jitter_m` (normal, metres) and take stochastic steps (`hypothesis_noise` times the
    # reverse SDE's noise). The reported pose is their `aggregate`: "mean" or "median" (joint-wise)
    # or "first" (hypothesis 0).
    hypotheses: int = 1
    start_jitter_m: float = 0.0
    hypothesis_noise: float = 0.0
    aggregate: str = "mean"

    def __post_init__(self) -> None:
        if self.steps < 1 or self.init_steps < 0:
            raise ConfigError("steps must be >= 1 and init steps >= 0")
        if self.step_delta is not None and self.step_delta <= 0:
            raise ConfigError(f"step_delta must be > 0, got {self.step_delta}")
        if not 0 <= self.release_fraction <= 1:
            raise ConfigError(f"release_fraction must be in [0, 1], got {self.release_fraction}")
        if self.chunk_size < 1:
            raise ConfigError(f"chunk_size must be >= 1, got {self.chunk_size}")
        if not 0 < self.t_end <= self.t_start <= 1:
            raise ConfigError(f"need 0 < t_end <= t_start <= 1, got {self.t_end}, {self.t_start}")
        if self.min_observed < 2:
            raise ConfigError("min_observed must be >= 2 (the translation solve needs two joints)")
        if self.warm_steps < 1:
            raise ConfigError(f"warm_steps must be >= 1, got {self.warm_steps}")
        if not self.t_end <= self.warm_t_start <= 1:
            raise ConfigError(f"need t_end <= warm_t_start <= 1, got {self.warm_t_start}")
        if not 0 <= self.warm_release_fraction <= 1:
            raise ConfigError(f"warm_release_fraction must be in [0, 1], got {self.warm_release_fraction}")
        if self.warm_step_delta is not None and self.warm_step_delta <= 0:
            raise ConfigError(f"warm_step_delta must be > 0, got {self.warm_step_delta}")
        if not 0 < self.ray_weight <= 1:
            raise ConfigError(f"ray_weight must be in (0, 1], got {self.ray_weight}")
        if not 0 <= self.ray_confidence_ratio <= 1:
            raise ConfigError(f"ray_confidence_ratio must be in [0, 1], got {self.ray_confidence_ratio}")
        if not 0 <= self.hip_ray_factor <= 1:
            raise ConfigError(f"hip_ray_factor must be in [0, 1], got {self.hip_ray_factor}")
        if not 0 <= self.twin_rate <= 1:
            raise ConfigError(f"twin_rate must be in [0, 1], got {self.twin_rate}")
        if not 0 <= self.proportion_rate <= 1:
            raise ConfigError(f"proportion_rate must be in [0, 1], got {self.proportion_rate}")
        if not (self.twin_ratio_cap == 0 or self.twin_ratio_cap >= 1):
            raise ConfigError(f"twin_ratio_cap must be 0 (off) or at least 1, got {self.twin_ratio_cap}")
        if not 1 <= self.length_iterations <= MAX_LENGTH_ITERATIONS:
            raise ConfigError(
                f"length_iterations must be in [1, {MAX_LENGTH_ITERATIONS}], got {self.length_iterations}"
            )
        if not 1 <= self.hypotheses <= MAX_HYPOTHESES:
            raise ConfigError(f"hypotheses must be in [1, {MAX_HYPOTHESES}], got {self.hypotheses}")
        if self.start_jitter_m < 0 or self.hypothesis_noise < 0:
            raise ConfigError("start_jitter_m and hypothesis_noise must be >= 0")
        if self.bf16 not in (True, False, None):
            raise ConfigError(f"bf16 must be true, false or null (where the device has it), got {self.bf16!r}")
        if self.aggregate not in AGGREGATES:
            raise ConfigError(f"aggregate must be one of {', '.join(AGGREGATES)}, got {self.aggregate!r}")

    @property
    def delta(self) -> float:
        """The probability-flow step size in effect: `step_delta`, or 1 / steps capped at
        MAX_AUTO_DELTA (so `--steps` far below 50 stays stable)."""
        return min(1.0 / self.steps, MAX_AUTO_DELTA) if self.step_delta is None else self.step_delta

    @property
    def warm_delta(self) -> float:
        """The step size of the warm-started loop."""
        return self.delta if self.warm_step_delta is None else self.warm_step_delta

    def to_dict(self) -> dict[str, float | int | str | bool | None]:
        return {**asdict(self), "delta": self.delta}


# Settings that do not change what a lift computes (or by under 0.1 mm): left out when a
# calibration (per joint or per measure) is matched to the settings of a lift.
CALIBRATION_IRRELEVANT = ("preset", "chunk_size", "bf16")


def calibration_settings(cfg: LiftConfig | dict[str, Any]) -> dict[str, Any]:
    """The settings a calibration must match: `cfg` (or a result's recorded `LiftConfig.to_dict()`)
    without what does not change the poses."""
    settings = cfg if isinstance(cfg, dict) else cfg.to_dict()
    return {k: v for k, v in settings.items() if k not in CALIBRATION_IRRELEVANT}


def settings_match(calibrated: dict[str, Any], wanted: dict[str, Any]) -> bool:
    """Whether a calibration made with `calibrated` settings holds for a lift with `wanted` ones.
    A setting added to LiftConfig after a calibration was made is absent from it; its default
    keeps the loop as it was (every new setting's default does), so that is what it was made with."""
    defaults = calibration_settings(LiftConfig())
    return set(calibrated) <= set(wanted) and all(calibrated.get(k, defaults.get(k)) == v for k, v in wanted.items())


# fast: settings chosen on held-out folds, never on Test100 (the figures behind each: docs/decisions.md, "The fast
# preset's settings"):
# - 20 prior steps of 0.03 from noise level 0.2;
# - before each step, observed joints move 0.75 of the way onto their rays (the 2D is not taken as exact); joints
#   under 0.6 times their pose's median confidence move less, in proportion; the hips move 0.6 of that (a 2D hip is
#   a surface landmark, the prior's hip a joint inside the pelvis);
# - then two rounds of the twin-limb term (rate 0.85) and the bone-proportion term (rate 0.7);
# - after the loop, twin limbs over 1.4 times each other are brought to 1.4;
# - one hypothesis by default; with --hypotheses K the others take the full SDE noise and the reported pose stays
#   hypothesis 0;
# - the network in bfloat16 where the CPU (AMX or AVX512-BF16) or GPU has it, float32 elsewhere.
_FAST = LiftConfig(preset="fast", init_steps=100, steps=20, t_start=0.2, step_delta=None, release_fraction=0.15,
                   ray_weight=0.75, ray_confidence_ratio=0.6, hip_ray_factor=0.6, twin_rate=0.85, proportion_rate=0.7,
                   length_iterations=2, twin_ratio_cap=1.4, hypothesis_noise=1.0, aggregate="first",
                   bf16=None)  # fmt: skip
PRESETS: dict[str, LiftConfig] = {
    "faithful": LiftConfig(),
    "fast": _FAST,
    "fast-bf16": replace(_FAST, preset="fast-bf16", bf16=True),
    # fast in float32 on every device: the same answer on CPUs with and without bfloat16 (docs/lifting.md)
    "fast-fp32": replace(_FAST, preset="fast-fp32", bf16=False),
}
DEFAULT_PRESET = "fast"


def get_preset(name: str) -> LiftConfig:
    try:
        return PRESETS[name]
    except KeyError:
        raise ConfigError(f"unknown preset {name!r}; presets: {', '.join(PRESETS)}") from None


TEMPORAL_MODES = ("none", "smooth", "two-pass", "clip")
# measured (benchmarks/accuracy/temporal.py): by far the least jitter and the cheapest; two-pass is about 1 mm
# more accurate with fast's softer rays but leaves 3-4 times the jitter
DEFAULT_TEMPORAL_MODE = "smooth"
DEFAULT_SIGMA_FRAMES = 2.0
