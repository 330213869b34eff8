"""User-facing errors: each carries one line naming what was wrong and what was expected."""

__all__ = ["ArgumentError", "ConfigError", "DatasetError", "FileError", "JointAttentionError",
           "RenderingUnavailable"]


class JointAttentionError(Exception):
    """Base class for errors the command line reports as one line, without a traceback."""


class ConfigError(JointAttentionError, ValueError):
    """A configuration value or preset is out of range or malformed."""


class ArgumentError(JointAttentionError, ValueError):
    """An argument of a call (an environment's action, a reset's options) is malformed."""


class FileError(JointAttentionError, ValueError):
    """A file the program reads is missing, unreadable, too large or not of the expected kind."""


class DatasetError(FileError):
    """A caregiver data-set file is missing, malformed or of an unknown schema version."""


class RenderingUnavailable(JointAttentionError, RuntimeError):
    """No off-screen OpenGL backend (EGL or OSMesa) could be started."""
