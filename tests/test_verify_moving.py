"""The ``moving-mass`` claim (verify/moving.py), half powers of a product, and the growth directions of a
``body-spectrum`` claim: what the prover writes is re-proved, what is false or malformed is not. A moving-mass
bound that fails is a proof step that does not go through (not re-proved: the checker decides it from the loads'
bounds, at no witness); a body-spectrum one fails at a body's row (refuted)."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.certificate import product_certificate
from inertiaproof.bounds.spectral import EPS, ROUNDING
from inertiaproof.bounds.time import BODY_FUNCTIONS, lumped_velocity_bounds, time_extreme
from inertiaproof.checks.other_components import acc_result
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile, Scaling
from inertiaproof.model.inertia import from_urdf
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import Profile as RunProfile
from inertiaproof.verify.cli import check
from inertiaproof.verify.product import FORMULAS

TROLLEY = robots.trolley_2r(loop=True, mass=2.0).trajectory  # a circle, smootherstep
ROD = from_urdf(np.array([1.5]), np.array([[0.3, 0.0, 0.0]]), np.diag([1e-3, 0.05, 0.05])[None])[0]
LINE = ParameterTrajectory(np.stack([ROD, ROD]), (
    MovingMass(1, 0.7, np.diag([1e-3, 2e-3, 2e-3]), Path("line", Profile("cosine", 0.5, 2.0), (0.1, 0.0, 0.0),
                                                          (0.8, 0.1, 0.0))),), (0.0, 4.0))

BALL = from_urdf(np.array([2.0]), np.array([[0.5, 0.1, 0.0]]), np.diag([4e-3, 4e-3, 4e-3])[None])[0]
MIXED = ParameterTrajectory(LINE.base, LINE.loads + (  # a moving mass beside two payloads
    Payload(1, BALL, Profile("smootherstep", 1.0, 1.5)), Payload(0, 0.5 * BALL, Profile("smoothstep", 0.2, 0.4))),
    LINE.span)


def _found(trajectory):
    found = {name: time_extreme(trajectory, name) for name in BODY_FUNCTIONS}
    found.update(lumped_velocity_bounds(trajectory))
    return found


def _beyond(found, everything):
    """Whether a certified side lies beyond the sampled one, which eigvalsh computes to within ROUNDING eps of the
    largest eigenvalue of f or Z along the trajectory (``everything``: its :func:`_found`; a sample may fall that far
    below a true lambda_min)."""
    slack = ROUNDING * EPS * max(everything[name]["observed"] for name in ("lmax_f", "lmax_Z"))
    if found.get("sense") == "min":
        return found["certified"] <= found["observed"] + slack
    return found["observed"] <= found["certified"] + slack


@pytest.mark.parametrize("trajectory", [TROLLEY, LINE], ids=["circle", "line"])
def test_every_bound_over_time_of_moving_loads_is_reproved_and_a_lower_one_is_not(trajectory):
    for name, found in _found(trajectory).items():
        cert = found["certificate"]
        assert Fraction(cert["claim"]["bound"]) == Fraction(found["certified"])
        assert check(cert)["status"] == "re-proved", (name, check(cert))
        tampered = copy.deepcopy(cert)  # beyond the value attained on the time grid: false
        lower = found["sense"] == "min" if "sense" in found else False
        tampered["claim"]["bound"] = str(Fraction(found["observed"]) * (Fraction(101, 100) if lower
                                                                         else Fraction(99, 100)))
        assert check(tampered)["status"] == _failed(cert), name


def _failed(cert):
    """The status of a false claim: a moving-mass bound is decided from the loads' bounds (no witness: not
    re-proved), a body-spectrum one at a body's row (refuted)."""
    return "not re-proved" if cert["claim"]["kind"] == "moving-mass" else "refuted"


def test_spectra_over_time_of_moving_loads_beside_payloads_are_reproved_and_a_lower_one_is_not():
    """The rest of Theta(t) (and of its rate) sweeps the hull of the payloads' segments: every bound is certified over
    it, sampled inside it, re-proved, and refuted below what the samples attain."""
    everything = _found(MIXED)
    for name, found in everything.items():
        lower = found.get("sense") == "min"
        assert _beyond(found, everything)
        cert = found["certificate"]
        assert len(cert["parameters"]) == (1 if name.startswith("psi") else 4)
        assert check(cert)["status"] == "re-proved", (name, check(cert))
        tampered = copy.deepcopy(cert)
        tampered["claim"]["bound"] = str(Fraction(found["observed"]) * (Fraction(101, 100) if lower
                                                                         else Fraction(99, 100)))
        assert check(tampered)["status"] == _failed(cert), name


def test_a_psi_claim_over_several_parameter_sets_is_a_bad_certificate():
    cert = copy.deepcopy(_found(LINE)["psi"]["certificate"])
    cert["parameters"] = cert["parameters"] * 2
    out = check(cert)
    assert out["status"] == "bad certificate" and "one set" in out["why"], out


@pytest.mark.parametrize("field, value, why", [
    ("mass", "-1", "not a consistent rigid body"),
    ("inertia_com", [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "3"]], "not a consistent rigid body"),
    ("path", {"shape": "spiral"}, "path.shape"),
    ("profile", {"shape": "exp", "rate": "1/2"}, "no bounded rate"),
])
def test_a_malformed_or_inconsistent_load_is_a_bad_certificate(field, value, why):
    cert = copy.deepcopy(_found(TROLLEY)["psi"]["certificate"])
    cert["loads"][0][field] = value
    out = check(cert)
    assert out["status"] == "bad certificate" and why in out["why"], out


def test_a_linear_ramp_has_no_bound_of_psidot():
    cert = copy.deepcopy(_found(LINE)["psi"]["certificate"])
    cert["claim"]["quantity"] = "psi_dot"
    cert["loads"][0]["profile"] = {"shape": "linear", "duration": "2", "rate": "0"}
    out = check(cert)
    assert out["status"] == "bad certificate" and "jumps" in out["why"], out


def test_eq_acc_constant_is_a_reproved_product_with_a_half_power():
    profile = RunProfile("test", examples=30, samples=300, rounds=4, symbolic_max_n=2, derandomize=True)
    result = acc_result(Context(profile, seed=0, outputs=Outputs()))
    constants = result.evidence["scenes"]["trolley-loop-2r"]["constants"]
    cert = constants["paper"]["certificate"].certificate
    assert cert["claim"]["formula"] == "eq_acc" and FORMULAS["eq_acc"][2] == [("psi_dot", 2), ("QJ_max", 1)]
    assert check(cert)["status"] == "re-proved"
    raised = copy.deepcopy(cert)  # dPsi* S^(1/2) below the product of the ingredients' bounds: the arithmetic fails
    raised["claim"]["bound"] = str(Fraction(cert["claim"]["bound"]) * Fraction(999, 1000))
    assert check(raised)["status"] == "not re-proved"
    # a lambda_max of f(Phi) may be negative: the half power's slot takes only (QJ)^T QJ
    negative = check(product_certificate("<=", 10.0, "eq_acc", [cert["ingredients"][0],
                                                                _found(TROLLEY)["lmax_f"]["certificate"]]))
    assert negative["status"] == "bad certificate" and "QJ_max" in negative["why"], negative


def test_a_scaling_without_bound_is_certified_along_its_growth_direction():
    sphere = ParameterTrajectory(ROD[None], (Scaling(0, Profile("exp", 0.0, 1.0, 0.5)),), (0.0, np.inf))
    found = time_extreme(sphere, "lmin_f")
    cert = found["certificate"]
    assert "directions" in cert and check(cert)["status"] == "re-proved"
    bad = copy.deepcopy(cert)
    bad["directions"][0][0] = "-1"  # a direction of negative mass lowers lambda_min without bound
    assert check(bad)["status"] == "refuted"
    upper = copy.deepcopy(cert)
    upper["claim"]["quantity"] = "lambda_max"
    assert check(upper)["status"] == "bad certificate"


def test_bounds_over_time_of_a_moving_mass_beside_a_payload_hold_on_random_trajectories():
    """Random bodies with a payload ramp and a moving mass: every certified side lies beyond what a time grid attains
    and is re-proved."""
    from hypothesis import given, settings
    from inertiaproof.counterexamples.trajectories import mixed_trajectories

    @settings(max_examples=15, deadline=None, derandomize=True)
    @given(mixed_trajectories(3, 1.0))
    def beyond_the_samples(mixed):
        everything = _found(mixed)
        for name, found in everything.items():
            assert _beyond(found, everything), name
            assert check(found["certificate"])["status"] == "re-proved", name

    beyond_the_samples()
