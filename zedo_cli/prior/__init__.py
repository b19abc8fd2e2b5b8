"""The 3D pose prior: the score network, the sub-VP SDE, sampling, denoising score-matching
training, the ControlNet-like control branch and adaptation, training recipes, and the weights
file format (save, strict load, the bundled priors).

Builds on `data` (skeletons, training poses); knows nothing of 2D, cameras or file formats.
"""

from __future__ import annotations

from .adapt import STRATEGIES, AdaptResult, adapt_prior, write_adapted_prior
from .control import ControlledScoreNet
from .model import PriorConfig, ScoreNet
from .recipes import Recipe, fit_prior, load_recipe, write_fitted_prior
from .sampling import sample_poses
from .sde import SubVPSDE
from .training import TrainConfig, TrainResult, train_score_model
from .weights import BUNDLED_PRIORS, DEFAULT_PRIOR, Prior, load_prior, resolve_prior_path, save_prior

__all__ = [
    "BUNDLED_PRIORS", "DEFAULT_PRIOR", "STRATEGIES", "AdaptResult", "ControlledScoreNet", "Prior", "PriorConfig",
    "Recipe", "ScoreNet", "SubVPSDE", "TrainConfig", "TrainResult", "adapt_prior", "fit_prior", "load_prior",
    "load_recipe", "resolve_prior_path", "sample_poses", "save_prior", "train_score_model", "write_adapted_prior",
    "write_fitted_prior",
]  # fmt: skip
