"""Random streams: one seed, independent named streams, reproducible."""

import numpy as np
import pytest

from jointattention.rng import stream


def test_same_arguments_same_sequence():
    """The same seed and name give the same draws."""
    assert np.array_equal(stream(3, "world").random(5), stream(3, "world").random(5))


def test_names_seeds_and_indices_give_different_streams():
    """Another name, seed or index gives another sequence."""
    base = stream(3, "world").random(5)
    for other in (stream(3, "agent"), stream(4, "world"), stream(3, "world", 1)):
        assert not np.array_equal(base, other.random(5))


def test_negative_seed_is_rejected():
    """Seeds are non-negative integers."""
    with pytest.raises(ValueError, match="seed"):
        stream(-1, "world")
