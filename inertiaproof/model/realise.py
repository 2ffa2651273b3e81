"""A nonnegative density with given inertial parameters (Theorem 1, necessity; Thm1-nec).

For f(Phi) > 0 the mass is m > 0 and Sigma_CoM = Q diag(sigma) Q^T > 0
(fPosDef_IFF_PosMassPosDefSigmaCoM). A uniform solid of mass m centred at
c = h / m and turned by Q has Sigma_CoM = Q diag(m k_i^2 / d) Q^T in terms
of its dimensions k_i, so the dimensions follow from sigma:

- the solid ellipsoid (d = 5) with semi-axes a_i = sqrt(5 sigma_i / m);
- the box (d = 12) with sides l_i = sqrt(12 sigma_i / m)
  = sqrt(6 (J_j + J_k - J_i) / m), J the principal moments of I_CoM: real
  exactly when the triangle inequalities hold.

Both are nonnegative Lebesgue densities with a 3-D carrier. Without f > 0
the construction fails and says why.
"""

from __future__ import annotations

import numpy as np

from .inertia import center_of_mass, sigma_com, unpack

__all__ = ["FACTOR", "quaternion", "realising_solid"]

FACTOR = {"ellipsoid": 5.0, "box": 12.0}


def quaternion(rotation):
    """(w, x, y, z) of a rotation matrix (Shepperd's method: the largest of the four squares first)."""
    r = np.asarray(rotation, dtype=float)
    t = np.trace(r)
    squares = np.array([1 + t, 1 + 2 * r[0, 0] - t, 1 + 2 * r[1, 1] - t, 1 + 2 * r[2, 2] - t])
    k = int(np.argmax(squares))
    s = 2.0 * np.sqrt(squares[k])
    if k == 0:
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif k == 1:
        q = [(r[2, 1] - r[1, 2]) / s, s / 4, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif k == 2:
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, s / 4, (r[1, 2] + r[2, 1]) / s]
    else:
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, s / 4]
    return np.array(q)


def realising_solid(phi, shape="ellipsoid"):
    """(density spec, None) of a uniform ``shape`` with inertial parameters phi, or (None, why not)."""
    m, _, _ = unpack(phi)
    if not m > 0:
        return None, f"mass m = {m:.6g} <= 0: no nonnegative density has it"
    sigma, axes = np.linalg.eigh(sigma_com(phi))
    if not sigma[0] > 0:
        return None, (f"Sigma_CoM has eigenvalue {sigma[0]:.6g} <= 0: a triangle inequality of I_CoM fails "
                      "or holds with equality, so no solid has these moments")
    if np.linalg.det(axes) < 0:
        axes[:, 0] = -axes[:, 0]
    dims = np.sqrt(FACTOR[shape] * sigma / m)
    spec = {"components": [{"type": "solid", "shape": shape, "mass": float(m), "dims": dims.tolist(),
                            "quaternion": quaternion(axes).tolist(), "position": center_of_mass(phi).tolist()}]}
    return spec, None
