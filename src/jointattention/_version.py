"""The package's version: one place, read by the files it writes and by the command line."""

__all__ = ["__version__"]

__version__ = "0.3.0"
