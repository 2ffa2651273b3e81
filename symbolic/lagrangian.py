"""The Lagrangian L = T - U (Lagrangian) and the Euler-Lagrange operator (LagrangeFormalism).

For a chain, T is built from each body's velocities obtained by differentiating
its frame along the motion (VelocityRigidMass, IntermediateKineticEnergy), not
from QJ: the paper's form, assembled from QJ in
:mod:`~inertiaproof.symbolic.robotics_equation`, is compared against it.
"""

from __future__ import annotations

from inertiaproof.symbolic.kinematics import matvec, skew, to_qq

__all__ = [
    "abstract_lagrangian", "chain_lagrangian", "chain_potential", "euler_lagrange", "quadratic_form",
    "spatial_inertia",
]


def euler_lagrange(calc, lagrangian):
    """(d/dt dL/dqd_k - dL/dq_k)_k (LagrangeFormalism): what equals tau + w along every motion."""
    return tuple(calc.d_t(calc.d_qd(lagrangian, k)) - calc.d_q(lagrangian, k) for k in range(1, calc.n + 1))


def spatial_inertia(phi):
    """Z(Phi) = [[m I3, -S(h)], [-S(h)^T, I]] (DefMatrixZ) of symbolic parameters (m, h1, h2, h3, I11, I22, I33, I12, I23, I13)."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = phi
    z = 0 * m
    s = skew([h1, h2, h3])
    inertia = [[i11, i12, i13], [i12, i22, i23], [i13, i23, i33]]
    top = [[m if i == j else z for j in range(3)] + [-s[i][j] for j in range(3)] for i in range(3)]
    bottom = [[-s[j][i] for j in range(3)] + inertia[i] for i in range(3)]
    return top + bottom


def quadratic_form(x, a, y):
    return sum((xi * ai for xi, ai in zip(x, matvec(a, y))), 0 * x[0])


def chain_lagrangian(twin):
    """L = sum_l (1/2 V_l^T Z(Phi_l) V_l + V_l^T psi_l) + nu/2 - U with V_l = (R_l^T v_l, omega_l) from d/dt of the frames.

    (IntermediateKineticEnergy, KineticEnergy); U = -a_g^T sum_l (m_l z_l + R_l h_l)
    (RespectivePotenitalEnergy, PotentialEnergy) for the chain's gravitational
    acceleration a_g (the paper's field g is -a_g).
    """
    jets = twin.jets
    kinetic = jets.gen("nu") / 2
    for l, velocity in enumerate(twin.body_velocities, 1):
        phi = jets.body_parameters(l)
        kinetic += quadratic_form(velocity, spatial_inertia(phi), velocity) / 2
        kinetic += sum((v * p for v, p in zip(velocity, jets.body_psi(l))), jets.zero)
    return jets.canonical(kinetic - chain_potential(twin))


def chain_potential(twin):
    """U(q, Theta) (PotentialEnergy), linear in Theta."""
    jets = twin.jets
    g = [jets.ring(to_qq(x)) for x in twin.gravity]
    total = jets.zero
    for l, frame in enumerate(twin.frames, 1):
        m, h1, h2, h3 = jets.body_parameters(l)[:4]
        moment = [m * z + rh for z, rh in zip(frame.origin, matvec(frame.rotation, [h1, h2, h3]))]
        total -= sum((gi * x for gi, x in zip(g, moment)), jets.zero)
    return jets.canonical(total)


def abstract_lagrangian(system):
    """L = 1/2 qd^T M qd + nu/2 + qd^T (QJ)^T Psi - U (KineticEnergy, Lagrangian) with generic M, U, QJ."""
    qd = system.q_dot
    m, qj = system.mass_matrix, system.body_jacobian
    kinetic = sum(qd[k] * m[k, j] * qd[j] for k in range(system.n) for j in range(system.n)) / 2
    lumped = sum(qd[k] * qj[r, k] * system.psi[r] for r in range(system.rows) for k in range(system.n))
    return kinetic + system.nu / 2 + lumped - system.potential
