"""What must vanish for each claim, and the known-wrong variants each claim's check must reject.

A claim maps a :class:`~inertiaproof.symbolic.derivations.Derivation` to the
entries that vanish iff the claim holds. A negative control is a deliberately
wrong variant (a dropped term, a transposed matrix, swapped Christoffel
indices, ...); the check must find its entries nonzero wherever the variant
differs from the correct term.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from inertiaproof.symbolic.properties import (
    Regressors,
    build_regressors,
    parameter_dependence,
    property1_matrix,
    rate_regressor_residual,
    regressor_residual,
    skew_defect,
)
from inertiaproof.symbolic.robotics_equation import RoboticEquation, coriolis, left_side, lumped_force, transpose

__all__ = [
    "Claim", "CLAIMS", "entries", "GRE_CONTROLS", "GRE_F_CONTROLS", "gre_f_residual", "gre_residual", "originals",
    "PARTICLE_CONTROLS", "PARTICLE_GRE", "particle_gre_residual", "PROP1_CONTROLS", "prop1_residual",
    "PROP2_CONTROLS", "prop2_residual", "RegressorTest", "swapped_coriolis", "zeros_like",
]


def zeros_like(calc, m):
    return tuple(tuple(calc.zero for _ in row) for row in m)


def swapped_coriolis(d):
    """C built from Gamma_kji instead of Gamma_ijk (Cristoffel with first and last index swapped)."""
    n = d.calc.n
    g = d.gamma
    return coriolis(d.calc, tuple(tuple(tuple(g[k][j][i] for k in range(n)) for j in range(n)) for i in range(n)))


# -- GRE: (LagrangeFormalism) = (RoboticEquation) ------------------------------------

def gre_residual(d, eq: RoboticEquation | None = None):
    """Euler-Lagrange left side minus M qdd + (C + M(q, Thetadot) + H) qd + G + J^T Q^T Psidot."""
    eq = eq or d.equation
    return tuple(a - b for a, b in zip(d.euler_lagrange, left_side(d.calc, eq)))


GRE_CONTROLS = {
    "drop M(q, Thetadot)": lambda d: {"eq": d.equation.with_terms(M_rates=zeros_like(d.calc, d.equation.M))},
    "transpose H": lambda d: {"eq": d.equation.with_terms(H=transpose(d.equation.H))},
    "swap Christoffel indices (Gamma_kji)": lambda d: {"eq": d.equation.with_terms(C=swapped_coriolis(d))},
    "drop J^T Q^T Psidot": lambda d: {"eq": d.equation.with_terms(psi_force=tuple(d.calc.zero
                                                                                   for _ in d.equation.G))},
}


# -- GRE-F: F (DefF) = M(q, Thetadot) -------------------------------------------------

def gre_f_residual(d, f=None, m_rates=None):
    f = f if f is not None else d.F
    m_rates = m_rates if m_rates is not None else d.equation.M_rates
    return tuple(a - b for ra, rb in zip(f, m_rates) for a, b in zip(ra, rb))


def _quadratic_mass_matrix_f(d):
    """DefF of M + Theta_1^2 E_11 (a mass matrix that is not linear in Theta) against its own M(q, Thetadot)."""
    from inertiaproof.symbolic.robotics_equation import mass_matrix_at_rates, parameter_rate_matrix

    calc = d.calc
    th = calc.theta[0]
    bent = tuple(tuple(x + (th * th if (k, j) == (0, 0) else calc.zero) for j, x in enumerate(row))
                 for k, row in enumerate(d.equation.M))
    return {"f": parameter_rate_matrix(calc, bent), "m_rates": mass_matrix_at_rates(calc, bent)}


GRE_F_CONTROLS = {
    "M(q, Theta) in place of M(q, Thetadot)": lambda d: {"m_rates": d.equation.M},
    "F with a factor 1/2": lambda d: {"f": tuple(tuple(x / 2 for x in row) for row in d.F)},
    "M not linear in Theta (+ Theta_1^2 in M_11)": _quadratic_mass_matrix_f,
}


# -- Prop1: Mdot - 2C - M(q, Thetadot) and H skew ------------------------------------------

def prop1_residual(d, n_matrix=None, h=None):
    n_matrix = n_matrix if n_matrix is not None else d.N
    h = h if h is not None else d.equation.H
    return skew_defect(n_matrix) + skew_defect(h)


def _mdot_without_rates(d):
    calc, eq = d.calc, d.equation
    partial = tuple(tuple(a - f for a, f in zip(ra, rf)) for ra, rf in zip(d.M_dot, d.F))
    return {"n_matrix": property1_matrix(calc, partial, eq.C, eq.M_rates)}


PROP1_CONTROLS = {
    "drop M(q, Thetadot)": lambda d: {"n_matrix": property1_matrix(d.calc, d.M_dot, d.equation.C,
                                                                    zeros_like(d.calc, d.equation.M))},
    "Mdot without its Thetadot part": _mdot_without_rates,
    "swap Christoffel indices (Gamma_kji)": lambda d: {"n_matrix": property1_matrix(
        d.calc, d.M_dot, swapped_coriolis(d), d.equation.M_rates)},
    "H = A + A^T instead of A - A^T (DefH)": lambda d: {"h": _symmetrised_lumped(d)},
}


def _symmetrised_lumped(d):
    """A + A^T with A = d(J^T Q^T Psi)/dq: the sign error in (DefH)."""
    calc = d.calc
    p = lumped_force(calc, d.system.body_jacobian, calc.psi)
    a = [[calc.d_q(p[k], j + 1) for j in range(calc.n)] for k in range(calc.n)]
    return tuple(tuple(a[k][j] + a[j][k] for j in range(calc.n)) for k in range(calc.n))


# -- Prop2: regressors ----------------------------------------------------------------------

@dataclass(frozen=True)
class RegressorTest:
    residual: tuple  # (RoboticRegressor) then (RoboticRegressorVel) entries
    impure: list  # entries of the regressors that depend on Theta or Thetadot


def prop2_residual(d, regressors: Regressors | None = None, rates=None):
    calc, s = d.calc, d.system
    regressors = regressors or d.regressors

    residual = regressor_residual(calc, d.equation, regressors, s.v, s.a) \
        + rate_regressor_residual(calc, d.equation, regressors, s.v, rates)
    return RegressorTest(residual, parameter_dependence(calc, regressors))


def _impure_regressor(d):
    """R with Theta_2 added to column 1 and Theta_1 subtracted from column 2: R Theta is unchanged, R is not free of Theta."""
    calc = d.calc
    t1, t2 = calc.theta[0], calc.theta[1]
    rows = []
    for row in d.regressors.R:
        row = list(row)
        row[0] = row[0] + t2 * d.system.a[0]
        row[1] = row[1] - t1 * d.system.a[0]
        rows.append(tuple(row))
    return {"regressors": Regressors(tuple(rows), d.regressors.R_M_velocity)}


def _shifted_rates(d):
    """R_M,l paired with the rates of the next body (parameter block shifted by one block, cyclically)."""
    rates = d.calc.theta_dot
    b = d.system.block if len(rates) > d.system.block else 1
    return {"rates": rates[b:] + rates[:b]}


PROP2_CONTROLS = {
    "swap Christoffel indices in R_C (Gamma_kji)": lambda d: {"regressors": build_regressors(
        d.calc, d.system.mass_matrix, d.system.potential, d.system.v, d.system.a, swap_christoffel=True)},
    "regressor depending on Theta (identity kept)": _impure_regressor,
    "R_M,l paired with Phidot of another body": _shifted_rates,
}


def originals(d):
    """The correct objects the controls' keyword arguments replace."""
    return {"eq": d.equation, "f": d.F, "m_rates": d.equation.M_rates, "n_matrix": d.N, "h": d.equation.H,
            "regressors": d.regressors, "rates": d.calc.theta_dot}


# -- GRE from particles (inertiaproof.symbolic.particles) -----------------------------------

def particle_gre_residual(p, euler_lagrange=None, paper=None):
    """What vanishes iff GRE describes the particles: (LagrangeFormalism) of the particles minus the paper's form at
    their moments; the same minus Newton-Meshchersky with added mass at rest; and, on pure loading, the difference
    to mass arriving with its body's velocity minus M(q, Thetadot) qd."""
    el = p.euler_lagrange if euler_lagrange is None else euler_lagrange
    paper = p.paper if paper is None else paper
    return (tuple(a - b for a, b in zip(el, paper)) + tuple(a - b for a, b in zip(el, p.newton_at_rest))
            + tuple(a - b for a, b in zip(p.loading_difference, p.loading_term)))


def _paper_control(name):
    return lambda p: {"paper": p.paper_form(GRE_CONTROLS[name](p.chain_derivation)["eq"])}


PARTICLE_CONTROLS = {
    **{f"paper's form: {name}": _paper_control(name) for name in GRE_CONTROLS},
    "added mass arriving with its body's velocity (the at-rest assumption dropped)":
        lambda p: {"euler_lagrange": p.newton_with_the_body},
}


@dataclass(frozen=True)
class Claim:
    id: str
    statement: str
    residual: Callable
    controls: dict
    subject: Callable  # the derived objects the claim is about (their size goes into the evidence)
    originals: Callable = originals  # the correct objects the controls replace
    kind: str = "symbolic-claim"  # the counterexample kind its replayer reads


PARTICLE_GRE = Claim("GRE", "Lagrange's equations of mass-carrying particles equal (RoboticEquation) at their Theta, "
                            "Thetadot, Psi, Psidot", particle_gre_residual, PARTICLE_CONTROLS,
                     lambda p: p.euler_lagrange,
                     originals=lambda p: {"paper": p.paper, "euler_lagrange": p.euler_lagrange},
                     kind="particle-claim")


CLAIMS = {
    "GRE": Claim("GRE", "Lagrange's equations (LagrangeFormalism) equal (RoboticEquation)", gre_residual,
                 GRE_CONTROLS, lambda d: d.euler_lagrange),
    "GRE-F": Claim("GRE-F", "F(q, Theta, Thetadot) of (DefF) equals M(q, Thetadot)", gre_f_residual, GRE_F_CONTROLS,
                   lambda d: d.F),
    "Prop1": Claim("Prop1", "Mdot - 2C - M(q, Thetadot) and H(q, Psi) are skew-symmetric", prop1_residual,
                   PROP1_CONTROLS, lambda d: d.N),
    "Prop2": Claim("Prop2", "M a + C v + G = sum_l R_l Phi_l and M(q, Thetadot) v = sum_l R_M,l Phidot_l with "
                            "regressors free of inertial parameters", prop2_residual, PROP2_CONTROLS,
                   lambda d: d.regressors),
}


def entries(residual):
    """(entries that must vanish, impure regressor entries)."""
    if isinstance(residual, RegressorTest):
        return residual.residual, residual.impure
    return tuple(residual), []
