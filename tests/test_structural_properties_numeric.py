"""Prop1 and Prop2 numerically: the checks hold, every wrong term is caught, and the regressors match Pinocchio's."""

import numpy as np
import pinocchio as pin
import pytest
from inertiaproof.checks.structural_properties_numeric import (
    PROP1_CONTROLS,
    PROP2_CONTROLS,
    Terms,
    prop1_result,
    prop2_result,
)

from inertiaproof.dynamics import regressors
from inertiaproof.dynamics.chain import Chain, Joint, origin
from inertiaproof.model.inertia import inertia_matrix, pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import Profile
from inertiaproof.suite.registry import REPLAYERS
from tests.pinocchio_oracle import pinocchio_model
from tests.test_model import random_phi

FAST = Profile("test", examples=30, samples=300, rounds=8, symbolic_max_n=2, derandomize=True)


def ctx():
    return Context(FAST, seed=0)


def test_prop1_holds_and_its_controls_are_caught():
    result = prop1_result(ctx())
    assert result.verdict == Verdict.HOLDS, result.summary
    assert all(c["caught"] for c in result.evidence["negative_controls"].values())
    assert result.evidence["hunt"]["smallest_margin"]["value"] > 0


@pytest.mark.parametrize("label", sorted(PROP1_CONTROLS))
def test_prop1_with_a_wrong_term_is_violated(label):
    result = prop1_result(ctx(), terms=PROP1_CONTROLS[label][0], examples=10)
    assert result.verdict == Verdict.VIOLATED
    data = result.counterexample["data"]
    assert data["residual"] > data["resolution"]
    assert REPLAYERS[result.counterexample["kind"]](data, ctx()).verdict == Verdict.HOLDS  # the correct code replays


def test_prop2_holds_and_its_controls_are_caught():
    result = prop2_result(ctx())
    assert result.verdict == Verdict.HOLDS, result.summary
    assert all(c["caught"] for c in result.evidence["negative_controls"].values())


@pytest.mark.parametrize("label", sorted(PROP2_CONTROLS))
def test_prop2_with_a_wrong_term_is_violated(label):
    result = prop2_result(ctx(), terms=PROP2_CONTROLS[label][0], examples=10)
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["data"]["residual"] > result.counterexample["data"]["resolution"]


def pinocchio_parameters(after):
    """10 x 10 map Phi (body frame, paper order) -> Pinocchio's (m, mc, Ixx, Ixy, Iyy, Ixz, Iyz, Izz) in the joint frame,
    which is the body frame before the joint's fixed transform ``after``."""
    moved = pseudo_inertia_inverse(after @ pseudo_inertia(np.eye(10)) @ after.T)
    i = inertia_matrix(moved)
    return np.stack([moved[:, 0], moved[:, 1], moved[:, 2], moved[:, 3], i[:, 0, 0], i[:, 0, 1], i[:, 1, 1],
                     i[:, 0, 2], i[:, 1, 2], i[:, 2, 2]], 0)


@pytest.mark.parametrize("chain", [
    robots.panda().chain, robots.ur5().chain, robots.revolute_prismatic(1.0).chain,
    Chain((Joint("revolute", (0.3, -0.2, 0.9), before=origin((0.1, 0.2, 0.3), (0.4, 0.1, -0.3))),
           Joint("prismatic", (1.0, 1.0, 0.0), before=origin((0.5, 0, 0), (0, 0.3, 0)), after=origin((0, 0.1, 0))),
           Joint("revolute", (0, 1, 0), before=origin((0, 0, 0.4)), after=origin((0.2, 0, 0), (0.1, 0, 0.2))))),
], ids=["panda", "ur5", "rp", "general-axes"])
def test_regressor_matches_pinocchio_joint_torque_regressor(chain):
    rng = np.random.default_rng(5)
    theta = random_phi(chain.n)
    model = pinocchio_model(chain, theta)
    data = model.createData()
    for _ in range(4):
        q, qd, qdd = rng.uniform(-1.5, 1.5, chain.n), rng.normal(size=chain.n), rng.normal(size=chain.n)
        qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
        rot, _ = chain.forward_kinematics(q)
        ours = regressors.regressor(qj, dqj, rot, chain.gravity, qd, qd, qdd)  # (N, n, 10)
        theirs = pin.computeJointTorqueRegressor(model, data, q, qd, qdd)  # (n, 10 N)
        for l, joint in enumerate(chain.joints):
            expected = theirs[:, 10 * l:10 * l + 10] @ pinocchio_parameters(joint.after)
            assert np.allclose(ours[l], expected, rtol=1e-11, atol=1e-11 * np.abs(theirs).max())
        tau = pin.rnea(model, data, q, qd, qdd)
        assert np.allclose(regressors.apply_regressor(ours, theta), tau, rtol=1e-11, atol=1e-11)


def test_regressors_do_not_see_the_parameters():
    """The same R_l serves any Theta: with two parameter sets the equation's sides agree for both."""
    chain = robots.panda().chain
    rng = np.random.default_rng(6)
    q, qd, v, a = rng.normal(size=(4, 3, chain.n))
    qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
    rot, _ = chain.forward_kinematics(q)
    r = regressors.regressor(qj, dqj, rot, chain.gravity, qd, v, a)
    from inertiaproof.dynamics import terms

    for theta in (random_phi(chain.n), rng.normal(size=(chain.n, 10))):
        lhs = ((terms.mass_matrix(qj, theta) @ a[..., None])[..., 0]
               + (terms.coriolis(terms.mass_matrix_partials(qj, dqj, theta), qd) @ v[..., None])[..., 0]
               + terms.gravity(qj, rot, theta, chain.gravity))
        assert np.allclose(regressors.apply_regressor(r, theta), lhs, rtol=1e-12, atol=1e-11)


def test_terms_default_to_the_model():
    from inertiaproof.dynamics import terms as model

    terms = Terms()
    assert terms.coriolis is model.coriolis and terms.lumped is model.lumped_velocity_matrix


@pytest.mark.parametrize("name", ["panda", "non-normal-2r", "passenger-platform"])
def test_coriolis_force_is_the_christoffel_form(name):
    """terms.coriolis_force (C qd in O(N n^2), used by generalized_forces) against C of the Christoffel symbols of
    dM/dq, batched and single; the comparison tells C from its transpose."""
    from inertiaproof.dynamics import motion, terms

    chain = robots.BUILTIN[name]().chain
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-1, 1, (2, 5, chain.n))
    theta = np.stack([random_phi(chain.n) for _ in range(5)])
    kin = motion.kinematics(chain, q)
    c = terms.coriolis(terms.mass_matrix_partials(kin.qj, kin.dqj, theta), qd)
    ref = (c @ qd[..., None])[..., 0]
    fast = terms.coriolis_force(kin.qj, kin.dqj, theta, qd)
    scale = np.abs(ref).max()
    assert np.abs(fast - ref).max() <= 1e-12 * scale
    assert np.allclose(terms.coriolis_force(kin.qj[0], kin.dqj[0], theta[0], qd[0]), fast[0], rtol=0, atol=1e-12 * scale)
    transposed = (np.swapaxes(c, -1, -2) @ qd[..., None])[..., 0]
    assert np.abs(transposed - fast).max() > 1e-6 * scale
