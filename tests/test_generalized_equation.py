"""GRE and GRE-F: the derivation holds, and each checker sees VIOLATED on a known-bad input."""

import dataclasses

import numpy as np
import pytest
from inertiaproof.symbolic import oracle
from inertiaproof.symbolic.claims import CLAIMS, entries, gre_residual
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.evidence import claim_result, run_claim
from inertiaproof.symbolic.identity import decide_randomised, fixed_point, point_from_json
from inertiaproof.symbolic.robotics_equation import transpose
from inertiaproof.symbolic.systems import SystemKey, profile_systems

from inertiaproof.result import Verdict
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import PROFILES

CI_SYSTEMS = profile_systems(PROFILES["ci"])


@pytest.fixture(scope="module")
def ci_derivations():
    return [derivation(k) for k in CI_SYSTEMS]


@pytest.mark.parametrize("claim_id", ["GRE", "GRE-F"])
def test_holds_with_every_negative_control_detected(ci_derivations, claim_id):
    claim = CLAIMS[claim_id]
    result = claim_result(claim, [run_claim(claim, d, rng=np.random.default_rng(1)) for d in ci_derivations])
    assert result.verdict == Verdict.HOLDS, result.summary
    controls = result.evidence["negative_controls"]
    assert controls and all(c["detected"] for c in controls.values())
    for system in result.evidence["systems"].values():
        assert system["randomised"]["error_probability"]["value"] < 1e-15


def _bad(d, **terms):
    return dataclasses.replace(d, equation=d.equation.with_terms(**terms))


@pytest.mark.parametrize("mutation", ["drop M(q, Thetadot)", "transpose H", "drop Psidot"])
def test_gre_checker_rejects_a_wrong_equation(ci_derivations, mutation):
    d = next(x for x in ci_derivations if x.key.label == "3R")
    calc = d.calc
    bad = {
        "drop M(q, Thetadot)": lambda: _bad(d, M_rates=tuple(tuple(calc.zero for _ in r) for r in d.equation.M)),
        "transpose H": lambda: _bad(d, H=transpose(d.equation.H)),
        "drop Psidot": lambda: _bad(d, psi_force=tuple(calc.zero for _ in d.equation.G)),
    }[mutation]()
    result = claim_result(CLAIMS["GRE"], [run_claim(CLAIMS["GRE"], bad, controls=False)])
    assert result.verdict == Verdict.VIOLATED
    data = result.counterexample["data"]
    value = calc.evaluate(gre_residual(bad)[data["entry"]], point_from_json(data["point"]))
    assert value != 0 and str(value) == data["value"]


def test_gre_checker_rejects_a_wrong_abstract_equation(ci_derivations):
    d = next(x for x in ci_derivations if x.key.label == "abstract-n2")
    bad = _bad(d, C=transpose(d.equation.C))
    assert claim_result(CLAIMS["GRE"], [run_claim(CLAIMS["GRE"], bad, controls=False)]).verdict == Verdict.VIOLATED


def test_gre_f_checker_rejects_half_of_f(ci_derivations):
    d = next(x for x in ci_derivations if x.key.label == "2R")
    bad = dataclasses.replace(d, F=tuple(tuple(x / 2 for x in row) for row in d.F))
    result = claim_result(CLAIMS["GRE-F"], [run_claim(CLAIMS["GRE-F"], bad, controls=False)])
    assert result.verdict == Verdict.VIOLATED


def test_a_blind_check_is_inconclusive(ci_derivations):
    """A control that changes a term but is not detected makes the check INCONCLUSIVE, not HOLDS."""
    d = next(x for x in ci_derivations if x.key.label == "2R")
    blind = dataclasses.replace(CLAIMS["GRE"], residual=lambda d, eq=None: tuple(0 * x for x in d.euler_lagrange))
    assert claim_result(blind, [run_claim(blind, d)]).verdict == Verdict.INCONCLUSIVE


def test_randomised_test_finds_a_nonzero_residual(ci_derivations):
    d = next(x for x in ci_derivations if x.key.label == "3R")
    formula = lambda at: entries(CLAIMS["GRE"].residual(at))[0]  # noqa: E731
    good = decide_randomised(formula, d, np.random.default_rng(0), points=2)
    assert good.holds and 0 < good.error_probability < 1e-15 and good.degree > 2
    bad = decide_randomised(formula, _bad(d, H=transpose(d.equation.H)), np.random.default_rng(0), points=2)
    assert not bad.holds and bad.witness["value"] != 0


@pytest.mark.parametrize("name", ["2R", "3R"])
def test_symbolic_equation_agrees_with_the_numeric_model(ci_derivations, name):
    d = next(x for x in ci_derivations if x.key.label == name)
    error, symbolic, numeric = oracle.generalized_forces_error(d, fixed_point(d.calc, 5))
    assert error < 1e-12 and np.max(np.abs(numeric)) > 1


def test_check_functions_run_under_the_registry(ci_derivations):
    from inertiaproof.checks.generalized_equation import generalized_robotics_equation

    result = generalized_robotics_equation(Context(PROFILES["ci"]))
    assert result.verdict == Verdict.HOLDS
    assert set(result.evidence["time_per_n"]) == {"n=1", "n=2", "n=3"}


def test_unknown_chain_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown chain"):
        SystemKey.chain("9R")
