"""Random inertial parameters Phi (paper order), from near-degenerate to ordinary.

``consistent_phi`` draws physically consistent bodies by their physics:
mass, centre of mass, and a density-weighted covariance Sigma_CoM = R diag(m a^2) R^T
with principal radii a spanning ``thinness`` decades (thin rods and flat
plates near the boundary of Theorem 1). ``pseudo_inertia_pd`` draws f > 0
directly, including nearly singular ones; ``any_phi`` draws arbitrary
10-vectors for checkers that must also see inconsistent input.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st

from inertiaproof.model.solids import phi_from_covariance

__all__ = ["any_phi", "consistent_phi", "log_uniform", "pseudo_inertia_pd", "rotations"]


def log_uniform(lo, hi):
    """Floats spread evenly over decades between lo > 0 and hi."""
    return st.floats(np.log10(lo), np.log10(hi), allow_nan=False).map(lambda e: float(10.0**e))


@st.composite
def rotations(draw):
    """A rotation matrix from a normalised quaternion."""
    q = np.array([draw(st.floats(-1, 1, allow_nan=False)) for _ in range(4)])
    n = np.linalg.norm(q)
    if n < 1e-3:
        return np.eye(3)
    w, x, y, z = q / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


@st.composite
def consistent_phi(draw, mass=(1e-3, 1e3), size=(1e-3, 10.0), thinness=6):
    """Phi with f(Phi) > 0: principal radii down to 10^-thinness of the body's size."""
    m = draw(log_uniform(*mass))
    scale = draw(log_uniform(*size))
    radii = scale * np.array([draw(log_uniform(10.0**-thinness, 1.0)) for _ in range(3)])
    rot = draw(rotations())
    com = scale * np.array([draw(st.floats(-3, 3, allow_nan=False)) for _ in range(3)])
    sigma_c = rot @ np.diag(m * radii**2) @ rot.T
    return phi_from_covariance(m, sigma_c, com)


@st.composite
def pseudo_inertia_pd(draw, min_eigenvalue=(1e-12, 1.0)):
    """f > 0 as Q diag(lambda) Q^T with the smallest eigenvalue down to ``min_eigenvalue[0]`` relative."""
    q, _ = np.linalg.qr(np.array([[draw(st.floats(-1, 1, allow_nan=False)) for _ in range(4)] for _ in range(4)])
                        + 1e-3 * np.eye(4))
    lam = np.array([draw(log_uniform(*min_eigenvalue))] + [draw(log_uniform(1e-2, 1.0)) for _ in range(3)])
    scale = draw(log_uniform(1e-3, 1e3))
    return scale * (q @ np.diag(lam) @ q.T)


any_phi = st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=10, max_size=10).map(np.array)
