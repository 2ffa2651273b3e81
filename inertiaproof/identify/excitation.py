"""What the data excite: the regressor's numerically null directions and an identifiable (base) parameter set.

The columns of A are scaled to unit length (A_s = A D^-1) so that the SVD's
singular values compare parameters of different units. Directions with sigma_i <= :data:`NULL_TOL` sigma_max
are numerically null: no torque of these data changes along them. The null space is written in reduced echelon
form (QR with column pivoting of its basis picks one leading parameter per direction, whose coefficient is 1 and
which no other direction contains), so each direction reads "raising P by 1 with ... changes no torque".
The base parameters are the leading columns of a QR with column pivoting of A_s (as many as the numerical
rank); each dependent column is a combination of them, so beta = theta_P + K theta_D with A theta = A_P beta.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

__all__ = ["NULL_TOL", "WEAK_TOL", "Excitation", "excitation"]

ZERO_COLUMN = 1e-10  # a column shorter than this times the longest is round-off: zero (a scale of its own would
# blow the round-off up to a unit column)
NULL_TOL = 1e-8  # sigma_i / sigma_max at or below which a direction is numerically null
WEAK_TOL = 1e-4  # ... below which (above NULL_TOL) it is weakly excited
SHOWN = 4  # entries of a direction printed


@dataclass(frozen=True)
class Excitation:
    scale: np.ndarray  # D (p,): column norms
    singular_values: np.ndarray  # of A_s, descending
    rank: int
    null: np.ndarray  # (p, k) echelon basis of the null space, original units: A null = 0 numerically
    leading: np.ndarray  # (k,) the leading parameter of each null direction
    base: np.ndarray  # (r,) indices of the base parameters (independent columns)
    dependent: np.ndarray  # (p - r,)
    combination: np.ndarray  # K (r, p - r): beta = theta[base] + K theta[dependent]
    names: tuple
    zero: np.ndarray = None  # (p,) bool: columns taken as zero

    def scaled(self, a):
        """A_s = A D^-1, the zero columns set to 0."""
        out = np.asarray(a, dtype=float) / self.scale
        if self.zero is not None:
            out[:, self.zero] = 0.0
        return out

    @property
    def condition(self):
        s = self.singular_values[:self.rank]
        return float(s[0] / s[-1]) if len(s) else float("inf")

    def identifiable(self):
        """(p,) bool: the parameter itself is determined by the data (orthogonal to every null direction)."""
        if self.null.shape[1] == 0:
            return np.ones(len(self.names), dtype=bool)
        scaled = self.null * self.scale[:, None]
        basis, _ = np.linalg.qr(scaled)
        return np.linalg.norm(basis, axis=1) < 1e-6

    def base_values(self, theta):
        theta = np.asarray(theta, dtype=float)
        return theta[self.base] + self.combination @ theta[self.dependent]

    def base_names(self):
        """One readable name per base parameter: 'P' or 'P + 0.5 Q - ...' (largest terms first)."""
        out = []
        for j, col in enumerate(self.base):
            terms = [(c, self.names[d]) for c, d in zip(self.combination[j], self.dependent)
                     if abs(c) > 1e-9 * max(1.0, np.abs(self.combination[j]).max())]
            terms.sort(key=lambda x: -abs(x[0]))
            text = self.names[col] + "".join(f" {'-' if c < 0 else '+'} {_coef(abs(c))}{n}" for c, n in terms[:SHOWN])
            out.append(text + (f" + {len(terms) - SHOWN} more" if len(terms) > SHOWN else ""))
        return out

    def null_directions(self):
        """The null directions in words, one a line."""
        out = []
        for k, lead in enumerate(self.leading):
            v = self.null[:, k]
            others = [(v[j], self.names[j]) for j in np.argsort(-np.abs(v * self.scale)) if j != lead and
                      abs(v[j] * self.scale[j]) > 1e-9 * abs(v[lead] * self.scale[lead])]
            name = self.names[lead]
            if not others:
                out.append(f"{name} does not enter the torques")
                continue
            shown = ", ".join(f"{n} by {c:+.4g}" for c, n in others[:SHOWN])
            more = f" and {len(others) - SHOWN} more" if len(others) > SHOWN else ""
            out.append(f"{name} only together with others: raising it by 1 with {shown}{more} changes no torque")
        return out

    def weak(self):
        """(sigma_i / sigma_max, top parameters) of weakly excited directions."""
        return [float(x) for x in self.singular_values[:self.rank] / self.singular_values[0] if x < WEAK_TOL]


def _coef(c):
    return "" if abs(c - 1) < 1e-12 else f"{c:.4g} "


def column_scale(a):
    """(D, zero): the column norms of ``a`` (1 for a zero column) and which columns are taken as zero."""
    norms = np.linalg.norm(a, axis=0)
    zero = norms <= ZERO_COLUMN * (norms.max() if norms.size else 0.0)
    return np.where(zero, 1.0, norms), zero


def scaled_factor(a):
    """(D, zero, A_s, R) with A_s = Q R its reduced QR: every question below is asked of R (p x p; the same singular
    values, right singular vectors and column pivots as A_s, whose columns R's preserve in length and angle)."""
    a = np.asarray(a, dtype=float)
    scale, zero = column_scale(a)
    scaled = a / scale
    scaled[:, zero] = 0.0
    return scale, zero, scaled, np.linalg.qr(scaled, mode="r")


def excitation(a, names, factor=None):
    """The :class:`Excitation` of rows ``a`` (m, p) whose columns are named ``names`` (``factor``: its
    :func:`scaled_factor`, when computed already)."""
    scale, zero, _, r = scaled_factor(a) if factor is None else factor
    _, s, vt = np.linalg.svd(r, full_matrices=False)
    if len(s) < r.shape[1]:
        s = np.concatenate([s, np.zeros(r.shape[1] - len(s))])
        vt = np.linalg.svd(np.vstack([r, np.zeros((r.shape[1] - r.shape[0], r.shape[1]))]))[2]
    top = s[0] if len(s) and s[0] > 0 else 1.0
    rank = int(np.sum(s > NULL_TOL * top))
    null_s = vt[rank:].T  # (p, k) in scaled coordinates
    k = null_s.shape[1]
    if k:
        _, _, piv = scipy.linalg.qr(null_s.T, pivoting=True, mode="economic")
        leading = np.sort(piv[:k])
        echelon = null_s @ np.linalg.solve(null_s[leading], np.eye(k))  # rows `leading` are the identity
        null = echelon / scale[:, None]
        null = null / null[leading, np.arange(k)]
    else:
        leading, null = np.zeros(0, dtype=int), np.zeros((r.shape[1], 0))
    _, _, piv = scipy.linalg.qr(r, mode="economic", pivoting=True)
    base, dependent = np.sort(piv[:rank]), np.sort(piv[rank:])
    if len(dependent):
        k_s = np.linalg.lstsq(r[:, base], r[:, dependent], rcond=None)[0]
        combination = k_s * scale[dependent][None, :] / scale[base][:, None]
    else:
        combination = np.zeros((rank, 0))
    return Excitation(scale, s, rank, null, leading, base, dependent, combination, tuple(names), zero)
