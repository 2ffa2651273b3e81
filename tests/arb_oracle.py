"""An independent evaluation of QJ(q) and M(q, Theta) in ball arithmetic (python-flint's arb), for the re-check of
certified sides (tests/test_arb_recheck.py).

Written from the chain's definition only (inertiaproof.dynamics.chain: T_l = T_{l-1} before_l X_l(g_l(q_l))
after_l; rows of body l are (R_l^T v_l, R_l^T omega_l)), never from the package's kinematics: every joint's
world axis u_k and a point p_k on it, then the origin velocity v_l = sum_k qdot_k (u_k x (z_l - p_k)) (revolute)
or qdot_k u_k (prismatic), omega_l = sum_k qdot_k u_k over revolute joints k <= l. The entries of ``q`` may be
arb balls: the result then encloses QJ and M over the whole box (sin and cos of a ball are rigorous).
Identity coordinate maps only.
"""

from __future__ import annotations

import numpy as np
from flint import acb_mat, arb, arb_mat

__all__ = ["arb_body_jacobian", "arb_mass_matrix", "ball", "eigen_enclosures", "mat"]


def ball(mid, rad=0.0):
    """An arb ball around a double (exactly represented) with radius rad (rounded up by arb)."""
    return arb(float(mid), float(rad)) if rad else arb(float(mid))


def mat(rows):
    """A list-of-lists of arb as an arb_mat."""
    return arb_mat([[x for x in row] for row in rows])


def _fixed(t):
    """A 4x4 double transform as exact arb entries."""
    return [[arb(float(x)) for x in row] for row in np.asarray(t, float)]


def _mul(a, b):
    return [[sum((a[i][k] * b[k][j] for k in range(len(b))), arb(0)) for j in range(len(b[0]))] for i in range(len(a))]


def _rodrigues(axis, angle):
    """4x4 rotation about a unit axis (doubles, exact as arb) by an arb angle."""
    x, y, z = (arb(float(v)) for v in axis)
    c, s = angle.cos(), angle.sin()
    v = 1 - c
    r = [[c + x * x * v, x * y * v - z * s, x * z * v + y * s],
         [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
         [z * x * v - y * s, z * y * v + x * s, c + z * z * v]]
    return [r[0] + [arb(0)], r[1] + [arb(0)], r[2] + [arb(0)], [arb(0), arb(0), arb(0), arb(1)]]


def _slide(axis, d):
    t = [[arb(1) if i == j else arb(0) for j in range(4)] for i in range(4)]
    for i in range(3):
        t[i][3] = arb(float(axis[i])) * d
    return t


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def arb_body_jacobian(chain, q):
    """QJ (6N x n) as a list of lists of arb at q (a sequence of arb or doubles)."""
    q = [x if isinstance(x, arb) else arb(float(x)) for x in q]
    n = chain.n
    frame = [[arb(1) if i == j else arb(0) for j in range(4)] for i in range(4)]
    axes, points, bodies = [], [], []
    for joint, qk in zip(chain.joints, q):
        if joint.coordinate.name != "identity":
            raise ValueError("the arb oracle knows identity coordinate maps only")
        frame = _mul(frame, _fixed(joint.before))
        rot = [row[:3] for row in frame[:3]]
        axes.append([sum((rot[i][j] * arb(float(joint.axis[j])) for j in range(3)), arb(0)) for i in range(3)])
        points.append([frame[i][3] for i in range(3)])
        frame = _mul(frame, _rodrigues(joint.axis, qk) if joint.revolute else _slide(joint.axis, qk))
        frame = _mul(frame, _fixed(joint.after))
        bodies.append(frame)
    rows = []
    for l, body in enumerate(bodies):
        rot = [row[:3] for row in body[:3]]
        z = [body[i][3] for i in range(3)]
        block = [[arb(0)] * n for _ in range(6)]
        for k in range(l + 1):
            u = axes[k]
            if chain.joints[k].revolute:
                v = _cross(u, [z[i] - points[k][i] for i in range(3)])
                w = u
            else:
                v, w = u, [arb(0)] * 3
            for i in range(3):  # rotate into body axes: R^T v, R^T w
                block[i][k] = sum((rot[j][i] * v[j] for j in range(3)), arb(0))
                block[3 + i][k] = sum((rot[j][i] * w[j] for j in range(3)), arb(0))
        rows.extend(block)
    return rows


def arb_mass_matrix(chain, q, z_blocks):
    """M = sum_l QJ_l^T Z_l QJ_l as an arb_mat; ``z_blocks`` (N, 6, 6) doubles (exact as arb)."""
    qj = arb_body_jacobian(chain, q)
    n = chain.n
    m = arb_mat(n, n)
    for l, z in enumerate(np.asarray(z_blocks, float)):
        block = mat(qj[6 * l:6 * l + 6])
        m += block.transpose() * mat(_fixed_rect(z)) * block
    return m


def _fixed_rect(a):
    return [[arb(float(x)) for x in row] for row in np.asarray(a, float)]


def down(x):
    """A double <= every point of the arb ball x (its lower end, rounded to a double and then one ulp down)."""
    return float(np.nextafter(float(x.lower()), -np.inf))


def up(x):
    """A double >= every point of the arb ball x."""
    return float(np.nextafter(float(x.upper()), np.inf))


def eigen_enclosures(m):
    """Rigorous ((low, high) of lambda_min, (low, high) of lambda_max) over every symmetric matrix in the arb_mat m.

    The symmetric midpoint matrix's eigenvalues are enclosed by acb_mat.eig (certified), and Weyl's inequality adds
    the spectral norm of the deviation, bounded by the Frobenius norm of the entrywise deviations (arb, rounded
    up)."""
    n = m.nrows()
    mid = arb_mat([[arb(m[i, j].mid()) for j in range(n)] for i in range(n)])
    mid = (mid + mid.transpose()) * arb(0.5)
    dev = arb(0)
    for i in range(n):
        for j in range(n):
            d = m[i, j] - mid[i, j]
            dev += arb(max(abs(down(d)), abs(up(d)))) ** 2
    dev = arb(up(dev.sqrt()))
    values = [v.real for v in acb_mat(mid).eig()]
    if any(not v.is_finite() for v in values):
        raise ArithmeticError("arb could not enclose the eigenvalues")
    lows, highs = [down(v - dev) for v in values], [up(v + dev) for v in values]
    order = np.argsort([float(v.mid()) for v in values])
    # every eigenvalue of a member lies in the union of the [low_i, high_i]: the smallest in [min low, high of the
    # lowest enclosure], the largest in [low of the highest, max high]
    return (min(lows), highs[order[0]]), (lows[order[-1]], max(highs))
