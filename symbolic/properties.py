"""Property 1 (skew symmetry) and Property 2 (regressors) of (RoboticEquation), generically.

Property 1: N = Mdot - 2 C - M(q, Thetadot) and H(q, Psi) are skew-symmetric,
with Mdot the total time derivative (through q and Theta).

Property 2: with the mass-matrix regressors M^h = dM/dTheta_h
(MassMatrixRegressors) and the potential regressors U^h = dU/dTheta_h, the
Appendix builds

    R_M(q, a)[k, h]      = sum_j M^h_kj a_j
    R_C(q, qd, v)[k, h]  = sum_ij Gamma^h_ijk qd_i v_j        (Gamma^h: (Cristoffel) of M^h)
    R_G(q)[k, h]         = dU^h/dq_k

so that M a + C v + G = (R_M + R_C + R_G) Theta (RoboticRegressor) and
M(q, Thetadot) v = R_M(q, v) Thetadot (RoboticRegressorVel); the columns of
body l form R_l and R_M,l.
"""

from __future__ import annotations

from dataclasses import dataclass

from inertiaproof.symbolic.robotics_equation import christoffel, coriolis, matvec

__all__ = [
    "build_regressors", "mass_matrix_regressors", "parameter_dependence", "property1_matrix",
    "rate_regressor_residual", "regressor_residual", "Regressors", "skew_defect", "total_derivative",
]


def total_derivative(calc, m):
    """Mdot = dM/dt along q(t) and Theta(t)."""
    return tuple(tuple(calc.d_t(x) for x in row) for row in m)


def property1_matrix(calc, m_dot, c, m_rates):
    """N = Mdot - 2 C - M(q, Thetadot) (Prop1)."""
    return tuple(tuple(a - 2 * b - f for a, b, f in zip(ra, rb, rf)) for ra, rb, rf in zip(m_dot, c, m_rates))


def skew_defect(a):
    """The entries of A + A^T on and above the diagonal: all vanish iff A is skew-symmetric."""
    n = len(a)
    return tuple(a[k][j] + a[j][k] for k in range(n) for j in range(k, n))


@dataclass(frozen=True)
class Regressors:
    """R(q, qd, v, a) = R_M(q, a) + R_C(q, qd, v) + R_G(q) and R_M(q, v), each n x len(Theta)."""

    R: tuple
    R_M_velocity: tuple  # R_M(q, v) of (RoboticRegressorVel)

    def body(self, matrix, l, width=10):
        """The n x 10 block of body l (1-based): R_l or R_M,l."""
        return tuple(row[width * (l - 1): width * l] for row in matrix)


def mass_matrix_regressors(calc, m):
    """M^h = dM/dTheta_h (MassMatrixRegressors) for every h."""
    return [tuple(tuple(calc.d_theta(x, h) for x in row) for row in m) for h in range(len(calc.theta))]


def build_regressors(calc, m, potential, v, a, swap_christoffel=False):
    """The Appendix's regressors from M and U; ``swap_christoffel`` builds a known-wrong R_C (Gamma_kji) for controls."""
    n = calc.n
    columns_r, columns_rm = [], []
    for h, mh in enumerate(mass_matrix_regressors(calc, m)):
        gamma = christoffel(calc, mh)
        if swap_christoffel:
            gamma = tuple(tuple(tuple(gamma[k][j][i] for k in range(n)) for j in range(n)) for i in range(n))
        uh = calc.d_theta(potential, h)
        rm_a = matvec(calc, mh, a)
        rc = matvec(calc, coriolis(calc, gamma), v)
        rg = tuple(calc.d_q(uh, k) for k in range(1, n + 1))
        columns_r.append(tuple(calc.canonical(x + y + z) for x, y, z in zip(rm_a, rc, rg)))
        columns_rm.append(tuple(calc.canonical(x) for x in matvec(calc, mh, v)))
    return Regressors(R=tuple(zip(*columns_r)), R_M_velocity=tuple(zip(*columns_rm)))


def regressor_residual(calc, eq, regressors, v, a):
    """M a + C v + G - R Theta (RoboticRegressor), entry by entry."""
    rhs = matvec(calc, regressors.R, calc.theta)
    return tuple(x + y + g - r for x, y, g, r in zip(matvec(calc, eq.M, a), matvec(calc, eq.C, v), eq.G, rhs))


def rate_regressor_residual(calc, eq, regressors, v, rates=None):
    """M(q, Thetadot) v - R_M(q, v) Thetadot (RoboticRegressorVel)."""
    lhs = matvec(calc, eq.M_rates, v)
    rhs = matvec(calc, regressors.R_M_velocity, rates or calc.theta_dot)
    return tuple(x - y for x, y in zip(lhs, rhs))


def parameter_dependence(calc, regressors):
    """Entries of R and R_M that depend on Theta or Thetadot: must be none ('free of inertial parameters')."""
    found = []
    for name, matrix in (("R", regressors.R), ("R_M", regressors.R_M_velocity)):
        for k, row in enumerate(matrix):
            for h, x in enumerate(row):
                roles = calc.free_roles(x) & {"theta", "theta_dot"}
                if roles:
                    found.append((name, k, h, sorted(roles)))
    return found
