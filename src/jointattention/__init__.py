"""jointattention: the bootstrap learning model for joint attention (Nagai, Hosoda, Asada).

A robot with a pan/tilt camera head learns, with no teacher, to look where a caregiver looks.
"""

__all__ = ["__version__"]

__version__ = "0.1.0"
