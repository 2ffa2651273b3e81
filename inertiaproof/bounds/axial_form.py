"""Lower forms of M(q, Theta) with an extra inertia about each body's own joint axis, for Theorem 2's
inf lambda_min(M) (Eq. (key step), body by body: M(q) = sum_l QJ_l^T Z_l QJ_l >= sum_l QJ_l^T Y_l QJ_l whenever
Y_l <= Z_l for every l).

The isotropic form Y_l = mu_l I (mu_l = lambda_min(Z_l)) drops each body to its smallest eigenvalue in every
direction; on wrists the light direction of M is a body turning about its own joint axis, whose inertia there
can be several times mu_l (built-in UR5: the last body, 2.2e-4 against 1.56e-4). The axial form keeps it:

    Y_l = mu I + kappa w w^T,   mu = (1 - shrink) min_v lambda_min(Z_vl),
    kappa = (1 - MARGIN) min_v 1 / (w^T (Z_vl - mu I)^(-1) w)

(kappa is the largest with Z_vl - mu I - kappa w w^T >= 0, a Schur complement, so Y_l <= Z_vl up to the margin)
for two covectors (:func:`axis_covectors`): w = tm(after_l)^(-T) e5 (w^T V the angular velocity about joint l's
axis; written in the joint frame kappa e5 e5^T commutes with the joint's turn) and w = Z_l s_l (the momentum of
the joint's unit twist s_l, which keeps an offset body's parallel-axis part m rho^2), each with shrink in
``SHRINKS``. The articulated-body recursion removes most of the rank-one term with the joint's own pivot
(P_l = A_l - A_l s_l s_l^T A_l / D_l, and A_l s_l lies mostly along w), so the turned matrices stay about as
isotropic as the isotropic form's and the pivot ladder (:mod:`inertiaproof.bounds.pivot_search`) proves this form
about as easily. A heavy invariant form (:func:`invariant_body_form`: Z_l's rotation average on the five other
coordinates, the Schur complement on the axis) keeps even more of M (example-robot-data UR5: 1.580e-2 of M's
1.583e-2) but its heavy, anisotropic composite inertias make the ladder prove nothing at 64x within 45,000 boxes
on every example-robot-data arm tried; it is tried last (configuration.mass_inf), with a probe.

Which bodies get an axial form (:func:`axial_lower_form`) is chosen greedily at sampled configurations (the
candidate that raises the form's sampled inf most, body by body), starting from the isotropic form; every
adopted Y_l is CHECKED in the body frame for every parameter set v: lambda_min(Z_vl - Y_l) > ROUNDING eps
||Z_vl - Y_l||_F (Weyl: the computed eigenvalue is within ROUNDING eps ||.||_F of the exact one, the difference's
own rounding included), else the body keeps mu_l I (rounded down by ROUNDING eps |Z_vl|_2). Nothing sampled
enters the certified side: the samples choose the form, the pivot ladder proves its inf.

Measured (ci budget, 45,000 boxes, ladder goal 2 unless said; inf lambda_min(M) sampled / the axial form's sampled
inf / certified, isotropic form's inf in brackets, load ~2-4): built-in UR5 2.244e-4 / 2.168e-4 / 2.065e-4
(1.485e-4); at goal 1.01 with the ci budget 2.147e-4 (1.045x). example-robot-data (`inertiaproof audit --profile
ci`): UR5 1.582e-2 / 1.579e-2 / 9.87e-3 (3.04e-3), xArm7 1.345e-4 / 1.244e-4 / 1.152e-4 (5.71e-5), Z1 2.786e-4 /
1.583e-4 / 1.535e-4 (1.336e-4), SO-101 1.318e-5 / 4.64e-6 / 4.59e-6 (1.78e-6; its jaw's com is off the axis and
its light direction mixes two joints), Panda finger chains 4.39e-3 / 2.65e-3 / 2.23e-3 (7.5e-7). Panda +2 kg
(built-in): no candidate raises the form's inf above the isotropic one's (1.437e-3; M 1.778e-3), nor does the
block form with an axis term.
"""

from __future__ import annotations

import itertools

import numpy as np

from inertiaproof.dynamics.twists import twist_map
from inertiaproof.model.inertia import spatial_inertia

from .spectral import EPS, ROUNDING

__all__ = ["MARGIN", "SHRINK", "SHRINKS", "axial_body_form", "axial_lower_form", "axis_covectors", "form_matrix", "form_lmin", "holds_below", "invariant_body_form"]

SHRINK = 0.05  # fraction by which the isotropic part stays below lambda_min(Z_l) (room for the axis term)
SHRINKS = (SHRINK, 0.5)  # tried per body and covector (0.5: room where the covector meets Z's light direction)
MARGIN = 1e-6  # relative amount by which the axis term stays below its largest value (room for the rounding check)


def axial_body_form(z, covector, shrink=SHRINK, margin=MARGIN):
    """Y = mu I + kappa w w^T <= Z_v for every v of ``z`` (V, 6, 6) (up to ``margin``; checked by the caller) for
    the covector w, mu = (1 - shrink) min_v lambda_min(Z_v), kappa = (1 - margin) min_v
    1 / (w^T (Z_v - mu I)^(-1) w) (module docstring); None where Z_v - mu I is not definite."""
    z, w = np.asarray(z, float), np.asarray(covector, float)
    mu = (1 - shrink) * float(np.linalg.eigvalsh(z)[:, 0].min())
    rest = z - mu * np.eye(6)
    if not mu > 0 or np.any(np.linalg.eigvalsh(rest)[:, 0] <= 0):
        return None
    kappa = (1 - margin) / max(float(w @ np.linalg.solve(r, w)) for r in rest)
    return mu * np.eye(6) + kappa * np.outer(w, w)


def axis_covectors(z, joint):
    """The two covectors tried for a body: the rotation about its joint axis (tm(after)^(-T) e5: w^T V is the
    angular velocity about the axis in the joint frame) and its momentum Z s (s = tm(after) e5, the joint's unit
    twist; Z of the lightest parameter set), which keeps the parallel-axis part m rho^2 of an offset body."""
    s = np.asarray(joint.unit_twist, float)
    light = z[int(np.argmin(np.trace(z, axis1=-2, axis2=-1)))]
    return np.linalg.inv(twist_map(joint.after)).T[:, 5], light @ s


def _turn(x):
    t = np.eye(6)
    c, s = np.cos(x), np.sin(x)
    for o in (0, 3):
        t[o, o] = t[o + 1, o + 1] = c
        t[o, o + 1], t[o + 1, o] = s, -s
    return t


def invariant_body_form(zj, shrink=SHRINK, margin=MARGIN):
    """The heavy invariant form: Y_j commuting with every rotation about z, Y_j <= Z_j (up to ``margin``; checked
    by the caller) for a 6 x 6 inertia ``zj`` in the joint frame: Z_j's rotation average A (exact from eight
    turns: harmonics 0-2) on the five coordinates C other than the axis rotation, scaled to
    (1 - shrink) lambda_min(A_CC^(-1/2) Z_CC A_CC^(-1/2)) A_CC, the axis' coupling to the linear z velocity kept
    (invariant), and the axis entry the Schur complement Z_55 - r^T (Z_CC - Y_CC)^(-1) r (r = Z_C5 - Y_C5) less
    a relative ``margin``. None where A_CC is not definite."""
    zj = 0.5 * (zj + zj.T)
    average = np.mean([_turn(x).T @ zj @ _turn(x) for x in 2 * np.pi * np.arange(8) / 8], 0)
    c = [0, 1, 2, 3, 4]
    zcc, acc = zj[np.ix_(c, c)], average[np.ix_(c, c)]
    w, u = np.linalg.eigh(acc)
    if w[0] <= 0:
        return None
    root = (u / np.sqrt(w)) @ u.T
    y = np.zeros((6, 6))
    y[np.ix_(c, c)] = (1 - shrink) * max(np.linalg.eigvalsh(root @ zcc @ root)[0], 0.0) * acc
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


def _heavy_candidates(z, joint):
    x = twist_map(joint.after)
    inverse = np.linalg.inv(x)
    for v in np.argsort(np.trace(z, axis1=-2, axis2=-1)):  # the lightest parameter set first
        yj = invariant_body_form(x.T @ z[v] @ x)
        if yj is not None:
            yield inverse.T @ yj @ inverse


def _light_candidates(z, joint):
    for w, shrink in itertools.product(axis_covectors(z, joint), SHRINKS):
        yield axial_body_form(z, w, shrink)


def axial_lower_form(chain, thetas, points, heavy=False):
    """(forms (1, N, 6, 6), axial (N,) bools): Y_l <= Z(Theta_v)_l for every parameter set v, Y_l an axial form
    of body l (:func:`axial_body_form` for both :func:`axis_covectors` and each of ``SHRINKS``; ``heavy``: the
    :func:`invariant_body_form` instead) where that raised the form's smallest lambda_min at ``points`` (greedy,
    body by body) and passed :func:`holds_below`, else mu_l I with mu_l = min_v lambda_min(Z_vl) less its
    rounding (ROUNDING eps |Z_vl|_2)."""
    z = spatial_inertia(np.asarray(thetas, float))  # (V, N, 6, 6)
    w = np.linalg.eigvalsh(z)
    mu = np.maximum((w[..., 0] - ROUNDING * EPS * np.abs(w).max(-1)).min(0), 0.0)
    forms = mu[:, None, None] * np.eye(6)  # (N, 6, 6)
    axial = np.zeros(chain.bodies, bool)
    best = form_lmin(chain, forms[None], points).min()
    for l in range(min(chain.bodies, chain.n)):
        for y in (_heavy_candidates if heavy else _light_candidates)(z[:, l], chain.z_joints[l]):
            y = None if y is None else 0.5 * (y + y.T)
            if y is None or not holds_below(z[:, l], y):
                continue
            trial = forms.copy()
            trial[l] = y
            value = form_lmin(chain, trial[None], points).min()
            if value > best * (1 + 1e-3):
                best, forms, axial[l] = value, trial, True
    return forms[None], axial
