"""The package's version, written here alone: pyproject.toml and the files it writes read it."""

__all__ = ["__version__"]

__version__ = "0.4.0"
