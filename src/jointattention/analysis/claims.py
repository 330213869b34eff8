"""The paper's qualitative claims, checked on a run's success curves (pure functions).

Conditions are grouped by their model and *reading* (for the bootstrap model: gate per step
or per trial, VF fallback, learning target; the readings where the paper is silent,
docs/model.md). Within each group every claim that the group's conditions allow is checked by
a stated rule; the gates are told apart by kind (:mod:`jointattention.agent.gates`), so a
model of your own with a gate is checked like the paper's:

- **starts no better than chance and rises** (each sigmoid condition): the first bin is at
  most chance + 0.05, and the final success (last 10% of bins) exceeds the first bin with
  the lower end of the paired 95% interval over seeds above zero; a curve that starts within
  0.05 of its ceiling only has to stay there.
- **sigmoid beats constant r** (at each object count run with both): final success of the
  sigmoid minus that of the constant rate, paired over seeds (common random numbers), lower
  95% bound above zero.
- **performance gate beats sigmoid / constant r** (5 objects, beyond the paper): the same
  rule; the performance gate's conditions are also checked for rising and the ceiling.
- **constant 1.0 stays near or below chance** (5 objects, a self-evaluating model): final
  success at most 1.25 x chance.
- **shuffled faces stay at chance** (the control): final success at most 1.25 x chance.
- **final success at least 0.9 of the ceiling** (each sigmoid condition: the paper's "high
  performance at the end even if many objects are set", read as 0.9 of the ceiling);
- **worst seed at least 0.75 of the ceiling** (each sigmoid condition: it bootstraps on every
  seed, not on some).

The claims of the neighbours' papers (the teacher, the developmental model, reinforcement
learning) are :mod:`.neighbours`'; :func:`check_claims` returns them too.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from .._files import write_text
from ..config import Config, model_options
from ..errors import FileError
from .claim_record import PAIRED_RULE, SOURCES, Claim, finals_of, paired, paired_lower, reading_of
from .neighbours import neighbour_claims
from .tables import Table

__all__ = ["SOURCES", "Claim", "check_claims", "claims_groups", "claims_markdown", "claims_of",
           "claims_summary", "claims_table", "reading_of", "readings_table",
           "write_claims"]


def _role(gate) -> str | None:
    """Which of the paper's claims a condition with ``gate`` is checked by (Gate.claims_role)."""
    return getattr(gate, "claims_role", None)


_RULES = {  # each claim's rule (the module docstring says why)
    "ceiling kept": "final within 0.05 of the ceiling",
    "rises": "first bin <= chance + 0.05; final - first bin: paired 95% lower bound > 0",
    "0.9 of ceiling": "mean final >= 0.9 x ceiling",
    "worst seed": "lowest seed's final >= 0.75 x ceiling",
    "beats": PAIRED_RULE,
    "chance": "mean final <= 1.25 x chance",
}


def check_claims(config: Config, curves: dict, ceilings: dict,
                 axis_errors: dict | None = None) -> list[Claim]:
    """Every claim each reading's conditions allow, the neighbours' included.

    ``curves`` as from :func:`jointattention.analysis.curves.condition_curves`, ``ceilings``
    {str(n): ceiling}, ``axis_errors`` as from
    :func:`jointattention.analysis.curves.condition_axis_errors` (None: not checked).
    """
    gates = {c.name: getattr(model_options(config, c), "gate", None)
             for c in config.experiment.conditions}
    groups: dict[str, list] = {}
    for c in config.experiment.conditions:
        groups.setdefault(reading_of(c, config), []).append(c)
    claims = []
    for reading, conds in groups.items():
        def add(rule, claim, holds, evidence, reading=reading):
            # the performance gate is the paper's future work, built here: our own target
            source = "project" if "performance gate" in claim else "paper"
            claims.append(Claim(reading, claim, bool(holds), evidence, _RULES[rule], source))

        finals = {c.name: finals_of(curves[c.name][1]) for c in conds}
        sigmoid = [c for c in conds if _role(gates[c.name]) == "sigmoid" and not c.shuffle_faces]
        performance = [c for c in conds
                       if _role(gates[c.name]) == "performance" and not c.shuffle_faces]
        for c in sigmoid + performance:
            per_seed = curves[c.name][1]
            first, final = per_seed[:, 0], finals[c.name]
            chance, ceiling = 1 / c.n_objects, ceilings.get(str(c.n_objects), np.nan)
            numbers = (f"first bin {first.mean():.3f}, final {final.mean():.3f}, chance "
                       f"{chance:.3f}, ceiling {ceiling:.3f}")
            n_objects = (f"{c.n_objects} objects" if c in sigmoid
                         else f"{c.n_objects} objects, performance gate")
            if first.mean() >= ceiling - 0.05:
                add("ceiling kept", f"{n_objects}: starts at the ceiling and stays there",
                    final.mean() >= ceiling - 0.05, numbers)
            else:
                add("rises", f"{n_objects}: starts no better than chance and rises",
                    first.mean() <= chance + 0.05 and paired_lower(final, first) > 0, numbers)
            add("0.9 of ceiling", f"{n_objects}: final success at least 0.9 of the ceiling",
                final.mean() >= 0.9 * ceiling,
                f"final {final.mean():.3f} = {final.mean() / ceiling:.2f} of ceiling "
                f"{ceiling:.3f}")
            add("worst seed", f"{n_objects}: worst seed at least 0.75 of the ceiling",
                final.min() >= 0.75 * ceiling,
                f"worst seed {final.min():.3f} = {final.min() / ceiling:.2f} of ceiling "
                f"{ceiling:.3f}")
        for p in (c for c in performance if c.n_objects == 5):
            for c in conds:
                if c.n_objects == 5 and not c.shuffle_faces and c is not p and _role(
                        gates[c.name]) in ("sigmoid", "constant"):
                    add("beats", f"5 objects: performance gate beats {gates[c.name].label}",
                        *paired(finals[p.name], finals[c.name]))
        for c in conds:
            if _role(gates[c.name]) != "constant" or c.shuffle_faces:
                continue
            rate = gates[c.name].rate
            for s in (s for s in sigmoid if s.n_objects == c.n_objects):
                add("beats", f"{c.n_objects} objects: sigmoid beats constant {rate}",
                    *paired(finals[s.name], finals[c.name]))
            if (rate == 1.0 and c.n_objects == 5
                    and not model_options(config, c).taught):
                # the paper's claim of a self-evaluating robot; a taught one learns (the
                # neighbours' claims)
                add("chance", "5 objects: constant 1.0 stays near or below chance",
                    finals[c.name].mean() <= 1.25 * 0.2,
                    f"final {finals[c.name].mean():.3f}, chance 0.200")
        for c in conds:
            if c.shuffle_faces:
                chance = 1 / c.n_objects
                add("chance", f"{c.n_objects} objects, shuffled faces: stays at chance",
                    finals[c.name].mean() <= 1.25 * chance,
                    f"final {finals[c.name].mean():.3f}, chance {chance:.3f}")
    return claims + neighbour_claims(config, curves, axis_errors)


_COLUMNS = ("reading", "source", "claim", "holds", "evidence", "rule")


def claims_table(claims: list[Claim]) -> Table:
    """The claims as a table: reading, source, claim, holds, evidence, rule (claims.csv)."""
    return Table(_COLUMNS, [(c.reading, c.source, c.claim, c.holds, c.evidence, c.rule)
                            for c in claims])


def write_claims(claims: list[Claim], stem: Path) -> list[Path]:
    """Write ``<stem>.csv`` (:func:`claims_table`) and ``<stem>.md`` (:func:`claims_markdown`)."""
    stem = Path(stem)
    return [write_text(stem.with_suffix(".csv"), claims_table(claims).to_csv()),
            write_text(stem.with_suffix(".md"), claims_markdown(claims))]


def claims_of(table: Table) -> list[Claim]:
    """The claims of a table :func:`claims_table` wrote and :func:`~.tables.read_csv` read.

    A claims.csv of an older version (no ``source`` column) names no source: each claim's
    is told from its words (:func:`_legacy_source`).
    """
    at = {name: i for i, name in enumerate(table.columns)}
    if not {"reading", "claim", "holds", "evidence"} <= set(at):
        raise FileError("not a claims table; expected the columns " + ", ".join(_COLUMNS))

    def get(row, name, default=""):
        return row[at[name]] if name in at else default

    return [Claim(get(r, "reading"), get(r, "claim"), get(r, "holds") is True,
                  get(r, "evidence"), get(r, "rule"),
                  get(r, "source") or _legacy_source(get(r, "claim")))
            for r in table.rows]


_NEIGHBOURS = ("teacher at least bootstrap", "developmental faster than teacher",
               "visual development improves accuracy", "horizontal before vertical",
               "gaze following emerges")


def _legacy_source(claim: str) -> str:
    """The source of a claim of version 0.3's claims.csv, told from its words."""
    if "follows caregivers it never saw" in claim or "performance gate" in claim:
        return "project"
    return "neighbours" if any(n in claim for n in _NEIGHBOURS) else "paper"


def claims_summary(claims: list[Claim]) -> str:
    """One line: how many claims hold, in all and by source, e.g. "15 of 24 claims hold (...)"."""
    parts = []
    for source in SOURCES:
        mine = [c for c in claims if c.source == source]
        if mine:
            parts.append(f"{_SHORT[source]} {sum(c.holds for c in mine)} of {len(mine)}")
    held = sum(c.holds for c in claims)
    return f"{held} of {len(claims)} claims hold" + (f" ({'; '.join(parts)})" if parts else "")



_SHORT = {"paper": "the paper's", "neighbours": "the neighbours'",
          "project": "this project's own targets"}


def claims_groups(claims: list[Claim]) -> list[tuple[str, list[tuple[str, list[Claim]]]]]:
    """The claims grouped by source (in :data:`SOURCES` order), then by reading (in run order)."""
    groups = []
    for source in SOURCES:
        readings: dict[str, list[Claim]] = {}
        for c in (c for c in claims if c.source == source):
            readings.setdefault(c.reading, []).append(c)
        if readings:
            groups.append((source, list(readings.items())))
    return groups


def claims_markdown(claims: list[Claim]) -> str:
    """claims.md: a summary line, then per source and reading a table of claim, holds, evidence.

    The settings of a reading are shown once, above its table, and each rule once, in a list
    the rows refer to ([1], [2]...), so that no row repeats them.
    """
    rules = list(dict.fromkeys(c.rule for c in claims if c.rule))
    lines = [claims_summary(claims) + ".", ""]
    for source, readings in claims_groups(claims):
        lines += [f"## {SOURCES[source]}", ""]
        for reading, mine in readings:
            # a long reading wraps: a code span may span lines (CommonMark)
            wrapped = "\n".join(textwrap.wrap(reading, 96, break_long_words=False))
            lines += [f"Reading: `{wrapped}`" if reading else "Reading: (none)", ""]
            table = Table(("claim", "holds", "evidence", "rule"),
                          [(c.claim, c.holds, c.evidence,
                            f"[{rules.index(c.rule) + 1}]" if c.rule else "") for c in mine])
            lines += [table.to_markdown()]
    if rules:
        lines += ["Rules:", ""] + [f"{i}. {rule}" for i, rule in enumerate(rules, 1)] + [""]
    return "\n".join(lines)


def readings_table(config: Config, curves: dict, ceilings: dict, claims: list[Claim]) -> Table:
    """One row per reading: final success of each condition, claims held, rank by the rule.

    Columns after the reading: one per object count and gate (``5 obj, sigmoid``: the mean
    final success over seeds and, in brackets, its fraction of the ceiling), the claims that
    hold of those checked, the mean fraction of the ceiling over the sigmoid conditions, and
    the rank by the rule that chooses the paper preset's reading (docs/readings.md):
    most claims held, ties broken by the higher mean fraction.
    """
    rows: dict[str, dict] = {}
    columns: list[str] = []
    sigmoid: dict[str, list[float]] = {}
    for c in config.experiment.conditions:
        if c.shuffle_faces:
            continue
        gate = getattr(model_options(config, c), "gate", None)
        column = f"{c.n_objects} obj, {gate.label if gate is not None else 'no gate'}"
        columns += [column] if column not in columns else []
        final = float(finals_of(curves[c.name][1]).mean())
        fraction = final / ceilings.get(str(c.n_objects), np.nan)
        reading = reading_of(c, config)
        rows.setdefault(reading, {})[column] = f"{final:.3f} ({fraction:.2f})"
        if _role(gate) == "sigmoid":
            sigmoid.setdefault(reading, []).append(fraction)
    held = {r: sum(c.holds for c in claims if c.reading == r) for r in rows}
    checked = {r: sum(c.reading == r for c in claims) for r in rows}
    mean = {r: float(np.mean(sigmoid[r])) if r in sigmoid else float("nan") for r in rows}
    order = sorted(rows, key=lambda r: (-held[r], -np.nan_to_num(mean[r], nan=-1.0)))
    return Table(("reading", *columns, "claims_held", "mean_fraction_sigmoid", "rank"),
                 [(r, *(rows[r].get(k, "") for k in columns), f"{held[r]} of {checked[r]}",
                   round(mean[r], 3), order.index(r) + 1) for r in rows])
