"""The ``skew-partials`` claim (Theorem 5): for every q in ``domain`` and row p of QJ, Y_p = dK_p/dq - (dK_p/dq)^T,
K_p = (QJ)^T e_p (DefK): ``max_sigma`` sigma_max(Y_p(q)) <= bound; ``rss_sigma`` sum_p sigma_max(Y_p(q))^2 <= bound^2.

Column k of QJ_l is c_k = X_l .. X_(k+1) s_k; dX_m/dq_m = -ad(s_m) X_m (Ad a Lie algebra automorphism) gives dc_k/dq_m
= [c_k, c_m] for k < m <= l, [a, b] = (w_a x v_b - w_b x v_a, w_a x w_b): Y_p[k, j] is component p of [c_k, c_j],
its derivative in q_i that of [[c_k, c_i], c_j] (k < i) + [c_k, [c_j, c_i]] (j < i). Y_p is skew, so
sigma_max(Y_p)^2 <= g_p = sum_(k<j) Y_p[k, j]^2 (equal up to 3 x 3). On a box (centre c, radii r) g_p(q) <= g_p(c) +
sum_i r_i |dg_p/dq_i| (mean value theorem, the derivative enclosed over the box); beyond 3 x 3 it may instead be
[[bound I, -Y], [-Y^T, bound I]] > 0 over Y_p's mean-value enclosure. A point refutes where a lower bound of
sigma_max(Y_p)^2 (g_p up to 3 x 3, else a Rayleigh quotient of Y_p^T Y_p), or of its sum over p, exceeds bound^2.
"""

from flint import arb, arb_mat

from . import tree
from .exact import unproved_pivot
from .kinematics import eigen
from .outcome import refuted

ZERO = arb(0)


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _bracket(a, b):
    return [x - y for x, y in zip(_cross(a[3:], b[:3]), _cross(b[3:], a[:3]))] + _cross(a[3:], b[3:])


def _rows(chain, centres, delta=None):
    """Per row p (body l, component): (l + 1, Y_p's entries {(k, j): ball} for k < j, their derivatives in q_0..q_l)
    at the point ``centres`` (no derivatives), or over it plus the balls ``delta``."""
    xs = [arb(c) + d for c, d in zip(centres, delta or [0] * len(centres))]
    out, cols = [], []
    for l, joint in enumerate(chain.joints):
        if l:
            x = joint.after_map * joint.turn(xs[l]) * joint.before_map
            cols = [[sum((x[i, m] * c[m] for m in range(6)), ZERO) for i in range(6)] for c in cols]
        cols.append([joint.subspace[i, 0] for i in range(6)])
        d = {(k, j): _bracket(cols[k], cols[j]) for j in range(l + 1) for k in range(j)}
        dd = [{(k, j): [a + b for a, b in zip(_bracket(d[k, i], cols[j]) if k < i else [ZERO] * 6,
                                              _bracket(cols[k], d[j, i]) if j < i else [ZERO] * 6)] for k, j in d}
              for i in range(l + 1) if delta]
        out += [(l + 1, {kj: v[p] for kj, v in d.items()}, [{kj: v[p] for kj, v in e.items()} for e in dd])
                for p in range(6)]
    return out


def _full(y, m):
    return arb_mat([[y.get((k, j), -y[j, k] if j < k else 0) for j in range(m)] for k in range(m)])


def _lower(y, m):
    """A ball whose lower end bounds sigma_max(Y)^2 from below, Y the point enclosure ``y``."""
    if m <= 3:
        return sum((v * v for v in y.values()), ZERO)
    a = _full(y, m).transpose() * _full(y, m)
    values, u = eigen(a)
    v = arb_mat([[u[i, values.index(max(values))]] for i in range(m)])
    return (v.transpose() * a * v)[0, 0] / (v.transpose() * v)[0, 0]


def _below(y, bound):
    """Whether sigma_max(Y) < bound for every Y in the ball matrix y: [[bound I, -Y], [-Y^T, bound I]] > 0."""
    m = y.nrows()
    return unproved_pivot([[bound if i == j else -y[j, i - m] if j < m <= i else 0 for j in range(2 * m)]
                           for i in range(2 * m)]) is None


def _test(chain, box, bound, rss):
    """(whether the claim holds on the box, the weights r_i |dg/dq_i| of its coordinates: where to cut)."""
    n, square = len(box), bound**2
    centres, delta = [c for c, _ in box], [arb(0, arb(r).abs_upper()) for _, r in box]
    spread = lambda ds: sum((d * t for d, t in zip(ds, delta)), ZERO)  # noqa: E731
    weigh = lambda ds: [float(r) * float(abs(d).abs_upper()) for (_, r), d in zip(box, ds)]  # noqa: E731
    total, slopes = ZERO, [ZERO] * n
    for (m, yc, _), (_, yb, dy) in zip(_rows(chain, centres), _rows(chain, centres, delta)):
        g = sum((v * v for v in yc.values()), ZERO)
        dg = [sum((2 * yb[kj] * e[kj] for kj in yb), ZERO) for e in dy] + [ZERO] * (n - m)
        if not rss and not g + spread(dg) <= square and (m <= 3 or not _below(
                _full({kj: v + spread([e[kj] for e in dy]) for kj, v in yc.items()}, m), bound)):
            return False, weigh(dg)
        total, slopes = total + g, [s + t for s, t in zip(slopes, dg)]
    return not rss or total + spread(slopes) <= square, weigh(slopes)


class Problem(tree.Claim):
    """A parsed skew-partials claim: its tree, the test of a box and how a point refutes it."""

    def __init__(self, cert):
        super().__init__(cert, {"schema", "claim", "chain", "domain", "tree", "witness", "provenance"},
                         ("max_sigma", "rss_sigma"))
        self.rss = self.quantity == "rss_sigma"

    def refute(self, point, why, boxes=0):
        """A refutation at ``point``: a lower bound of sigma_max(Y_p)^2 (or of its sum over p) above bound^2."""
        lows = [_lower(y, m) for m, y, _ in _rows(self.chain, point)]
        bad = [(None, sum(lows, ZERO))] if self.rss else [(p, v) for p, v in enumerate(lows) if v > self.bound**2]
        if bad and bad[0][1] > self.bound**2:
            what = "sum_p sigma_max(Y_p)^2" if self.rss else f"sigma_max(Y_p)^2 of row p = {bad[0][0] + 1}"
            return refuted(f"{why}: {what} >= {bad[0][1].lower().str(10, radius=False)} > bound^2",
                           {"q": [str(x) for x in point]}, {"lower": bad[0][1].str(10), "bound^2": str(self.bound**2)},
                           boxes)
        return None

    def walks(self):
        """[(label, name, root, test)]: ``test`` maps a box to (None, "") where the claim holds on it, else (the
        coordinates to cut, largest r_i |dg/dq_i| first; why)."""
        bound = arb(self.bound)

        def test(box):
            holds, weights = _test(self.chain, box, bound, self.rss)
            return (None, "") if holds else (tree.widest(weights, range(self.chain.n)),
                                             "the mean-value bound exceeds bound^2")
        return [("the tree", "tree", self.root, test)]


def prove(cert):
    """The :class:`Outcome` of the certificate's claim: every leaf of its tree proved, or where it is not."""
    problem = Problem(cert)
    if problem.bound < 0:
        return refuted("the bound is negative and every sigma_max(Y_p(q)) is >= 0",
                       {"q": [str(c) for c, _ in problem.root.balls()]}, {"lower": "0", "bound": str(problem.bound)})
    found = problem.witness is not None and problem.refute(problem.witness, "at the witness q")
    return found or tree.prove(problem, problem.walks())
