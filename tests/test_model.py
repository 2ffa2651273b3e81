"""The physical model against independent computations: Pinocchio, finite differences, exact formulas."""

import numpy as np
import pinocchio as pin
import pytest

from inertiaproof.dynamics import terms
from inertiaproof.dynamics.chain import Chain, Coordinate, Joint, origin
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile, Scaling
from inertiaproof.model.inertia import (
    from_urdf,
    inertia_com,
    pack,
    pseudo_inertia,
    pseudo_inertia_inverse,
    sigma_com,
    spatial_inertia,
    spatial_inertia_inverse,
    unit_body,
)
from inertiaproof.scene import robots
from tests.pinocchio_oracle import joint_variables, pinocchio_model

RNG = np.random.default_rng(7)


def random_phi(n):
    return np.stack([from_urdf(RNG.uniform(0.2, 5), RNG.normal(size=3) * 0.2,
                               np.diag(RNG.uniform(0.01, 0.2, 3))) for _ in range(n)])


def test_matrix_forms_invert():
    phi = RNG.normal(size=(50, 10))
    assert np.allclose(pseudo_inertia_inverse(pseudo_inertia(phi)), phi, rtol=0, atol=1e-13)
    assert np.allclose(spatial_inertia_inverse(spatial_inertia(phi)), phi, rtol=0, atol=1e-13)


def test_unit_body_is_the_first_counterexample():
    assert np.allclose(pseudo_inertia(unit_body()), np.diag([0.5, 0.5, 0.5, 1.0]))
    assert np.allclose(spatial_inertia(unit_body()), np.eye(6))


def test_com_quantities_match_pinocchio():
    phi = random_phi(5)
    for p in phi:
        m = p[0]
        body = pin.Inertia(m, p[1:4] / m, inertia_com(p))
        assert np.allclose(body.matrix(), spatial_inertia(p), atol=1e-12)
    s = sigma_com(phi)
    ic = inertia_com(phi)
    assert np.allclose(s, 0.5 * np.trace(ic, axis1=1, axis2=2)[:, None, None] * np.eye(3) - ic)


def test_urdf_rotation_enters_as_r_ic_rt():
    ic = np.diag([1.0, 2.0, 3.0])
    rot_z90 = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    phi = from_urdf(1.0, np.zeros(3), ic, rot_z90)
    assert np.allclose(phi, pack(1.0, np.zeros(3), np.diag([2.0, 1.0, 3.0])))


CHAINS = {
    "panda": robots.panda().chain,
    "ur5": robots.ur5().chain,
    "non-normal": robots.non_normal_2r().chain,
    "general-axes": Chain((
        Joint("revolute", (0.3, -0.2, 0.9), before=origin((0.1, 0.2, 0.3), (0.4, 0.1, -0.3))),
        Joint("prismatic", (1.0, 1.0, 0.0), before=origin((0.5, 0, 0), (0, 0.3, 0)), after=origin((0, 0.1, 0))),
        Joint("revolute", (0, 1, 0), before=origin((0, 0, 0.4)), coordinate=Coordinate("arctan")),
    ), name="general"),
}


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_dynamics_match_pinocchio(name):
    chain = CHAINS[name]
    theta = random_phi(chain.n)
    model = pinocchio_model(chain, theta)
    data = model.createData()
    q = RNG.uniform(-1.5, 1.5, size=(12, chain.n))
    qd, qdd = RNG.normal(size=q.shape), RNG.normal(size=q.shape)
    rot, _ = chain.forward_kinematics(q)
    qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
    m = terms.mass_matrix(qj, theta)
    c = terms.coriolis(terms.mass_matrix_partials(qj, dqj, theta), qd)
    g = terms.gravity(qj, rot, theta, chain.gravity)
    for b in range(len(q)):
        x = joint_variables(chain, q[b])
        dx = np.array([j.coordinate.derivative(v) for j, v in zip(chain.joints, q[b])])
        if np.allclose(dx, 1.0):
            tau = pin.rnea(model, data, x, qd[b], qdd[b])
            assert np.allclose(m[b] @ qdd[b] + c[b] @ qd[b] + g[b], tau, rtol=1e-12, atol=1e-11)
            assert np.allclose(pin.computeCoriolisMatrix(model, data, x, qd[b]) @ qd[b], c[b] @ qd[b], atol=1e-11)
        # with coordinate maps, M(q) = D^T M_pin(x) D with D = diag(dx/dq)
        mp = pin.crba(model, data, x)
        assert np.allclose(m[b], dx[:, None] * mp * dx[None, :], rtol=1e-12, atol=1e-12)
        assert np.allclose(g[b], dx * pin.computeGeneralizedGravity(model, data, x), atol=1e-11)


def test_jacobian_derivative_matches_central_differences():
    chain = CHAINS["general-axes"]
    q = RNG.uniform(-1, 1, size=(4, chain.n))
    h = 1e-6
    fd = np.stack([(chain.body_jacobian(q + h * e) - chain.body_jacobian(q - h * e)) / (2 * h)
                   for e in np.eye(chain.n)], -1)
    assert np.allclose(chain.body_jacobian_derivative(q), fd, atol=1e-8)


def test_prop1_skew_symmetry_numerically():
    chain = CHAINS["panda"]
    theta, theta_dot = random_phi(chain.n), RNG.normal(size=(chain.n, 10))
    q, qd = RNG.uniform(-1, 1, size=(8, chain.n)), RNG.normal(size=(8, chain.n))
    qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
    n = (terms.mass_matrix_time_derivative(qj, dqj, theta, theta_dot, qd)
         - 2 * terms.coriolis(terms.mass_matrix_partials(qj, dqj, theta), qd)
         - terms.mass_matrix(qj, theta_dot))
    assert np.abs(n + np.swapaxes(n, -1, -2)).max() < 1e-12 * np.abs(n).max()
    h = terms.lumped_velocity_matrix(dqj, RNG.normal(size=(8, 6 * chain.n)))
    assert np.array_equal(h, -np.swapaxes(h, -1, -2))


@pytest.mark.parametrize("shape", Profile.SHAPES)
def test_profile_derivatives_are_consistent(shape):
    p = Profile(shape, start=0.2, duration=0.7, rate=-0.8)
    t = np.linspace(0.0, 1.2, 241)[1:-1]
    t = t[np.abs(t - 0.2) > 1e-3]
    t = t[np.abs(t - 0.9) > 1e-3]
    h = 1e-6
    s, ds, dds = p.derivatives(t)
    after = t >= p.start
    assert np.allclose(ds, (p.derivatives(t + h)[0] - p.derivatives(t - h)[0]) / (2 * h), atol=1e-5)
    assert np.allclose(dds, (p.derivatives(t + h)[1] - p.derivatives(t - h)[1]) / (2 * h), atol=1e-4)
    assert np.all(np.abs(ds[after]) <= p.rate_bound() + 1e-12)


def test_trajectory_rates_are_time_derivatives():
    base = random_phi(2)
    traj = ParameterTrajectory(base, (
        Scaling(0, Profile("smootherstep", 0.1, 0.5)),
        Payload(1, random_phi(1)[0], Profile("cosine", 0.2, 0.6)),
        MovingMass(0, 2.0, np.diag([0.01, 0.02, 0.03]), Path("circle", Profile("smootherstep", 0.0, 1.0),
                                                            center=(0.3, 0, 0), radius=0.2, normal=(0, 1, 1))),
    ))
    t, h = np.linspace(0.05, 0.95, 17), 1e-6
    theta, theta_dot = traj.theta(t)
    assert np.allclose(theta_dot, (traj.theta(t + h)[0] - traj.theta(t - h)[0]) / (2 * h), atol=1e-6)
    psi, psi_dot = traj.psi(t)
    assert np.allclose(psi_dot, (traj.psi(t + h)[0] - traj.psi(t - h)[0]) / (2 * h), atol=1e-5)


@pytest.mark.parametrize("name", sorted(CHAINS))
def test_composite_mass_matrix_matches_pinocchio_and_the_formula(name):
    from inertiaproof.dynamics import composite

    chain = CHAINS[name]
    theta = random_phi(chain.n)
    model = pinocchio_model(chain, theta)
    data = model.createData()
    q = RNG.uniform(-2.5, 2.5, size=(2, 3, chain.n))
    m = composite.mass_matrix(chain, q, theta)
    assert m.shape == (2, 3, chain.n, chain.n)
    for b, x in enumerate(q.reshape(-1, chain.n)):
        dx = np.array([j.coordinate.derivative(v) for j, v in zip(chain.joints, x)])
        mp = pin.crba(model, data, joint_variables(chain, x))
        mp = np.triu(mp) + np.triu(mp, 1).T
        assert np.allclose(m.reshape(-1, chain.n, chain.n)[b], dx[:, None] * mp * dx[None, :], rtol=1e-12, atol=1e-12)
    stack = RNG.normal(size=(3, 1, chain.n, 10))  # any Theta, also inconsistent ones: M is linear in Theta
    assert np.allclose(composite.mass_matrix(chain, q[0][:, None], stack[:, 0][None]),
                       terms.mass_matrix(chain.body_jacobian(q[0])[:, None], stack[:, 0][None]), rtol=0, atol=1e-12)


def test_composite_mass_matrix_passes_complex_steps_and_chunks():
    from inertiaproof.dynamics import composite
    from inertiaproof.dynamics.twists import CHUNK

    chain = CHAINS["general-axes"]
    theta = random_phi(chain.n)
    q = RNG.uniform(-1, 1, size=(CHUNK + 5, chain.n))
    m = composite.mass_matrix(chain, q, theta)
    assert np.allclose(m, terms.mass_matrix(chain.body_jacobian(q), theta), rtol=0, atol=1e-12)
    step = 1e-30
    dm = np.stack([composite.mass_matrix(chain, q[:4] + 1j * step * e, theta).imag / step for e in np.eye(chain.n)], -1)
    qj, dqj = chain.body_jacobian(q[:4]), chain.body_jacobian_derivative(q[:4])
    assert np.allclose(dm, terms.mass_matrix_partials(qj, dqj, theta), rtol=0, atol=1e-12)


EPS = np.finfo(float).eps


def test_joints_moved_onto_z_keep_the_kinematics():
    from inertiaproof.dynamics.twists import axis_frame, twist_map

    for axis in ((0, 0, 1.0), (0, 0, -1.0), (1.0, 0, 0), (0.3, -0.4, 0.866)):
        a = axis_frame(np.asarray(axis) / np.linalg.norm(axis))
        assert np.allclose(a @ [0, 0, 1], np.asarray(axis) / np.linalg.norm(axis)) and np.allclose(a.T @ a, np.eye(3))
    assert np.array_equal(axis_frame((0, 0, 1.0)), np.eye(3))
    for tilt in (1e-3, 1e-5, 1e-7, 1e-9, 1e-12, 1e-15):  # near -e_z, where 1 + axis_z cancels (seed 3's Prop1 chain)
        axis = np.array([tilt, -0.7 * tilt, -1.0]) / np.linalg.norm([tilt, -0.7 * tilt, -1.0])
        a = axis_frame(axis)
        assert np.abs(a.T @ a - np.eye(3)).max() < 16 * EPS and np.abs(a[:, 2] - axis).max() < 16 * EPS, tilt
    t = origin((0.3, -0.2, 0.5), (0.4, 0.1, -0.7))
    v, w = RNG.normal(size=3), RNG.normal(size=3)
    r, p = t[:3, :3], t[:3, 3]
    assert np.allclose(twist_map(t) @ np.r_[v, w], np.r_[r.T @ (v + np.cross(w, p)), r.T @ w])
