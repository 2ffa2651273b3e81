"""Spectral functions of batched matrices (lambda_min, lambda_max, sigma_min, sigma_max, |lambda|_max) as named
values that know their convexity and which extreme over configurations Section 4 takes of them."""

from __future__ import annotations

from enum import Enum

import numpy as np

__all__ = ["CONVEX", "EPS", "ROUNDING", "Spectral", "spectral"]

EPS = np.finfo(float).eps
ROUNDING = 64.0  # rounding allowance of a computed eigen- or singular value, in units of eps * ||matrix||_F


class Spectral(str, Enum):
    """A spectral function. A str, so ``Spectral.LMIN == "lmin"``. ``convex``: convex in the matrix (lambda_max,
    sigma_max, |lambda|_max) or concave (lambda_min; sigma_min of a Gram form through lambda_min). ``sense``: the
    extreme Section 4 brackets ('max' of a convex kind, 'min' of the others): the certified side of a sup is an
    upper bound, of an inf a lower bound."""

    LMIN = "lmin"
    LMAX = "lmax"
    SMIN = "smin"
    SMAX = "smax"
    ABSMAX = "absmax"

    @property
    def convex(self):
        return self in (Spectral.LMAX, Spectral.SMAX, Spectral.ABSMAX)

    @property
    def sense(self):
        return "max" if self.convex else "min"

    def __call__(self, a):
        """The function of a batch (..., r, s): singular values by SVD, eigenvalues of the symmetric part."""
        if self in (Spectral.SMAX, Spectral.SMIN):
            s = np.linalg.svd(a, compute_uv=False)
            return s[..., 0] if self is Spectral.SMAX else s[..., -1]
        w = np.linalg.eigvalsh(a)
        if self is Spectral.LMAX:
            return w[..., -1]
        if self is Spectral.LMIN:
            return w[..., 0]
        return np.maximum(w[..., -1], -w[..., 0])


def spectral(a, kind):
    """Spectral function ``kind`` (a :class:`Spectral` or its name) of a batch (..., r, s)."""
    return Spectral(kind)(a)


CONVEX = frozenset(k for k in Spectral if k.convex)
