"""urdf2dh's version (``pyproject.toml`` holds the same)."""

__all__ = ["__version__"]

__version__ = "0.2.0"
