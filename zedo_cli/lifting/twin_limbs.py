"""Left/right limb-length consistency inside the lifting loop.

Depth from one image is ambiguous: with the observed joints held on their camera rays, a limb's
length is set by how far along its ray each end lies, and the prior alone leaves many lifted
poses with one upper arm, forearm, thigh or shank far longer than its twin (a body never is).
`twin_limb_step` moves the joints of each twin pair (observed joints only along their own rays,
so the ray constraint holds) by a damped Gauss-Newton step on the pair's log length ratio,
removing the fraction `rate` of the mismatch per loop iteration. Interleaved with the prior's
steps, the pose stays a sample of the prior while its twin limbs converge to equal lengths.

`cap_twin_ratios` runs after the loop: the last prior steps can leave a few poses with a limb far
longer than its twin (on held-out SyRIP folds, 1.5 % of poses over 1.6 times), so the same step,
applied only to the part of a pair's ratio above a cap, brings those limbs to the cap and leaves
every pair within it untouched.
"""

from __future__ import annotations

import math

import torch

# Levenberg damping of the Gauss-Newton step, in units of the pair's squared inverse lengths:
# where depth barely changes a limb's length (a limb across the rays), the step stays small.
DAMPING = 0.5
# Most a joint moves in one iteration (metres): a bound for poses far from any fix.
MAX_MOVE_M = 0.02
# Full-rate steps of `cap_twin_ratios`: enough for pairs up to about 2.5 times their twin to reach
# the cap under MAX_MOVE_M (held-out SyRIP folds: 2 or 3 left 0.2-0.7 % of poses over 1.6, 5 none).
CAP_ITERATIONS = 5


def twin_limb_step(
    x: torch.Tensor, unit: torch.Tensor, observed: torch.Tensor,
    pairs: list[tuple[tuple[int, int], tuple[int, int]]], rate: float, tolerance: float = 1.0,
) -> torch.Tensor:  # fmt: skip
    """Poses `x (B, J, 3)` (root-relative; the root's translation is fixed) with each twin limb
    pair's log length ratio reduced by about `rate`. `unit (B, J, 3)` are the joints' unit camera
    rays and `observed (B, J)` the joints held on them; `pairs` from `skeleton.twin_limbs`. With a
    `tolerance` above 1, only the part of a ratio above it counts as mismatch."""
    if rate <= 0 or not pairs:
        return x
    slack = math.log(tolerance)
    idx = torch.tensor([[lc, lp, rc, rp] for (lp, lc), (rp, rc) in pairs], device=x.device)  # (P, 4)
    ends = x[:, idx]  # (B, P, 4, 3): all pairs at once
    left, right = ends[:, :, 0] - ends[:, :, 1], ends[:, :, 2] - ends[:, :, 3]  # (B, P, 3)
    left2 = (left * left).sum(-1, keepdim=True).clamp_min(1e-8)  # (B, P, 1)
    right2 = (right * right).sum(-1, keepdim=True).clamp_min(1e-8)
    mismatch = 0.5 * (torch.log(left2) - torch.log(right2))  # log(left / right)
    if slack > 0:
        mismatch = torch.sign(mismatch) * (mismatch.abs() - slack).clamp_min(0.0)
    grad = torch.stack([left / left2, -left / left2, -right / right2, right / right2], dim=2)  # (B, P, 4, 3)
    grad = along_rays(grad, unit[:, idx], observed[:, idx])
    norm2 = (grad * grad).sum((2, 3))[..., None]  # (B, P, 1)
    scale = -rate * mismatch / (norm2 + DAMPING * (1.0 / left2 + 1.0 / right2))
    delta = torch.zeros_like(x)  # pairs that share a joint add their moves, in pair order
    delta.index_add_(1, idx.reshape(-1), (scale[..., None] * grad).reshape(x.shape[0], -1, 3))
    return x + capped(delta)


def cap_twin_ratios(
    x: torch.Tensor, unit: torch.Tensor, observed: torch.Tensor,
    pairs: list[tuple[tuple[int, int], tuple[int, int]]], cap: float,
) -> torch.Tensor:  # fmt: skip
    """Poses `x` (as in `twin_limb_step`) with every twin pair's length ratio brought to at most
    about `cap` (0: unchanged); pairs within it are not moved."""
    if cap <= 0:
        return x
    for _ in range(CAP_ITERATIONS):
        x = twin_limb_step(x, unit, observed, pairs, 1.0, tolerance=cap)
    return x


def along_rays(grad: torch.Tensor, unit: torch.Tensor, observed: torch.Tensor) -> torch.Tensor:
    """Joint gradients `grad (B, n, 3)` with those of observed joints (`observed (B, n)`) reduced to
    their component along the joints' unit rays `unit (B, n, 3)`: observed joints move only along
    their rays, so the ray constraint holds."""
    along = (grad * unit).sum(-1, keepdim=True) * unit
    return torch.where(observed[..., None], along, grad)


def capped(delta: torch.Tensor) -> torch.Tensor:
    """Joint moves `delta (B, J, 3)` each shortened to at most MAX_MOVE_M."""
    length = delta.norm(dim=-1, keepdim=True)
    return delta * (MAX_MOVE_M / length.clamp_min(MAX_MOVE_M))
