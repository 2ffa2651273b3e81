"""QJ against forward kinematics: it holds, and a wrong rate factor of a coordinate map turns Def2, CX-normal and
Prop1 VIOLATED with a replayable counterexample."""

import numpy as np
import pytest
from hypothesis import given, settings
from inertiaproof.checks.forward_kinematics import (
    PROPERTIES,
    forward_kinematics,
    kinematics_residuals,
    replay_forward_kinematics,
)
from inertiaproof.checks.normality import cx_normal, def2
from inertiaproof.checks.structural_properties_numeric import prop1
from inertiaproof.counterexamples.chains import chains_with_configurations

from inertiaproof.dynamics import chain as chain_module
from inertiaproof.result import Verdict
from inertiaproof.scene import robots


@settings(max_examples=30)
@given(chains_with_configurations("RP", tuple(chain_module.COORDINATE_MAPS)))
def test_qj_agrees_with_forward_kinematics_on_random_chains(example):
    chain, q, q_dot = example
    for name, (residual, resolution) in kinematics_residuals(chain, q, q_dot).items():
        assert (residual <= resolution).all(), name


def test_forward_kinematics_are_the_chains_frames():
    chain = robots.panda().chain
    q = np.random.default_rng(0).uniform(-1, 1, (5, chain.n))
    rotations, origins = chain.forward_kinematics(q)
    frames = forward_kinematics(chain, q)
    assert np.allclose(frames[..., :3, :3], rotations, atol=1e-14) and np.allclose(frames[..., :3, 3], origins,
                                                                                   atol=1e-14)


@pytest.fixture(params=["cubic", "arctan"])
def wrong_rate(request, monkeypatch):
    """The coordinate map's derivative off by a factor 2/3 (g' = 2 q^2 for q^3; 2/3 / (1 + q^2) for arctan)."""
    g, dg = chain_module.COORDINATE_MAPS[request.param]
    monkeypatch.setitem(chain_module.COORDINATE_MAPS, request.param, (g, lambda q: dg(q) * (2 / 3)))
    return request.param


@pytest.mark.parametrize("check", [def2, cx_normal, prop1])
def test_a_wrong_rate_factor_turns_the_checks_violated(ctx, wrong_rate, check):
    result = check(ctx)
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert "disagrees with the forward kinematics" in result.summary
    data = result.counterexample["data"] if result.counterexample["kind"] == "forward-kinematics" else None
    if data is not None:
        assert replay_forward_kinematics(data, ctx).verdict == Verdict.VIOLATED


def test_a_wrong_rate_factor_is_seen_by_qj_and_its_derivative(wrong_rate):
    chain = robots.non_normal_2r().chain
    if wrong_rate != "cubic":
        chain = chain_module.Chain((chain_module.Joint("revolute", (0, 0, 1), coordinate=chain_module.Coordinate(
            wrong_rate)),), name="arctan joint")
    q = np.array([[0.7] * chain.n])
    residuals = kinematics_residuals(chain, q, np.ones_like(q))
    for name in (PROPERTIES[1], PROPERTIES[2], PROPERTIES[3]):
        residual, resolution = residuals[name]
        assert residual[0] > 1e3 * resolution[0], name
