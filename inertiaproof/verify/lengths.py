"""An upper side of lambda_max(M(q, Theta)) for every q of a box, from the chain's lengths and the bodies' inertias
alone: the checker's own route to an upper claim that no tree of boxes could prove on a long chain.

Column k of QJ_b (body b >= k) is joint k's column s_k carried to body b by the twist maps X_(k+1), ..., X_b of
:mod:`.kinematics`. A map [[R^T, -R^T S(p)], [0, R^T]] takes (v, w) with |v| <= L, |w| <= A to one with
|v| <= L + |p| A, |w| <= A: every R is a rotation, built by the checker from rpy (and a joint's own turn is one,
p = 0), and its slide by |q| <= r is p = axis q. With the blocks of Z_b bounded in the 2-norm by a, b, c (:func:`_block_norms`),
|x^T Z_b y| <= a L_x L_y + b (L_x A_y + A_x L_y) + c A_x A_y, so |M_il(q)| <= S_il = the sum over b >= max(i, l)
(MassMatrix); in the term b = l, x_l is s_l itself: |x_i^T Z_l s_l| <= L |(Z_l s_l)_v| + A |(Z_l s_l)_w|, and
s_l^T Z_l s_l exactly when i = l. Then |lambda|_max(M(q)) <= rho(|M(q)|) <= rho(S) <= max_i (S x)_i / x_i for any x > 0
(Perron-Frobenius, Collatz-Wielandt): x is a float power iteration's, the ratios are balls.
"""

from __future__ import annotations

from fractions import Fraction

from flint import arb, fmpq

from .exact import ball_max, finite

__all__ = ["perron_side"]

ITERATIONS = 100  # of the float power iteration that picks x (any x > 0 gives a valid side)


def perron_side(chain, domain, bodies):
    """A ball whose upper end bounds lambda_max(M(q, Theta_v)) for every q in ``domain`` and every parameter set
    ``bodies[v]`` (6 x 6 exact rationals per body)."""
    reach = [_reach(chain, domain, k) for k in range(chain.n)]  # reach[k][b - k] = (L, A) of column k in body b
    sides = []
    for z in bodies:
        norms = [_block_norms(m) for m in z]
        own = [_own(chain.joints[b].subspace, z[b]) for b in range(chain.n)]
        s = [[arb(0)] * chain.n for _ in range(chain.n)]
        for i in range(chain.n):
            for l in range(i, chain.n):
                (li, ai), (zv, zw, ss) = reach[i][l - i], own[l]
                total = abs(ss) if i == l else li * zv + ai * zw
                for b in range(l + 1, chain.n):
                    (li, ai), (ll, al), (a, bb, c) = reach[i][b - i], reach[l][b - l], norms[b]
                    total += a * li * ll + bb * (li * al + ai * ll) + c * ai * al
                s[i][l] = s[l][i] = total
        sides.append(_collatz_wielandt(s))
    return ball_max(sides, "a parameter set's side")


def _reach(chain, domain, k):
    """(L, A) balls bounding the linear and angular parts of joint k's column in bodies k, k + 1, ..."""
    s = chain.joints[k].subspace
    out = [(_length(s[i, 0] for i in range(3)), _length(s[i, 0] for i in range(3, 6)))]
    for j in range(k + 1, chain.n):
        joint = chain.joints[j]
        lin, ang = _moved(*out[-1], joint.before)
        if not joint.revolute:
            lo, hi = domain[j]
            lin += max(abs(lo), abs(hi)) * ang
        out.append(_moved(lin, ang, joint.after))
    return out


def _moved(lin, ang, transform):
    r, p = transform
    return lin + _length(p[i, 0] for i in range(3)) * ang, ang  # R is a rotation (built by the checker): g = 1


def _own(column, z):
    """(|(Z s)_v|, |(Z s)_w|, s^T Z s) of body l's matrix and joint l's column s, which is x_l in body l exactly."""
    w = [sum((arb(z[i][j]) * column[j, 0] for j in range(6)), arb(0)) for i in range(6)]
    return _length(w[:3]), _length(w[3:]), sum((column[i, 0] * w[i] for i in range(6)), arb(0))


def _length(xs):
    """|x| of a vector of balls: the root of the upper end of |x|^2 (a ball straddling 0 has no real root)."""
    return arb(finite(sum((x * x for x in xs), arb(0)), "a squared length").upper()).sqrt()


def _block_norms(z):
    """(a, b, c) >= the 2-norms of Z's linear, coupling and angular 3 x 3 blocks."""
    block = lambda r, c: [[arb(z[r + i][c + j]) for j in range(3)] for i in range(3)]  # noqa: E731
    return _norm2(block(0, 0)), _norm2(block(0, 3)), _norm2(block(3, 3))


def _norm2(rows):
    """sqrt(||B||_1 ||B||_inf) >= ||B||_2, as a ball."""
    one = ball_max((sum((abs(rows[i][j]) for i in range(3)), arb(0)) for j in range(3)), "a column sum")
    inf = ball_max((sum((abs(x) for x in row), arb(0)) for row in rows), "a row sum")
    return (one * inf).sqrt()


def _collatz_wielandt(s):
    """max_i (S x)_i / x_i >= rho(S) for the nonnegative ball matrix S, x > 0 from a float power iteration."""
    n = len(s)
    mid = [[float(x.mid()) for x in row] for row in s]
    x = [1.0] * n
    for _ in range(ITERATIONS):
        y = [sum(mid[i][j] * x[j] for j in range(n)) for i in range(n)]
        top = max(y)
        if not top > 0:
            break
        x = [max(v / top, 1e-12) for v in y]
    exact = [arb(fmpq(f.numerator, f.denominator)) for f in map(Fraction, x)]
    return ball_max((sum((s[i][j] * exact[j] for j in range(n)), arb(0)) / exact[i] for i in range(n)),
                    "a Collatz-Wielandt ratio")
