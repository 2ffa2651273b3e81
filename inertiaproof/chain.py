"""Serial kinematic chains and the stacked body-twist Jacobian QJ.

A chain of n joints moves N = n bodies. Body l's frame is

    T_l(q) = T_{l-1}(q) . before_l . X_l(g_l(q_l)) . after_l,

with X_l a rotation about (revolute) or a translation along (prismatic) the
unit ``axis`` of the joint frame, and g_l the map from the generalized
coordinate to the joint variable (the identity for ordinary joints; a map
with vanishing derivative makes QJ non-normal, Definition 2).

``body_jacobian(q)`` is QJ of (MassMatrix): rows 6(l-1) .. 6l-1 map qdot to
(R_l^T v_l, omega_l), the origin's velocity in body axes and the body
angular velocity (VelocityRigidMass). Everything is batched over leading axes
of ``q`` and generic in dtype, so complex-step differentiation gives dQJ/dq
to round-off.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .inertia import rotation_rpy, skew

COMPLEX_STEP = 1e-30


@dataclass(frozen=True)
class Coordinate:
    """Map from a generalized coordinate to a joint variable, analytic so complex steps pass through."""

    name: str = "identity"

    def value(self, q):
        return COORDINATE_MAPS[self.name][0](q)

    def derivative(self, q):
        return COORDINATE_MAPS[self.name][1](q)


COORDINATE_MAPS = {  # name: (g, dg/dq), both analytic
    "identity": (lambda q: q, lambda q: np.ones_like(q)),
    # dg/dq = 3 q^2 vanishes at q = 0: QJ loses rank there (CX-normal)
    "cubic": (lambda q: q**3, lambda q: 3 * q**2),
    # dg/dq = 1 / (1 + q^2) fades as |q| grows: the infimum over q is 0, not attained
    "arctan": (lambda q: np.arctan(q), lambda q: 1 / (1 + q**2)),
}


def translation(xyz):
    t = np.eye(4)
    t[:3, 3] = xyz
    return t


def rotation(r):
    t = np.eye(4)
    t[:3, :3] = r
    return t


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return rotation([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return rotation([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def origin(xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)):
    """URDF-style fixed transform: translate by xyz, then rotate by rpy."""
    return translation(xyz) @ rotation(rotation_rpy(rpy))


@dataclass(frozen=True)
class Joint:
    kind: str  # "revolute" or "prismatic"
    axis: tuple = (0.0, 0.0, 1.0)
    before: np.ndarray = field(default_factory=lambda: np.eye(4))
    after: np.ndarray = field(default_factory=lambda: np.eye(4))
    coordinate: Coordinate = Coordinate()
    limits: tuple | None = None  # (lower, upper) of the generalized coordinate
    name: str = ""

    def __post_init__(self):
        if self.kind not in ("revolute", "prismatic"):
            raise ValueError(f"joint {self.name or '?'}: kind must be 'revolute' or 'prismatic', not {self.kind!r}")
        axis = np.asarray(self.axis, dtype=float)
        norm = np.linalg.norm(axis)
        if axis.shape != (3,) or not np.isfinite(norm) or norm == 0:
            raise ValueError(f"joint {self.name or '?'}: axis must be a nonzero 3-vector, got {self.axis!r}")
        object.__setattr__(self, "axis", tuple(axis / norm))
        for key in ("before", "after"):
            t = np.asarray(getattr(self, key), dtype=float)
            if t.shape != (4, 4) or not np.all(np.isfinite(t)):
                raise ValueError(f"joint {self.name or '?'}: {key} must be a finite 4x4 transform")
            object.__setattr__(self, key, t)
        if self.coordinate.name not in COORDINATE_MAPS:
            raise ValueError(f"joint {self.name or '?'}: unknown coordinate map {self.coordinate.name!r}")

    @property
    def revolute(self):
        return self.kind == "revolute"


@dataclass(frozen=True)
class Chain:
    joints: tuple
    name: str = "chain"
    gravity: tuple = (0.0, 0.0, -9.81)  # gravitational acceleration in the base frame

    def __post_init__(self):
        object.__setattr__(self, "joints", tuple(self.joints))
        if not self.joints:
            raise ValueError(f"chain {self.name}: needs at least one joint")

    @property
    def n(self):
        return len(self.joints)

    @property
    def bodies(self):
        return len(self.joints)

    @property
    def kinds(self):
        return "".join("R" if j.revolute else "P" for j in self.joints)

    @classmethod
    def from_dh(cls, rows, *, convention="standard", kinds=None, name="dh chain", gravity=(0.0, 0.0, -9.81),
                limits=None, coordinates=None):
        """A chain from Denavit-Hartenberg rows (a, alpha, d, theta).

        ``standard`` (distal): T_l = T_{l-1} Rz(theta_l) Tz(d_l) Tx(a_l) Rx(alpha_l).
        ``modified`` (Craig, proximal): T_l = T_{l-1} Rx(alpha_{l-1}) Tx(a_{l-1}) Rz(theta_l) Tz(d_l),
        with row l holding (a_{l-1}, alpha_{l-1}, d_l, theta_l).
        For a revolute joint theta is an offset; for a prismatic joint, d is.
        """
        if convention not in ("standard", "modified"):
            raise ValueError(f"DH convention must be 'standard' or 'modified', not {convention!r}")
        kinds = kinds or "R" * len(rows)
        joints = []
        for i, (row, kind) in enumerate(zip(rows, kinds)):
            a, alpha, d, theta = (float(x) for x in row)
            fixed_z = rot_z(theta) @ translation((0, 0, d))
            if convention == "standard":
                before, after = fixed_z, translation((a, 0, 0)) @ rot_x(alpha)
            else:
                before, after = rot_x(alpha) @ translation((a, 0, 0)) @ fixed_z, np.eye(4)
            joints.append(Joint(
                kind="revolute" if kind == "R" else "prismatic",
                axis=(0.0, 0.0, 1.0),
                before=before,
                after=after,
                coordinate=Coordinate((coordinates or {}).get(i, "identity")),
                limits=None if limits is None else tuple(limits[i]),
                name=f"joint{i + 1}",
            ))
        return cls(tuple(joints), name=name, gravity=tuple(gravity))

    # -- kinematics -------------------------------------------------------

    def _check_q(self, q):
        q = np.asarray(q)
        if q.shape[-1:] != (self.n,):
            raise ValueError(f"chain {self.name}: configurations need {self.n} coordinates, got shape {q.shape}")
        return q if np.iscomplexobj(q) else q.astype(float)

    def joint_frames(self, q):
        """World rotation, origin, axis and axis point of every joint and body.

        Returns R (..., N, 3, 3) and z (..., N, 3) of the body frames, and
        u (..., n, 3), p (..., n, 3): each joint's unit axis and a point on it.
        """
        q = self._check_q(q)
        batch = q.shape[:-1]
        rot = np.broadcast_to(np.eye(3, dtype=q.dtype), batch + (3, 3))
        pos = np.zeros(batch + (3,), dtype=q.dtype)
        rs, zs, us, ps = [], [], [], []
        for k, joint in enumerate(self.joints):
            rot, pos = rot @ joint.before[:3, :3], pos + rot @ joint.before[:3, 3]
            axis = np.asarray(joint.axis)
            u = rot @ axis
            us.append(u)
            ps.append(pos)
            x = joint.coordinate.value(q[..., k])
            if joint.revolute:
                s = skew(axis)
                rx = np.eye(3) + np.sin(x)[..., None, None] * s + (1 - np.cos(x))[..., None, None] * (s @ s)
                rot = rot @ rx
            else:
                pos = pos + x[..., None] * u
            rot, pos = rot @ joint.after[:3, :3], pos + rot @ joint.after[:3, 3]
            rs.append(rot)
            zs.append(pos)
        return np.stack(rs, -3), np.stack(zs, -2), np.stack(us, -2), np.stack(ps, -2)

    def forward_kinematics(self, q):
        """Body frames: rotations (..., N, 3, 3) and origins (..., N, 3) in the base frame (Layout)."""
        rot, pos, _, _ = self.joint_frames(q)
        return rot, pos

    def body_jacobian(self, q, frames=None):
        """QJ (..., 6N, n): qdot -> stacked (R_l^T v_l, omega_l) (Kinematics, DefBlockmatrixQ).

        ``frames``: ``joint_frames(q)`` when the caller already has them."""
        q = self._check_q(q)
        rot, pos, u, p = self.joint_frames(q) if frames is None else frames
        n = self.n
        dx = np.stack([joint.coordinate.derivative(q[..., k]) for k, joint in enumerate(self.joints)], -1)
        revolute = np.array([j.revolute for j in self.joints])
        # world columns for body l and joint k: (..., N, n, 3)
        lever = pos[..., :, None, :] - p[..., None, :, :]
        u_b = np.broadcast_to(u[..., None, :, :], lever.shape)
        lin = np.where(revolute[:, None], np.cross(u_b, lever), u_b)
        ang = np.where(revolute[:, None], u_b, 0.0)
        mask = np.tril(np.ones((n, n), dtype=bool))[..., None]  # body l moves with joints k <= l
        scale = dx[..., None, :, None] * mask
        lin, ang = lin * scale, ang * scale
        rt = np.swapaxes(rot, -1, -2)[..., :, None, :, :]  # R_l^T per (l, k)
        lin_b = (rt @ lin[..., None])[..., 0]
        ang_b = (rt @ ang[..., None])[..., 0]
        qj = np.concatenate([lin_b, ang_b], -1)  # (..., N, n, 6)
        return np.swapaxes(qj, -1, -2).reshape(q.shape[:-1] + (6 * n, n))

    def body_jacobian_derivative(self, q):
        """dQJ/dq (..., 6N, n, n), entry [r, k, j] = d QJ[r, k] / d q_j, by complex steps (exact to round-off)."""
        q = np.asarray(q, dtype=float)
        n = self.n
        steps = q[..., None, :] + 1j * COMPLEX_STEP * np.eye(n)  # (..., n_j, n)
        return np.moveaxis(self.body_jacobian(steps).imag / COMPLEX_STEP, -3, -1)

    def coordinate_box(self, default_prismatic=(-1.0, 1.0)):
        """Lower and upper corners of the configuration domain; revolute joints default to one period."""
        lo, hi = [], []
        for j in self.joints:
            if j.limits is not None:
                a, b = j.limits
            elif j.revolute and j.coordinate.name == "identity":
                a, b = -np.pi, np.pi
            else:
                a, b = default_prismatic
            lo.append(a)
            hi.append(b)
        return np.array(lo, dtype=float), np.array(hi, dtype=float)

    def periodic(self):
        """Which coordinates are angles of period 2 pi (revolute, identity map, no limits)."""
        return np.array([j.revolute and j.coordinate.name == "identity" and j.limits is None for j in self.joints])

