"""Where random generators are born: one seed, many named, independent streams.

Every random draw in the library comes from a :class:`numpy.random.Generator` made here, so
that a run is fixed by its seed alone, whatever the order in which parts of it execute or the
number of processes that run it.
"""

from __future__ import annotations

import zlib

import numpy as np

__all__ = ["stream", "streams"]


def _name_key(name: str) -> int:
    # crc32 is stable across processes and Python versions (unlike hash()).
    return zlib.crc32(name.encode("utf-8"))


def stream(seed: int, name: str, *index: int) -> np.random.Generator:
    """The generator for stream ``name`` (optionally numbered by ``index``) of ``seed``.

    Streams with different names or indices are statistically independent; the same
    arguments always give the same sequence.
    """
    if not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    entropy = [int(seed), _name_key(name), *(int(i) for i in index)]
    return np.random.default_rng(np.random.SeedSequence(entropy))


def streams(seed: int, *names: str) -> dict[str, np.random.Generator]:
    """A dict of named generators of ``seed``; a shorthand for several :func:`stream` calls."""
    return {name: stream(seed, name) for name in names}
