"""Prop1 and Prop2 (symbolic): each checker sees VIOLATED on a known-bad input."""

import dataclasses

import numpy as np
import pytest
from inertiaproof.symbolic.claims import CLAIMS
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.evidence import claim_result, run_claim
from inertiaproof.symbolic.properties import Regressors
from inertiaproof.symbolic.systems import profile_systems

from inertiaproof.result import Verdict
from inertiaproof.suite.profiles import PROFILES


@pytest.fixture(scope="module")
def ci_derivations():
    return [derivation(k) for k in profile_systems(PROFILES["ci"])]


def by_label(ds, label):
    return next(d for d in ds if d.key.label == label)


@pytest.mark.parametrize("claim_id", ["Prop1", "Prop2"])
def test_holds_with_every_negative_control_detected(ci_derivations, claim_id):
    claim = CLAIMS[claim_id]
    result = claim_result(claim, [run_claim(claim, d, rng=np.random.default_rng(2)) for d in ci_derivations])
    assert result.verdict == Verdict.HOLDS, result.summary
    assert all(c["detected"] for c in result.evidence["negative_controls"].values())


def test_prop1_checker_rejects_a_symmetric_part(ci_derivations):
    d = by_label(ci_derivations, "3R")
    m_dot = d.M_dot
    bad = dataclasses.replace(d, N=tuple(tuple(x + y for x, y in zip(rn, rm)) for rn, rm in zip(d.N, m_dot)))
    assert claim_result(CLAIMS["Prop1"], [run_claim(CLAIMS["Prop1"], bad, controls=False)]).verdict == \
        Verdict.VIOLATED


def test_prop2_checker_rejects_a_regressor_that_depends_on_parameters(ci_derivations):
    """R Theta unchanged but R depends on Theta: VIOLATED because the regressor is not free of inertial parameters."""
    d = by_label(ci_derivations, "2R")
    calc = d.calc
    t1, t2, a1 = calc.theta[0], calc.theta[1], d.system.a[0]
    rows = tuple((r[0] + t2 * a1, r[1] - t1 * a1) + tuple(r[2:]) for r in d.regressors.R)
    bad = dataclasses.replace(d, regressors=Regressors(rows, d.regressors.R_M_velocity))
    result = claim_result(CLAIMS["Prop2"], [run_claim(CLAIMS["Prop2"], bad, controls=False)])
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["data"]["impure"]


def test_prop2_checker_rejects_a_wrong_rate_regressor(ci_derivations):
    d = by_label(ci_derivations, "abstract-n2")
    wrong = tuple(tuple(2 * x for x in row) for row in d.regressors.R_M_velocity)
    bad = dataclasses.replace(d, regressors=Regressors(d.regressors.R, wrong))
    assert claim_result(CLAIMS["Prop2"], [run_claim(CLAIMS["Prop2"], bad, controls=False)]).verdict == \
        Verdict.VIOLATED


def test_regressors_are_free_of_inertial_parameters(ci_derivations):
    d = by_label(ci_derivations, "3R")
    roles = set().union(*(d.calc.free_roles(x) for row in d.regressors.R for x in row))
    assert roles and not roles & {"theta", "theta_dot"}
    assert len(d.regressors.R[0]) == 30 and d.system.block == 10
