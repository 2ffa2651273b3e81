"""A serial chain of a certificate, and M(q, Theta) + shift I proved positive definite over a box of configurations.

Joint l is a fixed transform ``before``, a turn about (slide along) its ``axis`` by q_l and a fixed ``after``, a
fixed transform a list of URDF origins {xyz, rpy} (decimals, read exactly) composed in order; each rotation Rz(yaw)
Ry(pitch) Rx(roll) is built with arb's sin and cos, so every transform is rigid and R^T its inverse. M(q, Theta) =
sum_l QJ_l^T Z(Phi_l) QJ_l (MassMatrix, DefMatrixZ; QJ_l's rows the twist (R_l^T v_l, omega_l) of body l,
VelocityRigidMass) is never formed: :meth:`Chain.pivots` factors it from the tip.
"""

import hashlib
from pathlib import Path

from flint import arb, arb_mat

from .exact import fields, need, unproved_pivot, vector

JOINTS, ORIGINS = 200, 64  # the longest chain a certificate may describe; the most origins of one fixed transform
SMALL = 2**-20  # a term whose whitened size times its weight is below this is bounded by its norm alone
NEAR = 0.4  # radius (rad) up to which a turn's loss is taken about the centre's derivative, beyond by harmonics
KINDS = ("revolute", "prismatic")


class Joint:
    def __init__(self, data, where):
        fields(data, ("kind", "axis", "before", "after"), where, optional=("name", "limits"))
        need(data["kind"] in KINDS, f"{where}.kind: one of {list(KINDS)}, not {data['kind']!r}")
        self.revolute = data["kind"] == "revolute"
        axis = [arb(x) for x in vector(data["axis"], 3, f"{where}.axis")]
        norm = sum(a * a for a in axis).sqrt()
        need(norm > 0, f"{where}.axis: the axis must be a nonzero vector")
        self.axis = arb_mat(3, 1, [a / norm for a in axis])
        self.before, self.after = (_composed(data[k], f"{where}.{k}") for k in ("before", "after"))
        self.limits = data.get("limits") and tuple(vector(data["limits"], 2, f"{where}.limits"))
        need(not self.limits or self.limits[0] <= self.limits[1], f"{where}.limits: lower > upper")
        self.before_map, self.after_map = _twist_map(self.before), _twist_map(self.after)
        k, zero = _skew(self.axis), arb_mat(3, 3)
        n_map = _blocks(-k, zero, zero, -k) if self.revolute else _blocks(zero, -k, zero, zero)
        self.generators = n_map, n_map * n_map  # N and N^2 of the twist map by delta (see _turn_matrices)
        rt = self.after[0].transpose()  # the column of QJ_l in body l's axes: (a x w, w) of a turn, (w, 0) of a slide
        w = rt * self.axis
        lin, ang = (_skew(-(rt * self.after[1])) * w, w) if self.revolute else (w, arb_mat(3, 1))
        self.subspace = arb_mat(6, 1, [x[i, 0] for x in (lin, ang) for i in range(3)])

    def turn(self, x):
        """The twist map of the joint's own transform at the ball x of its variable."""
        k, eye = _skew(self.axis), _diagonal([1] * 3)
        return _twist_map((eye + k * x.sin() + (k * k) * (1 - x.cos()), arb_mat(3, 1)) if self.revolute
                          else (eye, self.axis * x))


def _composed(origins, where):
    """(R, p) of a list of origins {xyz, rpy} applied in order."""
    need(isinstance(origins, list) and len(origins) <= ORIGINS, f"{where}: a list of at most {ORIGINS} origins")
    r, p = _diagonal([1] * 3), arb_mat(3, 1)
    for i, data in enumerate(origins):
        xyz, rpy = (vector(fields(data, ("xyz", "rpy"), f"{where}[{i}]")[k], 3, f"{where}[{i}].{k}")
                    for k in ("xyz", "rpy"))
        (cr, sr), (cp, sp), (cy, sy) = ((arb(a).cos(), arb(a).sin()) for a in rpy)
        ri = arb_mat([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                      [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], [-sp, cp * sr, cp * cr]])
        r, p = r * ri, p + r * arb_mat(3, 1, [arb(x) for x in xyz])
    return r, p


class Chain:
    """The certificate's ``joints``; its ``source`` {path, sha256}, where that file is found here, must match it."""

    def __init__(self, data):
        joints = fields(data, ("joints",), "chain", optional=("name", "source"))["joints"]
        need(isinstance(joints, list) and 0 < len(joints) <= JOINTS, f"chain.joints: a list of 1 to {JOINTS} joints")
        source = data.get("source")
        if source is not None:
            path, sha = fields(source, ("path", "sha256"), "chain.source")["path"], source["sha256"]
            need(isinstance(path, str) and isinstance(sha, str) and len(sha) == 64, "chain.source: strings")
            need(not Path(path).is_file() or hashlib.sha256(Path(path).read_bytes()).hexdigest() == sha,
                 f"chain.source: {path} is not the file the certificate is about (SHA-256 differs)")
        self.joints = [Joint(j, f"chain.joints[{i}]") for i, j in enumerate(joints)]
        self.n = len(self.joints)

    def pivots(self, box, inertias, shift, metric=None, memo=None, top=None, stop=None):
        """(l, pivot l) of the first pivot of sum_l QJ_l^T Z_l QJ_l + shift I (Z_l the ball matrices ``inertias``)
        not proved positive over ``box`` ((centre, radius) rationals), or (None, the smallest pivot).

        From the tip, d_l = s_l^T A_l s_l + shift, A_top = Z_top, A_(l-1) = Z_(l-1) + X_l^T (A_l - A_l s_l s_l^T A_l
        / d_l) X_l (articulated-body inertias): s_l is joint l's column in body l's axes, X_l the twist map from body
        l-1 to body l. Both steps are Loewner-monotone, so a lower bound of A_l bounds the pivots below; the turn by
        q_l = c_l + delta is bounded below by the turn by c_l less :func:`_turn_loss` in the ``metric`` (kind, ridge),
        the last one along joint 0's column only (:func:`_turned_form`). ``memo`` (for one set of inertias, shift and
        metric) keeps the state entering joint l, and the turn's loss pieces, by the coordinates beyond l. ``top``:
        the chain of joints 0..top; ``stop`` k: the pivots beyond k only, then (None, the lower bound of A_k)."""
        memo, top = {} if memo is None else memo, self.n - 1 if top is None else top
        marks = tuple((c.p, c.q, r.p, r.q) for c, r in box)  # fmpq hashes slowly
        start = next((l for l in range(stop or 0, top + 1) if (l, marks[l + 1:]) in memo), top)
        lower, smallest = memo.get((start, marks[start + 1:]), (inertias[top], None))
        for l in range(start, -1, -1):
            if l == stop:
                return None, lower
            memo[l, marks[l + 1:]] = lower, smallest
            joint, (centre, radius) = self.joints[l], box[l]
            u = lower * joint.subspace
            d = (joint.subspace.transpose() * u)[0, 0] + shift
            if not d > 0:
                return l, d
            smallest = _least(d, smallest)
            if not l:
                return None, smallest
            t = _congruence(lower - u * u.transpose() / d, joint.after_map)
            if l == 1:  # joint 0's pivot: joint 1's turn seen along joint 0's column only, a scalar
                base = self.joints[0].subspace
                w = joint.turn(arb(centre)) * joint.before_map * base
                d = (base.transpose() * inertias[0] * base)[0, 0] + _turned_form(joint, t, w, radius) + shift
                return (0, d) if not d > 0 else (None, _least(d, smallest))
            pieces = memo.setdefault(("loss", l, marks[l + 1:], _near(joint, radius)), {})
            t = _congruence(t - _turn_loss(joint, t, radius, metric, pieces), joint.turn(arb(centre)))
            lower = inertias[l - 1] + _congruence(t, joint.before_map)


def definite(a):
    """Whether every symmetric matrix in the ball matrix ``a`` (its upper triangle read) is positive definite."""
    return unproved_pivot([[a[min(i, j), max(i, j)] for j in range(a.ncols())] for i in range(a.nrows())]) is None


def _least(d, smallest):
    return d if smallest is None or d.mid() < smallest.mid() else smallest


def _skew(v):
    """S(v): S(v) x = v x x."""
    return arb_mat(3, 3, [0, -v[2, 0], v[1, 0], v[2, 0], 0, -v[0, 0], -v[1, 0], v[0, 0], 0])


def _diagonal(values):
    return arb_mat([[v if i == j else 0 for j in range(len(values))] for i, v in enumerate(values)])


def _blocks(*quarters):
    """The 6 x 6 matrix [[a, b], [c, d]] of the 3 x 3 ``quarters`` a, b, c, d."""
    return arb_mat([[quarters[2 * (i // 3) + j // 3][i % 3, j % 3] for j in range(6)] for i in range(6)])


def _twist_map(transform):
    """[[R^T, -R^T S(p)], [0, R^T]]: twists (v, omega) of a parent frame to those of a child frame at (R, p)."""
    r, p = transform
    rt = r.transpose()
    return _blocks(rt, -(rt * _skew(p)), arb_mat(3, 3), rt)


def _congruence(a, x):
    return x.transpose() * a * x


def _near(joint, radius):
    """Whether a turn by up to ``radius`` takes its loss about the centre's derivative (else by harmonics)."""
    return joint.revolute and arb(radius) < NEAR


def _turn_matrices(joint, t, near):
    """(kind, M) of the terms of X(delta)^T t X(delta) - t >= -sum_i w_i W(M_i) for |delta| <= radius, with the
    weights w_i of :func:`_turn_weights` and W(M) >= +-M (kind "abs") or W(M) >= M, 0 ("pos").

    The twist map by delta is I + s N + c N^2, s = sin delta, c = 1 - cos delta (N = -blockdiag(K, K), K =
    S(axis)); with s^2 = 2 c - c^2 the turned t is t + s G + c A + c^2 B + s c J, G = N^T t + t N, A = N^2 t +
    t N^2 + 2 H, B = N^2 t N^2 - H, J = N^T t N^2 + N^2 t N, H = N^T t N. ``near`` (up to NEAR) with |s| <= sin r,
    0 <= c <= 1 - cos r; beyond by harmonics: (G + J) sin d - J/2 sin 2d - (A + 2 B) (cos d - 1) + B/2 (cos 2d -
    1). A slide by delta is I + delta N, N = [[0, -S(axis)], [0, 0]]: t + delta G + delta^2 H."""
    n_map, q_map = joint.generators
    g, h = n_map.transpose() * t + t * n_map, _congruence(t, n_map)
    if not joint.revolute:
        return [("abs", g), ("pos", -h)]
    a = q_map * t + t * q_map + h * 2
    b = _congruence(t, q_map) - h
    j = n_map.transpose() * t * q_map + q_map * t * n_map
    if near:
        return [("abs", g), ("pos", -a), ("pos", -b), ("abs", j)]
    return [("abs", g + j), ("abs", j), ("pos", -(a + b * 2)), ("pos", b)]


def _turn_weights(joint, radius):
    """The weights (upper ends) of :func:`_turn_matrices`' terms for |delta| <= radius."""
    r = arb(radius)
    if not joint.revolute:
        weights = [r, r * r]
    elif _near(joint, radius):
        sin1, cos1 = r.sin(), 1 - r.cos()
        weights = [sin1, cos1, cos1 * cos1, sin1 * cos1]
    else:
        half = arb.pi() / 2
        sin1, sin2 = (x.sin() if x < half else arb(1) for x in (r, 2 * r))
        cos1, cos2 = (1 - x.cos() if x < 2 * half else arb(2) for x in (r, 2 * r))
        weights = [sin1, sin2 / 2, cos1, cos2 / 2]
    return [arb(w.abs_upper()) for w in weights]


def _turn_loss(joint, t, radius, metric, pieces):
    """L with X(delta)^T t X(delta) >= t - L for |delta| <= radius: each term M of :func:`_turn_matrices` bounded
    in a metric C C^T (C from t by :func:`_metric_factor`, or I; any invertible C is sound) as W(M) = C Y C^T, Y >=
    +-X (or X, 0) for X = C^-1 M C^-T (:func:`_bounding`), or as ||X||_F C C^T where its weight times ||X||_F is
    below SMALL. ``pieces`` (empty, or filled for the same t, metric and branch) keeps C, X, ||X||_F and Y."""
    if not pieces:
        pieces["factor"] = factor = _metric_factor(t, *metric) if metric else None
        inverse = factor.inv() if metric else None
        whitened = [(kind, inverse * m * inverse.transpose() if metric else m)
                    for kind, m in _turn_matrices(joint, t, _near(joint, radius))]
        pieces["terms"] = [[kind, x, _frobenius(x), None] for kind, x in whitened]
    total = arb_mat(6, 6)
    for weight, term in zip(_turn_weights(joint, radius), pieces["terms"]):
        kind, x, frobenius, bounding = term
        size = frobenius * weight
        if size < SMALL:
            total += _diagonal([size] * 6)
        else:
            term[3] = bounding = _bounding(x, kind) if bounding is None else bounding
            total += bounding * weight
    factor = pieces["factor"]
    return factor * total * factor.transpose() if metric else total


def _turned_form(joint, t, w, radius):
    """A lower bound of w^T X(delta)^T t X(delta) w over |delta| <= radius: :func:`_turn_matrices` as scalars."""
    form = lambda a: (w.transpose() * a * w)[0, 0]  # noqa: E731
    loss = arb(0)
    for weight, (kind, m) in zip(_turn_weights(joint, radius), _turn_matrices(joint, t, _near(joint, radius))):
        v = form(m)
        loss += weight * arb((abs(v) if kind == "abs" else v.max(arb(0))).abs_upper())
    return form(t) - loss


def _frobenius(a):
    """A ball >= ||A||_F for every A in the ball matrix a: the root of the upper end of tr(a^T a)."""
    return arb((a.transpose() * a).trace().abs_upper()).sqrt()


def eigen(a):
    """Approximate eigenvalues (floats) and eigenvectors (a real ball matrix) of the symmetric a's midpoint."""
    values, vectors = a.mid().eig(right=True, algorithm="approx")
    return [float(v.real.mid()) for v in values], arb_mat(a.nrows(), a.ncols(),
                                                         [x.real.mid() for x in vectors.entries()])


def _bounding(x, kind):
    """Y >= X and Y >= -X ("abs"), or Y >= X and Y >= 0 ("pos"): U f(S) U^T + ||X - U S U^T||_F I for the
    approximate eigen-decomposition U S U^T of X, f = |.| or max(., 0) (U (f(S) - S) U^T >= 0 for any U, and so is
    U f(S) U^T + U S U^T for |.|)."""
    values, u = eigen(x)
    f = abs if kind == "abs" else (lambda v: max(v, 0.0))
    rest = x - u * _diagonal([arb(v) for v in values]) * u.transpose()
    return u * _diagonal([arb(f(v)) for v in values]) * u.transpose() + _diagonal([_frobenius(rest)] * x.nrows())


def _metric_factor(t, kind, ridge):
    """C = V diag(h)^(1/2) from the approximate eigen-decomposition V diag(lambda) V^T of t: h = lambda shifted up so
    that the smallest is ``ridge`` times the largest |lambda| (``kind`` "shift"), or |lambda| plus that ("abs")."""
    values, v = eigen(t)
    top = ridge * (max(abs(x) for x in values) or 1.0)
    lift = top - min(min(values), 0.0)
    return v * _diagonal([arb(x + lift if kind == "shift" else abs(x) + top).sqrt() for x in values])
