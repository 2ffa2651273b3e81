"""The paper's form of the generalized robotics equation (RoboticEquation), term by term.

    M(q, Theta) qdd + (C(q, qd, Theta) + M(q, Thetadot) + H(q, Psi)) qd + G(q, Theta)
        = tau + w - J^T Q^T Psidot

Every function is written once against the calculus protocol
(:mod:`~inertiaproof.symbolic.calculus`) and works for the abstract system and
for the chains alike. Matrices are tuples of rows; indices in the docstrings
run from 1 as in the paper.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from inertiaproof.symbolic.lagrangian import spatial_inertia

__all__ = [
    "add", "assemble", "christoffel", "coriolis", "gravity", "left_side", "lumped_force", "lumped_velocity_matrix",
    "mass_matrix", "mass_matrix_at_rates", "mass_matrix_partials", "matvec", "parameter_rate_matrix",
    "RoboticEquation", "symmetric", "transpose",
]


def mass_matrix(calc, body_jacobian, parameter_blocks):
    """M = (QJ)^T blockdiag(Z(Phi_1), ..., Z(Phi_N)) QJ (MassMatrix, DefBlockmatrixZ)."""
    n = calc.n
    out = [[calc.zero] * n for _ in range(n)]
    for l, phi in enumerate(parameter_blocks):
        z = spatial_inertia(phi)
        block = body_jacobian[6 * l: 6 * l + 6]
        zb = [[sum((z[a][b] * block[b][j] for b in range(6)), calc.zero) for j in range(n)] for a in range(6)]
        for k in range(n):
            for j in range(k, n):
                out[k][j] += sum((block[a][k] * zb[a][j] for a in range(6)), calc.zero)
    return symmetric([[calc.canonical(out[min(k, j)][max(k, j)]) for j in range(n)] for k in range(n)])


def symmetric(rows):
    return tuple(tuple(row) for row in rows)


def mass_matrix_partials(calc, m):
    """dM[i][k][j] = d M_kj / d q_i (0-based), computed once per entry of the upper triangle."""
    n = calc.n
    out = []
    for i in range(1, n + 1):
        upper = {(k, j): calc.d_q(m[k][j], i) for k in range(n) for j in range(k, n)}
        out.append(tuple(tuple(upper[min(k, j), max(k, j)] for j in range(n)) for k in range(n)))
    return tuple(out)


def christoffel(calc, m, partials=None):
    """Gamma[i][j][k] = 1/2 (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) (Cristoffel), 0-based."""
    d = partials or mass_matrix_partials(calc, m)
    n = calc.n
    return tuple(tuple(tuple((d[i][k][j] + d[j][k][i] - d[k][i][j]) / 2 for k in range(n)) for j in range(n))
                 for i in range(n))


def coriolis(calc, gamma, velocity=None):
    """C[k][j] = sum_i Gamma[i][j][k] qd_i (DefCoriolis)."""
    qd = velocity or calc.q_dot
    n = calc.n
    return tuple(tuple(sum((gamma[i][j][k] * qd[i] for i in range(n)), calc.zero) for j in range(n)) for k in range(n))


def mass_matrix_at_rates(calc, m):
    """M(q, Thetadot): the mass matrix, a linear function of Theta, evaluated at Thetadot."""
    return tuple(tuple(calc.at_rates(x) for x in row) for row in m)


def parameter_rate_matrix(calc, m):
    """F[k][j] = sum_h dM_kj/dTheta_h Thetadot_h (DefF)."""
    return tuple(tuple(sum((calc.d_theta(x, h) * rate for h, rate in enumerate(calc.theta_dot)), calc.zero)
                       for x in row) for row in m)


def gravity(calc, potential):
    """G = (dU/dq)^T (DefGravitation)."""
    return tuple(calc.d_q(potential, k) for k in range(1, calc.n + 1))


def lumped_force(calc, body_jacobian, psi):
    """J^T Q^T Psi (KineticEnergy): with Psi the lumped velocity p(q, Psi); with Psidot the force of (RoboticEquation)."""
    return tuple(sum((row[k] * x for row, x in zip(body_jacobian, psi)), calc.zero) for k in range(calc.n))


def lumped_velocity_matrix(calc, lumped):
    """H[k][j] = d p_k / d q_j - d p_j / d q_k with p = J^T Q^T Psi (DefH)."""
    n = calc.n
    a = [[calc.d_q(lumped[k], j + 1) for j in range(n)] for k in range(n)]
    return tuple(tuple(a[k][j] - a[j][k] for j in range(n)) for k in range(n))


def matvec(calc, a, x):
    return tuple(sum((aij * xj for aij, xj in zip(row, x)), calc.zero) for row in a)


def add(*matrices):
    return tuple(tuple(sum(entries[1:], entries[0]) for entries in zip(*rows)) for rows in zip(*matrices))


def transpose(a):
    return tuple(zip(*a))


@dataclass(frozen=True)
class RoboticEquation:
    """The terms of (RoboticEquation) for one system."""

    M: tuple  # M(q, Theta)
    C: tuple  # C(q, qd, Theta) (DefCoriolis)
    M_rates: tuple  # M(q, Thetadot)
    H: tuple  # H(q, Psi) (DefH)
    G: tuple  # G(q, Theta) (DefGravitation)
    psi_force: tuple  # J^T Q^T Psidot

    def with_terms(self, **terms):
        return replace(self, **terms)


def assemble(calc, m, potential, body_jacobian, gamma=None):
    """The paper's terms from M, U and QJ, each by its own definition."""
    gamma = gamma or christoffel(calc, m)
    return RoboticEquation(
        M=m,
        C=coriolis(calc, gamma),
        M_rates=mass_matrix_at_rates(calc, m),
        H=lumped_velocity_matrix(calc, lumped_force(calc, body_jacobian, calc.psi)),
        G=gravity(calc, potential),
        psi_force=lumped_force(calc, body_jacobian, calc.psi_dot),
    )


def left_side(calc, eq):
    """M qdd + (C + M(q, Thetadot) + H) qd + G + J^T Q^T Psidot: by (RoboticEquation) this equals tau + w."""
    inertial = matvec(calc, eq.M, calc.q_ddot)
    velocity = matvec(calc, add(eq.C, eq.M_rates, eq.H), calc.q_dot)
    return tuple(a + b + g + f for a, b, g, f in zip(inertial, velocity, eq.G, eq.psi_force))
