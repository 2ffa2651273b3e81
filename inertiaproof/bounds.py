"""Ingredients and constants of the Section 4 bounds for a chain and a parameter trajectory, as plain data.

Configuration extremes (inf/sup over q of eigenvalues of M, singular values of
QJ, of Y_p = dK_p/dq - dK_p/dq^T (DefK)) are bracketed with
:func:`inertiaproof.extremes.bracket_extreme`. The certified side rests on
two facts:

- QJ is a trigonometric polynomial of degree <= 1 in every revolute
  coordinate and an algebraic polynomial of degree <= 1 in every prismatic one
  (joint rotations enter once per product; cross products of vectors turned by
  the same rotation are turned by it), so M = (QJ)^T Z QJ has degree <= 2.
  Bernstein's inequality (a full period) and Markov's (a finite interval)
  bound every partial derivative of x^T A(q) y by c_j sup |x^T A y|, hence
  the Taylor remainder of A on a box of radii r by 1/2 S (sum_j c_j r_j)^2,
  S = sup ||A|| over the Bernstein domain.
- lambda_max and sigma_max are convex, lambda_min concave, in the linear part
  A(c) + sum_j d_j dA/dq_j(c): their extremes over a box lie at its vertices.

Over time, Theta(t) of payloads and scalings lies on segments
Theta_base + s Phi_load with s in the profile's range; spectral extremes that
are concave or convex in Theta are then attained at the segment's ends (exact
for one load per body). Moving masses are bounded by positivity (Z(Phi_load) >= 0)
and by the profile's rate and acceleration bounds.

The entry point for audits is :func:`mass_matrix_bounds`.
"""

from __future__ import annotations

import itertools

import numpy as np

from . import composite
from .extremes import Bracket, bracket_extreme
from .inertia import pseudo_inertia, spatial_inertia
from .positive_map import key_step_certificate
from .trajectory import MovingMass, Payload, Scaling

EPS = np.finfo(float).eps
ROUNDING = 64.0  # rounding allowance of a computed eigenvalue, in units of eps * ||matrix||_F


# -- the configuration domain ---------------------------------------------------

def certification_obstacle(chain):
    """Why no certified configuration bracket exists for this chain (None if one does).

    The first joint may slide without limits: QJ does not depend on its coordinate."""
    for k, joint in enumerate(chain.joints):
        if joint.coordinate.name != "identity" and k > 0:
            return f"joint {k + 1} maps its coordinate by {joint.coordinate.name!r}: QJ is no trigonometric polynomial"
        if joint.coordinate.name != "identity" and k == 0:
            return "the first joint's coordinate map is not the identity"
        if not joint.revolute and joint.limits is None and k > 0:
            return f"joint {k + 1} slides without limits: the configuration domain is unbounded"
    return None


def search_box(chain):
    """The configuration box: joint limits, one period for unlimited revolute joints."""
    lo, hi = chain.coordinate_box()
    return lo, hi


def bernstein_domain(chain):
    """Box over which the derivative inequalities hold: a full period for every revolute coordinate."""
    lo, hi = search_box(chain)
    revolute = np.array([j.revolute for j in chain.joints])
    return np.where(revolute, -np.pi, lo), np.where(revolute, np.pi, hi)


def free_coordinates(chain):
    """Coordinates QJ depends on: not the first joint's (it moves the whole chain rigidly; body twists are invariant)."""
    free = np.ones(chain.n, bool)
    if chain.joints[0].coordinate.name == "identity":
        free[0] = False
    return free


def derivative_factors(chain, lo, hi, degree):
    """c_j with sup|dp/dq_j| <= c_j sup|p|: Bernstein (degree) on a period, Markov (2 degree^2 / width) on an interval."""
    revolute = np.array([j.revolute for j in chain.joints])
    return np.where(revolute, float(degree), 2.0 * degree**2 / np.maximum(hi - lo, 1e-300))


# -- matrix families A(q) with derivatives --------------------------------------

def jacobian_family(chain):
    """q -> (QJ, dQJ/dq) with QJ (K, 1, 6N, n): polynomial degree 1."""
    def evaluate(q, derivatives=True):
        qj = chain.body_jacobian(q)[:, None]
        return (qj, chain.body_jacobian_derivative(q)[:, None]) if derivatives else qj
    return evaluate, 1


def mass_family(chain, thetas):
    """q -> (M(q, Theta_v), dM/dq) for a stack of parameter sets thetas (V, N, 10): polynomial degree 2."""
    thetas = np.asarray(thetas, float)

    def evaluate(q, derivatives=True):
        m = composite.mass_matrix(chain, q[:, None], thetas[None])
        if not derivatives:
            return m
        return m, composite.mass_matrix_partials(chain, q[:, None], thetas[None])
    return evaluate, 2


def spectral(a, kind):
    """Spectral function of a batch (..., r, s): smax/smin (SVD), lmax/lmin/absmax (symmetric)."""
    if kind in ("smax", "smin"):
        s = np.linalg.svd(a, compute_uv=False)
        return s[..., 0] if kind == "smax" else s[..., -1]
    w = np.linalg.eigvalsh(a)
    if kind == "lmax":
        return w[..., -1]
    if kind == "lmin":
        return w[..., 0]
    return np.maximum(w[..., -1], -w[..., 0])


CONVEX = {"smax", "lmax", "absmax"}


def vertex_bound(a, da, radii, free, kind):
    """Extreme of the spectral function over the linear part a + sum_j d_j da_j, |d_j| <= r_j, at the box's vertices.

    ``a`` (K, V, r, s), ``da`` (K, V, r, s, n). Convex kinds give the max over
    vertices (an upper bound), lmin the min (a lower bound); a rounding
    allowance of the eigen/singular value computation is added outwards.
    """
    idx = np.flatnonzero(free)
    signs = np.array(list(itertools.product((-1.0, 1.0), repeat=len(idx)))) if len(idx) else np.zeros((1, 0))
    steps = signs[None] * radii[:, idx][:, None, :]  # (K, 2^d, d)
    lin = np.einsum("kvrsj,kej->kevrs", da[..., idx], steps) + a[:, None]
    vals = spectral(lin, kind)  # (K, 2^d, V)
    size = np.linalg.norm(a, axis=(-2, -1)) + np.einsum("kvj,kj->kv", np.linalg.norm(da, axis=(-3, -2)), radii)
    allowance = ROUNDING * EPS * size  # (K, V)
    if kind in CONVEX:
        return (vals.max(1) + allowance).max(1)
    return (vals.min(1) - allowance).min(1)


def configuration_bracket(chain, family, kind, *, quantity_name, samples, refine_s, rng, value_kind=None,
                          square=False, progress=None, thetas=None):
    """Bracket of sup (convex kinds) or inf (lmin, smin) over the chain's configurations of kind(A(q)).

    ``family`` is (evaluate, degree) from :func:`jacobian_family` or :func:`mass_family`;
    the value over a stack of parameter sets is the worst over the stack.
    ``value_kind`` overrides how the observed side is computed (e.g. 'smin' of
    QJ by SVD while the certified side bounds lmin of (QJ)^T QJ); ``square``
    squares observed singular values to match.
    """
    evaluate, degree = family
    sense = "max" if kind in CONVEX else "min"
    pick = np.max if sense == "max" else np.min
    obs_kind = value_kind or kind

    source = evaluate if value_kind is None else jacobian_family(chain)[0]

    def value(q):
        v = spectral(source(q, derivatives=False), obs_kind)
        return pick(v**2 if square else v, axis=-1)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    obstacle = certification_obstacle(chain)
    if obstacle is not None:
        return bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name, samples=samples,
                               refine_s=refine_s, rng=rng, free=free, note=obstacle)
    dlo, dhi = bernstein_domain(chain)
    factors = derivative_factors(chain, dlo, dhi, degree)
    apriori = apriori_bound(chain, thetas if degree == 2 else None, "sup")
    same = np.allclose(dlo[free], lo[free]) and np.allclose(dhi[free], hi[free])

    def bound_with(scale, kind_here):
        def box_bound(c, r):
            a, da = evaluate(c)
            v = vertex_bound(a, da, r, free, kind_here)
            rho = (r[:, free] * factors[free]).sum(1)
            rem = 0.5 * rho**2
            if scale is None:  # self-referential: the sup itself bounds the remainder (box holding the maximiser)
                return np.where(rem < 1, np.maximum(v, 0) / np.maximum(1 - rem, 1e-300), np.inf)
            return v + scale * rem if kind_here in CONVEX else v - scale * rem
        return box_bound

    stage = refine_s / 2 if (sense == "min" or not same) else refine_s
    scale, note = None, ""
    norm_kind = "smax" if degree == 1 else "absmax"
    if sense == "min" or not same:
        sup = bracket_extreme(value_for_norm(evaluate, norm_kind), bound_with(None, norm_kind), dlo, dhi, sense="max",
                              quantity_name=f"sup ||A|| for {quantity_name}", samples=samples, refine_s=stage,
                              rng=rng, free=free, weights=factors)
        scale = min(sup.certified, apriori)
        note = f"Taylor remainder scaled by sup ||A|| <= {scale:.6g} over a full period (certified)"
        if not np.isfinite(scale):
            return _with_fallback(bracket_extreme(value, None, lo, hi, sense=sense, quantity_name=quantity_name,
                                                  samples=samples, refine_s=stage, rng=rng, free=free,
                                                  note="sup ||A|| over a period not certified in the time budget"),
                                  kind, apriori, thetas is not None)
    result = bracket_extreme(value, bound_with(scale, kind), lo, hi, sense=sense, quantity_name=quantity_name,
                             samples=samples, refine_s=stage if scale is not None else refine_s, rng=rng, free=free,
                             weights=factors, progress=progress, note=note)
    if scale is not None and sense == "max" and scale < result.certified:
        result.certified, result.note = scale, note.replace("Taylor remainder scaled by sup", "the sup over a period")
        for point in result.convergence:
            point[2] = min(point[2], scale)
    psd = thetas is not None and bool(np.all(spectral(spatial_inertia(np.asarray(thetas, float)), "lmin") >= 0))
    return _with_fallback(result, kind, apriori, psd)


def _with_fallback(result, kind, apriori, psd):
    """Where branch and bound found no better certified side: the a priori length bound (sup) or 0 (inf of a PSD form)."""
    if kind == "lmin" and psd and result.certified is not None and result.certified < 0:
        result.certified = None
    if result.certified is not None and np.isfinite(result.certified):
        return result
    if kind in CONVEX:
        result.certified, result.note = apriori, (result.note + "; " if result.note else "") + \
            "branch and bound did not finish: a priori bound from link lengths (Frobenius norm)"
    elif kind == "lmin" and psd:
        result.certified, result.note = 0.0, (result.note + "; " if result.note else "") + \
            "branch and bound did not finish: 0, as M = (QJ)^T Z QJ with Z >= 0 (key step, positivity of L)"
    for point in result.convergence:
        point[1 if result.sense == "min" else 2] = float(result.certified)
    return result


def value_for_norm(evaluate, kind):
    def value(q):
        return spectral(evaluate(q, derivatives=False), kind).max(-1)
    return value


def lever_bounds(chain):
    """Certified |z_l - p_k| (l >= k) for all q: the sum of the translations of the fixed transforms and of the slides
    from joint k's axis to body l's origin (rotations keep lengths). Lower triangle of an n x n array; a slide
    without limits counts as 0 only as the first joint (it moves the joint points too): see certification_obstacle."""
    lengths = []
    for joint in chain.joints:
        slide = 0.0 if joint.revolute or joint.limits is None else max(abs(joint.limits[0]), abs(joint.limits[1]))
        lengths.append((np.linalg.norm(joint.before[:3, 3]), np.linalg.norm(joint.after[:3, 3]), slide))
    out = np.zeros((chain.n, chain.n))
    for l in range(chain.n):
        for k in range(l + 1):
            out[l, k] = sum(lengths[m][1] + lengths[m][2] for m in range(k, l + 1)) + sum(
                lengths[m][0] for m in range(k + 1, l + 1))
    return out


def column_bounds(chain):
    """Certified bounds (n x n, lower triangle) of the linear and angular parts of column k of body l's block:
    revolute R_l^T (u_k x (z_l - p_k), u_k) gives (|z_l - p_k|, 1), prismatic (R_l^T u_k, 0) gives (1, 0)."""
    revolute = np.array([j.revolute for j in chain.joints])
    mask = np.tril(np.ones((chain.n, chain.n), bool))
    linear = np.where(mask, np.where(revolute[None, :], lever_bounds(chain), 1.0), 0.0)
    angular = np.where(mask, np.where(revolute[None, :], 1.0, 0.0), 0.0)
    return linear, angular


def apriori_jacobian_blocks(chain):
    """Certified ||QJ_l||_F per body l for all q, from lengths alone (identity coordinate maps, bounded slides)."""
    linear, angular = column_bounds(chain)
    return np.sqrt((linear**2 + angular**2).sum(1))


def triangular_normality_floor(chain):
    """A certified lower bound of inf_q sigma_min(QJ)^2 over all q (0 when none is available).

    Column l of body l's block is the joint's constant unit twist s_l (identity
    coordinate maps), and the block has no columns right of l. With the projector
    P_l onto s_l, (QJ)^T QJ = sum_l QJ_l^T QJ_l >= sum_l QJ_l^T P_l QJ_l = W^T W,
    W lower triangular with rows s_l^T QJ_l / |s_l|: W_ll = |s_l| and
    |W_lk| <= (|s_l,v| lin_lk + |s_l,w| ang_lk) / |s_l| (column_bounds). The
    neighbour entry W_l,l-1 depends on joint l alone, a + b cos x_l + c sin x_l
    (a slide: affine in x_l), and is bounded exactly. The comparison matrix C
    (|W_ll| on, minus those bounds off the diagonal) has C^-1 >= |W^-1| entrywise,
    so sigma_min(QJ)^2 >= 1 / ||C^-1||_2^2 with ||C^-1||_2 <= min(||C^-1||_F,
    (||C^-1||_1 ||C^-1||_inf)^(1/2)), computed in rational arithmetic, rounded down.
    """
    from fractions import Fraction

    if certification_obstacle(chain) is not None:
        return 0.0
    linear, angular = column_bounds(chain)
    twists = [j.unit_twist for j in chain.z_joints]
    n = chain.n
    c = [[Fraction(0)] * n for _ in range(n)]
    for l, s in enumerate(twists):
        size = np.linalg.norm(s)
        c[l][l] = Fraction(float(np.nextafter(size, 0)))
        for k in range(l):
            bound = (np.linalg.norm(s[:3]) * linear[l, k] + np.linalg.norm(s[3:]) * angular[l, k]) / size
            if k == l - 1:
                bound = min(bound, _neighbour_bound(chain.z_joints[l], s, twists[k], chain.joints[l].limits) / size)
            c[l][k] = -Fraction(float(np.nextafter(bound * (1 + 1e-12) + 1e-300, np.inf)))
    inverse = [[Fraction(0)] * n for _ in range(n)]
    for col in range(n):  # forward substitution, exact
        for l in range(n):
            rhs = Fraction(int(l == col)) - sum((c[l][k] * inverse[k][col] for k in range(l)), Fraction(0))
            inverse[l][col] = rhs / c[l][l]
    frobenius = sum(x * x for row in inverse for x in row)
    ones = max(sum(abs(inverse[l][col]) for l in range(n)) for col in range(n))
    infinity = max(sum(abs(x) for x in row) for row in inverse)
    return float(np.nextafter(float(1 / min(frobenius, ones * infinity)), 0))


def _neighbour_bound(joint, s, previous, limits):
    """max over x of |s . X_after J(x) X_before s_prev|: a + b cos x + c sin x for a turn (|a| + (b^2 + c^2)^(1/2)),
    affine in x for a slide (its ends over the limits)."""
    y = previous if joint.before_twist is None else joint.before_twist @ previous
    v = s if joint.after_twist is None else joint.after_twist.T @ s
    if joint.revolute:
        a = v[2] * y[2] + v[5] * y[5]
        b = v[0] * y[0] + v[1] * y[1] + v[3] * y[3] + v[4] * y[4]
        c = v[0] * y[1] - v[1] * y[0] + v[3] * y[4] - v[4] * y[3]
        return abs(a) + np.hypot(b, c)
    if limits is None:
        return np.inf
    base, slope = v @ y, v[0] * y[4] - v[1] * y[3]
    return max(abs(base + slope * x) for x in limits)


def apriori_bound(chain, thetas, kind):
    """A certified bound of sup_q sigma_max(QJ) (thetas None) or of sup_q ||M(q, Theta_v)|| over all q, from lengths.

    With G[l, k] >= ||QJ_l[:, k]|| (column_bounds), ||QJ x||^2 = sum_l ||QJ_l x||^2 <=
    ||G |x| ||^2, so sigma_max(QJ) <= ||G||_2; and |x^T M x| <= sum_l max|lambda(Z_l)|
    ||QJ_l x||^2 <= ||D G||_2^2 with D = diag(max|lambda(Z_l)|^(1/2)). The computed
    spectral norm is inflated by its rounding allowance.
    """
    if certification_obstacle(chain) is not None:
        return np.inf
    linear, angular = column_bounds(chain)
    g = np.sqrt(linear**2 + angular**2)
    inflate = 1 + ROUNDING * EPS * chain.n
    if thetas is None:
        return float(np.linalg.norm(g, 2) * inflate)
    z = spectral(spatial_inertia(np.asarray(thetas, float)), "absmax")  # (V, N)
    return float(max(np.linalg.norm(np.sqrt(zv)[:, None] * g, 2) ** 2 for zv in z) * inflate**2)


# -- the ingredients over configurations ----------------------------------------------

def jacobian_sup(chain, **kw):
    """sup_q sigma_max(QJ) (SVD)."""
    return configuration_bracket(chain, jacobian_family(chain), "smax", quantity_name="sup_q sigma_max(QJ)", **kw)


def jacobian_normality(chain, **kw):
    """inf_q sigma_min(QJ)^2 = inf_q lambda_min((QJ)^T QJ) (Definition 2): observed by SVD of QJ; the certified side is
    the better of branch and bound and the chain's :func:`triangular_normality_floor`."""
    unit = np.tile(np.array([1.0, 0, 0, 0, 1, 1, 1, 0, 0, 0]), (chain.bodies, 1))[None]
    result = configuration_bracket(chain, mass_family(chain, unit), "lmin", value_kind="smin", square=True,
                                   quantity_name="inf_q sigma_min(QJ)^2", thetas=unit, **kw)
    floor = triangular_normality_floor(chain)
    if floor > (result.certified if result.certified is not None else -np.inf):
        result.certified = floor
        result.note = (result.note + "; " if result.note else "") + (
            "certified side from the block-triangular structure of QJ (unit twist of joint l in column l of body "
            "l's block, lengths bound the rest): valid for every q")
        for point in result.convergence:
            point[1] = max(point[1] if point[1] is not None else -np.inf, floor)
    return result


def mass_inf(chain, thetas, **kw):
    """inf over q and the parameter sets of lambda_min(M(q, Theta)); where branch and bound certifies less, the
    proof of Theorem 2 does: lambda_min(M) >= min_l lambda_min(Z(Phi_l)) inf_q sigma_min(QJ)^2 with the
    :func:`triangular_normality_floor`."""
    result = configuration_bracket(chain, mass_family(chain, thetas), "lmin",
                                   quantity_name="inf lambda_min(M(q, Theta))", thetas=thetas, **kw)
    z = spatial_inertia(np.asarray(thetas, float))
    z_min = float((spectral(z, "lmin") - ROUNDING * EPS * spectral(z, "absmax")).min())  # less its rounding
    floor = max(z_min, 0.0) * triangular_normality_floor(chain) * (1 - ROUNDING * EPS)
    if floor > (result.certified if result.certified is not None else -np.inf):
        result.certified = floor
        result.note = (result.note + "; " if result.note else "") + (
            "certified side min_l lambda_min(Z(Phi_l)) times the block-triangular floor of inf sigma_min(QJ)^2")
        for point in result.convergence:
            point[1] = max(point[1] if point[1] is not None else -np.inf, floor)
    return result


def mass_sup(chain, thetas, kind="lmax", name="sup lambda_max(M(q, Theta))", **kw):
    """sup over q and the parameter sets of lambda_max (or sigma_max, kind='absmax') of M(q, Theta)."""
    return configuration_bracket(chain, mass_family(chain, thetas), kind, quantity_name=name, thetas=thetas, **kw)


def skew_partials(dqj):
    """Y_p = dK_p/dq - (dK_p/dq)^T for every row p of QJ (DefK, proof of Theorem 5): (..., 6N, n, n)."""
    return dqj - np.swapaxes(dqj, -1, -2)


def skew_partial_sup(chain, *, samples, refine_s, rng, progress=None):
    """Brackets of max_p sup_q sigma_max(Y_p(q)) and of sup_q (sum_p sigma_max(Y_p)^2)^(1/2).

    Y_p has degree <= 1 per coordinate like QJ, so a first-order Bernstein bound
    applies: sigma(Y_p(q)) <= sigma(Y_p(c)) + S rho on a box, with S the sup itself.
    """
    def sigmas(q):
        return spectral(skew_partials(chain.body_jacobian_derivative(q)), "smax")  # (K, 6N)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    obstacle = certification_obstacle(chain)
    factors = derivative_factors(chain, *bernstein_domain(chain), 1)
    same = np.allclose(bernstein_domain(chain)[0][free], lo[free]) and np.allclose(bernstein_domain(chain)[1][free], hi[free])

    def max_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.where(rho < 1, sigmas(c).max(1) / np.maximum(1 - rho, 1e-300), np.inf)

    usable = obstacle is None and same
    worst = bracket_extreme(lambda q: sigmas(q).max(1), max_bound if usable else None, lo, hi, sense="max",
                            quantity_name="max_p sup_q sigma_max(Y_p)", samples=samples, refine_s=refine_s / 2,
                            rng=rng, free=free, weights=factors, progress=progress,
                            note=obstacle or ("" if same else "joint limits inside a period: no certified side"))
    s = worst.certified

    def rss_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.sqrt(((sigmas(c) + s * rho[:, None]) ** 2).sum(1))

    rss = bracket_extreme(lambda q: np.sqrt((sigmas(q) ** 2).sum(1)),
                          rss_bound if usable and s is not None and np.isfinite(s) else None, lo, hi, sense="max",
                          quantity_name="sup_q (sum_p sigma_max(Y_p)^2)^(1/2)", samples=samples, refine_s=refine_s / 2,
                          rng=rng, free=free, weights=factors, note=worst.note)
    return worst, rss


# -- the ingredients over time ----------------------------------------------------

ACCELERATION_PEAK = {"constant": 0.0, "linear": 0.0, "smoothstep": 6.0, "smootherstep": 10.0 / np.sqrt(3.0),
                     "cosine": np.pi**2 / 2}


def profile_range(profile, span):
    """[min, max] of s(t) over the span (the ramps are monotone; exp is monotone)."""
    t0, t1 = span
    if profile.shape == "exp":
        a = np.exp(profile.rate * (t0 - profile.start))
        b = np.exp(profile.rate * (t1 - profile.start)) if np.isfinite(t1) else (np.inf if profile.rate > 0 else 0.0)
        return min(a, b), max(a, b)
    s0 = float(profile.derivatives(t0)[0])
    s1 = float(profile.derivatives(t1 if np.isfinite(t1) else profile.start + profile.duration + 1)[0])
    return min(s0, s1), max(s0, s1)


def profile_acceleration_bound(profile):
    """sup_t |s''(t)| (inf for 'linear', whose rate jumps)."""
    if profile.shape == "exp":
        return profile.rate**2 if profile.rate <= 0 else np.inf
    if profile.shape == "linear":
        return np.inf
    return ACCELERATION_PEAK[profile.shape] / (profile.duration**2 if profile.shape != "constant" else 1.0)


def affine_loads(trajectory):
    """True when every load is a payload or a scaling: Theta(t) is affine in the profiles' values s_i(t)."""
    return all(isinstance(load, (Payload, Scaling)) for load in trajectory.loads)


def parameter_vertices(trajectory):
    """Stacks (V, N, 10) of Theta and of Thetadot whose convex hulls hold Theta(t) and Thetadot(t) for all t.

    None when a moving mass makes Theta(t) non-affine. With one load the hull of
    Theta is the segment the trajectory sweeps: extremes over it are exact.
    """
    if not affine_loads(trajectory):
        return None
    loads = trajectory.loads
    ranges = [profile_range(load.profile, trajectory.span) for load in loads]
    rates = [load.profile.rate_bound() for load in loads]
    values, rate_values = [], []
    for corner in itertools.product(*[(a, b) for a, b in ranges]) if loads else [()]:
        values.append(_theta_at(trajectory, corner, None))
    for corner in itertools.product(*[(-r, r) for r in rates]) if loads else [()]:
        for s in itertools.product(*[(a, b) for a, b in ranges]) if loads else [()]:
            rate_values.append(_theta_at(trajectory, s, corner))
    return np.array(values), np.array(rate_values)


def _theta_at(trajectory, s, ds):
    """Theta (ds None) or Thetadot for profile values s and rates ds, in the order ParameterTrajectory.theta uses."""
    theta = trajectory.base.astype(float).copy()
    dot = np.zeros_like(theta)
    for load, si, k in zip(trajectory.loads, s, range(len(s))):
        if isinstance(load, Scaling):  # an unbounded s leaves non-finite entries, which callers leave out
            dsi = 0.0 if ds is None else ds[k]
            with np.errstate(invalid="ignore"):
                theta[load.body], dot[load.body] = si * theta[load.body], dsi * theta[load.body] + si * dot[load.body]
    for load, si, k in zip(trajectory.loads, s, range(len(s))):
        if isinstance(load, Payload):
            theta[load.body] += si * load.phi
            dot[load.body] += (0.0 if ds is None else ds[k]) * load.phi
    return theta if ds is None else dot


def _path_geometry(path):
    """(max |c|, max |dc/ds|, max |d2c/ds2|) of a load's path over s in [0, 1]."""
    if path.shape == "line":
        a, b = np.asarray(path.start, float), np.asarray(path.end, float)
        return max(np.linalg.norm(a), np.linalg.norm(b)), np.linalg.norm(b - a), 0.0
    r = path.radius
    return np.linalg.norm(path.center) + r, 2 * np.pi * r, (2 * np.pi) ** 2 * r


def _moving_mass_terms(load):
    """Certified bounds of one moving mass: sup ||f(Phi_p)||, sup sigma(f(Phidot_p)), Psi*, dPsi*."""
    cmax, d1, d2 = _path_geometry(load.path)
    m = load.mass
    rate, acc = load.path.profile.rate_bound(), profile_acceleration_bound(load.path.profile)
    sigma_c = 0.5 * np.trace(load.inertia_com) * np.eye(3) - load.inertia_com
    lever = np.sqrt(1 + cmax**2)
    return {
        "f_norm": m * (1 + cmax**2) + np.linalg.eigvalsh(sigma_c)[-1],
        "f_rate": m * rate * d1 * (2 * cmax + 1),
        "psi": m * rate * d1 * lever,
        "psi_dot": m * (acc * d1 + rate**2 * d2) * lever if np.isfinite(acc) else np.inf,
    }


BODY_FUNCTIONS = {  # name: (matrix of Phi, spectral kind, uses Thetadot)
    "lmin_f": (pseudo_inertia, "lmin", False),
    "lmax_f": (pseudo_inertia, "lmax", False),
    "lmin_Z": (spatial_inertia, "lmin", False),
    "lmax_Z": (spatial_inertia, "lmax", False),
    "smax_fdot": (pseudo_inertia, "absmax", True),
    "smax_Zdot": (spatial_inertia, "absmax", True),
}


def time_extreme(trajectory, name, *, samples=2001, horizon=None):
    """min over bodies of inf_t (lmin_*) or max over bodies of sup_t (the others) of a body function, bracketed.

    Returns dict(observed, certified, witness_time, body, how). The observed side
    is a true value on a time grid; the certified side comes from the segment
    ends (payloads, scalings) or from positivity and rate bounds (moving masses).
    """
    build, kind, rate = BODY_FUNCTIONS[name]
    t = trajectory.times(samples, horizon)
    theta, theta_dot = trajectory.theta(t)
    vals = spectral(build(theta_dot if rate else theta), kind)  # (T, N)
    sense = "min" if kind == "lmin" else "max"
    flat = np.argmin(vals) if sense == "min" else np.argmax(vals)
    ti, body = np.unravel_index(flat, vals.shape)
    observed = float(vals[ti, body])
    verts = parameter_vertices(trajectory)
    if verts is not None:
        stack = verts[1] if rate else verts[0]
        finite = np.all(np.isfinite(stack), axis=(-2, -1))
        cvals = spectral(build(stack[finite]), kind)
        if finite.all():
            certified = float(cvals.min() if sense == "min" else cvals.max())
            how = ("exact: the extreme over t is at an end of the segment Theta_base + s Phi_load (one load per body)"
                   if len(trajectory.loads) <= 1 else "the hull of the loads' segments (an outer bound)")
        elif sense == "min":
            certified = float(cvals.min())
            how = "a scaling grows without bound on the span; growth of a consistent body only raises lambda_min"
        else:
            certified, how = np.inf, "a profile grows without bound on the span: the supremum is infinite"
    else:
        certified, how = _moving_mass_bound(trajectory, name), "positivity of the loads and their rate bounds"
    return {"observed": observed, "certified": certified, "witness_time": float(t[ti]), "body": int(body), "how": how,
            "sense": sense}


def _moving_mass_bound(trajectory, name):
    build, kind, rate = BODY_FUNCTIONS[name]
    base = spectral(build(trajectory.base), kind)
    extra = np.zeros(trajectory.bodies)
    for load in trajectory.loads:
        if not isinstance(load, MovingMass):
            return -np.inf if kind == "lmin" else np.inf
        terms = _moving_mass_terms(load)
        factor = 2.0 if build is spatial_inertia else 1.0  # ||Z(F)|| <= 2 ||F|| for F >= 0 or |F| bounded (key step)
        extra[load.body] += factor * (terms["f_rate"] if rate else terms["f_norm"])
    if rate:
        return float(extra.max())
    if kind == "lmin":
        return float(base.min())  # adding a consistent body only adds a PSD term
    return float((base + extra).max())


def lumped_velocity_bounds(trajectory, *, samples=2001):
    """Psi* = sup_t ||Psi||, dPsi* = sup_t ||Psidot||: observed on a time grid, certified from the paths and profiles."""
    t = trajectory.times(samples)
    psi, psi_dot = trajectory.psi(t)
    n_psi, n_dot = np.linalg.norm(psi, axis=-1), np.linalg.norm(psi_dot, axis=-1)
    cert_psi = cert_dot = 0.0
    for load in trajectory.loads:
        if isinstance(load, MovingMass):
            terms = _moving_mass_terms(load)
            cert_psi += terms["psi"]
            cert_dot += terms["psi_dot"]
    return {"psi": {"observed": float(n_psi.max()), "certified": cert_psi, "witness_time": float(t[np.argmax(n_psi)])},
            "psi_dot": {"observed": float(n_dot.max()), "certified": cert_dot, "witness_time": float(t[np.argmax(n_dot)])}}


# -- the entry point for audits -----------------------------------------------------------

def mass_matrix_bounds(chain, theta, *, samples=2000, refine_s=0.5, rng=None, progress=None):
    """alpha1 and alpha2 of Theorems 2 and 3 (paper and sharpest certified) and the observed eigenvalue extremes of
    M(q, theta) for constant parameters ``theta`` (N, 10) over the chain's joint limits.

    Returns a plain dict: for each of "lower" and "upper": paper (the paper's
    constant from bracketed ingredients: value, lower, upper), certified (the
    sharpest constant the suite certifies and how), observed (the bracket of the
    true extreme: lower, upper, witness). Unlimited prismatic joints give an
    unbounded domain: the upper extreme may be infinite and is not certified.
    """
    rng = np.random.default_rng(0) if rng is None else rng
    theta = np.asarray(theta, float)
    kw = dict(samples=samples, refine_s=refine_s, rng=rng, progress=progress)
    cert = key_step_certificate()
    f = pseudo_inertia(theta)
    z = spatial_inertia(theta)
    xi, zeta = float(spectral(f, "lmin").min()), float(spectral(f, "lmax").max())
    z_min, z_max = float(spectral(z, "lmin").min()), float(spectral(z, "lmax").max())
    gamma = jacobian_normality(chain, **kw)
    sigma = jacobian_sup(chain, **kw)
    low = mass_inf(chain, theta[None], **kw)
    high = mass_sup(chain, theta[None], **kw)
    return {
        "key_step_certificate": {k: v for k, v in cert.items() if k != "choi"},
        "ingredients": {"xi": xi, "zeta": zeta, "lambda_min_Z": z_min, "lambda_max_Z": z_max,
                        "inf_sigma_min_QJ_sq": _bracket_data(gamma), "sup_sigma_max_QJ": _bracket_data(sigma)},
        "lower": lower_constants(xi, z_min, gamma, low),
        "upper": upper_constants(zeta, z_max, sigma, high),
    }


def _bracket_data(b: Bracket):
    return {"lower": b.lower, "upper": b.upper, "witness": np.asarray(b.witness).tolist(), "note": b.note,
            "convergence": b.convergence}


def lower_constants(xi, z_min, gamma: Bracket, observed: Bracket, xi_observed=None):
    """Theorem 2: the paper's alpha1 = xi gamma and the sharpest certified constant.

    ``xi`` is min_l inf_t lambda_min(f(Phi_l)) (a certified lower bound; for constant Phi exact), ``xi_observed``
    its observed value (default: xi), ``z_min`` a certified min_l inf_t lambda_min(Z(Phi_l)), ``gamma`` the
    bracket of inf_q sigma_min(QJ)^2, ``observed`` that of inf lambda_min(M). The paper's alpha1 lies in
    [paper.lower, paper.upper]: its ingredients at their certified sides and at their observed values;
    paper.value is the upper end (observed ingredients), an estimate, not the paper's constant itself.
    """
    xi_observed = xi if xi_observed is None else xi_observed
    paper = {"value": xi_observed * gamma.upper, "lower": xi * max(gamma.lower, 0.0), "upper": xi_observed * gamma.upper,
             "note": "min_l inf_t lambda_min(f(Phi_l)) inf_q lambda_min((QJ)^T QJ) lies in [lower, upper] (certified, "
                     "observed ingredients); value = upper, an upper estimate"}
    structural = z_min * max(gamma.lower, 0.0)
    direct = observed.lower if np.isfinite(observed.lower) else -np.inf
    certified = max(structural, direct, paper["lower"])
    how = ("certified lower side of inf lambda_min(M) (branch and bound, or the proof of Theorem 2 with the "
           "block-triangular normality floor)" if direct >= structural else
           "min_l inf_t lambda_min(Z(Phi_l)) times the certified lower side of inf_q sigma_min(QJ)^2 (the proof of "
           "Theorem 2 at the level of Z)")
    return {"paper": paper, "certified": {"value": certified, "how": how},
            "observed": _bracket_data(observed)}


def upper_constants(zeta, z_max, sigma: Bracket, observed: Bracket, zeta_observed=None):
    """Theorem 3: the paper's alpha2 = 2 zeta S^2 and the sharpest certified constant.

    ``zeta`` is max_l sup_t lambda_max(f(Phi_l)) (a certified upper bound), ``zeta_observed`` its observed value
    (default: zeta), ``z_max`` a certified max_l sup_t lambda_max(Z(Phi_l)), ``sigma`` the bracket of
    sup_q sigma_max(QJ), ``observed`` that of sup lambda_max(M). The paper's alpha2 lies in
    [paper.lower, paper.upper]; paper.value is the lower end (observed ingredients), an estimate.
    """
    zeta_observed = zeta if zeta_observed is None else zeta_observed
    paper = {"value": 2 * zeta_observed * sigma.lower**2, "lower": 2 * zeta_observed * sigma.lower**2,
             "upper": 2 * zeta * sigma.upper**2,
             "note": "2 max_l sup_t lambda_max(f(Phi_l)) sup_q sigma_max(QJ)^2 lies in [lower, upper] (observed, "
                     "certified ingredients); value = lower, a lower estimate"}
    structural = z_max * sigma.upper**2
    direct = observed.upper
    certified = min(structural, direct, paper["upper"])
    how = ("certified upper side of sup lambda_max(M) by branch and bound (or from lengths)" if direct <= structural
           else "max_l sup_t lambda_max(Z(Phi_l)) times the certified sup_q sigma_max(QJ)^2 (the proof at the level of Z)")
    return {"paper": paper, "certified": {"value": certified, "how": how}, "observed": _bracket_data(observed)}
