"""The identification's linear equations: one row per sample and joint (Property 2, RoboticRegressor).

tau_k(t_s) = sum_l R_l(q, qd, qd, qdd)[k] . Phi_l + b_k qd_k + c_k sign(qd_k), with R_l from
:func:`inertiaproof.dynamics.regressors.regressor` on the chain's QJ and dQJ/dq
(:func:`inertiaproof.dynamics.motion.kinematics`), batched over samples in chunks of :data:`CHUNK`. Row s n + k is
sample s, joint k; column 10 l + h is Phi_l's h-th entry (the paper's order), then per joint the viscous and the
Coulomb coefficient when friction is asked for. For the payload's time-dependent case the mass regressor
R_M,l(q, qd) gives M(q, Thetadot) qd = sum_l R_M,l Phidot_l (RoboticRegressorVel).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.dynamics import motion, regressors

from .problem import NormalEquations

__all__ = ["CHUNK", "LinearRows", "friction_columns", "regressor_blocks", "stacked"]

CHUNK = 1000  # samples per batch of kinematics (dQJ/dq of 1,000 samples of 7 joints: 27 MB)


def regressor_blocks(chain, q, qd, qdd, *, rate=False):
    """R_l (S, N, n, 10) at the samples; with ``rate`` also R_M,l(q, qd) (S, N, n, 10) of the Thetadot term."""
    count = len(q)
    out = np.empty((count, chain.n, chain.n, 10))
    out_rate = np.empty_like(out) if rate else None
    for start in range(0, count, CHUNK):
        part = slice(start, min(start + CHUNK, count))
        kin = motion.kinematics(chain, q[part])
        out[part] = regressors.regressor(kin.qj, kin.dqj, kin.rotations, chain.gravity, qd[part], qd[part], qdd[part])
        if rate:
            out_rate[part] = regressors.mass_regressor(kin.qj, qd[part])
    return out if not rate else (out, out_rate)


def stacked(blocks):
    """Rows (S n, 10 N) of regressor blocks (S, N, n, 10): row s n + k, column 10 l + h."""
    s, bodies, n, _ = blocks.shape
    return np.ascontiguousarray(np.transpose(blocks, (0, 2, 1, 3)).reshape(s * n, bodies * 10))


def friction_columns(qd, joints):
    """(columns (S n, 2 n), names): per joint k the viscous column qd_k and the Coulomb column sign(qd_k), each
    nonzero only on joint k's rows."""
    count, n = qd.shape
    cols = np.zeros((count, n, 2 * n))
    idx = np.arange(n)
    cols[:, idx, 2 * idx] = qd
    cols[:, idx, 2 * idx + 1] = np.sign(qd)
    names = [f"{j}.{kind}" for j in joints for kind in ("viscous", "coulomb")]
    return cols.reshape(count * n, 2 * n), names


@dataclass(frozen=True)
class LinearRows:
    """A b with the names of A's columns: the bodies whose Phi fill 10 columns each, then ``extra``."""

    a: np.ndarray
    b: np.ndarray
    bodies: tuple
    extra: tuple = ()
    joints: int = 1

    def normal_equations(self, source=None):
        return NormalEquations.of_rows(self.a, self.b, self.bodies, self.extra, source)

    def columns(self, keep):
        """The rows restricted to the boolean mask ``keep`` of columns (names kept alike)."""
        keep = np.asarray(keep, dtype=bool)
        names = self.column_names()
        return self.a[:, keep], [n for n, k in zip(names, keep) if k]

    def column_names(self):
        from .problem import PHI_NAMES

        return [f"{b}.{p}" for b in self.bodies for p in PHI_NAMES] + list(self.extra)

    def torques(self, theta):
        """A theta as (S, n)."""
        return (self.a @ np.asarray(theta, dtype=float)).reshape(-1, self.joints)
