"""A zedo result as `zedo lift --config`: the settings it records, to lift again.

A result records its lift's options (`params.options`, zedo lift's own values of the options the
poses depend on) and the prior's sha256, so `zedo lift INPUT --config RESULT.zedo.json` lifts
with the same settings and, on the same machine, gives the same poses. Results written before
`params.options` was recorded are read from the rest of `params` (preset, the LiftConfig numbers,
seed, person, temporal mode, ...) where that is enough; what cannot be reproduced from a result is
refused with a one-line reason: a LiftConfig number no option sets, a camera from the command line
or a calibration file that an older result does not name, a prior that is not bundled.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import ConfigError
from ..strict_json import loads
from .config_file import ConfigFile, check_values
from .model import Options

PRIOR_NEEDED = "give the weights file with --prior"


def read_params(path: str) -> dict[str, Any]:
    """A JSON or JSON Lines result's `params` (a JSON Lines result's header line)."""
    try:
        with open(path, encoding="utf-8") as f:
            text = f.readline() if Path(path).suffix.lower() in (".jsonl", ".ndjson") else f.read()
        doc = loads(text)
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read the --config file ({exc.strerror or exc})") from None
    except (ValueError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: a --config is a TOML file or a zedo result, and this is neither ({exc})") from None
    params = doc.get("params") if isinstance(doc, dict) else None
    if not isinstance(params, dict) or not str(doc.get("schema", "")).startswith("zedo.pose3d"):
        raise ConfigError(f"{path}: not a zedo result (no schema zedo.pose3d and params): a --config is a TOML "
                          "file or a result of zedo lift")  # fmt: skip
    return params


def result_config(path: str, model: type[Options]) -> ConfigFile:
    """The lift settings a result records, as `path`'s --config for `zedo lift`."""
    if model.command != "lift":
        raise ConfigError(f"{path}: a zedo result is a --config of zedo lift (it records the lift's settings); "
                          f"zedo {model.command} reads a TOML file")  # fmt: skip
    params = read_params(path)
    prior = params.get("prior") if isinstance(params.get("prior"), dict) else {}
    sha = prior.get("sha256") if isinstance(prior.get("sha256"), str) else None
    recorded = params.get("options")
    if isinstance(recorded, dict):
        unknown = sorted(set(recorded) - set(model.keys()))
        if unknown:
            raise ConfigError(f"{path}: params.options.{unknown[0]}: not an option of this zedo's lift (the result "
                              f"was written by zedo {params.get('zedo_version', 'of another version')})")  # fmt: skip
        values = dict(recorded)
        check_values(f"{path}: params.options", values, model)
        return ConfigFile(path, values, prior_sha256=sha)
    values, needs = _older_result(path, params, prior)
    check_values(f"{path}: params", values, model)
    return ConfigFile(path, values, prior_sha256=sha, needs=needs)


def _older_result(path: str, params: dict[str, Any], prior: dict[str, Any]) -> tuple[dict[str, Any], dict[str, str]]:
    """The options of a result that records no `params.options`, from its preset, LiftConfig
    numbers and the rest of params; refused where they do not say how it was lifted."""
    from ..lifting.config import CALIBRATION_IRRELEVANT, PRESETS, LiftConfig
    from ..prior.weights import BUNDLED_PRIORS
    from .lift import CONFIG_KEYS

    config, preset = params.get("config"), params.get("preset")
    if not isinstance(config, dict) or preset not in PRESETS:
        raise ConfigError(f"{path}: params: no preset and config recorded: not a result zedo lift can lift again")
    base = PRESETS[preset]
    values: dict[str, Any] = {"preset": preset}
    for key in CONFIG_KEYS:
        if key in config and config[key] != getattr(base, key):
            values[key] = config[key]
    for key in ("seed", "min_confidence", "person", "fps", "save_hypotheses"):
        if params.get(key) is not None:
            values[key] = params[key]
    temporal = params.get("temporal")
    if isinstance(temporal, dict):
        values["temporal"], values["sigma"] = temporal.get("mode", "none"), temporal.get("sigma_frames", 2.0)
    try:
        from dataclasses import replace

        wanted = replace(base, **{k: values[k] for k in CONFIG_KEYS if k in values}).to_dict()
    except (TypeError, ConfigError) as exc:
        raise ConfigError(f"{path}: params.config: {exc}") from None
    # bf16 and chunk_size do not change the poses (CALIBRATION_IRRELEVANT): older `fast` results record bf16
    # false, where `fast` now says null (bfloat16 where the device has it).
    fixed = [k for k in wanted if k in config and k not in (*CONFIG_KEYS, *CALIBRATION_IRRELEVANT)
             and config[k] != wanted[k]]  # fmt: skip
    if fixed or set(config) - set(LiftConfig().to_dict()):
        odd = fixed or sorted(set(config) - set(wanted))
        raise ConfigError(f"{path}: params.config.{odd[0]}: {config.get(odd[0])!r}, not the {preset} preset's and "
                          "set by no option of zedo lift: this lift cannot be repeated from its result")  # fmt: skip
    sources = params.get("camera_sources") or ["pseudo"]
    if set(sources) != {"pseudo"}:
        raise ConfigError(f"{path}: lifted with a camera from {' and '.join(s for s in sources if s != 'pseudo')} "
                          "(--focal, --principal-point or --intrinsics), which a result of this zedo version does "
                          "not record: give the camera options in a TOML --config or as flags")  # fmt: skip
    if params.get("camera") is not None:
        values["camera"] = params["camera"]
    needs: dict[str, str] = {}
    name = Path(str(prior.get("file", ""))).stem
    if name in BUNDLED_PRIORS and BUNDLED_PRIORS[name] == prior.get("file"):
        values["prior"] = name
    elif prior:
        needs["prior"] = (f"{path}: lifted with the prior {json.dumps(prior.get('file'))}, which is not bundled and "
                          f"whose place the result does not record: {PRIOR_NEEDED}")  # fmt: skip
    return values, needs
