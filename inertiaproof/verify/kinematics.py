"""A serial chain of a certificate, and M(q, Theta) + shift I proved positive definite over a box of configurations.

Joint l has a fixed transform ``before``, a turn about (slide along) its ``axis`` through the origin by q_l, and a
fixed transform ``after``, so body l's frame is T_l = T_(l-1) before_l X_l(q_l) after_l. A fixed transform is a
list of origins, each written as URDF writes one, ``xyz`` and ``rpy`` (decimal strings, read exactly), composed in
order: the checker builds each rotation Rz(yaw) Ry(pitch) Rx(roll) itself with arb's sin and cos, so every
transform is rigid by construction and R^T is its inverse. Optional ``limits``: the joint's [lower, upper].
M(q, Theta) = sum_l QJ_l^T
Z(Phi_l) QJ_l (MassMatrix, DefMatrixZ), QJ_l's rows the twist (R_l^T v_l, omega_l) of body l (VelocityRigidMass);
it is never formed: :meth:`Chain.pivots` factors it from the tip as articulated-body inertias.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from flint import arb, arb_mat

from .exact import BadCertificate, rational_matrix

__all__ = ["Chain", "definite", "eigen", "twist_map"]

JOINTS = 200  # the longest chain a certificate may describe
ORIGINS = 64  # the most origins one fixed transform may compose



class Joint:
    def __init__(self, data, where):
        if not isinstance(data, dict) or not set(data) <= {"name", "kind", "axis", "before", "after", "limits"}:
            raise BadCertificate(f"{where}: a joint is an object of name, kind, axis, before, after and limits")
        self.revolute = {"revolute": True, "prismatic": False}.get(data.get("kind"))
        if self.revolute is None:
            raise BadCertificate(f"{where}.kind: 'revolute' or 'prismatic', not {data.get('kind')!r}")
        axis = [arb(x) for x in rational_matrix([data.get("axis")], (1, 3), f"{where}.axis")[0]]
        norm = sum(a * a for a in axis).sqrt()
        if not norm > 0:
            raise BadCertificate(f"{where}.axis: the axis must be a nonzero vector")
        self.axis = arb_mat(3, 1, [a / norm for a in axis])
        self.before = _composed(data.get("before"), f"{where}.before")
        self.after = _composed(data.get("after"), f"{where}.after")
        self.limits = data.get("limits") and tuple(rational_matrix([data["limits"]], (1, 2), f"{where}.limits")[0])
        if self.limits and self.limits[0] > self.limits[1]:
            raise BadCertificate(f"{where}.limits: lower > upper")
        self.before_map, self.after_map = twist_map(self.before), twist_map(self.after)
        k, zero = _skew(self.axis), arb_mat(3, 3)
        n_map = _blocks(-k, zero, zero, -k) if self.revolute else _blocks(zero, -k, zero, zero)
        self.generators = n_map, n_map * n_map  # N and N^2 of the twist map by delta (see _expansion)
        self.subspace = _subspace(self)

    def motion_map(self, centre, radius=None):
        """The twist map of the joint's own motion by the coordinate ``centre`` (a rational), or by every
        delta with |delta| <= ``radius`` when centre is None."""
        return twist_map(self.motion(arb(centre) if centre is not None else arb(0, arb(radius).abs_upper())))

    def motion(self, x):
        """The joint's own transform (R, p) at the ball x of its variable."""
        if not self.revolute:
            return _identity(), self.axis * x
        k = _skew(self.axis)
        return _identity() + k * x.sin() + (k * k) * (1 - x.cos()), arb_mat(3, 1)


def _transform(data, where):
    """(R, p) of an origin {xyz, rpy}: R = Rz(yaw) Ry(pitch) Rx(roll) built here, p = xyz."""
    if not isinstance(data, dict) or set(data) != {"xyz", "rpy"}:
        raise BadCertificate(f"{where}: an origin {{xyz, rpy}}")
    xyz, rpy = (rational_matrix([data[k]], (1, 3), f"{where}.{k}")[0] for k in ("xyz", "rpy"))
    (cr, sr), (cp, sp), (cy, sy) = ((arb(a).cos(), arb(a).sin()) for a in rpy)
    r = arb_mat([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                 [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                 [-sp, cp * sr, cp * cr]])
    return r, arb_mat(3, 1, [arb(x) for x in xyz])


def _source(source):
    """The chain's source file (path as given, SHA-256), checked against the file where it is found here."""
    if source is None:
        return None
    if not (isinstance(source, dict) and set(source) == {"path", "sha256"} and isinstance(source["path"], str)
            and isinstance(source["sha256"], str) and len(source["sha256"]) == 64):
        raise BadCertificate("chain.source: {path, sha256}")
    path = Path(source["path"])
    if path.is_file() and hashlib.sha256(path.read_bytes()).hexdigest() != source["sha256"]:
        raise BadCertificate(f"chain.source: {path} is not the file the certificate is about (SHA-256 differs)")
    return path, source["sha256"], path.is_file()


def _composed(origins, where):
    """(R, p) of a list of origins applied one after the other."""
    if not isinstance(origins, list) or len(origins) > ORIGINS:
        raise BadCertificate(f"{where}: a list of at most {ORIGINS} origins")
    r, p = _identity(), arb_mat(3, 1)
    for i, data in enumerate(origins):
        ri, pi = _transform(data, f"{where}[{i}]")
        r, p = r * ri, p + r * pi
    return r, p


def _identity():
    return arb_mat(3, 3, [1, 0, 0, 0, 1, 0, 0, 0, 1])


def _skew(v):
    """S(v): S(v) x = v x x."""
    return arb_mat(3, 3, [0, -v[2, 0], v[1, 0], v[2, 0], 0, -v[0, 0], -v[1, 0], v[0, 0], 0])


class Chain:
    def __init__(self, data):
        joints = data.get("joints") if isinstance(data, dict) and set(data) <= {"name", "source", "joints"} else None
        if not isinstance(joints, list) or not joints or len(joints) > JOINTS:
            raise BadCertificate(f"chain: {{name, source, joints}}, a list of 1 to {JOINTS} joints")
        self.name, self.source = str(data.get("name", "chain")), _source(data.get("source"))
        self.joints = [Joint(j, f"chain.joints[{i}]") for i, j in enumerate(joints)]
        self.n = len(self.joints)

    def pivots(self, box, inertias, shift, metric=None, memo=None, top=None, stop=None):
        """Prove sum_l QJ_l^T Z_l QJ_l + shift I > 0 for every q in ``box`` (a list of (centre, radius) rationals),
        with Z_l the 6 x 6 ball matrices ``inertias``: (l, pivot l's ball) of the first pivot not proved positive,
        or (None, the smallest pivot).

        The pivots of the LDL^T decomposition from the tip are d_l = s_l^T A_l s_l + shift, with A_n = Z_n and
        A_(l-1) = Z_(l-1) + X_l^T (A_l - A_l s_l s_l^T A_l / d_l) X_l (articulated-body inertias with an
        armature ``shift``): s_l is joint l's column in body l's axes, X_l the twist map from body l-1 to body l,
        which depends on q_l alone. Both steps are monotone in the Loewner order, so a lower bound L_l of A_l
        over the box gives lower bounds of the pivots; the turn by q_l = c_l + delta, |delta| <= r_l, is bounded
        below by the turn by c_l less :func:`_turn_loss` (in the ``metric`` (kind, ridge) of
        :func:`_metric_factor`, or the identity). The last turn is seen only along the base joint's column: a
        scalar (:func:`_turned_form`).
        ``memo`` (a dict kept for one set of inertias, shift and metric) holds the recursion's state entering
        joint l by the coordinates beyond l: boxes that differ only in nearer coordinates share it. ``top``: the
        chain of joints 0..top only (body top's inertia as given); ``stop`` k: the pivots of joints beyond k only,
        returning (None, the lower bound of A_k) where they are positive."""
        top = self.n - 1 if top is None else top
        start, state = top, (inertias[top], None)
        if memo is not None:
            for l in range(stop or 0, top + 1):
                key = (l, tuple(box[l + 1:]))
                if key in memo:
                    start, state = l, memo[key]
                    break
        lower, smallest = state
        for l in range(start, -1, -1):
            if l == stop:
                return None, lower
            if memo is not None:
                memo[(l, tuple(box[l + 1:]))] = (lower, smallest)
            joint, (centre, radius) = self.joints[l], box[l]
            s = joint.subspace
            u = lower * s
            d = (s.transpose() * u)[0, 0] + shift
            if not d > 0:
                return l, d
            smallest = d if smallest is None or d.mid() < smallest.mid() else smallest
            if l == 1:
                base = self.joints[0].subspace
                w = joint.motion_map(centre) * joint.before_map * base
                t = _congruence(lower - u * u.transpose() / d, joint.after_map)
                d = (base.transpose() * inertias[0] * base)[0, 0] + _turned_form(joint, t, w, radius) + shift
                if not d > 0:
                    return 0, d
                return None, d if d.mid() < smallest.mid() else smallest
            if l:
                t = _congruence(lower - u * u.transpose() / d, joint.after_map)
                t = _congruence(t - _turn_loss(joint, t, radius, metric), joint.motion_map(centre))
                lower = inertias[l - 1] + _congruence(t, joint.before_map)
        return None, smallest


def definite(a):
    """Whether every symmetric matrix in the ball matrix ``a`` (its upper triangle read) is positive definite: every
    pivot of its LDL^T a positive ball."""
    n = a.nrows()
    s = [[a[min(i, j), max(i, j)] for j in range(n)] for i in range(n)]
    for k in range(n):
        if not s[k][k] > 0:
            return False
        for i in range(k + 1, n):
            f = s[i][k] / s[k][k]
            for j in range(k + 1, i + 1):
                s[i][j] -= f * s[k][j]
                s[j][i] = s[i][j]
    return True


def _subspace(joint):
    """Joint l's column of QJ_l in body l's axes: (a x w, w) for a turn, (w, 0) for a slide, with w its axis
    and a a point on it, seen from body l."""
    rt = joint.after[0].transpose()
    w = rt * joint.axis
    lin, ang = (_skew(-(rt * joint.after[1])) * w, w) if joint.revolute else (w, arb_mat(3, 1))
    return arb_mat(6, 1, [lin[i, 0] for i in range(3)] + [ang[i, 0] for i in range(3)])


def _blocks(a, b, c, d):
    return arb_mat([[a[i, j] for j in range(3)] + [b[i, j] for j in range(3)] for i in range(3)]
                   + [[c[i, j] for j in range(3)] + [d[i, j] for j in range(3)] for i in range(3)])


def twist_map(transform):
    """The map of twists (v, omega) of a parent frame to those of a child frame whose pose in the parent is
    (R, p): [[R^T, -R^T S(p)], [0, R^T]]."""
    r, p = transform
    rt = r.transpose()
    top = -(rt * _skew(p))
    return arb_mat([[rt[i, j] for j in range(3)] + [top[i, j] for j in range(3)] for i in range(3)]
                   + [[0, 0, 0] + [rt[i, j] for j in range(3)] for i in range(3)])


def _congruence(a, x):
    return x.transpose() * a * x


SMALL = 2**-20  # a term whose whitened size times its weight is below this is bounded by its norm alone (Panda's
# deep split: 2^-10 left 14% of the tail boxes the prover proved unproved, 2^-20 one in 500)


NEAR = 0.4  # radius (rad) up to which a turn's loss is taken about the centre's derivative, beyond by harmonics


def _turn_terms(joint, t, radius):
    """Terms (weight, kind, M) with X(delta)^T t X(delta) - t >= -sum weight W(M) for |delta| <= radius, W(M) >= +-M
    (kind "abs") or W(M) >= M, 0 ("pos").

    The joint's twist map by delta is I + s N + c N^2, s = sin delta, c = 1 - cos delta (N = -blockdiag(K, K),
    K = S(axis)); with s^2 = 2 c - c^2 the turned t is t + s G + c A + c^2 B + s c J, G = N^T t + t N,
    A = N^2 t + t N^2 + 2 H, B = N^2 t N^2 - H, J = N^T t N^2 + N^2 t N, H = N^T t N: coefficients of independent
    functions of delta, so all vanish for a t the turn leaves invariant. Up to NEAR, with |s| <= sin r and
    0 <= c <= 1 - cos r, as they stand (the first order is the centre's derivative); beyond, by harmonics:
    (G + J) sin d - J/2 sin 2d - (A + 2 B) (cos d - 1) + B/2 (cos 2d - 1). A slide by delta
    is I + delta N, N = [[0, -S(axis)], [0, 0]]: t + delta G + delta^2 H."""
    n_map, q_map = joint.generators
    r = arb(radius)
    g, h = n_map.transpose() * t + t * n_map, _congruence(t, n_map)
    if not joint.revolute:
        return [(r, "abs", g), (r * r, "pos", -h)]
    a = q_map * t + t * q_map + h * 2
    b = _congruence(t, q_map) - h
    j = n_map.transpose() * t * q_map + q_map * t * n_map
    if r < NEAR:
        sin1, cos1 = r.sin(), 1 - r.cos()
        return [(sin1, "abs", g), (cos1, "pos", -a), (cos1 * cos1, "pos", -b), (sin1 * cos1, "abs", j)]
    half = arb.pi() / 2
    sin1, sin2 = (x.sin() if x < half else arb(1) for x in (r, 2 * r))
    cos1, cos2 = (1 - x.cos() if x < 2 * half else arb(2) for x in (r, 2 * r))
    return [(sin1, "abs", g + j), (sin2 / 2, "abs", j), (cos1, "pos", -(a + b * 2)), (cos2 / 2, "pos", b)]


def _turn_loss(joint, t, radius, metric=None):
    """A bound L with X(delta)^T t X(delta) >= t - L for |delta| <= radius (see :meth:`Chain.pivots`): each term of
    :func:`_turn_terms` in a metric H = C C^T (``relative``: C from t's eigen-decomposition, shifted definite; else
    C = I; any invertible C is sound), W(M) = C Y C^T with Y >= +-X (or X, 0) for X = C^-1 M C^-T (:func:`_bounding`); a
    term whose loss is below SMALL in that metric as ||X||_F C C^T."""
    factor = _metric_factor(t, *metric) if metric else _scalar(arb(1), 6)
    total = arb_mat(6, 6)
    for weight, kind, m in _turn_terms(joint, t, radius):
        x = _whitened(factor, m)
        size = _frobenius(x) * arb(weight.abs_upper())
        total += _scalar(size, 6) if size < SMALL else _bounding(x, kind) * arb(weight.abs_upper())
    return factor * total * factor.transpose()


def _turned_form(joint, t, w, radius):
    """A lower bound of w^T X(delta)^T t X(delta) w over |delta| <= radius (:func:`_turn_terms`, as scalars)."""
    form = lambda a: (w.transpose() * a * w)[0, 0]
    loss = arb(0)
    for weight, kind, m in _turn_terms(joint, t, radius):
        v = form(m)
        bound = abs(v) if kind == "abs" else v.max(arb(0))
        loss += arb(weight.abs_upper()) * arb(bound.abs_upper())
    return form(t) - loss


def _whitened(c, a):
    return c.solve(c.solve(a).transpose()).transpose()


def _frobenius(a):
    sizes = [a[i, j].abs_upper() for i in range(a.nrows()) for j in range(a.ncols())]
    return arb(sum(x * x for x in sizes).sqrt().abs_upper())


def _scalar(x, n):
    return arb_mat([[x if i == j else 0 for j in range(n)] for i in range(n)])

def eigen(a):
    """Approximate eigenvalues (floats) and eigenvectors (a real ball matrix) of the symmetric a's midpoint."""
    values, vectors = a.mid().eig(right=True, algorithm="approx")
    n = a.nrows()
    return [float(v.real.mid()) for v in values], arb_mat([[vectors[i, j].real.mid() for j in range(n)]
                                                         for i in range(n)])


def _bounding(x, kind):
    """Y >= X and Y >= -X ("abs"), or Y >= X and Y >= 0 ("pos"): U f(S) U^T + ||X - U S U^T||_F I for the
    approximate eigen-decomposition U S U^T of X, f = |.| or max(., 0) (U f(S) U^T - U S U^T = U (f(S) - S) U^T
    >= 0 for any U, and so is U f(S) U^T + U S U^T for |.|)."""
    values, u = eigen(x)
    n = x.nrows()
    approx = u * _diagonal([arb(v) for v in values]) * u.transpose()
    f = abs if kind == "abs" else (lambda v: max(v, 0.0))
    return u * _diagonal([arb(f(v)) for v in values]) * u.transpose() + _scalar(_frobenius(x - approx), n)


def _diagonal(values):
    n = len(values)
    return arb_mat([[values[i] if i == j else 0 for j in range(n)] for i in range(n)])


def _metric_factor(t, kind, ridge):
    """C = V diag(h)^(1/2) from the approximate eigen-decomposition V diag(lambda) V^T of t: h = lambda shifted up so
    that the smallest is ``ridge`` times the largest |lambda| (``kind`` "shift"), or |lambda| plus that ("abs")."""
    values, v = eigen(t)
    top = ridge * (max(abs(x) for x in values) or 1.0)
    lift = top - min(min(values), 0.0)
    return v * _diagonal([arb(x + lift if kind == "shift" else abs(x) + top).sqrt() for x in values])
