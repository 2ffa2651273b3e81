"""The identification problem in normal-equation form: the data enter only through H, g, c.

For stacked regressor rows A (one row per sample and joint, Property 2: tau = sum_l R_l Phi_l, plus friction
columns) and measured torques b, the squared torque residual of parameters theta is

    r(theta) = |A theta - b|^2 = theta^T H theta - 2 g^T theta + c,   H = A^T A, g = A^T b, c = b^T b.

theta stacks the bodies' Phi_l (ten each, the paper's order m, h1, h2, h3, I11, I22, I33, I12, I23, I13; about
the body frame's origin, h = m c) and then the optional friction parameters (per joint: viscous, Coulomb).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["NormalEquations", "PHI_NAMES"]

PHI_NAMES = ("m", "h1", "h2", "h3", "I11", "I22", "I33", "I12", "I23", "I13")


@dataclass(frozen=True)
class NormalEquations:
    """H (p x p), g (p), c and what the columns are: `bodies` names the bodies whose Phi fill columns
    10 l .. 10 l + 9 in order; the remaining columns are named in `extra` (friction); `rows` is the number of
    scalar equations (samples times joints) behind the sums, `source` what they were formed from."""

    H: np.ndarray
    g: np.ndarray
    c: float
    bodies: tuple[str, ...]
    extra: tuple[str, ...] = ()
    rows: int = 0
    source: dict | None = None

    @property
    def size(self) -> int:
        return 10 * len(self.bodies) + len(self.extra)

    def residual(self, theta) -> float:
        """r(theta) in float64 (not a certified value)."""
        theta = np.asarray(theta, dtype=float)
        return float(theta @ self.H @ theta - 2.0 * self.g @ theta + self.c)

    def body_slice(self, l: int) -> slice:
        return slice(10 * l, 10 * l + 10)

    def column_names(self) -> list[str]:
        return [f"{b}.{p}" for b in self.bodies for p in PHI_NAMES] + list(self.extra)

    @classmethod
    def of_rows(cls, a, b, bodies, extra=(), source=None) -> "NormalEquations":
        a = np.asarray(a, dtype=float)
        b = np.asarray(b, dtype=float)
        return cls(a.T @ a, a.T @ b, float(b @ b), tuple(bodies), tuple(extra), int(a.shape[0]), source)
