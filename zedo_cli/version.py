"""The package version, in one place (the result files and weights metadata record it)."""

__version__ = "0.1.0"
