"""Lower forms of M(q, Theta) whose body inertias are invariant under their own joint's turn, for Theorem 2's
inf lambda_min(M) (Eq. (key step), body by body: M(q) = sum_l QJ_l^T Z_l QJ_l >= sum_l QJ_l^T Y_l QJ_l whenever
Y_l <= Z_l for every l).

The articulated-body pivot test (:mod:`inertiaproof.bounds.pivots`) loses where a joint turns an anisotropic
articulated inertia over an interval (a Loewner lower bound must push heavy directions onto light ones); it does
not lose where the turned matrix commutes with the turn. A body inertia Y_l that, written in joint l's frame
(Y_j = X^T Y_l X, X = tm(after_l)), commutes with every rotation about z (blockdiag(Rz, Rz)) makes the last body's
turn exact, and keeps the body's inertia about its own axis, the light direction of M on wrists (UR5: the last
body's inertia about joint 6), where the isotropic form mu_l I (mu_l = lambda_min(Z_l)) drops to the body's
smallest eigenvalue.

Construction (:func:`axial_body_form`, a heuristic: anything below Z_l is sound): the rotation average A of Z_j
(exact from eight turns: Z_j's dependence on the angle has harmonics 0, 1, 2), on the five coordinates other than
the rotation about z, C, Y_CC = (1 - ``SHRINK``) s A_CC with s = lambda_min(A_CC^(-1/2) Z_CC A_CC^(-1/2)) (so
Z_CC - Y_CC > 0), the coupling of the axis rotation to the linear z velocity kept (Y_25 = Z_25, invariant), and
the axis entry Y_55 the Schur complement Z_55 - r^T (Z_CC - Y_CC)^(-1) r (r = Z_C5 - Y_C5) less a relative
``MARGIN``: then Z_j - Y_j >= 0 (a Schur complement argument) up to the margin. The invariant 6 x 6 matrices are
a I2 + b J on the xy blocks, scalars on z: Y_j has that structure exactly (A and e5 are invariant).

Which bodies get their axial form (:func:`axial_lower_form`) is chosen greedily at sampled configurations (where
the form's sampled inf rises), starting from the isotropic form; every adopted Y_l is CHECKED in the body frame
for every parameter set v: lambda_min(Z_vl - Y_l) > ROUNDING eps ||Z_vl - Y_l||_F (Weyl: the computed eigenvalue
is within ROUNDING eps ||.||_F of the exact one), else the body keeps mu_l I. Nothing sampled enters the
certified side: the samples choose the form, the pivot ladder proves its inf.

Measured (issue 12, ci budget 45,000 boxes, load ~1.5): UR5 built-in, the last body axial: the form's sampled inf
2.172e-4 (M: 2.248e-4; isotropic 1.485e-4), its ladder proves 2.068e-4 (1.087x of M, 7.9 s). Panda +2 kg, the
payload body axial: the form's inf barely rises (1.457e-3 vs 1.437e-3) and the ladder proves nothing at 64x
within 45,000 boxes (heavy, anisotropic composite inertias at the proximal turns); all bodies axial: form inf
1.615e-3, the ladder 2.8x.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.dynamics.twists import twist_map
from inertiaproof.model.inertia import spatial_inertia

from .spectral import EPS, ROUNDING

__all__ = ["MARGIN", "SHRINK", "axial_body_form", "axial_lower_form", "form_matrix", "form_lmin", "holds_below"]

SHRINK = 0.05  # fraction by which the other five coordinates' block stays below Z's (room for the axis entry)
MARGIN = 1e-6  # relative amount by which the axis entry stays below its Schur complement (room for the check)
TURNS = 2 * np.pi * np.arange(8) / 8  # rotation average: exact for harmonics up to 2 (and beyond, to 7)


def _turn(x):
    t = np.eye(6)
    c, s = np.cos(x), np.sin(x)
    for o in (0, 3):
        t[o, o] = t[o + 1, o + 1] = c
        t[o, o + 1], t[o + 1, o] = s, -s
    return t


def axial_body_form(zj, shrink=SHRINK, margin=MARGIN):
    """An invariant (under rotations about z) Y_j with Y_j <= Z_j (up to ``margin``; checked by the caller) for a
    6 x 6 inertia ``zj`` in the joint frame, keeping the axis entry (e5) as high as the rest allows (module
    docstring)."""
    zj = 0.5 * (zj + zj.T)
    average = np.mean([_turn(x).T @ zj @ _turn(x) for x in TURNS], 0)
    c = [0, 1, 2, 3, 4]
    zcc, acc = zj[np.ix_(c, c)], average[np.ix_(c, c)]
    w, u = np.linalg.eigh(acc)
    if w[0] <= 0:
        return None
    root = (u / np.sqrt(w)) @ u.T
    scale = np.linalg.eigvalsh(root @ zcc @ root)[0]
    y = np.zeros((6, 6))
    y[np.ix_(c, c)] = (1 - shrink) * max(scale, 0.0) * acc
    y[2, 5] = y[5, 2] = zj[2, 5]
    r = zj[c, 5] - y[c, 5]
    schur = zj[5, 5] - r @ np.linalg.solve(zcc - y[np.ix_(c, c)], r)
    y[5, 5] = schur - margin * abs(schur)
    return 0.5 * (y + y.T)


def holds_below(z, y):
    """Whether Y <= Z_v for every v is certified: lambda_min(Z_v - Y) > ROUNDING eps ||Z_v - Y||_F (Weyl; the
    difference is formed exactly up to one rounding per entry, covered by the same term)."""
    d = np.asarray(z) - y
    return bool(np.all(np.linalg.eigvalsh(d)[..., 0] - ROUNDING * EPS * np.linalg.norm(d, axis=(-2, -1)) > 0))


def form_matrix(chain, forms, q):
    """sum_l QJ_l(q)^T Y_l QJ_l(q) for forms (V, N, 6, 6) and q (K, n): (K, V, n, n)."""
    qj = chain.body_jacobian(q).reshape(len(q), chain.bodies, 6, chain.n)
    return np.einsum("kbin,vbij,kbjm->kvnm", qj, forms, qj, optimize=True)


def form_lmin(chain, forms, q, chunk=4096):
    """lambda_min of :func:`form_matrix` (K, V), in chunks of configurations."""
    q = np.atleast_2d(q)
    return np.concatenate([np.linalg.eigvalsh(form_matrix(chain, forms, q[k:k + chunk]))[..., 0]
                           for k in range(0, len(q), chunk)]) if len(q) else np.zeros((0, len(forms)))


def axial_lower_form(chain, thetas, points):
    """(forms (1, N, 6, 6), axial (N,) bools): Y_l <= Z(Theta_v)_l for every parameter set v, Y_l the axial form
    of body l where that raised the form's smallest lambda_min at ``points`` (greedy, body by body) and passed
    :func:`holds_below`, else mu_l I with mu_l = min_v lambda_min(Z_vl) less its rounding
    (ROUNDING eps |Z_vl|_2)."""
    z = spatial_inertia(np.asarray(thetas, float))  # (V, N, 6, 6)
    w = np.linalg.eigvalsh(z)
    mu = np.maximum((w[..., 0] - ROUNDING * EPS * np.abs(w).max(-1)).min(0), 0.0)
    forms = mu[:, None, None] * np.eye(6)  # (N, 6, 6)
    axial = np.zeros(chain.bodies, bool)
    best = form_lmin(chain, forms[None], points).min()
    for l in range(min(chain.bodies, chain.n)):
        x = twist_map(chain.z_joints[l].after)
        inverse = np.linalg.inv(x)
        for v in np.argsort(np.trace(z[:, l], axis1=-2, axis2=-1)):  # the lightest parameter set first
            yj = axial_body_form(x.T @ z[v, l] @ x)
            if yj is None:
                continue
            y = inverse.T @ yj @ inverse
            y = 0.5 * (y + y.T)
            if not holds_below(z[:, l], y):
                continue
            trial = forms.copy()
            trial[l] = y
            value = form_lmin(chain, trial[None], points).min()
            if value > best * (1 + 1e-3):
                best, forms, axial[l] = value, trial, True
            break
    return forms[None], axial
