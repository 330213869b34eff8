"""The paper's claims, checked by stated rules on success curves."""

from __future__ import annotations

import numpy as np

from jointattention.analysis.claims import (
    check_claims,
    claims_markdown,
    claims_of,
    claims_summary,
    claims_table,
    reading_of,
)
from jointattention.config import ConditionConfig, Config, ExperimentConfig

CONDS = (
    ConditionConfig(name="sig", n_objects=5),
    ConditionConfig(name="c07", n_objects=5, model={"gate": {"kind": "constant", "rate": 0.7}}),
    ConditionConfig(name="c10", n_objects=5, model={"gate": {"kind": "constant", "rate": 1.0}}),
    ConditionConfig(name="shuf", n_objects=5, shuffle_faces=True),
    ConditionConfig(name="trial-sig", n_objects=5, model={"gate_per": "trial"}),
    ConditionConfig(name="sig10", n_objects=10),
    ConditionConfig(name="c09-10", n_objects=10, model={"gate": {"kind": "constant", "rate": 0.9}}),
)
CONFIG = Config(experiment=ExperimentConfig(n_seeds=3, conditions=CONDS))
CEILINGS = {"5": 0.9, "10": 0.8}


def _curves(rng, **finals):
    """Per-seed curves (3 seeds, 10 bins) rising from 0.2 to each condition's final value."""
    out = {}
    for name, final in finals.items():
        base = np.linspace(0.2, final, 10)
        out[name] = (np.arange(1, 11), base + rng.normal(0, 0.005, (3, 10)))
    return out


def _verdicts(claims, reading):
    return {c.claim: c.holds for c in claims if c.reading == reading}


def test_claims_hold_when_the_curves_show_them():
    """A rising sigmoid above the constants, a flat 1.0 and a flat control all hold."""
    rng = np.random.default_rng(0)
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, sig10=0.75,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    step = _verdicts(claims, reading_of(CONDS[0], CONFIG))
    assert step == {
        "5 objects: starts no better than chance and rises": True,
        "5 objects: final success at least 0.9 of the ceiling": True,
        "5 objects: worst seed at least 0.75 of the ceiling": True,
        "10 objects: starts no better than chance and rises": False,  # 0.2 is above 0.1 + 0.05
        "10 objects: final success at least 0.9 of the ceiling": True,
        "10 objects: worst seed at least 0.75 of the ceiling": True,
        "10 objects: sigmoid beats constant 0.9": True,
        "5 objects: sigmoid beats constant 0.7": True,
        "5 objects: sigmoid beats constant 1.0": True,
        "5 objects: constant 1.0 stays near or below chance": True,
        "5 objects, shuffled faces: stays at chance": True,
    }
    trial = _verdicts(claims, reading_of(CONDS[4], CONFIG))
    assert trial == {"5 objects: starts no better than chance and rises": True,
                     "5 objects: final success at least 0.9 of the ceiling": False,
                     "5 objects: worst seed at least 0.75 of the ceiling": False}


def test_claims_fail_when_the_curves_contradict_them():
    """A sigmoid below a constant, a learning 1.0 and a rising control are each reported."""
    rng = np.random.default_rng(1)
    curves = _curves(rng, sig=0.5, c07=0.7, c10=0.6, shuf=0.6, sig10=0.3,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    step = _verdicts(claims, reading_of(CONDS[0], CONFIG))
    assert not step["10 objects: sigmoid beats constant 0.9"]  # equal finals do not beat
    assert not step["5 objects: sigmoid beats constant 0.7"]
    assert not step["5 objects: constant 1.0 stays near or below chance"]
    assert not step["5 objects, shuffled faces: stays at chance"]
    assert "| NO |" in claims_table(claims).to_markdown()


def test_one_failing_seed_fails_the_worst_seed_claim():
    """Nine seeds at the ceiling and one at chance: the mean may pass, the worst seed does not."""
    config = Config(experiment=ExperimentConfig(n_seeds=10, conditions=CONDS[:1]))
    per_seed = np.tile(np.linspace(0.2, 0.88, 10), (10, 1))
    per_seed[3] = np.linspace(0.2, 0.25, 10)
    claims = check_claims(config, {"sig": (np.arange(1, 11), per_seed)}, {"5": 0.9})
    verdicts = _verdicts(claims, reading_of(CONDS[0], config))
    assert verdicts["5 objects: worst seed at least 0.75 of the ceiling"] is False
    assert verdicts["5 objects: starts no better than chance and rises"] is True


def test_the_readings_table_ranks_by_claims_then_by_fraction_of_the_ceiling():
    """One row per reading, a column per object count and gate, rank 1 for most claims held."""
    from jointattention.analysis.claims import readings_table

    rng = np.random.default_rng(0)
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, sig10=0.75,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    table = readings_table(CONFIG, curves, CEILINGS, claims)
    assert table.columns == ("reading", "5 obj, sigmoid", "5 obj, constant 0.7",
                             "5 obj, constant 1.0", "10 obj, sigmoid", "10 obj, constant 0.9",
                             "claims_held", "mean_fraction_sigmoid", "rank")
    rows = {r[0]: r for r in table.rows}
    step, trial = rows[reading_of(CONDS[0], CONFIG)], rows[reading_of(CONDS[4], CONFIG)]
    assert step[-1] == 1 and trial[-1] == 2
    assert trial[2:6] == ("", "", "", "") and trial[1].endswith("(0.33)")


def test_every_claim_states_its_rule():
    """Each claim carries the rule it was checked by, and the table shows it."""
    rng = np.random.default_rng(0)
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, sig10=0.75,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    assert all(c.rule for c in claims)
    table = claims_table(claims)
    assert table.columns[-1] == "rule" and "paired 95% lower bound > 0" in table.to_markdown()


def test_claims_md_shows_each_reading_once_and_each_rule_once():
    """claims.md groups the claims by reading: its settings and each rule appear once.

    The rows refer to the rules by number, the first line counts the claims that hold, and
    no line is over 300 characters.
    """
    rng = np.random.default_rng(0)
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, sig10=0.75,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    text = claims_markdown(claims)
    held = sum(c.holds for c in claims)
    assert text.splitlines()[0].startswith(f"{held} of {len(claims)} claims hold")
    for reading in {c.reading for c in claims}:
        assert text.count(reading.split(", ")[-1]) >= 1
        assert text.replace("\n", " ").count(reading) == 1, reading
    for rule in {c.rule for c in claims}:
        assert text.count(rule) == 1, rule
    assert max(map(len, text.splitlines())) <= 300
    assert claims_of(read_csv_text(claims_table(claims).to_csv())) == claims


def read_csv_text(text: str):
    """A table as :func:`read_csv` reads a file of ``text``."""
    import tempfile
    from pathlib import Path

    from jointattention.analysis.tables import read_csv

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "t.csv"
        path.write_text(text)
        return read_csv(path)


def test_claims_are_the_papers_the_neighbours_or_the_projects_own():
    """The paper's claims, the neighbours' and this project's own targets are told apart.

    claims.csv files of version 0.3 (no source column) are read with each claim's source.
    """
    rng = np.random.default_rng(0)
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, sig10=0.75,
                     **{"trial-sig": 0.3, "c09-10": 0.3})
    assert {c.source for c in check_claims(CONFIG, curves, CEILINGS)} == {"paper"}
    old = read_csv_text(
        "reading,claim,holds,evidence,rule\n"
        "r,5 objects: sigmoid beats constant 0.7,True,e,x\n"
        "r,5 objects (n5): follows caregivers it never saw,False,e,x\n"
        "r,teacher-n5: teacher at least bootstrap (n5),True,e,x\n"
        "r,\"5 objects, performance gate: final success at least 0.9 of the ceiling\",True,e,x\n")
    assert [c.source for c in claims_of(old)] == ["paper", "project", "neighbours", "project"]
    summary = claims_summary(claims_of(old))
    assert summary == ("3 of 4 claims hold (the paper's 1 of 1; the neighbours' 1 of 1; this "
                       "project's own targets 1 of 2)")


def test_the_docs_claims_are_what_the_code_writes_from_their_csv():
    """Each docs/results/<run>/claims.md is what :func:`claims_markdown` writes from its CSV."""
    from pathlib import Path

    from jointattention.analysis.tables import read_csv

    results = Path(__file__).resolve().parent.parent / "docs" / "results"
    files = sorted(results.glob("*/claims.md"))
    assert files
    for md in files:
        claims = claims_of(read_csv(md.with_suffix(".csv")))
        assert md.read_text() == claims_markdown(claims), md
