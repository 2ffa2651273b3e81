"""Floating-point cross-checks of the symbolic chain against the numeric model (an extra, not a proof).

At a rational point the symbolic QJ and the symbolic left side of
(RoboticEquation) are evaluated exactly and compared with
:meth:`Chain.body_jacobian` and :func:`inertiaproof.dynamics.generalized_forces`
(the numeric model verified against Pinocchio) at the same point in floats.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from inertiaproof.symbolic.jets import COORDINATE_POLYNOMIALS
from inertiaproof.symbolic.robotics_equation import left_side

from inertiaproof.dynamics import terms
from inertiaproof.dynamics.chain import COORDINATE_MAPS

__all__ = ["body_jacobian_error", "coordinate_polynomial_errors", "generalized_forces_error", "numeric_motion"]

COORDINATE_POINTS = (Fraction(-3, 2), Fraction(-1, 3), Fraction(0), Fraction(2, 7), Fraction(5, 4))


def _trimmed(coefficients):
    out = list(coefficients)
    while out and out[-1] == 0:
        out.pop()
    return tuple(out)


def coordinate_polynomial_errors():
    """{map: (g' is exactly the derivative of g, max relative |g(q) - chain's g(q)| at a few rationals)} for the
    symbolic twins of the coordinate maps (the chain rule factor d/dq_k of the jet calculus is g')."""
    out = {}
    for name, (value, derivative) in COORDINATE_POLYNOMIALS.items():
        same = _trimmed(derivative) == _trimmed(tuple(k * c for k, c in enumerate(value))[1:])
        numeric = COORDINATE_MAPS[name][0]
        error = max(abs(float(sum(c * x**k for k, c in enumerate(value))) - numeric(float(x)))
                    / max(1.0, abs(numeric(float(x)))) for x in COORDINATE_POINTS)
        out[name] = (same, error)
    return out


def numeric_motion(jets, point):
    """The floats of a point: theta (N, 10), theta_dot, psi (6N), psi_dot, qd, qdd."""
    get = lambda role, *i: float(point.get((role, tuple(i)), 0))  # noqa: E731
    n, bodies = jets.n, jets.bodies
    return {
        "qd": np.array([get("qd", k) for k in range(1, n + 1)]),
        "qdd": np.array([get("qdd", k) for k in range(1, n + 1)]),
        "theta": np.array([[get("theta", l, i) for i in range(10)] for l in range(1, bodies + 1)]),
        "theta_dot": np.array([[get("theta_dot", l, i) for i in range(10)] for l in range(1, bodies + 1)]),
        "psi": np.array([get("psi", l, i) for l in range(1, bodies + 1) for i in range(6)]),
        "psi_dot": np.array([get("psi_dot", l, i) for l in range(1, bodies + 1) for i in range(6)]),
    }


def body_jacobian_error(d, point):
    """max |QJ_symbolic - Chain.body_jacobian| at the point."""
    twin, jets = d.system.twin, d.calc
    exact = np.array([[float(jets.evaluate(x, point)) for x in row] for row in d.system.body_jacobian])
    return float(np.max(np.abs(exact - twin.chain.body_jacobian(twin.numeric_point(point)))))


def generalized_forces_error(d, point):
    """(max relative error, symbolic values, numeric values) of tau + w from (RoboticEquation) at the point."""
    twin, jets = d.system.twin, d.calc
    chain = twin.chain
    q = twin.numeric_point(point)
    motion = numeric_motion(jets, point)
    rotations, _ = chain.forward_kinematics(q)
    numeric = terms.generalized_forces(chain.body_jacobian(q), chain.body_jacobian_derivative(q), rotations,
                                          np.array(chain.gravity), motion["qdd"], motion["qd"], motion["theta"],
                                          motion["theta_dot"], motion["psi"], motion["psi_dot"])
    symbolic = np.array([float(jets.evaluate(x, point)) for x in left_side(jets, d.equation)])
    scale = max(1.0, float(np.max(np.abs(numeric))))
    return float(np.max(np.abs(symbolic - numeric)) / scale), symbolic, numeric
