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

from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from inertiaproof.model.inertia import rotation_rpy

from .twists import CHUNK, Arena, Motion, ZJoint, chunks, fixed_map, turn_frames, turn_twists

__all__ = [
    "Chain", "COMPLEX_STEP", "Coordinate", "COORDINATE_MAPS", "Joint", "origin", "rot_x", "rot_z", "rotation",
    "translation",
]

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


def decimal(x):
    """A float as the decimal Python writes it (the shortest that reads back as the same float)."""
    return repr(float(x))


@dataclass(frozen=True)
class Origin:
    """A fixed transform as written: translate by ``xyz``, then rotate by ``rpy`` (URDF), decimal strings."""

    xyz: tuple = ("0", "0", "0")
    rpy: tuple = ("0", "0", "0")

    @classmethod
    def of(cls, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)):
        """The origin of numbers written as Python writes them."""
        return cls(tuple(map(decimal, xyz)), tuple(map(decimal, rpy)))

    def matrix(self):
        return origin([float(x) for x in self.xyz], [float(x) for x in self.rpy])


def composed(origins):
    """The 4x4 transform of origins applied one after the other."""
    t = np.eye(4)
    for o in origins:
        t = t @ o.matrix()
    return t


WRITTEN = 1e-9  # how far a joint's transforms, axis and limits may lie from those it is written with


@dataclass(frozen=True)
class Written:
    """A joint as its source writes it: the origins its fixed transforms compose (``before``, ``after``), and its
    axis and limits as decimal strings (None: the source writes none, or the joint was made from numbers)."""

    before: tuple = ()
    after: tuple = ()
    axis: tuple | None = None
    limits: tuple | None = None

    def disagrees(self, joint):
        """Whether the joint's numbers are not those written (within :data:`WRITTEN`)."""
        far = lambda a, b: np.abs(np.asarray(a, float) - np.asarray(b, float)).max() > WRITTEN  # noqa: E731
        axis = None if self.axis is None else np.array([float(x) for x in self.axis])
        return (far(composed(self.before), joint.before) or far(composed(self.after), joint.after)
                or axis is not None and far(axis / np.linalg.norm(axis), joint.axis)
                or (self.limits is None) != (joint.limits is None)
                or self.limits is not None and far([float(x) for x in self.limits], joint.limits))


@dataclass(frozen=True)
class Joint:
    kind: str  # "revolute" or "prismatic"
    axis: tuple = (0.0, 0.0, 1.0)
    before: np.ndarray = field(default_factory=lambda: np.eye(4))
    after: np.ndarray = field(default_factory=lambda: np.eye(4))
    coordinate: Coordinate = Coordinate()
    limits: tuple | None = None  # (lower, upper) of the generalized coordinate
    name: str = ""
    written: Written | None = None  # the joint as its source writes it (dropped where the numbers differ)

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
        if self.written is not None and self.written.disagrees(self):  # e.g. limits replaced after it was made: the
            object.__setattr__(self, "written", None)  # numbers are the joint, a certificate writes them as floats

    @property
    def revolute(self):
        return self.kind == "revolute"

    @classmethod
    def of_origins(cls, kind, axis, before=(), after=(), **kw):
        """A joint whose fixed transforms compose the :class:`Origin` tuples ``before`` and ``after``."""
        return cls(kind, axis, composed(before), composed(after), written=Written(tuple(before), tuple(after)), **kw)


@dataclass(frozen=True)
class Chain:
    joints: tuple
    name: str = "chain"
    gravity: tuple = (0.0, 0.0, -9.81)  # gravitational acceleration in the base frame
    source: tuple | None = None  # (path as given, SHA-256 of its bytes) of the file the chain was read from

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
            z_origin, x_origin = Origin.of((0, 0, d), (0, 0, theta)), Origin.of((a, 0, 0), (alpha, 0, 0))
            if convention == "standard":
                before, after = fixed_z, translation((a, 0, 0)) @ rot_x(alpha)
                written = Written((z_origin,), (x_origin,))
            else:
                before, after = rot_x(alpha) @ translation((a, 0, 0)) @ fixed_z, np.eye(4)
                written = Written((x_origin, z_origin), ())
            joints.append(Joint(
                kind="revolute" if kind == "R" else "prismatic",
                axis=(0.0, 0.0, 1.0),
                before=before,
                after=after,
                coordinate=Coordinate((coordinates or {}).get(i, "identity")),
                limits=None if limits is None else tuple(limits[i]),
                name=f"joint{i + 1}",
                written=written if limits is None else replace(written, limits=tuple(map(decimal, limits[i]))),
            ))
        return cls(tuple(joints), name=name, gravity=tuple(gravity))

    def to_data(self):
        """Plain data (counterexample files); :meth:`from_data` rebuilds the chain."""
        return {"name": self.name, "gravity": list(self.gravity), "joints": [
            {"kind": j.kind, "axis": list(j.axis), "before": np.asarray(j.before).tolist(),
             "after": np.asarray(j.after).tolist(), "coordinate": j.coordinate.name,
             "limits": None if j.limits is None else list(j.limits), "name": j.name} for j in self.joints]}

    @classmethod
    def from_data(cls, data):
        return cls(tuple(Joint(j["kind"], tuple(j["axis"]), np.array(j["before"]), np.array(j["after"]),
                               Coordinate(j["coordinate"]), None if j["limits"] is None else tuple(j["limits"]),
                               j["name"]) for j in data["joints"]), name=data["name"], gravity=tuple(data["gravity"]))

    # -- kinematics -------------------------------------------------------

    def _check_q(self, q):
        q = np.asarray(q)
        if q.shape[-1:] != (self.n,):
            raise ValueError(f"chain {self.name}: configurations need {self.n} coordinates, got shape {q.shape}")
        return q if np.iscomplexobj(q) else q.astype(float)

    @cached_property
    def z_joints(self):
        """The joints moved onto the z axis of their joint frames (:class:`inertiaproof.twists.ZJoint`)."""
        return tuple(ZJoint.of(joint) for joint in self.joints)

    def flat_coordinates(self, q):
        """Configurations (..., n) as coordinate rows (n, K), batch last, and the batch shape."""
        q = self._check_q(q)
        return np.ascontiguousarray(q.reshape(-1, self.n).T), q.shape[:-1]

    def motions(self, x):
        """The joints' :class:`inertiaproof.twists.Motion` at coordinate rows x (n, K)."""
        return [Motion(joint, row) for joint, row in zip(self.joints, x)]

    def joint_frames(self, q):
        """World rotation, origin, axis and axis point of every joint and body.

        Returns R (..., N, 3, 3) and z (..., N, 3) of the body frames, and
        u (..., n, 3), p (..., n, 3): each joint's unit axis and a point on it.
        A frame is kept as [R^T; z^T] (4, 3, K): a fixed transform t acts by t^T [R^T; z^T].
        """
        x, batch = self.flat_coordinates(q)
        count, n = x.shape[1], self.n
        bodies = np.empty((n, 4, 3, count), x.dtype)
        axes = np.empty((n, 2, 3, count), x.dtype)
        for part in chunks(count):
            frame = np.zeros((4, 3, part.stop - part.start), x.dtype)
            frame[:3] = np.eye(3)[:, :, None]
            for k, (joint, motion) in enumerate(zip(self.z_joints, self.motions(x[:, part]))):
                frame = fixed_map(joint.before_frame, frame)
                axes[k, ..., part] = frame[2:]
                turn_frames(frame, motion)
                frame = fixed_map(joint.after_frame, frame)
                bodies[k, ..., part] = frame
        rot = np.transpose(bodies[:, :3], (3, 0, 2, 1)).reshape(batch + (n, 3, 3))
        pos, u, p = (np.transpose(a, (2, 0, 1)).reshape(batch + (n, 3)) for a in (bodies[:, 3], axes[:, 0], axes[:, 1]))
        return rot, pos, u, p

    def forward_kinematics(self, q):
        """Body frames: rotations (..., N, 3, 3) and origins (..., N, 3) in the base frame (Layout)."""
        rot, pos, _, _ = self.joint_frames(q)
        return rot, pos

    def jacobian_blocks(self, x):
        """QJ at coordinate rows x (n, K) as blocks (N, 6, n, K), batch last; block l is zero right of column l.

        Block l is carried along the chain: QJ_l = X_after (J(x_l) X_before QJ_{l-1} + column l), with
        X the twist maps of the fixed transforms and J(x_l) the joint's own turn about (slide along) z;
        two buffers take turns as source and target of the fixed maps.
        """
        count, n = x.shape[1], self.n
        blocks = np.zeros((n, 6, n, count), x.dtype)
        parts = chunks(count)
        for part in parts:
            size = part.stop - part.start
            arena = Arena("jacobian", (12 * n + 4 * n) * (parts[0].stop - parts[0].start), x.dtype)
            buffers, scratch, side = (arena.take(6, n, size), arena.take(6, n, size)), arena.take(4 * n * size), 0
            for l, (joint, motion) in enumerate(zip(self.z_joints, self.motions(x[:, part]))):
                if l:
                    if joint.before_twist is not None:
                        fixed_map(joint.before_twist, buffers[side][:, :l], out=buffers[1 - side][:, :l])
                        side = 1 - side
                    turn_twists(buffers[side][:, :l], motion, scratch)
                    if joint.after_twist is not None:
                        fixed_map(joint.after_twist, buffers[side][:, :l], out=buffers[1 - side][:, :l])
                        side = 1 - side
                buffers[side][:, l] = motion.scale(joint.unit_twist[:, None])
                blocks[l, :, :l + 1, part] = buffers[side][:, :l + 1]
        return blocks

    def body_jacobian(self, q):
        """QJ (..., 6N, n): qdot -> stacked (R_l^T v_l, omega_l) (Kinematics, DefBlockmatrixQ); a view of
        :meth:`jacobian_blocks`, whose storage keeps the batch last."""
        x, batch = self.flat_coordinates(q)
        blocks = self.jacobian_blocks(x)
        return np.moveaxis(blocks.reshape(6 * self.n, self.n, -1), -1, 0).reshape(batch + (6 * self.n, self.n))

    def body_jacobian_derivative(self, q):
        """dQJ/dq (..., 6N, n, n), entry [r, k, j] = d QJ[r, k] / d q_j, by complex steps (exact to round-off)."""
        x, batch = self.flat_coordinates(np.asarray(q, dtype=float))
        count, n = x.shape[1], self.n
        out = np.empty((6 * n, n, n, count))
        step = 1j * COMPLEX_STEP * np.eye(n)[:, :, None]  # (n, n_j, 1)
        for part in chunks(count, max(CHUNK // n, 1)):
            steps = (x[:, None, part] + step).reshape(n, -1)  # (n, n_j * k)
            blocks = self.jacobian_blocks(steps).imag.reshape(6 * n, n, n, -1)
            out[..., part] = blocks / COMPLEX_STEP
        return np.moveaxis(out, -1, 0).reshape(batch + (6 * n, n, n))

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

