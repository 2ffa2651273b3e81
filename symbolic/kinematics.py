"""The exact symbolic twin of a :class:`inertiaproof.chain.Chain`: forward kinematics and QJ.

The chain's fixed transforms are floats; the twin makes them exact: a rotation
becomes the rational rotation of a rationalised unit quaternion (exactly
orthogonal), a translation its 12-digit decimal. ``rationalisation_error``
says how far the twin is from the float chain. Joint frames follow
:meth:`Chain.joint_frames`:

    T_l = T_{l-1} . before_l . X_l(x_l) . after_l,   x_l = g_l(q_l),

with X_l = I + sin x S(u) + (1 - cos x) S(u)^2 (revolute about unit axis u) or a
translation x u (prismatic). QJ (MassMatrix, DefBlockmatrixQ) has the rows
(R_l^T dz_l/dq_k, vee(R_l^T dR_l/dq_k)) of body l and column k (VelocityRigidMass).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property

import numpy as np
from inertiaproof.symbolic.jets import JetSpace
from sympy.polys.domains import QQ

from inertiaproof.errors import InputError

__all__ = [
    "ChainTwin", "Frame", "matmul", "matvec", "rational", "rational_axis", "rational_rotation",
    "rational_transform", "skew", "SNAP", "to_qq", "TOLERANCE", "transpose", "vee",
]

SNAP = 1e-12  # entries this close to -1, 0, 1 are taken as exactly that
TOLERANCE = 1e-9  # the largest accepted distance between the twin's transforms and the chain's


def to_qq(x):
    """A Fraction (or int) as an element of SymPy's QQ."""
    x = Fraction(x)
    return QQ(x.numerator, x.denominator)


def rational(x):
    """The 12-digit decimal of a float as an exact Fraction."""
    return Fraction(repr(round(float(x), 12))) + 0


def rational_rotation(r):
    """An exactly orthogonal rational matrix near the float rotation r (3x3 nested Fractions)."""
    r = np.asarray(r, dtype=float)
    snapped = np.round(r)
    if np.all(np.abs(r - snapped) < SNAP) and np.allclose(snapped @ snapped.T, np.eye(3)):
        return [[Fraction(int(x)) for x in row] for row in snapped]
    w, x, y, z = _quaternion(r)
    scale = max(abs(w), abs(x), abs(y), abs(z))
    w, x, y, z = (Fraction(v / scale).limit_denominator(10**6) for v in (w, x, y, z))
    n = w * w + x * x + y * y + z * z
    return [
        [(w * w + x * x - y * y - z * z) / n, 2 * (x * y - w * z) / n, 2 * (x * z + w * y) / n],
        [2 * (x * y + w * z) / n, (w * w - x * x + y * y - z * z) / n, 2 * (y * z - w * x) / n],
        [2 * (x * z - w * y) / n, 2 * (y * z + w * x) / n, (w * w - x * x - y * y + z * z) / n],
    ]


def _quaternion(r):
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    trace = np.trace(r)
    candidates = [trace, r[0, 0], r[1, 1], r[2, 2]]
    i = int(np.argmax(candidates))
    if i == 0:
        w = 0.5 * np.sqrt(1 + trace)
        return w, (r[2, 1] - r[1, 2]) / (4 * w), (r[0, 2] - r[2, 0]) / (4 * w), (r[1, 0] - r[0, 1]) / (4 * w)
    a, b, c = [(0, 1, 2), (1, 2, 0), (2, 0, 1)][i - 1]
    v = [0.0, 0.0, 0.0]
    v[a] = 0.5 * np.sqrt(1 + r[a, a] - r[b, b] - r[c, c])
    v[b] = (r[a, b] + r[b, a]) / (4 * v[a])
    v[c] = (r[a, c] + r[c, a]) / (4 * v[a])
    w = (r[c, b] - r[b, c]) / (4 * v[a])
    return w, v[0], v[1], v[2]


def rational_transform(t):
    """(R, p): the exact twin of a 4x4 float transform."""
    return rational_rotation(np.asarray(t)[:3, :3]), [rational(x) for x in np.asarray(t)[:3, 3]]


def rational_axis(u):
    axis = [rational(x) for x in u]
    if sum(a * a for a in axis) != 1:
        raise InputError(f"joint axis {tuple(u)} is not a rational unit vector: no exact symbolic twin")
    return axis


def skew(x):
    """S(x) as nested lists (paper, Notation)."""
    z = 0 * x[0]
    return [[z, -x[2], x[1]], [x[2], z, -x[0]], [-x[1], x[0], z]]


def vee(w):
    """The vector x with S(x) = w for a skew 3x3 w."""
    return [w[2][1], w[0][2], w[1][0]]


def matmul(a, b):
    return [[sum((a[i][k] * b[k][j] for k in range(1, len(b))), a[i][0] * b[0][j]) for j in range(len(b[0]))]
            for i in range(len(a))]


def matvec(a, x):
    return [sum((a[i][k] * x[k] for k in range(1, len(x))), a[i][0] * x[0]) for i in range(len(a))]


def transpose(a):
    return [list(col) for col in zip(*a)]


@dataclass(frozen=True)
class Frame:
    rotation: list  # 3x3 ring elements, body axes -> base axes
    origin: list  # 3 ring elements, in the base frame


class ChainTwin:
    """A chain's exact symbolic kinematics over its :class:`JetSpace`."""

    def __init__(self, chain):
        self.chain = chain
        self.jets = JetSpace([j.kind for j in chain.joints], [j.coordinate.name for j in chain.joints])
        self.fixed = [(rational_transform(j.before), rational_transform(j.after)) for j in chain.joints]
        self.axes = [rational_axis(j.axis) for j in chain.joints]
        self.gravity = [rational(g) for g in chain.gravity]

    @cached_property
    def rationalisation_error(self):
        """Largest |exact - float| over every entry of the fixed transforms, axes and gravity."""
        worst = 0.0
        for joint, (before, after) in zip(self.chain.joints, self.fixed):
            for t, (r, p) in ((joint.before, before), (joint.after, after)):
                worst = max(worst, float(np.max(np.abs(np.array(r, dtype=float) - t[:3, :3]))),
                            float(np.max(np.abs(np.array(p, dtype=float) - t[:3, 3]))))
        if worst > TOLERANCE:
            raise InputError(f"chain {self.chain.name}: fixed transforms are {worst:.2e} from their exact twin "
                             f"(more than {TOLERANCE:g})")
        return worst

    def _lift(self, m):
        ring = self.jets.ring
        return [[ring(to_qq(x)) for x in row] for row in m]

    def _joint_motion(self, k):
        """(rotation, translation) of joint k's motion X_k(x_k) as ring elements."""
        jets, ring = self.jets, self.jets.ring
        u = [ring(to_qq(a)) for a in self.axes[k - 1]]
        if self.chain.joints[k - 1].revolute:
            c, s = jets.joint_variable(k)
            su = skew(u)
            su2 = matmul(su, su)
            rot = [[(ring.one if i == j else ring.zero) + s * su[i][j] + (1 - c) * su2[i][j] for j in range(3)]
                   for i in range(3)]
            return [[jets.canonical(x) for x in row] for row in rot], [ring.zero] * 3
        x = jets.joint_variable(k)
        identity = [[ring.one if i == j else ring.zero for j in range(3)] for i in range(3)]
        return identity, [x * a for a in u]

    @cached_property
    def frames(self):
        """Body frames T_l(q) (Layout), reduced modulo sin^2 + cos^2 = 1."""
        jets, ring = self.jets, self.jets.ring
        rot = [[ring.one if i == j else ring.zero for j in range(3)] for i in range(3)]
        pos = [ring.zero] * 3
        out = []
        for k, ((before_r, before_p), (after_r, after_p)) in enumerate(self.fixed, 1):
            pos = [a + b for a, b in zip(pos, matvec(rot, self._lift([before_p])[0]))]
            rot = matmul(rot, self._lift(before_r))
            motion_r, motion_p = self._joint_motion(k)
            pos = [a + b for a, b in zip(pos, matvec(rot, motion_p))]
            rot = matmul(rot, motion_r)
            pos = [a + b for a, b in zip(pos, matvec(rot, self._lift([after_p])[0]))]
            rot = matmul(rot, self._lift(after_r))
            rot = [[jets.canonical(x) for x in row] for row in rot]
            pos = [jets.canonical(x) for x in pos]
            out.append(Frame(rot, pos))
        return out

    def _body_twist(self, frame, derivative):
        """(R^T dz, vee(R^T dR)) for a derivation of the frame's entries, reduced."""
        jets = self.jets
        rt = transpose(frame.rotation)
        dz = [derivative(x) for x in frame.origin]
        dr = [[derivative(x) for x in row] for row in frame.rotation]
        lin = matvec(rt, dz)
        ang = vee(matmul(rt, dr))
        return [jets.canonical(x) for x in lin + ang]

    @cached_property
    def body_jacobian(self):
        """QJ (6N x n) as nested lists: column k of body l is (R_l^T dz_l/dq_k, vee(R_l^T dR_l/dq_k)) (Kinematics)."""
        n = self.jets.n
        rows = [[None] * n for _ in range(6 * n)]
        for l, frame in enumerate(self.frames):
            for k in range(1, n + 1):
                column = self._body_twist(frame, lambda x, k=k: self.jets.d_q(x, k)) if k <= l + 1 \
                    else [self.jets.zero] * 6
                for r in range(6):
                    rows[6 * l + r][k - 1] = column[r]
        return rows

    @cached_property
    def body_velocities(self):
        """(R_l^T v_l, omega_l) of every body by differentiating its frame along the motion (VelocityRigidMass)."""
        return [self._body_twist(frame, self.jets.d_t) for frame in self.frames]

    def numeric_point(self, point):
        """The float configuration q of a point {('tan_half', (k,)): t_k, ('q', (k,)): q_k}."""
        q = []
        for k in range(1, self.jets.n + 1):
            joint = self.chain.joints[k - 1]
            if joint.revolute and joint.coordinate.name == "identity":
                q.append(2 * np.arctan(float(point[("tan_half", (k,))])))
            else:
                q.append(float(point[("q", (k,))]))
        return np.array(q)
