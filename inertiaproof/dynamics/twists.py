"""Fixed and joint transforms acting on batched twists, wrenches, frames and inertial parameters.

Every batched quantity here is stored with its components first and the K
configurations last, e.g. twists (6, ..., K): a fixed transform acts on all
configurations by one matrix product, a joint's own motion by a few
elementwise operations on slabs of rows. Every joint is moved onto the z
axis of its joint frame (:class:`ZJoint`), so a turn mixes only the x and y
rows. Everything is generic in dtype: a complex step passes through.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

from inertiaproof.model.inertia import skew

__all__ = [
    "Arena", "axis_frame", "CHUNK", "chunks", "fixed_map", "flat_view", "Motion", "plane_turn", "real_product",
    "turn_frames", "turn_twists", "turn_wrenches", "twist_map", "ZJoint",
]

CHUNK = 2048  # configurations per pass over a chain: the working set stays in the core's cache


def chunks(count, size=CHUNK):
    """Slices of at most ``size`` configurations covering range(count)."""
    return [slice(start, min(start + size, count)) for start in range(0, count, size)]


@lru_cache(maxsize=16)
def _buffer(tag, size, dtype):
    return np.empty(size, dtype)


class Arena:
    """Contiguous views carved from one flat buffer that is kept between calls: fresh large temporaries are
    paged in by the kernel on every call, which costs about as much as the arithmetic here. The views are
    scratch, never results; not for concurrent use from several threads."""

    def __init__(self, tag, size, dtype):
        self.buffer, self.used = _buffer(tag, size, np.dtype(dtype)), 0

    def take(self, *shape):
        size = int(np.prod(shape))
        view = self.buffer[self.used:self.used + size].reshape(shape)
        self.used += size
        return view


def axis_frame(axis):
    """The rotation A about e_z x axis taking e_z to the unit ``axis`` (A = I for e_z; a half turn about x for -e_z).

    Rodrigues' form I + S + S^2 / (1 + c), S = skew(e_z x axis), c = axis_z; near -e_z the factor is
    (1 - c) / |e_z x axis|^2 (the same for a unit axis), since 1 + c cancels: it lost up to 1e-6 of A's
    orthogonality there.
    """
    a = np.asarray(axis, dtype=float)
    v, c = np.cross([0.0, 0.0, 1.0], a), a[2]
    vv = v @ v
    if vv == 0.0:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    s = skew(v)
    return np.eye(3) + s + s @ s * ((1.0 - c) / vv if c < 0 else 1.0 / (1.0 + c))


def twist_map(t):
    """6 x 6 map from the twist (v, omega) of a frame F (origin velocity and angular velocity in F's axes) to
    the twist of the frame F t rigidly attached to it: [[R^T, -R^T S(r)], [0, R^T]] for t = (R, r)."""
    r, shift = t[:3, :3], t[:3, 3]
    x = np.zeros((6, 6))
    x[:3, :3] = x[3:, 3:] = r.T
    x[:3, 3:] = -r.T @ skew(shift)
    return x


def real_product(a, b, out=None):
    """a @ b for a real matrix a and a real or complex b (rows, K): a complex b as interleaved real pairs, so
    that a complex step costs one real product of twice the width."""
    if np.iscomplexobj(b):
        product = (a @ np.ascontiguousarray(b).view(float)).view(b.dtype)
        if out is None:
            return product
        out[:] = product
        return out
    return np.matmul(a, b, out=out)


def flat_view(a, rows):
    """a (rows, ...) as (rows, -1) without copying; raises if that would need a copy."""
    view = a.view()
    view.shape = (rows, -1)
    return view


def fixed_map(x, stacked, out=None):
    """x (r, r) applied to stacked (r, ..., K), components first; None stands for the identity (no copy)."""
    if x is None:
        if out is None:
            return stacked
        out[:] = stacked
        return out
    rows = len(x)
    flat = real_product(x, stacked.reshape(rows, -1), None if out is None else flat_view(out, rows))
    return flat.reshape(stacked.shape)


def plane_turn(x, y, c, s, inverse=False, scratch=None):
    """In place: (x, y) <- (c x - s y, s x + c y), the turn by the angle of (c, s) (inverse: by minus it).

    ``scratch``: a 1-D buffer of at least 2 x.size entries for the two products (None: allocate).
    """
    if scratch is None:
        sx, sy = s * x, s * y
    else:
        sx = np.multiply(s, x, out=scratch[:x.size].reshape(x.shape))
        sy = np.multiply(s, y, out=scratch[x.size:2 * x.size].reshape(x.shape))
    x *= c
    y *= c
    if inverse:
        x += sy
        y -= sx
    else:
        x -= sy
        y += sx


class Motion:
    """A joint's variable x = g(q), its rate factor g'(q) (None when exactly 1), and cos x, sin x of a turn."""

    __slots__ = ("revolute", "value", "rate", "cos", "sin")

    def __init__(self, joint, q):
        identity = joint.coordinate.name == "identity"
        self.revolute = joint.revolute
        self.value = q if identity else joint.coordinate.value(q)
        self.rate = None if identity else joint.coordinate.derivative(q)
        self.cos, self.sin = (np.cos(self.value), np.sin(self.value)) if self.revolute else (None, None)

    def double_angle(self):
        """(cos 2x, sin 2x)."""
        return self.cos * self.cos - self.sin * self.sin, 2 * self.cos * self.sin

    def scale(self, x):
        """x times the rate factor g'(q)."""
        return x if self.rate is None else x * self.rate


def turn_twists(twists, motion, scratch=None):
    """In place: twists (6, ..., K) of a frame carried through the joint's turn about z by x (slide along z):
    (v, omega) -> (Rz(x)^T v, Rz(x)^T omega), or v -> v + x (omega x e_z)."""
    if motion.revolute:
        plane_turn(twists[0::3], twists[1::3], motion.cos, motion.sin, inverse=True, scratch=scratch)
    else:
        shift = motion.value * twists[3]
        twists[0] += motion.value * twists[4]
        twists[1] -= shift


def turn_wrenches(wrenches, motion, scratch=None):
    """In place: wrenches (6, ..., K) (force, torque) carried back through the joint, the transpose of
    :func:`turn_twists`: (f, tau) -> (Rz(x) f, Rz(x) tau), or tau -> tau + x (e_z x f)."""
    if motion.revolute:
        plane_turn(wrenches[0::3], wrenches[1::3], motion.cos, motion.sin, scratch=scratch)
    else:
        shift = motion.value * wrenches[1]
        wrenches[4] += motion.value * wrenches[0]
        wrenches[3] -= shift


def turn_frames(frames, motion):
    """In place: frames [R^T; z^T] (4, 3, K) followed by the joint's turn (slide): R -> R Rz(x), or z -> z + x R e_z."""
    if motion.revolute:
        plane_turn(frames[0], frames[1], motion.cos, motion.sin, inverse=True)
    else:
        frames[3] += motion.value * frames[2]


@dataclass(frozen=True, eq=False)
class ZJoint:
    """A joint moved onto the z axis: ``before`` = before A, a turn about (slide along) e_z, ``after`` = A^T after,
    with A e_z = axis.

    ``before_twist`` and ``after_twist`` are the fixed transforms' twist maps
    (:func:`twist_map`), ``before_frame`` and ``after_frame`` their maps t^T of
    frames [R^T; z^T]; None stands for the identity.
    """

    before: np.ndarray
    after: np.ndarray
    revolute: bool
    coordinate: object

    @classmethod
    def of(cls, joint):
        a = np.eye(4)
        a[:3, :3] = axis_frame(joint.axis)
        return cls(joint.before @ a, a.T @ joint.after, joint.revolute, joint.coordinate)

    @staticmethod
    def _unless_identity(t, build):
        return None if np.array_equal(t, np.eye(4)) else build(t)

    @cached_property
    def before_twist(self):
        return self._unless_identity(self.before, twist_map)

    @cached_property
    def after_twist(self):
        return self._unless_identity(self.after, twist_map)

    @cached_property
    def before_frame(self):
        return self._unless_identity(self.before, np.transpose)

    @cached_property
    def after_frame(self):
        return self._unless_identity(self.after, np.transpose)

    @cached_property
    def unit_twist(self):
        """The joint's twist per unit rate in the body frame after it: after_twist e_6 (turn) or e_3 (slide)."""
        unit = np.eye(6)[:, 5 if self.revolute else 2]
        return unit if self.after_twist is None else self.after_twist @ unit

    @cached_property
    def unit_axis(self):
        """k when the unit twist is e_k (no fixed transform after the joint), else None."""
        nonzero = np.flatnonzero(self.unit_twist)
        return int(nonzero[0]) if len(nonzero) == 1 and self.unit_twist[nonzero[0]] == 1.0 else None
