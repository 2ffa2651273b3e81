"""The linear solve of forward dynamics, qdd = M(q, Theta)^-1 (tau - bias), in the scaling that decides its digits.

A chain whose links span kilometres and millimetres has cond(M) near 1e20 from its units alone. Scaled to a unit
diagonal, S M S with S = diag(M)^-1/2, its condition is what the solve's error goes with (van der Sluis: for a
positive definite M the Jacobi scaling is within a factor n of the best diagonal one), so that is the number a study
compares with its limit. The scaling is by powers of two, which round nothing.
"""

from __future__ import annotations

import numpy as np

__all__ = ["jacobi_scaling", "scaled_condition", "solve_mass"]


def jacobi_scaling(mass):
    """Powers of two s (..., n) with diag(s M s) in [1, 4); 1 where a diagonal entry is not positive and finite."""
    d = np.diagonal(mass, axis1=-2, axis2=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.exp2(-np.floor(np.log2(d) / 2))
    return np.where((d > 0) & np.isfinite(s), s, 1.0)


def _scaled(mass):
    """(s, s M s) with s = :func:`jacobi_scaling` (M)."""
    s = jacobi_scaling(mass)
    return s, mass * s[..., :, None] * s[..., None, :]


def scaled_condition(mass):
    """cond(s M s) (2-norm, via SVD), batched: about how many digits a :func:`solve_mass` answer loses."""
    return np.linalg.cond(_scaled(mass)[1])


def solve_mass(mass, rhs):
    """x with M x = rhs (both batched over leading axes; rhs (..., n)), solved as (s M s) y = s rhs, x = s y."""
    s, scaled = _scaled(mass)
    return s * np.linalg.solve(scaled, (s * rhs)[..., None])[..., 0]
