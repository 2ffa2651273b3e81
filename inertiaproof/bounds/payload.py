"""Beyond the paper: Theorems 2-4 over every consistent payload a body may carry (the payload envelope).

The payload set P (a :class:`PayloadSet`) holds the Phi_p of every mass distribution of mass at most m supported
in the ellipsoid E = {c + d : sum_i d_i^2 / a_i^2 <= 1} of body k's frame (a ball of radius R when a_i = R):
pseudo-inertias J = f(Phi_p) >= 0 with tr(Q J) >= 0 for the ellipsoid's Q and J_44 <= m (Wensing, Kim and Slotine
2017). By the S-lemma this LMI set is the closed convex hull of the point masses m' delta_x, 0 <= m' <= m, x in E
(``tests/test_payload.py`` compares the two descriptions). The payload enters M(q, Theta + Phi_p e_k) = M(q, Theta)
+ QJ_k^T Z(Phi_p) QJ_k linearly (DefMatrixZ), so:

- inf lambda_min over P is the bare arm's, as Z(Phi_p) >= 0: alpha1 does not change (LowerBoundedness);
- lambda_max is convex in Phi_p, and for a point mass v^T Z(m delta_x) v = m |p + omega x d|^2, d = x - c (p the
  velocity of c, omega the angular velocity of body k for qdot = v), is convex in d: the sup over P is attained by a
  point mass m on the boundary of E, which :func:`worst_point_masses` finds by alternating the top eigenvector and
  the point;
- Young's inequality |p + omega x d|^2 <= (1 + eps) |p|^2 + (1 + 1/eps) omega^T U omega, with U >= S(d)^T S(d) on E
  (:func:`cover_inertia`; R^2 I for a ball), gives Z(Phi_p) <= Z(Phi_U) on P for Phi_U = (1 + eps) Phi(m delta_c)
  + (1 + 1/eps) m U on (I11, I22, I33) (:func:`covering_parameters`). eps = (omega^T U omega)^(1/2) / |p| at the
  worst point mass makes it touch there for a ball: the sup over P is certified as the sup of the arm with Phi_U
  added to body k (UpperBoundedness);
- a payload taken up as s(t) Phi_p has Thetadot = s' Phi_p and sigma_max(M(q, Thetadot)) = |s'| lambda_max(M(q,
  Phi_p)) (BoundedEffectofVaryingParam): the same with the payload alone;
- the paper's zeta and mu: f(m' delta_x) = m' y y^T, y = (x, 1), and |y|^2 <= (|c| + a_max)^2 + 1 on E;
- particles moving inside E at speeds |v| <= V (``speed``): psi_k = sum_i w_i (v_i, x_i x v_i), so Psi* <= m V
  (1 + (|c| + a_max)^2)^(1/2) (Theorem 5); Z(Phidot) = sum_i w_i (Adot_i^T A_i + A_i^T Adot_i), A = [I3, -S(x)],
  Adot = [0, -S(v)], so sigma_max(Z(Phidot)) <= 2 Psi*'s bound, and f(Phidot) = sum_i w_i (ydot y^T + y ydot^T),
  ydot = (v, 0), likewise: both add to chi (BoundedEffectofVaryingParam), with sigma_max(M(q, Thetadot)) <=
  sup_q sigma_max(QJ)^2 sigma_max(Z(Thetadot)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import point_mass, pseudo_inertia, skew
from inertiaproof.presentation import bracket_evidence

from . import formulas
from .certificate import PayloadClaim, payload_f_certificate, sum_certificate
from .configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup, skew_partial_sup
from .constants import bracket_certificate, lower_constants, paper_product, upper_constants
from .domain import free_coordinates, search_box
from .extremes import Bracket, local_search
from .spectral import spectral
from .time import vertex_extreme

__all__ = ["PayloadSet", "cover_inertia", "covering_parameters", "envelope", "flange_bound", "psi_square",
           "with_payload", "worst_point_masses", "zeta_over_set"]

ALTERNATIONS = 8  # rounds of (top eigenvector, farthest point) per configuration: each raises lambda_max
LOCAL_STARTS = 4  # the best sampled configurations refined by local search
LOCAL_ROUNDS = 30
EPS_RANGE = (1e-6, 1e6)  # Young's eps is clipped to this range (any eps > 0 is sound)
SPHERE_POINTS = 2000  # points of the set's boundary where the observed zeta is sampled
FARTHEST_ROUNDS = 4  # linearisation steps towards the point of an ellipsoid farthest in velocity (1 decides a ball)


@dataclass(frozen=True)
class PayloadSet:
    """Every consistent payload of mass at most ``mass`` supported in the ellipsoid with ``semi_axes`` (a, b, c) along
    body ``body``'s axes (a ball when they are equal) around ``centre`` (3, body ``body``'s frame; ``body`` counts
    from 0). Numbers are Fractions, as written."""

    body: int
    mass: Fraction
    centre: tuple
    semi_axes: tuple

    def __post_init__(self):
        object.__setattr__(self, "mass", Fraction(self.mass))
        object.__setattr__(self, "centre", tuple(Fraction(x) for x in self.centre))
        object.__setattr__(self, "semi_axes", tuple(Fraction(x) for x in self.semi_axes))

    @classmethod
    def ball(cls, body, mass, centre, radius):
        return cls(body, mass, centre, (radius,) * 3)

    @classmethod
    def from_json(cls, written):
        """The set a certificate's ``payload`` field (:meth:`to_json`) writes."""
        axes = written["semi_axes"] if "semi_axes" in written else [written["radius"]] * 3
        return cls(written["body"] - 1, Fraction(written["mass"]), tuple(map(Fraction, written["centre"])),
                   tuple(map(Fraction, axes)))

    @property
    def reach(self):
        """The largest semi-axis: every point of the set is within it of the centre."""
        return max(self.semi_axes)

    @property
    def floats(self):
        """(m, c (3,), semi-axes (3,)) as floats."""
        return float(self.mass), np.array([float(x) for x in self.centre]), np.array([float(x) for x in self.semi_axes])

    def with_mass(self, mass):
        return replace(self, mass=Fraction(mass))

    def describe(self):
        a, b, c = (float(x) for x in self.semi_axes)
        where = (f"within {a:g} m of {[float(x) for x in self.centre]}" if a == b == c else
                 f"in the ellipsoid with semi-axes ({a:g}, {b:g}, {c:g}) m around {[float(x) for x in self.centre]}")
        return f"payloads up to {float(self.mass):g} kg {where} on body {self.body + 1}"

    def to_json(self):
        """The certificate's ``payload`` field (body counted from 1): ``radius`` for a ball, else ``semi_axes``."""
        a, b, c = self.semi_axes
        shape = {"radius": str(a)} if a == b == c else {"semi_axes": [str(x) for x in self.semi_axes]}
        return {"body": self.body + 1, "mass": str(self.mass), "centre": [str(x) for x in self.centre], **shape}


def cover_inertia(semi_axes):
    """U (3,), the diagonal of the least diagonal U >= |d|^2 I - d d^T (= S(d)^T S(d), Tjaja) for every d of the
    ellipsoid with these semi-axes: U_i = the larger square of the other two. Proof for a >= b >= c (U = (b^2, a^2,
    a^2)): U - |d|^2 I + d d^T = E + d d^T, E = diag(b^2, a^2, a^2) - |d|^2 I, with E_22 = E_33 >= 0; if E_11 < 0 it
    is >= 0 iff det >= 0 (one eigenvalue of E + d d^T at most is negative), i.e. 1 + d^T E^-1 d <= 0, which reduces
    to d_1^2 / a^2 + (d_2^2 + d_3^2) / b^2 <= 1: true on the ellipsoid as c <= b. A ball of radius R: R^2 I."""
    s = np.asarray(semi_axes, float) ** 2
    return np.array([max(s[1], s[2]), max(s[0], s[2]), max(s[0], s[1])])


def covering_parameters(payloads, eps):
    """Phi_U (10,): Z(Phi_p) <= Z(Phi_U) for every Phi_p of the set (Young's inequality with ``eps``,
    :func:`cover_inertia`)."""
    m, c, axes = payloads.floats
    phi = (1.0 + eps) * point_mass(m, c)
    phi[4:7] += (1.0 + 1.0 / eps) * m * cover_inertia(axes)
    return phi


def with_payload(theta, payloads, phi):
    """theta (N, 10) with ``phi`` added to the set's body."""
    out = np.array(theta, float)
    out[payloads.body] += phi
    return out


def flange_bound(payloads):
    """beta (a Fraction) >= m ((|c| + a_max)^2 + 1) >= lambda_max(f(Phi_p)) over the payload set, exactly: |c| is
    bounded above by a rational whose square is checked against |c|^2."""
    r2 = sum(x * x for x in payloads.centre)
    root = Fraction(math.sqrt(float(r2)))
    while root * root < r2:
        root *= 1 + Fraction(1, 2**50)
    reach = payloads.reach
    return payloads.mass * (r2 + 2 * reach * root + reach**2 + 1)


def _farthest(p, omega, semi_axes, rounds=FARTHEST_ROUNDS):
    """d on the ellipsoid's boundary raising |p + omega x d| (batched): steps to the maximiser over the ellipsoid of
    the linearisation, d = S g / (g^T S g)^(1/2), g = (p + omega x d) x omega, S = diag(a_i^2); each step raises the
    (convex) objective, and for a ball the first is the maximiser (omega x d along the part of p across omega)."""
    s = np.asarray(semi_axes, float) ** 2
    fallback = np.cross(omega, [1.0, 0, 0])  # any direction across omega where p has no part across it
    fallback[np.linalg.norm(fallback, axis=1) < 1e-12] = [0.0, 1.0, 0]
    d = np.zeros_like(p)
    for _ in range(rounds):
        g = np.cross(p + np.cross(omega, d), omega)
        g = np.where((np.linalg.norm(g, axis=1) > 1e-300)[:, None], g, fallback)
        reach = np.sqrt(np.einsum("ki,ki->k", g * s, g))  # 0: g lies across a flat ellipsoid (or R = 0), d = 0
        d = s * g / np.where(reach > 0, reach, 1.0)[:, None]
    return d


def worst_point_masses(chain, theta, payloads, q, rounds=ALTERNATIONS):
    """(values (K,), points (K, 3), eps (K,)): at configurations q (K, n), a point mass m on the set's boundary that
    lambda_max(M(q, theta + m delta_x)) reaches (attained there: a lower side of the sup over the set), and Young's
    eps = (omega^T U omega)^(1/2) / |p| of its top eigenvector, which makes Z(Phi_U) touch it on a ball."""
    q = np.atleast_2d(np.asarray(q, float))
    m, c, axes = payloads.floats
    base = composite.mass_matrix(chain, q, theta)
    qj = chain.body_jacobian(q)[:, 6 * payloads.body:6 * payloads.body + 6]
    x = np.broadcast_to(c, (len(q), 3)).copy()
    for step in range(rounds + 1):
        a = qj[:, :3] - skew(x) @ qj[:, 3:]  # linear velocity of the point x
        values, vectors = np.linalg.eigh(base + m * np.swapaxes(a, 1, 2) @ a)
        twist = np.einsum("kij,kj->ki", qj, vectors[..., -1])
        omega, p = twist[:, 3:], twist[:, :3] + np.cross(twist[:, 3:], c)
        if step == rounds:
            break
        x = c + _farthest(p, omega, axes)
    speed = np.linalg.norm(p, axis=1)
    spin = np.sqrt(np.einsum("ki,i,ki->k", omega, cover_inertia(axes), omega))
    eps = np.clip(spin / np.where(speed > 0, speed, 1.0), *EPS_RANGE)
    return values[:, -1], x, eps


def _worst(chain, theta, payloads, samples, rng, extra=()):
    """(value, q, point, eps) of the worst point mass found: sampled configurations, then local search."""
    lo, hi = search_box(chain)
    qs = np.concatenate([lo + (hi - lo) * rng.random((samples, chain.n)), np.reshape(extra, (-1, chain.n))])
    values = worst_point_masses(chain, theta, payloads, qs)[0]
    starts = qs[np.argsort(values)[::-1][:LOCAL_STARTS]]
    best, _ = local_search(lambda q: worst_point_masses(chain, theta, payloads, q)[0], starts, lo, hi,
                           free_coordinates(chain), sign=-1.0, rounds=LOCAL_ROUNDS)
    values, points, eps = worst_point_masses(chain, theta, payloads, best)
    k = int(np.argmax(values))
    return float(values[k]), best[k], points[k], float(eps[k])


def _sup_over_set(chain, theta, payloads, quantity, kw, goal=None, boxes=None):
    """The bracket of sup over q and the payload set of lambda_max(M(q, theta + Phi_p)): attained by the worst point
    mass found, certified as the sup with Phi_U (:func:`covering_parameters`) at its eps, the ladder's targets scaled
    to the attained value (``goal``, ``boxes``: the ladder's, :func:`.configuration.mass_sup`). A witness found by the
    certifying search is tried as a start too."""
    rng = kw["rng"]
    value, q, point, eps = _worst(chain, theta, payloads, kw["samples"], rng)
    covered = with_payload(theta, payloads, covering_parameters(payloads, eps))[None]
    b = mass_sup(chain, covered, goal=goal, boxes=boxes, attained=value, **kw)
    found = _worst(chain, theta, payloads, 0, rng, extra=[b.witness, q])
    if found[0] > value:
        value, q, point = found[:3]
    return Bracket(quantity, "max", value, b.certified, np.asarray(q), b.convergence, b.boxes,
                   f"attained by a point mass at {np.round(point, 6).tolist()}; certified with Phi_U (eps {eps:.6g}) at "
                   f"body {payloads.body + 1}: {b.note}",
                   PayloadClaim(b.certify, theta[None], payloads, "lambda_max", eps), b.proof), point


def _boundary(payloads):
    """(SPHERE_POINTS, 3) points on the boundary of the set's ellipsoid (a Fibonacci sphere, stretched)."""
    _, c, axes = payloads.floats
    i = np.arange(SPHERE_POINTS) + 0.5
    z, turn = 1 - 2 * i / SPHERE_POINTS, np.pi * (1 + 5**0.5) * i
    return c + axes * np.stack([np.sqrt(1 - z * z) * np.cos(turn), np.sqrt(1 - z * z) * np.sin(turn), z], 1)


def zeta_over_set(theta, payloads):
    """(observed, certified, certificate) of max_l lambda_max(f(Phi_l)) over the payload set: observed on points of
    its boundary."""
    f = pseudo_inertia(theta)
    k = payloads.body
    y = np.concatenate([_boundary(payloads), np.ones((SPHERE_POINTS, 1))], 1)
    loaded = spectral(f[k] + float(payloads.mass) * y[:, :, None] * y[:, None, :], "lmax").max()
    others = spectral(np.delete(f, k, 0), "lmax").max(initial=-np.inf)
    bound = flange_bound(payloads)
    certificate = payload_f_certificate(theta[None], payloads, bound)
    certified = np.inf if certificate is None else float(Fraction(certificate["claim"]["bound"]))
    return float(max(loaded, others)), certified, certificate


def envelope(chain, theta, payloads, *, rate, speed=None, masses=(), goal=None, boxes=None, samples=2000, rounds=20,
             rng=None, progress=None):
    """alpha1, alpha2 and chi (Theorems 2-4) over the payload set ``payloads`` for an arm of constant parameters
    ``theta`` (N, 10) whose payload is taken up at a peak rate ``rate`` (sup |s'|, 1/s): per constant the paper's
    value and the sharpest certified one with their certificates (as
    :func:`inertiaproof.bounds.constants.lower_constants` and ``upper_constants``), the bracket of the true extreme, and the worst payload found (a point mass: mass, CoM and
    inertia about the CoM, zero). ``masses`` (below the set's): the curve of alpha2 and chi against the payload's
    mass, one row per mass (alpha1 does not depend on it). ``goal``: the ratio to which the pivot ladders narrow the
    sup brackets of the full payload (:func:`inertiaproof.bounds.configuration.mass_sup`), ``boxes`` the count of
    boxes the ladder of alpha2's may test (None: the bracket budget's); the curve's use the defaults. ``speed`` (m/s,
    a Fraction): the payload's particles move inside the set at most this fast, which chi includes, and Theorem 5's
    constants are added (``theorem5``)."""
    rng = np.random.default_rng(0) if rng is None else rng
    theta = np.asarray(theta, float)
    kw = dict(samples=samples, rounds=rounds, rng=rng, progress=progress)
    gamma, sigma = jacobian_normality(chain, **kw), jacobian_sup(chain, **kw)
    low = mass_inf(chain, theta[None], **kw)
    low.certify = PayloadClaim(low.certify, theta[None], payloads, "lambda_min")
    xi, xi_certificate = vertex_extreme(theta[None], "lmin_f", "the bare arm's bodies (a payload only adds f >= 0)")
    z_min, z_certificate = vertex_extreme(theta[None], "lmin_Z", "the bare arm's bodies (a payload only adds Z >= 0)")
    lower = lower_constants(xi, z_min, gamma, low, xi_certificate=xi_certificate, z_certificate=z_certificate)

    high, worst = _sup_over_set(chain, theta, payloads, "sup over q and payloads of lambda_max(M)", kw, goal, boxes)
    zeta_observed, zeta, zeta_certificate = zeta_over_set(theta, payloads)
    upper = upper_constants(zeta, np.inf, sigma, high, zeta_observed, zeta_certificate)
    return {"payload": payloads.to_json(), "rate": rate,
            "worst_payload": {"mass": float(payloads.mass), "com": worst.tolist(), "inertia_about_com": [[0.0] * 3] * 3,
                              "q": np.asarray(high.witness).tolist()},
            "lower": lower, "upper": upper, "chi": _chi(chain, payloads, rate, sigma, kw, goal, speed),
            **({"theorem5": _theorem5(chain, payloads, speed, kw)} if speed is not None else {}),
            "brackets": {"inf lambda_min(M)": bracket_evidence(low), "sup lambda_max(M)": bracket_evidence(high)},
            "curve": [_curve_row(chain, theta, payloads.with_mass(mass), rate, sigma, kw, speed) for mass in masses],
            "ingredients": {"inf_sigma_min_QJ_sq": gamma, "sup_sigma_max_QJ": sigma, "zeta": [zeta_observed, zeta]}}


def psi_square(payloads, speed):
    """r (a Fraction) with Psi* <= r^(1/2) for particles moving at speeds <= ``speed`` in the set: (m V)^2 (1 + (|c| +
    a_max)^2) <= V^2 m beta (:func:`flange_bound`)."""
    return Fraction(speed) ** 2 * payloads.mass * flange_bound(payloads)


def _theorem5(chain, payloads, speed, kw):
    """Theorem 5 (BoundedEffectOfLumpedVel) for the moving payload: the paper's sqrt(6N) Psi* max_p sup_q
    sigma_max(Y_p) and Psi* sup_q (sum_p sigma_max(Y_p)^2)^(1/2); the sups are the prover's (Bernstein), their
    brackets' certified sides citing ``skew-partials`` certificates."""
    worst, rss = skew_partial_sup(chain, **kw)
    psi = math.sqrt(psi_square(payloads, speed)) * (1 + 4 * np.finfo(float).eps)
    return {"psi_star": psi, "paper": formulas.lumped_velocity(psi, worst.upper, 6 * chain.n),
            "sharp": formulas.lumped_velocity_sharp(psi, rss.upper),
            "brackets": {"max_p sup_q sigma_max(Y_p)": bracket_evidence(worst),
                         "sup_q (sum_p sigma_max(Y_p)^2)^(1/2)": bracket_evidence(rss)}}


def _moving(chain, payloads, speed, sigma, factor):
    """(value, certificate) of factor * 2 Psi*'s bound * sup_q sigma_max(QJ)^2: the moving particles' share of chi."""
    r = 4 * psi_square(payloads, speed) * factor
    return paper_product("upper", math.sqrt(r) * sigma.upper**2, "moving_share", [bracket_certificate(sigma)], r)


def _chi(chain, payloads, rate, sigma, kw, goal=None, speed=None):
    """Theorem 4 for the payload's ramp: the paper's chi = sqrt(69 N) mu S^2, mu = rate sup_P lambda_max(f(Phi_p)),
    and the sharpest certified rate sup lambda_max(M(q, Phi_p)) (the payload alone), with the bracket of the true
    sup_t,q sigma_max(M(q, Thetadot)); with ``speed``, each plus the moving particles' share (a ``sum``
    certificate)."""
    alone = np.zeros((chain.n, 10))
    b, _ = _sup_over_set(chain, alone, payloads, "sup over q and payloads of lambda_max(M(q, Phi_p))", kw, goal)
    exact_rate = Fraction(rate)
    flange = payload_f_certificate(alone[None], payloads, flange_bound(payloads))
    mu = float(exact_rate * Fraction(flange["claim"]["bound"]))
    paper_value, paper_cert = paper_product(
        "upper", formulas.chi(mu, sigma.upper, chain.n), "chi_ramp", [flange, bracket_certificate(sigma)], exact_rate)
    observed_mu = float(rate * payloads.mass) * (1 + (_boundary(payloads) ** 2).sum(1).max())  # m |y|^2 attained
    sharp_value, sharp_cert = paper_product(
        "upper", float(exact_rate) * b.upper, "chi_ramp_sharp", [bracket_certificate(b)], exact_rate)
    if speed is not None:
        paper_value, paper_cert = sum_certificate("<=", [paper_cert, _moving(chain, payloads, speed, sigma,
                                                                             69 * chain.n)[1]])
        sharp_value, sharp_cert = sum_certificate("<=", [sharp_cert, _moving(chain, payloads, speed, sigma, 1)[1]])
    return {"paper": {"value": formulas.chi(observed_mu, sigma.lower, chain.n), "upper": paper_value,
                      **({"certificate": paper_cert} if paper_cert else {})},
            "certified": {"value": sharp_value, "how": "the payload's rate times the certified sup of lambda_max(M(q, "
                          "Phi_p)) over q and the payload set (the payload alone)" + (
                              "" if speed is None else ", plus the moving particles' share"),
                          **({"certificate": sharp_cert} if sharp_cert else {})},
            "observed": {"lower": float(rate) * b.observed, "upper": sharp_value, "witness": np.asarray(b.witness).tolist()}}


def _curve_row(chain, theta, payloads, rate, sigma, kw, speed=None):
    high, _ = _sup_over_set(chain, theta, payloads, "sup over q and payloads of lambda_max(M)", kw)
    return {"mass": float(payloads.mass), "alpha2": {"attained": high.observed, "certified": high.upper,
                                                 "certificate": bracket_certificate(high)},
            "chi": _chi(chain, payloads, rate, sigma, kw, speed=speed)}
