"""The 3D pose prior: the score network, the sub-VP SDE, sampling, denoising score-matching
training, the ControlNet-like control branch and adaptation, ensembles of seeds, training
recipes, and the weights file format (save, strict load, the bundled priors).

Builds on `data` (skeletons, training poses); knows nothing of 2D, cameras or file formats.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".adapt": ["AdaptResult", "adapt_prior", "write_adapted_prior"],
        ".combine": ["combine_priors"],
        ".control": ["ControlledScoreNet"],
        ".ensemble": ["EnsembleScoreNet"],
        ".model": ["PriorConfig", "ScoreNet"],
        ".recipes": ["Recipe", "fit_prior", "load_recipe", "write_fitted_prior"],
        ".sampling": ["sample_poses"],
        ".sde": ["SubVPSDE"],
        ".schedules": ["STRATEGIES", "TrainConfig"],
        ".training": ["TrainResult", "train_score_model"],
        ".weights": ["BUNDLED_PRIORS", "DEFAULT_PRIOR", "Prior", "load_prior", "resolve_prior_path", "save_prior"],
    },
)
