"""The episodic memory's recall, its costly parts (:func:`.episodic.memory_recall`).

The face code (:func:`face_code_into`), the base rate's grid (:func:`cell_of`,
:func:`count_around`), whether two face codes are the same (:func:`same_code`), how far a
face is from each distinct face code (:func:`code_distances_into`), which trials are near it
(:func:`weighted_kth` over the codes, then :func:`near_slots` from each code's list of trials),
and how many near places agree with each (:func:`votes_into`). The lists (``links``, one row
each): ``CODE_OF[slot]``, the slot's code; ``NEXT``/``PREV[slot]``, the code's next and
previous slot in slot order (-1: none); ``HEAD[u]``, code u's first slot; ``LAST[u]``, its slot
written last in this lap of the ring (-1: none yet); ``AGREE[slot]``, the places of the slot's
code within the voting radius of its place (:mod:`._agreement`). The ring writes slots in
increasing order, so a new slot of u goes right after ``LAST[u]``: before it, u's slots of this
lap; after it, those of the last lap.
"""

from __future__ import annotations

import numpy as np

from ..._jit import jit

__all__ = ["AGREE", "CODE_OF", "HEAD", "NEXT", "cell_of", "code_distances_into", "count_around",
           "face_code_into", "link", "near_slots", "new_lap", "no_links", "same_code", "unlink",
           "votes_into", "weighted_kth"]

CODE_OF, NEXT, PREV, HEAD, LAST, AGREE = range(6)  # the rows of links


def no_links(capacity: int) -> np.ndarray:
    """The lists of an empty memory of ``capacity`` slots."""
    links = np.full((6, capacity), -1, np.int64)
    links[CODE_OF] = links[AGREE] = 0
    return links


@jit
def cell_of(pan_rad, tilt_rad, lo_rad, cell_rad, shape) -> tuple[int, int]:
    """The base-rate grid's cell of a place (the edge cells take the places beyond)."""
    i = min(max(int((pan_rad - lo_rad[0]) / cell_rad), 0), shape[0] - 1)
    j = min(max(int((tilt_rad - lo_rad[1]) / cell_rad), 0), shape[1] - 1)
    return i, j


@jit
def count_around(pan_rad, tilt_rad, grid, lo_rad, cell_rad, by) -> None:
    """Add ``by`` to the grid cells within the voting radius (two cells) of a place."""
    ci, cj = cell_of(pan_rad, tilt_rad, lo_rad, cell_rad, grid.shape)
    for di in range(-2, 3):
        for dj in range(-2, 3):
            i, j = ci + di, cj + dj
            if di * di + dj * dj <= 4 and 0 <= i < grid.shape[0] and 0 <= j < grid.shape[1]:
                grid[i, j] += by


@jit
def face_code_into(face, projection, out) -> None:
    """``out = face @ projection``: the face window's compact code.

    ``projection`` is (pixels, code length): each entry of the code sums over the pixels in
    order, all entries at once along a row (the loop vectorises).
    """
    out[:] = 0.0
    for i in range(len(face)):
        fi, row = face[i], projection[i]
        for j in range(len(out)):
            out[j] += row[j] * fi


@jit
def same_code(a, b) -> bool:
    """Whether two face codes are equal, entry by entry (a column of entry-major codes too)."""
    for j in range(len(a)):  # noqa: SIM110 (a plain loop: numba compiles no generator in all())
        if a[j] != b[j]:
            return False
    return True


@jit
def link(links, slot: int, u: int) -> None:
    """Put ``slot`` in code ``u``'s list, in slot order (see the module)."""
    links[CODE_OF, slot] = u
    p = links[LAST, u]
    if p < 0:
        q = links[HEAD, u]
        links[HEAD, u] = slot
    else:
        q = links[NEXT, p]
        links[NEXT, p] = slot
    links[PREV, slot], links[NEXT, slot] = p, q
    if q >= 0:
        links[PREV, q] = slot
    links[LAST, u] = slot


@jit
def unlink(links, slot: int) -> None:
    """Take ``slot`` out of its code's list."""
    u, p, q = links[CODE_OF, slot], links[PREV, slot], links[NEXT, slot]
    if p < 0:
        links[HEAD, u] = q
    else:
        links[NEXT, p] = q
    if q >= 0:
        links[PREV, q] = p


@jit
def new_lap(links, n_codes: int) -> None:
    """The ring starts again at slot 0: no code has a slot of this lap yet."""
    for u in range(n_codes):
        links[LAST, u] = -1


@jit
def near_slots(links, counts, d2u, d2_k: float, n_codes: int):
    """The slots of every code within ``d2_k`` (squared distances ``d2u``), in slot order.

    Each code's list is in slot order; several are merged.
    """
    n_near = n_lists = 0
    for u in range(n_codes):
        if d2u[u] <= d2_k and counts[u] > 0:
            n_near += counts[u]
            n_lists += 1
    near, at = np.empty(n_near, np.int64), np.empty(n_lists, np.int64)
    n_lists = 0
    for u in range(n_codes):
        if d2u[u] <= d2_k and counts[u] > 0:
            at[n_lists] = links[HEAD, u]
            n_lists += 1
    for i in range(n_near):
        best = -1
        for j in range(n_lists):
            if at[j] >= 0 and (best < 0 or at[j] < at[best]):
                best = j
        near[i] = at[best]
        at[best] = links[NEXT, at[best]]
    return near


_SHORT_K = 64  # up to this k, one pass keeping the smallest values beats a quickselect


@jit
def _kth_in_one_pass(values, weights, k: int) -> float:
    """:func:`weighted_kth` by one pass that keeps the smallest values seen, sorted.

    Values at or above the k-th smallest kept so far are passed over: with thousands of
    distinct codes and a few neighbours, nearly all of them.
    """
    kept, kept_w = np.empty(k + 1), np.empty(k + 1, np.int64)
    m = total = 0  # entries kept, their summed weight
    for i in range(len(values)):
        w, v = weights[i], values[i]
        if w <= 0 or (total >= k and v >= kept[m - 1]):
            continue
        p = m
        while p > 0 and kept[p - 1] > v:
            kept[p], kept_w[p] = kept[p - 1], kept_w[p - 1]
            p -= 1
        kept[p], kept_w[p] = v, w
        m, total = m + 1, total + w
        while m > 1 and total - kept_w[m - 1] >= k:  # the largest is not among the k smallest
            m, total = m - 1, total - kept_w[m - 1]
    below = 0
    for p in range(m):
        below += kept_w[p]
        if below >= k:
            return kept[p]
    return kept[m - 1]


@jit
def weighted_kth(values, weights, k: int) -> float:
    """The k-th smallest (k >= 1) of ``values`` each repeated ``weights`` times.

    ``np.partition(np.repeat(values, weights), k - 1)[k - 1]`` (``weights`` >= 0 sum to at
    least ``k``): for small k by one pass (:func:`_kth_in_one_pass`), else by a three-way
    quickselect on the distinct values.
    """
    if k <= _SHORT_K:
        return _kth_in_one_pass(values, weights, k)
    a, w = values.copy(), weights.copy()
    lo, hi = 0, len(a)
    while True:
        pivot = a[(lo + hi) // 2]
        lt, i, gt = lo, lo, hi
        while i < gt:  # a[lo:lt] < pivot, a[lt:i] == pivot, a[gt:hi] > pivot
            if a[i] < pivot:
                a[i], a[lt], w[i], w[lt] = a[lt], a[i], w[lt], w[i]
                lt += 1
                i += 1
            elif a[i] > pivot:
                gt -= 1
                a[i], a[gt], w[i], w[gt] = a[gt], a[i], w[gt], w[i]
            else:
                i += 1
        below = equal = 0
        for j in range(lo, lt):
            below += w[j]
        for j in range(lt, gt):
            equal += w[j]
        if k <= below:
            hi = lt
        elif k <= below + equal:
            return pivot
        else:
            k -= below + equal
            lo = gt


@jit
def votes_into(near, weight, aims, radius_rad: float, votes) -> None:
    """``votes[a]``: the weight of the near places within ``radius_rad`` of place ``a``.

    Summed over the places in their order in ``near``. When every weight is the same (the
    trials of one face: its own, at weight 1, or the nearest face's), a sum of c of them is
    the same whichever c they are: then the places within the radius are counted, comparing
    only the places in the neighbouring strips of pan (a bucket sort by pan) instead of all
    pairs, and the count looked up in the table of those sums.
    """
    n, r2 = len(near), radius_rad * radius_rad
    same = True
    for b in range(n):
        same = same and weight[b] == weight[0]
    if not same or n < 32:
        for a in range(n):
            pa, ta = aims[near[a], 0], aims[near[a], 1]
            v = 0.0
            for b in range(n):
                if (aims[near[b], 0] - pa) ** 2 + (aims[near[b], 1] - ta) ** 2 < r2:
                    v += weight[b]
            votes[a] = v
        return
    lo = hi = aims[near[0], 0]
    for b in range(n):
        lo, hi = min(lo, aims[near[b], 0]), max(hi, aims[near[b], 0])
    width = radius_rad * (1.0 + 1e-9)  # a hair wider: two places closer than the radius are
    n_strips = int((hi - lo) / width) + 1  # in the same or the next strip, rounding and all
    start = np.zeros(n_strips + 1, np.int64)  # places of strip s: order[start[s]:start[s + 1]]
    strip = np.empty(n, np.int64)
    for b in range(n):
        strip[b] = min(int((aims[near[b], 0] - lo) / width), n_strips - 1)
        start[strip[b] + 1] += 1
    for s in range(n_strips):
        start[s + 1] += start[s]
    order, filled = np.empty(n, np.int64), start[:-1].copy()
    for b in range(n):
        order[filled[strip[b]]] = b
        filled[strip[b]] += 1
    sums = np.empty(n + 1)  # sums[c]: c of the weights added one by one
    sums[0] = 0.0
    for c in range(n):
        sums[c + 1] = sums[c] + weight[0]
    for a in range(n):
        pa, ta = aims[near[a], 0], aims[near[a], 1]
        count = 0
        for s in range(max(strip[a] - 1, 0), min(strip[a] + 2, n_strips)):
            for o in range(start[s], start[s + 1]):
                b = near[order[o]]
                count += (aims[b, 0] - pa) ** 2 + (aims[b, 1] - ta) ** 2 < r2
        votes[a] = sums[count]


_TILE_CODES = 128  # codes measured against every face of a batch while they are in cache


@jit
def code_distances_into(queries, codes, n_codes: int, d2) -> None:
    """``d2[q, u]``: the squared distance from face code ``queries[q]`` to ``codes[:, u]``.

    Each sum runs over the code's entries in order, whatever the batch (the same bits as one
    face alone); a tile of codes serves every face of the batch before the next is read.
    """
    for u0 in range(0, n_codes, _TILE_CODES):
        u1 = min(u0 + _TILE_CODES, n_codes)
        for q in range(len(queries)):
            row_d2 = d2[q, u0:u1]
            row_d2[:] = 0.0
            for j in range(queries.shape[1]):
                cj, row = queries[q, j], codes[j, u0:u1]
                for u in range(u1 - u0):
                    row_d2[u] += (row[u] - cj) ** 2
