"""Certified lambda_min / lambda_max of M(q, Theta) on a box from the pivots of the articulated-body factorisation
(Loewner-monotone, O(n) 6 x 6 operations per box and trial value). Used, through the ladder of
:mod:`inertiaproof.bounds.pivot_search`, for inf_q sigma_min(QJ)^2 (unit bodies, Definition 2) and Theorem 2's
inf lambda_min(M) >= inf lambda_min(sum_l mu_l QJ_l^T QJ_l) (isotropic bodies), where it is well behaved, in
profiles with a budget of at least ``PIVOT_MIN_ROUNDS`` rounds per bracket; and by :mod:`inertiaproof.bounds.interface`
for the two halves of a chain split at a body (:func:`articulated_lower`, :func:`interface_test`, ``top``).

Measured (issue 12, Panda's sampled minimiser, bound / value at the centre for a box of the radius in every free
joint): unit bodies 0.98 (0.01 rad), 0.90 (0.1 rad), 0.51 (0.3 rad); with real inertias (2 kg) 0.99 (0.03 rad),
0.91 (0.1 rad), nothing at 0.3 rad (joint 6 alone: 0.97 at 0.1 rad; before the loss about the centre's derivative:
0.93 at 0.03, nothing at 0.1). A Loewner lower bound of Phi(x)^T P Phi(x) over an interval of x must drop heavy
directions of an anisotropic articulated inertia onto its light ones, which the real inertias' wrist (light
eigenvalue 1e-3 of M against heavy 5) feels most. ``python bench/pivot_radius.py`` prints the bound
against the radius.

M(q) + a I > 0 exactly when every pivot of its tip-first LDL^T factorisation is positive. In body coordinates
(MassMatrix: M = sum_b QJ_b^T Z_b QJ_b, body twists V_b = Phi_b(q_b) V_(b-1) + s_b qdot_b, Phi_b the twist map of
before_b Jz(q_b) after_b) the pivots are those of the articulated-body recursion with armature a:

    A_(n-1) = Z_(n-1),  D_b = s_b^T A_b s_b + a,  P_b = A_b - A_b s_b s_b^T A_b / D_b,
    A_(b-1) = Z_(b-1) + Phi_b^T P_b Phi_b.

Every step is monotone in the Loewner order where the pivots are positive (P is a Schur complement; congruence
keeps the order), so Loewner LOWER bounds L_b <= A_b(q) valid on the whole box give lower bounds of every
pivot. The only box-dependent step is the turn (slide) of joint b: F(x) = Phi_b(x)^T P Phi_b(x) is a
trigonometric polynomial of degree 2 in x (a polynomial of degree 2 for a slide); its five Fourier
coefficients about the centre (from five samples, exact) give, for d = x - c_b, |d| <= r_b, S = sin min(r, pi/2),
E = 1 - cos min(r, pi) (:func:`_turn_terms`):

    up to SWITCH rad:  F(x) >= F(c_b) - S |F_1s + 2 F_2s| - E pos(F_1c + 4 F_2c) - 2 E^2 pos(-F_2c) - 2 S E |F_2s|
    beyond:            F(x) >= F(c_b) - S |F_1s| - E pos(F_1c) - (1 - cos min(2r, pi)) pos(F_2c) - sin min(2r, pi/2) |F_2s|

(the first from sin 2d = 2 sin d - 2 sin d (1 - cos d), cos 2d - 1 = -4 (1 - cos d) + 2 (1 - cos d)^2: its first
order term is the derivative F'(c) = F_1s + 2 F_2s, not the sum of the two harmonics' sizes; |.| and pos(.) the
matrix absolute value and positive part in a metric from F(c_b): its eigenvalues shifted up to definite, or
|F(c_b)|, each plus a ridge; the ladder calibrates which, |F| for the real inertias only). |F(c_b)| keeps the light
directions of an indefinite P (the pivot's own direction is negative) on their own scale: SO-101's bodies
themselves, nothing at 64x -> 1.45x at 45,000 boxes. The last turn (joint 2) is seen only along s_1: its scalar
form s_1^T F(x) s_1 is bounded the same way with scalars (exact to second order). So M(q) + a I > 0 on the box
when all pivot bounds are positive: lambda_min(M) >= -a. The upper side (lambda_max) is the same test of -M + a I,
i.e. bodies -Z. Bisection over a gives the bound of a box.

Rounding (stated): each level's Loewner bound is lowered by ``ROUNDING`` eps times the Frobenius norms of the
matrices formed at that level (the five samples times 1 + 3 sum of the loss weights, for the Fourier sums, and the
loss), each pivot bound by ``ROUNDING`` eps (|s|^2 ||L||_F + |a|), the scalar form by ``ROUNDING`` eps (its
samples, the turned matrix, the loss); the absolute values and positive parts in a metric carry the residual of
the computed roots of the metric (:func:`_bounding_parts`), Weyl for the eigen-decompositions.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from inertiaproof.budget import available_cores
from inertiaproof.dynamics.twists import twist_map
from inertiaproof.model.inertia import spatial_inertia

from .spectral import EPS, ROUNDING

__all__ = ["METRICS", "PIVOT_LIMIT", "PIVOT_MIN_ROUNDS", "PivotFamily", "RIDGE", "RIDGES", "SWITCH",
           "articulated_lower", "eigen_compose", "interface_test", "pivot_bounds", "pivot_test"]

PIVOT_MIN_ROUNDS = 20  # bracket budgets (rounds) from which the pivot ladders run (ci and deep; audits with --bounds all)
PIVOT_LIMIT = 8  # free coordinates up to which the ladders run (a 7-joint arm and its gripper's slide)
RIDGE = 1e-2  # relative ridge of the loss metric (default; the ladder picks one of RIDGES per form)
METRICS = ("shift", "abs")  # the turned matrix at the centre F made definite by a shift of its eigenvalues, or |F|
# (measured, Panda deep: |F| takes the block form's ladder 1.03x -> 1.05x, so only the real inertias try it)
RIDGES = (1e-3, 1e-2, 1e-1)  # measured (Panda): unit bodies best at 1e-2, the weighted form at 1e-1; 1e-4 needs 10-100x the boxes
SWITCH = 0.4  # radius (rad) up to which a turn's loss is taken about the centre's derivative (see _turn_terms)
ANGLES = 2 * np.pi * np.arange(5) / 5
SPLIT = 512  # boxes per thread from which pivot_test splits its boxes over threads


def eigen_compose(u, w):
    """u diag(w) u^T for stacks u (..., 6, 6), w (..., 6)."""
    return (u * w[..., None, :]) @ np.swapaxes(u, -1, -2)


def _bounding_parts(terms, kinds, metric=None):
    """For symmetric A_t (T, ..., 6, 6) (``terms``) a W_t with W_t >= A_t and W_t >= -A_t (kind 'abs': the
    matrix absolute value) or W_t >= A_t and W_t >= 0 (kind 'pos': the positive part), in the metric of
    H > 0 (H^(1/2) f(H^(-1/2) A H^(-1/2)) H^(1/2); H = I when None; ``metric`` is H's eigen-decomposition
    (values (..., 6) > 0, vectors)). Any H > 0 is valid; H near the matrix being bounded keeps the loss relative
    to it in every direction. Also returns each term's spread in that metric (T, ...): the largest |eigenvalue|
    of H^(-1/2) A H^(-1/2) (a heuristic only: the relative size of the loss).

    Rounding (Frobenius norms, all upper bounds of spectral norms): with R ~ H^(1/2) and T ~ H^(-1/2) the
    computed roots (whatever they are; T invertible), X~ = fl(T A T) is within e2 = ROUNDING eps ||T||^2 ||A||
    of X = T A T (Higham 3.5); Y = f(X~) from its eigen-decomposition, lifted by e1 = ROUNDING eps
    (||X~|| + ||Y||) (Weyl), then by e2, satisfies Y >= +-X (or Y >= X, 0), so T^-1 Y T^-1 >= +-A exactly.
    With rho >= ||R T - I|| (computed, plus ROUNDING eps ||R|| ||T||) and Delta = R - T^-1,
    ||Delta|| <= rho ||R|| / (1 - rho), and fl(R Y R) is within ||Delta|| ||Y|| (2 ||R|| + ||Delta||)
    + ROUNDING eps ||R||^2 ||Y|| of T^-1 Y T^-1: that much is added as a multiple of I (rho >= 1/2: +inf)."""
    terms = np.asarray(terms)
    absolute = np.array([k == "abs" for k in kinds])[(slice(None),) + (None,) * (terms.ndim - 1)]
    eye = np.eye(terms.shape[-1])
    norm = (lambda x: np.linalg.norm(x, axis=(-2, -1)))
    if metric is None:
        w, u = np.linalg.eigh(terms)
        out = eigen_compose(u, np.where(absolute[..., 0], np.abs(w), np.maximum(w, 0)))
    else:
        hw, hu = metric
        hw = np.maximum(hw, 1e-300)
        root, inv = eigen_compose(hu, np.sqrt(hw)), eigen_compose(hu, 1 / np.sqrt(hw))
        x = inv @ terms @ inv
        w, u = np.linalg.eigh(x)
        y = eigen_compose(u, np.where(absolute[..., 0], np.abs(w), np.maximum(w, 0)))
        n_root, n_inv = norm(root), norm(inv)
        lift = ROUNDING * EPS * (norm(x) + norm(y) + n_inv**2 * norm(terms))
        y = y + lift[..., None, None] * eye
        rho = norm(root @ inv - eye) + ROUNDING * EPS * n_root * n_inv
        with np.errstate(divide="ignore", invalid="ignore"):
            delta = np.where(rho < 0.5, rho * n_root / (1 - rho), np.inf)
        n_y = norm(y)
        lift = delta * n_y * (2 * n_root + delta) + ROUNDING * EPS * n_root**2 * n_y
        out = root @ y @ root + lift[..., None, None] * eye
    slack = ROUNDING * EPS * (norm(terms) + norm(out))
    return out + slack[..., None, None] * eye, np.abs(w).max(-1)


def _harmonics(samples):
    """(F1c, F1s, F2c, F2s) of a trigonometric polynomial of degree 2 from its samples (5, ...) at c + ANGLES: the
    Fourier coefficients about the centre c (exact: five samples, five coefficients)."""
    return tuple(np.tensordot(0.4 * w, samples, axes=1)
                 for w in (np.cos(ANGLES), np.sin(ANGLES), np.cos(2 * ANGLES), np.sin(2 * ANGLES)))


def _turn_terms(f1c, f1s, f2c, f2s, rr):
    """The four terms T_k (kinds abs, pos, pos, abs) and weights w_k >= 0 with F(c + d) - F(c) >= -sum_k w_k W_k for
    every |d| <= r, W_k >= +-T_k (abs) or W_k >= T_k, 0 (pos). Up to ``SWITCH`` rad about the centre's
    derivative: sin d G1 - (1 - cos d) G2 + 2 (1 - cos d)^2 F2c - 2 sin d (1 - cos d) F2s with G1 = F1s + 2 F2s,
    G2 = F1c + 4 F2c (weights S, E, 2 E^2, 2 S E; S = sin min(r, pi/2), E = 1 - cos min(r, pi)); beyond, term by
    term: F1s sin d - F1c (1 - cos d) - F2c (1 - cos 2d) + F2s sin 2d (weights S, E, 1 - cos min(2r, pi),
    sin min(2r, pi/2)), which loses less on wide intervals. The choice depends on r only."""
    near = rr <= SWITCH
    sin_r, cos_r = np.sin(np.minimum(rr, np.pi / 2)), 1 - np.cos(np.minimum(rr, np.pi))
    sin_2r, cos_2r = np.sin(np.minimum(2 * rr, np.pi / 2)), 1 - np.cos(np.minimum(2 * rr, np.pi))
    terms = np.stack([np.where(near, f1s + 2 * f2s, f1s), np.where(near, f1c + 4 * f2c, f1c),
                      np.where(near, -f2c, f2c), f2s])
    weights = (sin_r, cos_r, np.where(near, 2 * cos_r**2, cos_2r), np.where(near, 2 * sin_r * cos_r, sin_2r))
    return terms, weights


class PivotFamily:
    """The chain's fixed maps and body inertias (a stack of parameter sets) for :func:`pivot_bounds`."""

    def __init__(self, chain, thetas=None, ridge=RIDGE, inertias=None, metrics=METRICS[:1]):
        """Bodies from parameter rows ``thetas`` (V, N, 10) or directly as symmetric 6 x 6 ``inertias`` (V, N, 6, 6)
        (any body forms, e.g. lower forms of the spatial inertias); ``metrics`` the kinds of loss metric a ladder
        may calibrate."""
        self.chain = chain
        self.ridge = ridge  # relative ridge of the turns' loss metric: any value is sound
        self.metrics = metrics
        self.metric = metrics[0]  # the metric's kind (METRICS): any is sound
        self.z = spatial_inertia(np.asarray(thetas, float)) if inertias is None else np.asarray(inertias, float)
        self.twists = np.array([j.unit_twist for j in chain.z_joints])  # (n, 6)
        self.revolute = [j.revolute for j in chain.z_joints]
        self.after = [twist_map(j.after) for j in chain.z_joints]
        self.before = [twist_map(j.before) for j in chain.z_joints]

    def turn_maps(self, b, x):
        """tm(Jz(x)) for x (K,): (K, 6, 6)."""
        x = np.asarray(x, float)
        out = np.zeros(x.shape + (6, 6))
        if self.revolute[b]:  # blockdiag(Rz(x)^T, Rz(x)^T)
            c, s = np.cos(x), np.sin(x)
            for o in (0, 3):
                out[:, o, o] = out[:, o + 1, o + 1] = c
                out[:, o, o + 1], out[:, o + 1, o] = s, -s
                out[:, o + 2, o + 2] = 1.0
        else:  # [[I, -S(x e_z)], [0, I]]
            out[:] = np.eye(6)
            out[:, 0, 4], out[:, 1, 3] = x, -x
        return out

    def rotated_lower(self, b, p, c, r, relative=True):
        """A Loewner lower bound over |x - c| <= r (K,) of Phi_b(x)^T p Phi_b(x), p (K, V, 6, 6); and its loss
        (K, V; a heuristic for where to split): relative to the centre's matrix in its metric, or (``relative``
        False: the identity metric) absolute.

        A turn: with d = x - c, F(c + d) - F(c) = sin d G1 - (1 - cos d) G2 + 2 (1 - cos d)^2 F2c
        - 2 sin d (1 - cos d) F2s, G1 = F1s + 2 F2s (F'(c)), G2 = F1c + 4 F2c (from cos 2d - 1 = -4 (1 - cos d)
        + 2 (1 - cos d)^2 and sin 2d = 2 sin d - 2 sin d (1 - cos d)), the Fourier coefficients taken about c;
        with S = sin min(r, pi/2) >= |sin d| and E = 1 - cos min(r, pi) >= 1 - cos d >= 0 the loss is
        S |G1| + E pos(G2) + 2 E^2 pos(-F2c) + 2 S E |F2s|. A slide: F(c + d) = F0 + d F1 + d^2 F2 exactly."""
        after, before = self.after[b], self.before[b]
        q = after.T @ p @ after  # tm(after)^T p tm(after)
        rr = r[:, None, None, None]
        if self.revolute[b]:
            samples = np.stack([self._turned(b, q, c + d) for d in ANGLES])  # (5, K, V, 6, 6)
            terms, weights = _turn_terms(*_harmonics(samples), rr)
            h = self._metric(samples[0]) if relative else None
            parts, spread = _bounding_parts(terms, ("abs", "pos", "pos", "abs"), h)
            centre = samples[0]
            size = np.linalg.norm(samples, axis=(-2, -1)).sum(0) * (1 + 3 * sum(weights))[..., 0, 0]
        else:
            f0, fp, fm = (self._turned(b, q, c + d) for d in (0.0, 1.0, -1.0))
            f1, f2 = 0.5 * (fp - fm), 0.5 * (fp + fm) - f0
            h = self._metric(f0) if relative else None
            parts, spread = _bounding_parts(np.stack([f1, f2]), ("abs", "abs"), h)
            weights = (rr, rr**2)
            centre = f0
            size = (np.linalg.norm(f0, axis=(-2, -1)) + np.linalg.norm(fp, axis=(-2, -1))
                    + np.linalg.norm(fm, axis=(-2, -1))) * (1 + r[:, None]) ** 2
        loss = sum(w * part for w, part in zip(weights, parts))
        measure = sum(w[..., 0, 0] * x for w, x in zip(weights, spread))  # the loss in the metric (or absolute)
        lower = before.T @ (centre - loss) @ before
        norm_b = np.linalg.norm(before) ** 2 * np.linalg.norm(after) ** 2
        loss_norm = np.linalg.norm(loss, axis=(-2, -1))
        slack = ROUNDING * EPS * norm_b * (size + loss_norm)
        return lower - slack[..., None, None] * np.eye(6), measure

    def rotated_form_lower(self, b, p, c, r, v):
        """A lower bound over |x - c| <= r (K,) of v^T tm(before)^T Phi_b(x)^T p Phi_b(x) tm(before) v, p (K, V, 6, 6):
        the same expansion as :meth:`rotated_lower` for the scalar trigonometric (a slide: algebraic)
        polynomial, exact to the second order; used for the last turn, whose matrix is only seen along v. Also
        returns the loss (K, V)."""
        after, w = self.after[b], self.before[b] @ v
        q = after.T @ p @ after
        rr = r[:, None]
        if self.revolute[b]:
            samples = np.stack([(self._turned(b, q, c + d) @ w) @ w for d in ANGLES])  # (5, K, V)
            terms, weights = _turn_terms(*_harmonics(samples), rr)
            loss = (weights[0] * np.abs(terms[0]) + weights[1] * np.maximum(terms[1], 0)
                    + weights[2] * np.maximum(terms[2], 0) + weights[3] * np.abs(terms[3]))
            size = np.abs(samples).sum(0) * (1 + 3 * sum(weights))
        else:
            f0, fp, fm = ((self._turned(b, q, c + d) @ w) @ w for d in (0.0, 1.0, -1.0))
            samples = np.stack([f0, fp, fm])
            loss = rr * np.abs(0.5 * (fp - fm)) + rr**2 * np.abs(0.5 * (fp + fm) - f0)
            size = np.abs(samples).sum(0) * (1 + rr) ** 2
        norm_b = np.linalg.norm(after) ** 2 * float(w @ w)
        return samples[0] - loss - ROUNDING * EPS * (norm_b * np.linalg.norm(q, axis=(-2, -1)) + size + loss), loss

    def _metric(self, f):
        """The metric the turn's loss is measured in: the turned matrix at the centre made definite, as its
        eigen-decomposition (values, vectors): ``metric`` 'shift' puts a ridge of ``ridge`` times its largest
        |eigenvalue| above its smallest eigenvalue, if negative; 'abs' takes |eigenvalues| plus that ridge. Any
        definite metric is valid (_bounding_parts)."""
        w, u = np.linalg.eigh(f)
        top = self.ridge * np.maximum(np.abs(w).max(-1), 1e-300)
        if self.metric == "abs":
            return np.abs(w) + top[..., None], u
        return w + (top - np.minimum(w[..., 0], 0))[..., None], u

    def _turned(self, b, q, x):
        t = self.turn_maps(b, x)[:, None]  # (K, 1, 6, 6)
        return np.swapaxes(t, -1, -2) @ q @ t


def pivot_test(family: PivotFamily, sign, armature, centres, radii, top=None):
    """Whether sign * M(q) + a I > 0 on each box for every parameter set: (K, V) booleans, and per joint the
    relative loss of its turn (K, n) (where splitting helps). ``armature`` (K, V). ``top``: the chain of joints
    0..top only, body top's inertia that of the family (a head of :mod:`inertiaproof.bounds.interface`).
    From 2 ``SPLIT`` boxes on, the boxes are split over the cores' threads (batched NumPy and LAPACK release the
    GIL; the answer is the same)."""
    return _threaded(lambda *a: _pivot_test(family, sign, *a, top=top), armature, centres, radii)


def interface_test(family: PivotFamily, armature, lower, k, centres, radii):
    """Whether the articulated inertia A_k(q) that the tail (bodies k+1..n-1) hands to body k, with armature a, is
    >= ``lower`` (V, 6, 6) on each box, every pivot of joints k+1..n-1 positive: (K, V) booleans and the turns'
    relative losses (K, n). The Loewner lower bound of A_k (:func:`articulated_lower`) less ``lower`` is checked
    definite with lambda_min moved down by ``ROUNDING`` eps (||A_k bound||_F + ||lower||_F) (Weyl: the bound's last
    sum Z_k + turned part, the subtraction and the eigensolver)."""
    def test(armature, centres, radii):
        ok, a, losses = articulated_lower(family, armature, k, centres, radii)
        slack = ROUNDING * EPS * (np.linalg.norm(a, axis=(-2, -1)) + np.linalg.norm(lower, axis=(-2, -1)))
        return ok & (np.linalg.eigvalsh(a - lower)[..., 0] - slack > 0), losses

    return _threaded(test, armature, centres, radii)


def articulated_lower(family: PivotFamily, armature, k, centres, radii):
    """A Loewner lower bound over each box of A_k(q), the articulated inertia with armature a (K, V) that bodies
    k+1..n-1 hand to body k (A_k = Z_k + Phi_(k+1)^T P_(k+1) Phi_(k+1)): (whether every pivot of joints k+1..n-1
    is positive (K, V), the bound (K, V, 6, 6), the turns' relative losses (K, n)). At radius 0: A_k(q) less its
    rounding allowance."""
    return _descend(family, family.z, armature, centres, radii, family.chain.n - 1, k, True)


def _threaded(test, armature, centres, radii):
    workers = min(available_cores(), 8, len(centres) // SPLIT)
    if workers < 2:
        return test(armature, centres, radii)
    parts = np.array_split(np.arange(len(centres)), workers)
    with ThreadPoolExecutor(workers) as pool:
        found = list(pool.map(lambda k: test(armature[k], centres[k], radii[k]), parts))
    return np.concatenate([ok for ok, _ in found]), np.concatenate([loss for _, loss in found])


def _schur(a, s, armature):
    """The pivot D = s^T A s + a and the Schur complement P = A - A s s^T A / D, both rounded down (P where D > 0)."""
    u = a @ s
    d = u @ s + armature
    d = d - ROUNDING * EPS * (np.dot(s, s) * np.linalg.norm(a, axis=(-2, -1)) + np.abs(armature))
    safe = np.where(d > 0, d, 1.0)
    p = a - u[..., :, None] * u[..., None, :] / safe[..., None, None]
    p = p - (ROUNDING * EPS * (np.linalg.norm(a, axis=(-2, -1)) + (u * u).sum(-1) / safe))[..., None, None] * np.eye(6)
    return d, p


def _descend(family, z, armature, centres, radii, top, bottom, relative):
    """The pivots of joints top..bottom + 1 from A_top = Z_top and the turns between them: (ok (K, V), the Loewner
    lower bound of A_bottom (K, V, 6, 6), the turns' losses (K, n))."""
    a = np.broadcast_to(z[None, :, top], (len(centres),) + z.shape[:1] + (6, 6)).copy()
    ok = np.ones((len(centres), z.shape[0]), bool)
    losses = np.zeros((len(centres), family.chain.n))
    for b in range(top, bottom, -1):
        d, p = _schur(a, family.twists[b], armature)
        ok &= d > 0
        g, loss = family.rotated_lower(b, p, centres[:, b], radii[:, b], relative=relative)
        losses[:, b] = loss.max(1)
        a = z[None, :, b - 1] + g
    return ok, a, losses


def _pivot_test(family, sign, armature, centres, radii, top=None):
    z = sign * family.z  # (V, N, 6, 6)
    top = family.chain.n - 1 if top is None else top
    ok, a, losses = _descend(family, z, armature, centres, radii, top, min(top, 1), sign > 0)
    d, p = _schur(a, family.twists[min(top, 1)], armature)
    ok &= d > 0
    if top >= 1:  # the last turn (joint 1) is seen only along s_0: its scalar form
        s0 = family.twists[0]
        form, form_loss = family.rotated_form_lower(1, p, centres[:, 1], radii[:, 1], s0)
        d0 = (z[:, 0] @ s0) @ s0 + form + armature
        losses[:, 1] = (form_loss / np.maximum(np.abs(d0), 1e-300)).max(1)
        d0 = d0 - ROUNDING * EPS * (np.dot(s0, s0) * np.linalg.norm(z[:, 0], axis=(-2, -1)) + np.abs(form) + np.abs(armature))
        ok &= d0 > 0
    return ok, losses


def pivot_bounds(family: PivotFamily, kind, centres, radii, start, *, steps=40):
    """Certified bound of lambda_min ('lmin', a lower bound) or lambda_max ('lmax', an upper bound) of M on each
    box, by bisection between a value ``start`` (K, V) that is attained (the centre's eigenvalue) and the
    largest (lmin) or smallest (lmax) armature that passes :func:`pivot_test`. Returns ((K,) the worst over the
    stack, -inf / inf where nothing passed), and per box the joints' losses (K, n)."""
    sign = 1.0 if kind == "lmin" else -1.0
    start = np.asarray(start, float)
    span = np.maximum(np.abs(start), 1e-300)
    # passing side: gamma = start - t * span for t in [0, 1] (lmin: gamma below the centre's lambda_min)
    lo_t, hi_t = np.zeros(start.shape), np.ones(start.shape)
    ok, losses = pivot_test(family, sign, -(sign * (start - sign * hi_t * span)), centres, radii)
    good = np.where(ok, hi_t, np.nan)  # t of a passing gamma
    if not ok.any():
        return np.full(len(centres), -np.inf if kind == "lmin" else np.inf), losses
    for _ in range(steps):
        mid = 0.5 * (lo_t + hi_t)
        gamma = start - sign * mid * span
        ok, _ = pivot_test(family, sign, -sign * gamma, centres, radii)
        hi_t = np.where(ok, mid, hi_t)
        lo_t = np.where(ok, lo_t, mid)
        good = np.where(ok, mid, good)
    gamma = np.where(np.isnan(good), -sign * np.inf, start - sign * np.nan_to_num(good) * span)
    return (gamma.min(1) if kind == "lmin" else gamma.max(1)), losses
