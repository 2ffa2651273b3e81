"""An upper side of lambda_max(M(q, Theta)) for every q of a box from the chain's lengths and the bodies' inertias
alone: the checker's route to an upper claim that no tree of boxes could prove on a long chain.

Column k of QJ_b (b >= k) is s_k carried to body b by the twist maps X_(k+1), ..., X_b. A map [[R^T, -R^T S(p)],
[0, R^T]] takes (v, w) with |v| <= L, |w| <= A to one with |v| <= L + |p| A, |w| <= A: every R is a rotation built
by the checker (a joint's turn has p = 0, its slide by |q| <= r p = axis q). With the blocks of Z_b bounded in the
2-norm by a, b, c, |x^T Z_b y| <= a L_x L_y + b (L_x A_y + A_x L_y) + c A_x A_y, so |M_il(q)| <= S_il = the sum over
b >= max(i, l) (MassMatrix), the term b = l with s_l itself. Then lambda_max(M(q)) <= rho(S) <= max_i (S x)_i / x_i
for any x > 0 (Perron-Frobenius, Collatz-Wielandt): x from a float power iteration, the ratios balls.
"""

from flint import arb

from .exact import ball_max, dyadic, finite

ITERATIONS = 100  # of the float power iteration that picks x (any x > 0 gives a valid side)


def perron_side(chain, domain, bodies):
    """A ball whose upper end bounds lambda_max(M(q, Theta_v)) for every q in ``domain`` and every parameter set
    ``bodies[v]`` (6 x 6 exact rationals per body)."""
    reach = [_reach(chain, domain, k) for k in range(chain.n)]  # reach[k][b - k] = (L, A) of column k in body b
    return ball_max((_collatz_wielandt(_sizes(chain, reach, z)) for z in bodies), "a parameter set's side")


def _sizes(chain, reach, z):
    """S_il >= |M_il(q)| for the bodies' matrices ``z``."""
    n = chain.n
    s = [[arb(0)] * n for _ in range(n)]
    norms = [[_norm2([[arb(m[r + i][c + j]) for j in range(3)] for i in range(3)]) for r, c in
              ((0, 0), (0, 3), (3, 3))] for m in z]
    own = []  # (|(Z s)_v|, |(Z s)_w|, s^T Z s) of body l and joint l's column s
    for b, joint in enumerate(chain.joints):
        w = [sum((arb(z[b][i][j]) * joint.subspace[j, 0] for j in range(6)), arb(0)) for i in range(6)]
        own.append((_length(w[:3]), _length(w[3:]), sum((joint.subspace[i, 0] * w[i] for i in range(6)), arb(0))))
    for i in range(n):
        for l in range(i, n):
            (li, ai), (zv, zw, ss) = reach[i][l - i], own[l]
            total = abs(ss) if i == l else li * zv + ai * zw
            for b in range(l + 1, n):
                (li, ai), (ll, al), (a, bb, c) = reach[i][b - i], reach[l][b - l], norms[b]
                total += a * li * ll + bb * (li * al + ai * ll) + c * ai * al
            s[i][l] = s[l][i] = total
    return s


def _reach(chain, domain, k):
    """(L, A) balls bounding the linear and angular parts of joint k's column in bodies k, k + 1, ..."""
    s = chain.joints[k].subspace
    out = [(_length(s[i, 0] for i in range(3)), _length(s[i, 0] for i in range(3, 6)))]
    moved = lambda lin, ang, rp: (lin + _length(rp[1][i, 0] for i in range(3)) * ang, ang)  # noqa: E731
    for j in range(k + 1, chain.n):
        joint = chain.joints[j]
        lin, ang = moved(*out[-1], joint.before)
        lin += 0 if joint.revolute else max(abs(domain[j][0]), abs(domain[j][1])) * ang
        out.append(moved(lin, ang, joint.after))
    return out


def _length(xs):
    """|x| of a vector of balls: the root of the upper end of |x|^2 (a ball straddling 0 has no real root)."""
    return arb(finite(sum((x * x for x in xs), arb(0)), "a squared length").upper()).sqrt()


def _norm2(rows):
    """sqrt(||B||_1 ||B||_inf) >= ||B||_2, as a ball."""
    one, inf = (ball_max((sum((abs(x) for x in line), arb(0)) for line in lines), "a line sum")
                for lines in (zip(*rows), rows))
    return (one * inf).sqrt()


def _collatz_wielandt(s):
    """max_i (S x)_i / x_i >= rho(S) for the nonnegative ball matrix S, x > 0 from a float power iteration."""
    n, x = len(s), [1.0] * len(s)
    mid = [[float(v.mid()) for v in row] for row in s]
    for _ in range(ITERATIONS):
        y = [sum(mid[i][j] * x[j] for j in range(n)) for i in range(n)]
        top = max(y)
        if not top > 0:
            break
        x = [max(v / top, 1e-12) for v in y]
    exact = [arb(dyadic(v)) for v in x]
    return ball_max((sum((s[i][j] * exact[j] for j in range(n)), arb(0)) / exact[i] for i in range(n)),
                    "a Collatz-Wielandt ratio")
