"""90 % intervals of the measures from per-joint uncertainty radii.

A zedo result may carry `uncertainty_m` per person: for each joint, the radius in metres of
the ball around the reported root-relative position that holds the true joint with 90 %
probability. A measure depends on several joints at once, so its interval is derived by
sampling, not by combining worst cases:

- each joint's error is modelled as an isotropic 3D Gaussian whose 90 % ball has the given
  radius: sigma = r / 2.5003 (2.5003 = the 90 % quantile of the chi distribution with 3
  degrees of freedom, sqrt(6.2514)); joints are independent;
- `samples` poses (default 1000) are drawn around the reported pose with a seeded generator and
  every measure m is computed on each. With q5, q95 the 5th and 95th percentiles of the sampled
  values and m0 the reported value, the interval is the union of the percentile interval
  [q5, q95] and its reflection about m0, [2 m0 - q95, 2 m0 - q5] (the "basic" bootstrap
  interval), clipped to the measure's range (0 to 180 degrees for a symmetry angle).

Why both: noise only ever increases an angle near its lower bound (a symmetry angle of 0
cannot go lower), so the reported value is already biased up and the samples around it more
so. The percentile interval alone then lies above a truly symmetric pair's 0 every time; the
reflected one corrects that bias to first order, but alone it collapses to [0, 0] for a
reported 0 and covers only 75 to 86 % in the simulation of `benchmarks/analyze_intervals.py`.
Their union holds the truth 91 to 94 % of the time there for joint errors of 4 to 8 mm (84 to
93 % at 16 mm; README, "Uncertainty").

Why not the worst case over the balls: it is not a 90 % interval (if each of the 6 joints of a
symmetry angle is in its ball with probability 0.9, all of them are with as little as 0.4) and it
is much wider, so nearly every call would be "uncertain". The Gaussian is the maximum-entropy
error with the stated spread; the model ignores correlation between joints (depth errors of a
lifted pose are correlated), which this interval does not capture. A joint whose radius is
unknown (null) leaves every measure that uses it without an interval.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

CHI3_Q90 = 2.50028  # sqrt of the chi-square(3) 90 % quantile 6.251389
DEFAULT_SAMPLES = 1000
_CHUNK = 200_000  # sampled poses per batch (memory: chunk * J * 3 floats)


def sample_intervals(
    poses: np.ndarray,
    radii: np.ndarray,
    measures: Callable[[np.ndarray], dict[str, np.ndarray]],
    *,
    ranges: dict[str, tuple[float, float]] | None = None,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """`{name: (low_90, high_90)}`, each `(N,)`, for every measure of `measures(poses (M, J, 3))`.

    `poses (N, J, 3)` and `radii (N, J)` in metres; NaN where a radius or a joint is unknown.
    `ranges`: per measure, the values it can take (the interval is clipped to them).
    """
    rng = np.random.default_rng(seed)
    n = len(poses)
    sigma = radii / CHI3_Q90  # (N, J)
    reported = measures(poses)
    per = max(1, _CHUNK // max(samples, 1))
    lows: dict[str, list[np.ndarray]] = {}
    highs: dict[str, list[np.ndarray]] = {}
    for start in range(0, n, per):
        p, s = poses[start : start + per], sigma[start : start + per]
        draws = p[None] + rng.standard_normal((samples, *p.shape)) * s[None, ..., None]  # (S, n, J, 3)
        values = measures(draws.reshape(-1, *p.shape[1:]))
        for name, v in values.items():
            # a NaN draw means a joint (or its radius) is unknown: no interval
            q5, q95 = np.percentile(v.reshape(samples, len(p)), [5.0, 95.0], axis=0)
            m0 = reported[name][start : start + per]
            # the reflected interval, widened to hold the percentile one: never narrower than either
            low, high = np.minimum(2.0 * m0 - q95, q5), np.maximum(2.0 * m0 - q5, q95)
            if ranges and name in ranges:
                low, high = np.clip(low, *ranges[name]), np.clip(high, *ranges[name])
            lows.setdefault(name, []).append(low)
            highs.setdefault(name, []).append(high)
    return {k: (np.concatenate(lows[k]), np.concatenate(highs[k])) for k in lows}
