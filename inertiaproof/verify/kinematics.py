"""A serial chain of a certificate, and M(q, Theta) + shift I proved positive definite over a box of configurations.

Joint l has a fixed transform ``before``, a turn about (slide along) its ``axis`` by q_l and a fixed ``after``:
T_l = T_(l-1) before_l X_l(q_l) after_l. A fixed transform is a list of URDF origins {xyz, rpy} (decimals, read
exactly) composed in order; the checker builds each rotation Rz(yaw) Ry(pitch) Rx(roll) with arb's sin and cos, so
every transform is rigid by construction and R^T is its inverse. M(q, Theta) = sum_l QJ_l^T Z(Phi_l) QJ_l
(MassMatrix, DefMatrixZ), QJ_l's rows the twist (R_l^T v_l, omega_l) of body l (VelocityRigidMass), is never
formed: :meth:`Chain.pivots` factors it from the tip as articulated-body inertias.
"""

import hashlib
from pathlib import Path

from flint import arb, arb_mat

from .exact import need, unproved_pivot, vector

JOINTS, ORIGINS = 200, 64  # the longest chain a certificate may describe; the most origins of one fixed transform
SMALL = 2**-20  # a term whose whitened size times its weight is below this is bounded by its norm alone
NEAR = 0.4  # radius (rad) up to which a turn's loss is taken about the centre's derivative, beyond by harmonics


class Joint:
    def __init__(self, data, where):
        need(isinstance(data, dict) and set(data) <= {"name", "kind", "axis", "before", "after", "limits"},
             f"{where}: a joint is an object of name, kind, axis, before, after and limits")
        self.revolute = {"revolute": True, "prismatic": False}.get(data.get("kind"))
        need(self.revolute is not None, f"{where}.kind: 'revolute' or 'prismatic', not {data.get('kind')!r}")
        axis = [arb(x) for x in vector(data.get("axis"), 3, f"{where}.axis")]
        norm = sum(a * a for a in axis).sqrt()
        need(norm > 0, f"{where}.axis: the axis must be a nonzero vector")
        self.axis = arb_mat(3, 1, [a / norm for a in axis])
        self.before, self.after = (_composed(data.get(k), f"{where}.{k}") for k in ("before", "after"))
        self.limits = data.get("limits") and tuple(vector(data["limits"], 2, f"{where}.limits"))
        need(not self.limits or self.limits[0] <= self.limits[1], f"{where}.limits: lower > upper")
        self.before_map, self.after_map = twist_map(self.before), twist_map(self.after)
        k, zero = _skew(self.axis), arb_mat(3, 3)
        n_map = _blocks(-k, zero, zero, -k) if self.revolute else _blocks(zero, -k, zero, zero)
        self.generators = n_map, n_map * n_map  # N and N^2 of the twist map by delta (see _turn_matrices)
        rt = self.after[0].transpose()  # the column of QJ_l in body l's axes: (a x w, w) of a turn, (w, 0) of a slide
        w = rt * self.axis
        lin, ang = (_skew(-(rt * self.after[1])) * w, w) if self.revolute else (w, arb_mat(3, 1))
        self.subspace = arb_mat(6, 1, [lin[i, 0] for i in range(3)] + [ang[i, 0] for i in range(3)])

    def motion(self, x):
        """The joint's own transform (R, p) at the ball x of its variable."""
        if not self.revolute:
            return _diagonal([1] * 3), self.axis * x
        k = _skew(self.axis)
        return _diagonal([1] * 3) + k * x.sin() + (k * k) * (1 - x.cos()), arb_mat(3, 1)


def _composed(origins, where):
    """(R, p) of a list of origins {xyz, rpy} applied in order, each R = Rz(yaw) Ry(pitch) Rx(roll) built here."""
    need(isinstance(origins, list) and len(origins) <= ORIGINS, f"{where}: a list of at most {ORIGINS} origins")
    r, p = _diagonal([1] * 3), arb_mat(3, 1)
    for i, data in enumerate(origins):
        need(isinstance(data, dict) and set(data) == {"xyz", "rpy"}, f"{where}[{i}]: an origin {{xyz, rpy}}")
        xyz, rpy = (vector(data[k], 3, f"{where}[{i}].{k}") for k in ("xyz", "rpy"))
        (cr, sr), (cp, sp), (cy, sy) = ((arb(a).cos(), arb(a).sin()) for a in rpy)
        ri = arb_mat([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                      [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr], [-sp, cp * sr, cp * cr]])
        r, p = r * ri, p + r * arb_mat(3, 1, [arb(x) for x in xyz])
    return r, p


def _source(source):
    """The chain's source file (path as given, SHA-256), checked against the file where it is found here."""
    if source is None:
        return None
    need(isinstance(source, dict) and set(source) == {"path", "sha256"} and isinstance(source["path"], str)
         and isinstance(source["sha256"], str) and len(source["sha256"]) == 64, "chain.source: {path, sha256}")
    path = Path(source["path"])
    need(not path.is_file() or hashlib.sha256(path.read_bytes()).hexdigest() == source["sha256"],
         f"chain.source: {path} is not the file the certificate is about (SHA-256 differs)")
    return path, source["sha256"], path.is_file()


def _skew(v):
    """S(v): S(v) x = v x x."""
    return arb_mat(3, 3, [0, -v[2, 0], v[1, 0], v[2, 0], 0, -v[0, 0], -v[1, 0], v[0, 0], 0])


class Chain:
    def __init__(self, data):
        joints = data.get("joints") if isinstance(data, dict) and set(data) <= {"name", "source", "joints"} else None
        need(isinstance(joints, list) and 0 < len(joints) <= JOINTS,
             f"chain: {{name, source, joints}}, a list of 1 to {JOINTS} joints")
        self.name, self.source = str(data.get("name", "chain")), _source(data.get("source"))
        self.joints = [Joint(j, f"chain.joints[{i}]") for i, j in enumerate(joints)]
        self.n = len(self.joints)

    def pivots(self, box, inertias, shift, metric=None, memo=None, top=None, stop=None):
        """Prove sum_l QJ_l^T Z_l QJ_l + shift I > 0 for every q in ``box`` ((centre, radius) rationals), Z_l the
        6 x 6 ball matrices ``inertias``: (l, pivot l's ball) of the first pivot not proved positive, or (None, the
        smallest pivot).

        The pivots of the LDL^T decomposition from the tip are d_l = s_l^T A_l s_l + shift, A_n = Z_n and A_(l-1) =
        Z_(l-1) + X_l^T (A_l - A_l s_l s_l^T A_l / d_l) X_l (articulated-body inertias with an armature): s_l is
        joint l's column in body l's axes, X_l the twist map from body l-1 to body l (a function of q_l). Both steps
        are Loewner-monotone, so a lower bound of A_l over the box bounds the pivots below; the turn by q_l = c_l +
        delta, |delta| <= r_l, is bounded below by the turn by c_l less :func:`_turn_loss` in the ``metric`` (kind,
        ridge). The last turn is seen only along the base joint's column: a scalar (:func:`_turned_form`). ``memo``
        (for one set of inertias, shift and metric) holds the state entering joint l by the coordinates beyond l.
        ``top``: the chain of joints 0..top only; ``stop`` k: the pivots beyond k only, returning (None, the lower
        bound of A_k) where they are positive."""
        top = self.n - 1 if top is None else top
        start, state = top, (inertias[top], None)
        marks = memo is not None and tuple((c.p, c.q, r.p, r.q) for c, r in box)  # fmpq hashes slowly
        for l in range(stop or 0, top + 1) if memo is not None else ():
            if (l, marks[l + 1:]) in memo:
                start, state = l, memo[l, marks[l + 1:]]
                break
        lower, smallest = state
        for l in range(start, -1, -1):
            if l == stop:
                return None, lower
            if memo is not None:
                memo[l, marks[l + 1:]] = (lower, smallest)
            joint, (centre, radius) = self.joints[l], box[l]
            s = joint.subspace
            u = lower * s
            d = (s.transpose() * u)[0, 0] + shift
            if not d > 0:
                return l, d
            smallest = d if smallest is None or d.mid() < smallest.mid() else smallest
            if not l:
                break
            t = _congruence(lower - u * u.transpose() / d, joint.after_map)
            if l == 1:
                base = self.joints[0].subspace
                w = twist_map(joint.motion(arb(centre))) * joint.before_map * base
                d = (base.transpose() * inertias[0] * base)[0, 0] + _turned_form(joint, t, w, radius) + shift
                return (0, d) if not d > 0 else (None, d if d.mid() < smallest.mid() else smallest)
            pieces = memo.setdefault(("loss", l, marks[l + 1:], _near(joint, radius)), {}) if memo is not None else {}
            t = _congruence(t - _turn_loss(joint, t, radius, metric, pieces), twist_map(joint.motion(arb(centre))))
            lower = inertias[l - 1] + _congruence(t, joint.before_map)
        return None, smallest


def definite(a):
    """Whether every symmetric matrix in the ball matrix ``a`` (its upper triangle read) is positive definite."""
    return unproved_pivot([[a[min(i, j), max(i, j)] for j in range(a.ncols())] for i in range(a.nrows())]) is None


def _blocks(a, b, c, d):
    return arb_mat([[a[i, j] for j in range(3)] + [b[i, j] for j in range(3)] for i in range(3)]
                   + [[c[i, j] for j in range(3)] + [d[i, j] for j in range(3)] for i in range(3)])


def twist_map(transform):
    """The map of twists (v, omega) of a parent frame to those of a child frame at (R, p) in it:
    [[R^T, -R^T S(p)], [0, R^T]]."""
    r, p = transform
    rt = r.transpose()
    return _blocks(rt, -(rt * _skew(p)), arb_mat(3, 3), rt)


def _congruence(a, x):
    return x.transpose() * a * x


def _near(joint, radius):
    """Whether a turn by up to ``radius`` takes its loss about the centre's derivative (else by harmonics)."""
    return joint.revolute and arb(radius) < NEAR


def _turn_matrices(joint, t, near):
    """(kind, M) of the terms of :func:`_turn_weights`: X(delta)^T t X(delta) - t >= -sum weight W(M) for |delta|
    <= radius, W(M) >= +-M (kind "abs") or W(M) >= M, 0 ("pos").

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
    """The weights of :func:`_turn_matrices`' terms for |delta| <= radius, upper ends."""
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


def _turn_loss(joint, t, radius, metric=None, pieces=None):
    """A bound L with X(delta)^T t X(delta) >= t - L for |delta| <= radius: each term of :func:`_turn_matrices` in a
    metric H = C C^T (``metric``: C from t's eigen-decomposition, :func:`_metric_factor`; else C = I; any invertible
    C is sound), W(M) = C Y C^T with Y >= +-X (or X, 0) for X = C^-1 M C^-T (:func:`_bounding`); a term whose loss
    is below SMALL as ||X||_F C C^T. ``pieces`` (a dict, empty or filled by an earlier call with the same t, metric
    and branch) keeps C, each X, ||X||_F and Y, which do not depend on the radius."""
    pieces = {} if pieces is None else pieces
    if "terms" not in pieces:
        factor = _metric_factor(t, *metric) if metric else None
        inverse = factor.inv() if metric else None
        pieces["factor"], pieces["terms"] = factor, []
        for kind, m in _turn_matrices(joint, t, _near(joint, radius)):
            x = inverse * m * inverse.transpose() if metric else m
            pieces["terms"].append([kind, x, _frobenius(x), None])
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
    """A lower bound of w^T X(delta)^T t X(delta) w over |delta| <= radius (:func:`_turn_matrices`, as scalars)."""
    form = lambda a: (w.transpose() * a * w)[0, 0]  # noqa: E731
    loss = arb(0)
    for weight, (kind, m) in zip(_turn_weights(joint, radius), _turn_matrices(joint, t, _near(joint, radius))):
        v = form(m)
        loss += weight * arb((abs(v) if kind == "abs" else v.max(arb(0))).abs_upper())
    return form(t) - loss


def _frobenius(a):
    """A ball >= ||A||_F for every A in the ball matrix a: the root of the upper end of tr(a^T a)."""
    return arb((a.transpose() * a).trace().abs_upper()).sqrt()


def _diagonal(values):
    out = arb_mat(len(values), len(values))
    for i, v in enumerate(values):
        out[i, i] = v
    return out


def eigen(a):
    """Approximate eigenvalues (floats) and eigenvectors (a real ball matrix) of the symmetric a's midpoint."""
    values, vectors = a.mid().eig(right=True, algorithm="approx")
    n = a.nrows()
    return [float(v.real.mid()) for v in values], arb_mat([[vectors[i, j].real.mid() for j in range(n)]
                                                         for i in range(n)])


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
