"""`--device`: the device a command runs the network on (torch is imported only here, inside the function)."""

from __future__ import annotations

from ..errors import ConfigError, plural


def check_device(device: str) -> str:
    """The device to run on: `cpu`, `cuda` / `cuda:N` when torch sees that GPU, `mps` where
    available, or `auto` (CUDA when torch sees a GPU, else the CPU)."""
    import torch

    if device == "auto":
        return "cuda" if torch.cuda.is_available() else "cpu"
    try:
        dev = torch.device(device)
    except (RuntimeError, ValueError):
        raise ConfigError(f"--device must be cpu, cuda, cuda:N or auto, got {device!r}") from None
    if dev.type == "cpu":
        return device
    if dev.type == "cuda":
        if not torch.cuda.is_available():
            raise ConfigError(f"--device {device}: no CUDA GPU is available to this torch ({torch.__version__}); "
                              "use --device cpu")  # fmt: skip
        if dev.index is not None and dev.index >= torch.cuda.device_count():
            raise ConfigError(f"--device {device}: torch sees {plural(torch.cuda.device_count(), 'CUDA GPU')}")
        return device
    if dev.type == "mps" and torch.backends.mps.is_available():
        return device
    raise ConfigError(f"--device must be cpu, cuda, cuda:N or auto, got {device!r}")
