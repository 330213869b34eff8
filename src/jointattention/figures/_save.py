"""Figures without pyplot, saved whole or not at all.

They are made with :class:`matplotlib.figure.Figure`, so the library never chooses or changes
matplotlib's backend.
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from .._files import atomic_path

__all__ = ["new_figure", "save_figure"]


def new_figure(width_in: float, height_in: float) -> Figure:
    """An empty figure of that size, laid out tightly when saved."""
    return Figure(figsize=(width_in, height_in), layout="tight")


def save_figure(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Write ``fig`` to ``path`` (format from its suffix) atomically."""
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format=path.suffix[1:])
    return path
