"""The paper's claims, checked by stated rules on success curves."""

from __future__ import annotations

import numpy as np

from jointattention.analysis.claims import check_claims, claims_table, reading_of
from jointattention.config import ConditionConfig, Config, ExperimentConfig

CONDS = (
    ConditionConfig(name="sig", n_objects=5),
    ConditionConfig(name="c07", n_objects=5, model={"gate": {"kind": "constant", "rate": 0.7}}),
    ConditionConfig(name="c10", n_objects=5, model={"gate": {"kind": "constant", "rate": 1.0}}),
    ConditionConfig(name="shuf", n_objects=5, shuffle_faces=True),
    ConditionConfig(name="trial-sig", n_objects=5, model={"gate_per": "trial"}),
)
CONFIG = Config(experiment=ExperimentConfig(n_seeds=3, conditions=CONDS))
CEILINGS = {"5": 0.9}


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
    curves = _curves(rng, sig=0.85, c07=0.5, c10=0.2, shuf=0.2, **{"trial-sig": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    step = _verdicts(claims, reading_of(CONDS[0], CONFIG))
    assert step == {
        "5 objects: starts no better than chance and rises": True,
        "5 objects: final success at least 0.9 of the ceiling": True,
        "5 objects: sigmoid beats constant 0.7": True,
        "5 objects: sigmoid beats constant 1.0": True,
        "5 objects: constant 1.0 stays near or below chance": True,
        "5 objects, shuffled faces: stays at chance": True,
    }
    trial = _verdicts(claims, reading_of(CONDS[4], CONFIG))
    assert trial == {"5 objects: starts no better than chance and rises": True,
                     "5 objects: final success at least 0.9 of the ceiling": False}


def test_claims_fail_when_the_curves_contradict_them():
    """A sigmoid below a constant, a learning 1.0 and a rising control are each reported."""
    rng = np.random.default_rng(1)
    curves = _curves(rng, sig=0.5, c07=0.7, c10=0.6, shuf=0.6, **{"trial-sig": 0.3})
    claims = check_claims(CONFIG, curves, CEILINGS)
    step = _verdicts(claims, reading_of(CONDS[0], CONFIG))
    assert not step["5 objects: sigmoid beats constant 0.7"]
    assert not step["5 objects: constant 1.0 stays near or below chance"]
    assert not step["5 objects, shuffled faces: stays at chance"]
    assert "| NO |" in claims_table(claims).to_markdown()
