"""Training `zedo augment`'s domain-conditioned network, and its weights file.

File contract (format "zedo.augmenter", version 1), also in weights_spec/README.md: tensors
`model.net.*` (the score network, as in a prior) and `model.tokens` (2, embed) (adult, infant),
float16 or float32; metadata (strings) `format`, `format_version`, `skeleton`, `joints`,
`model_config`, `sde_config`, `domains`, `sizes` (canonical size and infant log-normal, see
augment.py), `training`, `data`, `license`, `zedo_version`, `created`, and `initialised_from`
(file and sha256 of the prior it started from) when it did.
"""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import torch

from ..data.adult import PoseAugmentation
from ..data.datasets import PoseSet
from ..data.skeleton import Skeleton
from ..errors import ConfigError, WeightsError
from ..prior.model import PriorConfig, ScoreNet
from ..prior.schedules import AUGMENTER_TRAINING, TrainConfig
from ..prior.sde import SubVPSDE
from ..prior.training import TrainProgress, TrainResult, train_score_model
from ..prior.weights import (
    Prior,
    check_tensor_header,
    file_sha256,
    json_field,
    load_model_state,
    model_tensors,
    network_metadata,
    read_network_configs,
    read_safetensors,
    read_safetensors_header,
    write_safetensors_atomic,
)
from .conversion import SizeModel, domain_training_set, fit_size_model
from .domain_model import DOMAINS, DomainScoreNet

AUGMENTER_FORMAT = "zedo.augmenter"
AUGMENTER_FORMAT_VERSION = "1"
# Started from the adult prior, a few epochs over the balanced adult + infant set suffice (docs/benchmarks.md).
ROTATE_ALL = PoseAugmentation(rotate=True)


@dataclass
class Augmenter:
    """A loaded augmenter: the conditional network (eval, float32), its SDE, joint set and sizes."""

    model: DomainScoreNet
    sde: SubVPSDE
    skeleton: Skeleton
    sizes: SizeModel
    metadata: dict[str, Any]
    sha256: str
    path: str

    @property
    def label(self) -> str:
        return f"{Path(self.path).name} (sha256 {self.sha256[:12]})"


@dataclass
class AugmenterTraining:
    model: DomainScoreNet
    sde: SubVPSDE
    result: TrainResult
    sizes: SizeModel


def build_augmenter_net(init: Prior | None, num_joints: int, seed: int) -> DomainScoreNet:
    """A domain-conditioned network: a copy of `init`'s plain network, or a fresh one."""
    gen = torch.Generator().manual_seed(seed)
    if init is None:
        with torch.random.fork_rng():
            torch.manual_seed(seed)
            net = ScoreNet(PriorConfig(num_joints))
    elif isinstance(init.model, ScoreNet):
        if init.skeleton.num_joints != num_joints:
            raise ConfigError(f"--init {init.label} has {init.skeleton.num_joints} joints, the data {num_joints}")
        net = copy.deepcopy(init.model)
    else:
        raise ConfigError(f"--init {init.label} carries a control branch; start from a plain prior")
    for p in net.parameters():
        p.requires_grad_(True)
    return DomainScoreNet(net, token_generator=gen)


def train_augmenter(
    adult: PoseSet,
    infant: PoseSet,
    cfg: TrainConfig = AUGMENTER_TRAINING,
    *,
    init: Prior | None = None,
    device: str = "cpu",
    callback: Callable[[TrainProgress], None] | None = None,
) -> AugmenterTraining:
    """Train the conditional network on size-normalised adult and infant poses (balanced),
    every batch turned by random rotations."""
    if init is not None and init.skeleton.name != adult.skeleton.name:
        raise ConfigError(f"--init {init.label} is for {init.skeleton.name}, the data for {adult.skeleton.name}")
    sizes = fit_size_model(adult, infant)
    poses, labels = domain_training_set(adult, infant, sizes)
    model = build_augmenter_net(init, adult.skeleton.num_joints, cfg.seed)
    sde = init.sde if init is not None else SubVPSDE()
    result = train_score_model(
        model, sde, poses, cfg, device=device, callback=callback, augment=ROTATE_ALL, labels=labels
    )
    return AugmenterTraining(model.cpu(), sde, result, sizes)


def save_augmenter(
    path: str | Path,
    state: dict[str, torch.Tensor],
    cfg: PriorConfig,
    sde: SubVPSDE,
    skeleton: Skeleton,
    sizes: SizeModel,
    *,
    training: dict[str, Any],
    data: dict[str, Any],
    license_text: str,
    dtype: torch.dtype = torch.float16,
    initialised_from: dict[str, str] | None = None,
) -> str:
    """Write an augmenter file atomically; return its sha256."""
    metadata = network_metadata(AUGMENTER_FORMAT, AUGMENTER_FORMAT_VERSION, skeleton, cfg, sde, training=training,
                                data=data, license_text=license_text)  # fmt: skip
    metadata["domains"] = json.dumps(list(DOMAINS))
    metadata["sizes"] = json.dumps(sizes.to_dict())
    if initialised_from is not None:
        metadata["initialised_from"] = json.dumps(initialised_from)
    return write_safetensors_atomic(path, model_tensors(state, dtype), metadata)


def load_augmenter(path: str | Path, *, device: str = "cpu") -> Augmenter:
    """Load an augmenter strictly (format, version, configs, every tensor)."""
    path = Path(path)
    meta, header = read_safetensors_header(path)
    if meta.get("format") != AUGMENTER_FORMAT:
        hint = " (that is a prior: give it to lift or adapt)" if meta.get("format") == "zedo.prior" else ""
        raise WeightsError(f"{path}: metadata 'format' is {meta.get('format')!r}, not {AUGMENTER_FORMAT!r}{hint}")
    if meta.get("format_version") != AUGMENTER_FORMAT_VERSION:
        raise WeightsError(
            f"{path}: format_version {meta.get('format_version')!r} is not supported "
            f"(this zedo reads augmenter version {AUGMENTER_FORMAT_VERSION})"
        )
    skel, cfg, sde = read_network_configs(meta, path)
    if json_field(meta, "domains", path) != list(DOMAINS):
        raise WeightsError(f"{path}: metadata 'domains' must be {list(DOMAINS)}")
    try:
        sizes = SizeModel(**json_field(meta, "sizes", path))
    except TypeError as exc:
        raise WeightsError(f"{path}: metadata 'sizes' has unknown or missing fields ({exc})") from None
    check_tensor_header(path, header, lambda: DomainScoreNet(ScoreNet(cfg)))  # before any allocation
    _, tensors = read_safetensors(path)
    model = DomainScoreNet(ScoreNet(cfg))
    load_model_state(model, tensors, path)
    model.to(device).eval()
    parsed = ("model_config", "sde_config", "domains", "sizes", "training", "data", "initialised_from")
    metadata = {k: (json_field(meta, k, path) if k in parsed else v) for k, v in meta.items()}
    return Augmenter(model, sde, skel, sizes, metadata, file_sha256(path), str(path))
