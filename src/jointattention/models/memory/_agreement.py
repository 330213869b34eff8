"""How many of a face code's kept places agree with each: the recall's votes, kept up to date.

A recall lets the places kept for the face codes nearest a face vote (:func:`._recall.votes_into`):
each place counts the places within the voting radius. A face seen often recalls its own code's
places alone, and their counts change only when the code keeps or forgets a place. So
:func:`.episodic.memory_store` keeps them (``links[AGREE, slot]``: the code's places within the
radius of the slot's, itself included; :func:`agree_keep`, :func:`agree_forget`), and a recall of
one code's places reads them (:func:`votes_of`) instead of counting every pair anew: the same
votes, bit for bit.
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit
from ._recall import AGREE, CODE_OF, HEAD, NEXT, votes_into

__all__ = ["agree_forget", "agree_keep", "votes_of"]


@jit
def agree_keep(links, aims, slot: int, r2: float) -> None:
    """The slot's place joins its code's (linked): it and each near it count each other."""
    pa, ta, n = aims[slot, 0], aims[slot, 1], 1
    b = links[HEAD, links[CODE_OF, slot]]
    while b >= 0:
        if b != slot and (aims[b, 0] - pa) ** 2 + (aims[b, 1] - ta) ** 2 < r2:
            links[AGREE, b] += 1
            n += 1
        b = links[NEXT, b]
    links[AGREE, slot] = n


@jit
def agree_forget(links, aims, slot: int, r2: float) -> None:
    """The slot's place leaves its code's (still linked): each near it counts one fewer."""
    pa, ta = aims[slot, 0], aims[slot, 1]
    b = links[HEAD, links[CODE_OF, slot]]
    while b >= 0:
        if b != slot and (aims[b, 0] - pa) ** 2 + (aims[b, 1] - ta) ** 2 < r2:
            links[AGREE, b] -= 1
        b = links[NEXT, b]


@jit
def votes_of(near, weight, links, aims, radius_rad: float, votes) -> None:
    """:func:`._recall.votes_into`'s votes of the places ``near`` (slots), into ``votes``.

    When they are one code's (one weight), each is its count of agreeing places, as that many
    weights summed one by one; else they are counted (:func:`._recall.votes_into`).
    """
    n = len(near)
    one = n > 0
    for b in range(n):
        one = one and links[CODE_OF, near[b]] == links[CODE_OF, near[0]]
    if not one:
        votes_into(near, weight, aims, radius_rad, votes)
        return
    sums = np.empty(n + 1)  # sums[c]: c of the weights added one by one
    sums[0] = 0.0
    for c in range(n):
        sums[c + 1] = sums[c] + weight[0]
    for a in range(n):
        votes[a] = sums[links[AGREE, near[a]]]
