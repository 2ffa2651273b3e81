"""Inertial parameters of one rigid body and their matrix forms.

All functions are pure and batched over leading axes: ``phi`` has shape
``(..., 10)`` in the paper's order (eq:Phi)

    Phi = (m, h1, h2, h3, I11, I22, I33, I12, I23, I13)

with ``h`` the first moment of mass and ``I`` the inertia about the origin of
the body-fixed frame (MassDistributionToInertialParam).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "center_of_mass", "from_urdf", "from_urdf_row", "inertia_com", "inertia_from_sigma", "inertia_matrix", "pack",
    "PHI_FIELDS", "point_mass", "pseudo_inertia", "pseudo_inertia_inverse", "rotation_rpy", "sigma_com",
    "sigma_from_inertia", "skew", "spatial_inertia", "spatial_inertia_inverse", "unit_body", "unpack",
    "URDF_FIELDS", "urdf_inertia",
]

PHI_FIELDS = ("m", "h1", "h2", "h3", "I11", "I22", "I33", "I12", "I23", "I13")
URDF_FIELDS = ("mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "iyz", "ixz")


def skew(x):
    """S(x) with S(x) y = x cross y (paper, Notation). Shape (..., 3) -> (..., 3, 3)."""
    x = np.asarray(x)
    if not np.iscomplexobj(x):
        x = np.asarray(x, dtype=float)
    s = np.zeros(x.shape + (3,), dtype=x.dtype)
    s[..., 0, 1], s[..., 0, 2] = -x[..., 2], x[..., 1]
    s[..., 1, 0], s[..., 1, 2] = x[..., 2], -x[..., 0]
    s[..., 2, 0], s[..., 2, 1] = -x[..., 1], x[..., 0]
    return s


def inertia_matrix(phi):
    """The 3x3 inertia I about the frame origin (eq:I)."""
    phi = np.asarray(phi, dtype=float)
    return phi[..., _INERTIA_INDEX]


_INERTIA_INDEX = np.array([[4, 7, 9], [7, 5, 8], [9, 8, 6]])


def unpack(phi):
    """Split Phi into (m, h, I) with shapes (...), (..., 3), (..., 3, 3)."""
    phi = np.asarray(phi, dtype=float)
    return phi[..., 0], phi[..., 1:4], inertia_matrix(phi)


def pack(m, h, inertia):
    """Inverse of :func:`unpack`; ``inertia`` is symmetrised first."""
    inertia = np.asarray(inertia, dtype=float)
    inertia = 0.5 * (inertia + np.swapaxes(inertia, -1, -2))
    m = np.asarray(m, dtype=float)
    h = np.asarray(h, dtype=float)
    return np.concatenate(
        [
            m[..., None],
            h,
            np.stack(
                [
                    inertia[..., 0, 0],
                    inertia[..., 1, 1],
                    inertia[..., 2, 2],
                    inertia[..., 0, 1],
                    inertia[..., 1, 2],
                    inertia[..., 0, 2],
                ],
                -1,
            ),
        ],
        -1,
    )


def _trace_identity(a):
    """tr(A) I3 for a batch of 3x3 matrices."""
    return np.trace(a, axis1=-2, axis2=-1)[..., None, None] * np.eye(3)


def sigma_from_inertia(inertia):
    """Sigma = tr(I)/2 I3 - I (DefTrafoInertialParameters)."""
    return 0.5 * _trace_identity(inertia) - inertia


def inertia_from_sigma(sigma):
    """I = tr(Sigma) I3 - Sigma, the inverse map of Theorem 1."""
    return _trace_identity(sigma) - sigma


def pseudo_inertia(phi):
    """f(Phi) = [[Sigma, h], [h^T, m]] (DefTrafoInertialParameters), shape (..., 4, 4)."""
    m, h, inertia = unpack(phi)
    f = np.zeros(m.shape + (4, 4))
    f[..., :3, :3] = sigma_from_inertia(inertia)
    f[..., :3, 3] = h
    f[..., 3, :3] = h
    f[..., 3, 3] = m
    return f


def pseudo_inertia_inverse(f):
    """Phi from f(Phi); f^{-1}: sym(4) -> R^10 (Theorem 1, second part)."""
    f = np.asarray(f, dtype=float)
    f = 0.5 * (f + np.swapaxes(f, -1, -2))
    return pack(f[..., 3, 3], f[..., :3, 3], inertia_from_sigma(f[..., :3, :3]))


def spatial_inertia(phi):
    """Z(Phi) = [[m I3, -S(h)], [-S(h)^T, I]] (DefMatrixZ), shape (..., 6, 6)."""
    phi = np.asarray(phi, dtype=float)
    z = np.zeros(phi.shape[:-1] + (6, 6))
    z[..., 0, 0] = z[..., 1, 1] = z[..., 2, 2] = phi[..., 0]
    minus_s = -skew(phi[..., 1:4])
    z[..., :3, 3:] = minus_s
    z[..., 3:, :3] = np.swapaxes(minus_s, -1, -2)
    z[..., 3:, 3:] = phi[..., _INERTIA_INDEX]
    return z


def spatial_inertia_inverse(z):
    """Phi from Z(Phi); the mass is the mean of the translational diagonal."""
    z = np.asarray(z, dtype=float)
    m = np.trace(z[..., :3, :3], axis1=-2, axis2=-1) / 3.0
    s = 0.5 * (z[..., 3:, :3] - z[..., :3, 3:])  # = S(h)
    h = np.stack([s[..., 2, 1], s[..., 0, 2], s[..., 1, 0]], -1)
    return pack(m, h, z[..., 3:, 3:])


def center_of_mass(phi):
    """c = h / m (RespectivePotenitalEnergy); inf/nan where m = 0."""
    m, h, _ = unpack(phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        return h / m[..., None]


def inertia_com(phi):
    """I_CoM = I - S(h)^T S(h) / m, the inertia about the centre of mass."""
    m, h, inertia = unpack(phi)
    s = skew(h)
    with np.errstate(divide="ignore", invalid="ignore"):
        return inertia - np.swapaxes(s, -1, -2) @ s / m[..., None, None]


def sigma_com(phi):
    """Sigma_CoM = Sigma - h h^T / m = tr(I_CoM)/2 I3 - I_CoM (I_Sigma_IsTranslationInvariant)."""
    m, h, inertia = unpack(phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        return sigma_from_inertia(inertia) - h[..., :, None] * h[..., None, :] / m[..., None, None]


def rotation_rpy(rpy):
    """URDF rotation R = Rz(yaw) Ry(pitch) Rx(roll), batched over (..., 3)."""
    r, p, y = np.moveaxis(np.asarray(rpy, dtype=float), -1, 0)
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    return np.stack(
        [
            np.stack([cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr], -1),
            np.stack([sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], -1),
            np.stack([-sp, cp * sr, cp * cr], -1),
        ],
        -2,
    )


def from_urdf(mass, com, inertia_about_com, rotation=None):
    """Phi from the URDF convention.

    ``mass`` (...), ``com`` (..., 3) in the link frame, ``inertia_about_com``
    (..., 3, 3) in the axes of the inertial frame, ``rotation`` (..., 3, 3)
    from those axes to the link frame (``rotation_rpy(rpy)``). The parallel
    axis theorem gives I = R I_c R^T + m S(c)^T S(c).
    """
    mass = np.asarray(mass, dtype=float)
    com = np.asarray(com, dtype=float)
    ic = np.asarray(inertia_about_com, dtype=float)
    if rotation is not None:
        rotation = np.asarray(rotation, dtype=float)
        ic = rotation @ ic @ np.swapaxes(rotation, -1, -2)
    s = skew(com)
    inertia = ic + mass[..., None, None] * (np.swapaxes(s, -1, -2) @ s)
    return pack(mass, mass[..., None] * com, inertia)


def urdf_inertia(ixx, iyy, izz, ixy, iyz, ixz):
    """The 3x3 matrix from URDF's six entries."""
    return inertia_matrix(np.stack(np.broadcast_arrays(0, 0, 0, 0, ixx, iyy, izz, ixy, iyz, ixz), -1))


def from_urdf_row(row):
    """Phi from a URDF-style row (mass, com_x, com_y, com_z, ixx, iyy, izz, ixy, iyz, ixz)."""
    row = np.asarray(row, dtype=float)
    return from_urdf(row[..., 0], row[..., 1:4], urdf_inertia(*np.moveaxis(row[..., 4:10], -1, 0)))


def point_mass(m, position):
    """Phi of a point mass (a degenerate body: f >= 0 with rank 1)."""
    position = np.asarray(position, dtype=float)
    s = skew(position)
    m = np.asarray(m, dtype=float)
    return pack(m, m[..., None] * position, m[..., None, None] * (np.swapaxes(s, -1, -2) @ s))


def unit_body():
    """Phi = (1, 0, I3): the paper's first counterexample body, f = diag(I3/2, 1), Z = I6."""
    return pack(1.0, np.zeros(3), np.eye(3))
