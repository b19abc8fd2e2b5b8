"""Priors as safetensors files with self-describing metadata; strict loading; bundled priors.

File contract (format version 1), also stated in weights_spec/README.md:
- tensors `model.<parameter name>` (float16 or float32) for every entry of the score network's
  state dict, and `template` (J, 3) float32: the pose used to initialise lifting (metres,
  root-relative);
- metadata (all strings): `format` = "zedo.prior", `format_version` = "1", `skeleton`,
  `joints` (JSON list), `model_config`, `sde_config`, `training`, `data` (JSON objects),
  `license`, `zedo_version`, `created`.

Format version 2 adds one kind of network, written only for it: metadata `architecture` =
"control" (a frozen base plus the controllable branch of `control.py`, tensors under
`model.base.*`, `model.branch_*`, `model.zero_*`, `model.prompt`) and `adapted_from` (JSON: the
base prior's file name and sha256). Plain priors are still written as version 1, so older
zedo versions read them; a version-2 file gives those a clear "not supported" error.
Version 2 also holds an ensemble (`ensemble.py`): metadata `architecture` = "ensemble" and
`members` (the count, 2 to 16), tensors `model.members.<i>.*` of same-config score networks.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from importlib import resources
from pathlib import Path
from typing import Any

import torch
from safetensors import SafetensorError
from safetensors.torch import load_file, save_file
from torch import nn

from ..data.skeleton import Skeleton, get_skeleton
from ..errors import ConfigError, WeightsError
from ..files import atomic_path
from ..strict_json import loads
from ..version import __version__
from .control import ControlledScoreNet
from .ensemble import EnsembleScoreNet
from .model import PriorConfig, ScoreNet
from .sde import SubVPSDE

FORMAT = "zedo.prior"
FORMAT_VERSION = "1"
CONTROL_FORMAT_VERSION = "2"
READABLE_VERSIONS = (FORMAT_VERSION, CONTROL_FORMAT_VERSION)
ARCHITECTURES = ("scorenet", "control", "ensemble")
MAX_MEMBERS = 16
MODEL_PREFIX = "model."

# Priors shipped inside the package: name -> file in zedo_cli/weights/.
BUNDLED_PRIORS: dict[str, str] = {
    "syrip12-scratch": "syrip12-scratch.safetensors",  # the default for lifting
    "adult12-rotscale": "adult12-rotscale.safetensors",  # the default base of `zedo adapt`
}
DEFAULT_PRIOR = "syrip12-scratch"


@dataclass
class Prior:
    """A loaded prior: the network (eval mode, float32), its SDE, skeleton and template.

    `model` is a ScoreNet, a ControlledScoreNet for an adapted prior that carries its branch, or
    an EnsembleScoreNet (several seeds of one recipe, their predictions averaged).
    """

    model: ScoreNet | ControlledScoreNet
    sde: SubVPSDE
    skeleton: Skeleton
    template: torch.Tensor  # (J, 3) metres, root-relative
    metadata: dict[str, Any]
    sha256: str
    path: str

    @property
    def label(self) -> str:
        return f"{Path(self.path).name} (sha256 {self.sha256[:12]})"


def file_sha256(path: str | Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def save_prior(
    path: str | Path,
    state: dict[str, torch.Tensor],
    cfg: PriorConfig,
    sde: SubVPSDE,
    skeleton: Skeleton,
    template: torch.Tensor,
    *,
    training: dict[str, Any],
    data: dict[str, Any],
    license_text: str,
    dtype: torch.dtype = torch.float16,
    architecture: str = "scorenet",
    adapted_from: dict[str, Any] | None = None,
    members: int | None = None,
) -> str:
    """Write a prior atomically (temporary file then rename) and return its sha256.

    `architecture` "control" marks a controlled network's state and "ensemble" the state of
    `members` networks (format version 2); `adapted_from` names the base prior (file name,
    sha256) an adapted prior came from.
    """
    if architecture not in ARCHITECTURES:
        raise WeightsError(f"unknown architecture {architecture!r}; known: {', '.join(ARCHITECTURES)}")
    if template.shape != (skeleton.num_joints, 3):
        raise WeightsError(f"template must have shape ({skeleton.num_joints}, 3)")
    tensors = model_tensors(state, dtype)
    tensors["template"] = template.detach().to("cpu", torch.float32).contiguous()
    metadata = network_metadata(FORMAT, FORMAT_VERSION, skeleton, cfg, sde, training=training, data=data,
                                license_text=license_text)  # fmt: skip
    if adapted_from is not None:
        metadata["adapted_from"] = json.dumps(adapted_from)
    if architecture != "scorenet":
        metadata["format_version"] = CONTROL_FORMAT_VERSION
        metadata["architecture"] = architecture
    if architecture == "ensemble":
        if members is None or not 2 <= members <= MAX_MEMBERS:
            raise WeightsError(f"an ensemble needs 2 to {MAX_MEMBERS} members, got {members!r}")
        metadata["members"] = str(members)
    return write_safetensors_atomic(path, tensors, metadata)


def model_tensors(state: dict[str, torch.Tensor], dtype: torch.dtype) -> dict[str, torch.Tensor]:
    """A network's state dict as `model.*` tensors of `dtype`, ready to write."""
    return {MODEL_PREFIX + k: v.detach().to("cpu", dtype).contiguous() for k, v in state.items()}


def network_metadata(
    fmt: str,
    version: str,
    skeleton: Skeleton,
    cfg: PriorConfig,
    sde: SubVPSDE,
    *,
    training: dict[str, Any],
    data: dict[str, Any],
    license_text: str,
) -> dict[str, str]:
    """The metadata every zedo weights file carries (format, joint set, configs, provenance)."""
    return {
        "format": fmt,
        "format_version": version,
        "skeleton": skeleton.name,
        "joints": json.dumps(list(skeleton.joints)),
        "model_config": json.dumps(cfg.to_dict()),
        "sde_config": json.dumps(sde.to_dict()),
        "training": json.dumps(training),
        "data": json.dumps(data),
        "license": license_text,
        "zedo_version": __version__,
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
    }


def write_safetensors_atomic(path: str | Path, tensors: dict[str, torch.Tensor], metadata: dict[str, str]) -> str:
    """Write a safetensors file atomically (temporary file then rename); return its sha256."""
    path = Path(path)
    with atomic_path(path, overwrite=True) as tmp:  # the commands check --overwrite before training
        save_file(tensors, str(tmp), metadata=metadata)
    return file_sha256(path)


TENSOR_DTYPES = ("F16", "BF16", "F32")  # what a weights file may store (loaded as float32)


def read_safetensors_header(path: Path) -> tuple[dict[str, str], dict[str, tuple[tuple[int, ...], str]]]:
    """Metadata and each tensor's (shape, dtype) of a safetensors file, without loading a tensor."""
    if not path.is_file():
        raise WeightsError(f"{path}: weights file not found")
    try:
        from safetensors import safe_open

        with safe_open(str(path), framework="pt") as fh:
            meta = fh.metadata() or {}
            header = {}
            for name in fh.keys():
                info = fh.get_slice(name)
                header[name] = (tuple(int(d) for d in info.get_shape()), str(info.get_dtype()))
        return meta, header
    except (SafetensorError, OSError, ValueError) as exc:
        raise WeightsError(f"{path}: not a readable safetensors file ({_one_line(exc)})") from None


def read_safetensors(path: Path) -> tuple[dict[str, str], dict[str, torch.Tensor]]:
    """Metadata and tensors of a safetensors file, with a WeightsError naming the file on failure.
    Every tensor must be finite (a NaN or inf weight makes every lifted pose NaN)."""
    meta, _ = read_safetensors_header(path)
    try:
        tensors = load_file(str(path))
    except (SafetensorError, OSError, ValueError) as exc:
        raise WeightsError(f"{path}: not a readable safetensors file ({_one_line(exc)})") from None
    for name, tensor in tensors.items():
        if tensor.is_floating_point() and not all_finite(tensor):
            raise WeightsError(f"{path}: tensor {name!r} holds NaN or infinite values")
    return meta, tensors


def all_finite(tensor: torch.Tensor) -> bool:
    """No NaN or infinity in `tensor`: its minimum and maximum are finite (torch.aminmax
    propagates NaN). One pass without isfinite's boolean copy: 3 ms instead of 30 ms for the
    7.2M weights of a bundled prior."""
    if tensor.numel() == 0:
        return True
    low, high = torch.aminmax(tensor)
    return bool(torch.isfinite(low) & torch.isfinite(high))


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def json_field(meta: dict[str, str], key: str, path: Path) -> Any:
    if key not in meta:
        raise WeightsError(f"{path}: metadata field {key!r} is missing")
    try:
        return loads(meta[key])
    except (ValueError, RecursionError):  # JSONDecodeError; a repeated key; integers past the digit limit; deep nesting
        raise WeightsError(f"{path}: metadata field {key!r} is not valid JSON") from None


MAX_CONFIG_INT = 2**31 - 1  # sizes and step counts of a network's config; larger is a broken or hostile file


def _config_object(meta: dict[str, str], key: str, path: Path) -> dict[str, Any]:
    """A JSON object of metadata whose numbers are all finite (JSON as Python reads it allows NaN)."""
    value = json_field(meta, key, path)
    if not isinstance(value, dict):
        raise WeightsError(f"{path}: metadata field {key!r} must be a JSON object")
    for name, number in value.items():
        if isinstance(number, float) and not math.isfinite(number):
            raise WeightsError(f"{path}: metadata {key}.{name} is {number}, not a finite number")
        if isinstance(number, int) and not isinstance(number, bool) and abs(number) > MAX_CONFIG_INT:
            raise WeightsError(f"{path}: metadata {key}.{name} is an integer of {len(str(abs(number)))} digits, "
                               f"beyond {MAX_CONFIG_INT}")  # fmt: skip
    return value


def _check_sde(sde_cfg: dict[str, Any], path: Path) -> None:
    """subVP numbers that give finite noise levels: 0 <= beta_min < beta_max, N >= 1."""
    beta_min, beta_max, scales = (sde_cfg.get(k) for k in ("beta_min", "beta_max", "num_scales"))
    numbers = all(isinstance(v, int | float) and not isinstance(v, bool) for v in (beta_min, beta_max))
    if not numbers or not 0 <= beta_min < beta_max <= MAX_BETA:  # type: ignore[operator]
        raise WeightsError(f"{path}: metadata sde_config needs 0 <= beta_min < beta_max <= {MAX_BETA:g}, "
                           f"got beta_min {beta_min!r}, beta_max {beta_max!r}")  # fmt: skip
    if not isinstance(scales, int) or isinstance(scales, bool) or not 1 <= scales <= MAX_SCALES:
        raise WeightsError(f"{path}: metadata sde_config.num_scales must be an integer from 1 to {MAX_SCALES}, "
                           f"got {scales!r}")  # fmt: skip


# exp(-B(1)) underflows to 0 in float32 beyond B ~ 100; the paper's beta_max is 20.
MAX_BETA = 100.0
MAX_SCALES = 100_000  # the SDE's discretisation: 100x the paper's 1000


def read_network_configs(meta: dict[str, str], path: Path) -> tuple[Skeleton, PriorConfig, SubVPSDE]:
    """The skeleton, network and SDE configs a weights file's metadata declares, checked: every
    problem is a WeightsError naming the file and the field (the file is the bad input)."""
    try:
        skel = get_skeleton(meta.get("skeleton", ""))
    except ConfigError as exc:
        raise WeightsError(f"{path}: metadata 'skeleton': {exc}") from None
    if json_field(meta, "joints", path) != list(skel.joints):
        raise WeightsError(f"{path}: metadata 'joints' do not match skeleton {skel.name}")
    try:
        cfg = PriorConfig(**_config_object(meta, "model_config", path))
        sde_cfg = dict(_config_object(meta, "sde_config", path))
        if sde_cfg.pop("type", None) != "subvp":
            raise WeightsError(f"{path}: only subVP SDE priors are supported")
        _check_sde(sde_cfg, path)
        sde = SubVPSDE(**sde_cfg)
    except TypeError as exc:
        raise WeightsError(f"{path}: metadata config has unknown fields ({exc})") from None
    except ConfigError as exc:  # PriorConfig's checks (sizes, dropout, ...)
        raise WeightsError(f"{path}: metadata model_config: {exc}") from None
    if cfg.num_joints != skel.num_joints:
        raise WeightsError(f"{path}: model has {cfg.num_joints} joints, skeleton {skel.num_joints}")
    return skel, cfg, sde


def check_tensor_header(
    path: Path, header: dict[str, tuple[tuple[int, ...], str]], build: Callable[[], nn.Module],
    other_tensors: dict[str, tuple[int, ...]] | None = None,
) -> nn.Module:  # fmt: skip
    """The file's tensors (names, shapes, dtypes from `header`) against the network that
    `build()` makes from the metadata, built on the meta device: no memory is allocated, so a
    file whose metadata declares a huge network fails here, before any allocation. Returns that
    network (on the meta device: `load_model_state(..., assign=True)` gives it the file's tensors)."""
    with torch.device("meta"):
        model = build()
    expected = {MODEL_PREFIX + k: tuple(v.shape) for k, v in model.state_dict().items()} | (other_tensors or {})
    missing = sorted(set(expected) - set(header))
    if missing:
        raise WeightsError(f"{path}: tensors do not match the model (missing {missing[:3]})")
    extra = sorted(set(header) - set(expected))
    if extra:
        raise WeightsError(f"{path}: unexpected tensors {extra[:3]}")
    for name, shape in expected.items():
        found, dtype = header[name]
        if found != shape:
            raise WeightsError(f"{path}: tensors do not match the model ({name} has shape {list(found)}, "
                               f"the metadata's model_config needs {list(shape)})")  # fmt: skip
        if dtype not in TENSOR_DTYPES:
            raise WeightsError(f"{path}: tensor {name!r} is {dtype}, not one of {', '.join(TENSOR_DTYPES)}")
    return model


def load_model_state(
    model: nn.Module, tensors: dict[str, torch.Tensor], path: Path, *, other_tensors: tuple[str, ...] = (),
    assign: bool = False,
) -> None:  # fmt: skip
    """Load the `model.*` tensors strictly into `model` (float32); any tensor that is neither
    the model's nor one of `other_tensors` is an error. `assign`: the tensors (float32 copies)
    become the parameters, for a `model` built on the meta device."""
    state = {k[len(MODEL_PREFIX) :]: v.to(torch.float32, copy=True) for k, v in tensors.items()
             if k.startswith(MODEL_PREFIX)}  # fmt: skip
    try:
        model.load_state_dict(state, strict=True, assign=assign)
    except RuntimeError as exc:
        first = str(exc).splitlines()[0]
        raise WeightsError(f"{path}: tensors do not match the model ({first})") from None
    extra = set(tensors) - {MODEL_PREFIX + k for k in state} - set(other_tensors)
    if extra:
        raise WeightsError(f"{path}: unexpected tensors {sorted(extra)[:3]}")


def load_prior(path: str | Path, *, skeleton: str | None = None, device: str = "cpu") -> Prior:
    """Load a prior strictly: format and version, skeleton, configs and every tensor must match.

    `skeleton`, when given, is the joint set the caller needs; a prior of another is an error.
    """
    path = Path(path)
    meta, header = read_safetensors_header(path)
    if meta.get("format") != FORMAT:
        raise WeightsError(f"{path}: metadata 'format' is {meta.get('format')!r}, not {FORMAT!r}")
    if meta.get("format_version") not in READABLE_VERSIONS:
        raise WeightsError(
            f"{path}: format_version {meta.get('format_version')!r} is not supported "
            f"(this zedo reads versions {', '.join(READABLE_VERSIONS)})"
        )
    architecture = "scorenet" if meta["format_version"] == FORMAT_VERSION else meta.get("architecture")
    if architecture not in ARCHITECTURES:
        known = ", ".join(ARCHITECTURES)
        raise WeightsError(f"{path}: metadata 'architecture' is {architecture!r}, not one of {known}")
    skel, cfg, sde = read_network_configs(meta, path)
    if skeleton is not None and skel.name != skeleton:
        raise WeightsError(f"{path}: prior is for skeleton {skel.name!r}, not {skeleton!r}")

    members = _member_count(meta, path) if architecture == "ensemble" else 0

    def build() -> nn.Module:
        if architecture == "ensemble":
            return EnsembleScoreNet([ScoreNet(cfg) for _ in range(members)])
        if architecture == "control":
            return ControlledScoreNet(ScoreNet(cfg))  # the prompt's initial values are the file's
        return ScoreNet(cfg)

    model = check_tensor_header(path, header, build, {"template": (skel.num_joints, 3)})  # on the meta device
    _, tensors = read_safetensors(path)
    # The file's tensors become the parameters: no random initial weights are drawn only to be
    # overwritten (about a third of loading a prior; docs/lifting.md, "Start-up and large batches").
    load_model_state(model, tensors, path, other_tensors=("template",), assign=True)
    template = tensors["template"]
    model.to(device).eval()
    parsed = ("model_config", "sde_config", "training", "data", "adapted_from")
    metadata = {k: (json_field(meta, k, path) if k in parsed else v) for k, v in meta.items()}
    return Prior(model, sde, skel, template.float().to(device), metadata, file_sha256(path), str(path))


def _member_count(meta: dict[str, str], path: Path) -> int:
    """An ensemble file's metadata `members`: an integer from 2 to MAX_MEMBERS."""
    text = meta.get("members")
    if text is None:
        raise WeightsError(f"{path}: metadata field 'members' is missing (an ensemble prior names its member count)")
    if not (text.isascii() and text.isdigit() and len(text) < 6) or not 2 <= int(text) <= MAX_MEMBERS:
        raise WeightsError(f"{path}: metadata 'members' must be an integer from 2 to {MAX_MEMBERS}, got {text!r}")
    return int(text)


def bundled_prior_path(name: str = DEFAULT_PRIOR) -> Path:
    if name not in BUNDLED_PRIORS:
        raise WeightsError(f"unknown bundled prior {name!r}; bundled: {', '.join(BUNDLED_PRIORS)}")
    path = Path(str(resources.files("zedo_cli") / "weights" / BUNDLED_PRIORS[name]))
    if not path.is_file():
        raise WeightsError(f"bundled prior {name!r} is not installed ({path} missing)")
    return path


def resolve_prior_path(spec: str | None) -> Path:
    """A bundled prior's name (None = the default) or a path to a weights file."""
    if spec is None:
        return bundled_prior_path(DEFAULT_PRIOR)
    if spec in BUNDLED_PRIORS:
        return bundled_prior_path(spec)
    return Path(spec)
