"""Bone proportions inside the lifting loop.

With its joints on their camera rays, a lifted pose's bone lengths are set by how deep each joint
lies, and the prior alone leaves them off: on held-out SyRIP poses the lifted bones' shares of the
skeleton's size were 8-14 % from the truth's, while the infants' own shares vary by 3-8 % about
their mean (hips lifted 14 % too narrow). `bone_proportion_step` moves each bone's length towards
its share of the pose's current size (the sum of its bone lengths) in the prior's template, by a
damped Gauss-Newton step on the log length ratio, with observed joints moving only along their
rays (as `twin_limbs.twin_limb_step` does). It fixes proportions, not size, so a larger or smaller
infant keeps its size.
"""

from __future__ import annotations

import torch

from ..data.skeleton import Skeleton, bone_lengths
from .twin_limbs import DAMPING, along_rays, capped


def template_fractions(template: torch.Tensor, skeleton: Skeleton) -> torch.Tensor:
    """Each bone's share `(B,)` of the template pose's size, left and right bones averaged (the
    template is one training pose, whose twins differ)."""
    lengths = torch.as_tensor(bone_lengths(template.detach().cpu().double().numpy()[None], skeleton)[0])
    flip = skeleton.flip_permutation
    index = {frozenset(bone): k for k, bone in enumerate(skeleton.bones)}
    mirror = [index.get(frozenset((flip[a], flip[b])), k) for k, (a, b) in enumerate(skeleton.bones)]
    even = ((lengths + lengths[mirror]) / 2).clamp_min(1e-6)  # a degenerate template must not give log(0)
    return (even / even.sum()).to(template.dtype).to(template.device)


def bone_proportion_step(
    x: torch.Tensor, unit: torch.Tensor, observed: torch.Tensor, bones: torch.Tensor, fractions: torch.Tensor,
    rate: float,
) -> torch.Tensor:  # fmt: skip
    """Poses `x (B, J, 3)` (root-relative; the root's translation fixed) with each bone's log ratio
    of its length to `fractions (nb,)` times the pose's size reduced by about `rate`. `bones (nb, 2)`
    are joint index pairs, `unit (B, J, 3)` the joints' unit camera rays, `observed (B, J)` the
    joints held on them. A joint in several bones takes the mean of their moves."""
    if rate <= 0:
        return x
    parent, child = bones[:, 0], bones[:, 1]
    vector = x[:, child] - x[:, parent]  # (B, nb, 3)
    length2 = (vector * vector).sum(-1).clamp_min(1e-8)
    length = length2.sqrt()
    size = length.sum(1, keepdim=True)
    mismatch = torch.log(length) - torch.log(fractions * size)  # (B, nb); size held fixed in the step
    to_child = along_rays(vector / length2[..., None], unit[:, child], observed[:, child])
    to_parent = along_rays(-vector / length2[..., None], unit[:, parent], observed[:, parent])
    norm2 = (to_child * to_child).sum(-1) + (to_parent * to_parent).sum(-1)
    scale = (-rate * mismatch / (norm2 + DAMPING * 2.0 / length2))[..., None]
    delta = torch.zeros_like(x)
    delta.index_add_(1, child, scale * to_child)
    delta.index_add_(1, parent, scale * to_parent)
    count = torch.bincount(bones.reshape(-1), minlength=x.shape[1]).clamp_min(1).to(x.dtype)
    return x + capped(delta / count[:, None])
