"""Beyond the paper: Theorems 2-4 over every consistent payload a body may carry (the payload envelope).

The payload set P (a :class:`Ball`) holds the Phi_p of every mass distribution of mass at most m supported in the
ball |x - c| <= R of body k's frame: pseudo-inertias J = f(Phi_p) >= 0 with tr(Q J) >= 0 for the ball's Q and
J_44 <= m (Wensing, Kim and Slotine 2017). By the S-lemma this LMI set is the closed convex hull of the point
masses m' delta_x, 0 <= m' <= m, |x - c| <= R (``tests/test_payload.py`` compares the two descriptions). The
payload enters M(q, Theta + Phi_p e_k) = M(q, Theta) + QJ_k^T Z(Phi_p) QJ_k linearly (DefMatrixZ), so:

- inf lambda_min over P is the bare arm's, as Z(Phi_p) >= 0: alpha1 does not change (LowerBoundedness);
- lambda_max is convex in Phi_p, and for a point mass v^T Z(m delta_x) v = m |p + omega x (x - c)|^2 (p the velocity
  of c, omega the angular velocity of body k for qdot = v) is convex in x: the sup over P is attained by a point
  mass m on the sphere, which :func:`worst_point_masses` finds by alternating the top eigenvector and the point;
- Young's inequality |p + omega x d|^2 <= (1 + eps) |p|^2 + (1 + 1/eps) R^2 |omega|^2 (|d| <= R) gives Z(Phi_p) <=
  Z(Phi_U) on P for Phi_U = (1 + eps) Phi(m delta_c) + (1 + 1/eps) m R^2 (0, 0, 0, 0, 1, 1, 1, 0, 0, 0)
  (:func:`covering_parameters`), with equality at the worst point mass when eps = R |omega| / |p| there: the sup
  over P is certified as the sup of the arm with Phi_U added to body k (UpperBoundedness);
- a payload taken up as s(t) Phi_p has Thetadot = s' Phi_p and sigma_max(M(q, Thetadot)) = |s'| lambda_max(M(q,
  Phi_p)) (BoundedEffectofVaryingParam): the same with the payload alone;
- the paper's zeta and mu: f(m' delta_x) = m' y y^T, y = (x, 1), and |y|^2 <= (|c| + R)^2 + 1 on the ball.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import point_mass, pseudo_inertia, skew

from . import formulas
from .certificate import PayloadClaim, payload_f_certificate
from .configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup
from .constants import bracket_certificate, lower_constants, paper_product, upper_constants
from .domain import free_coordinates, search_box
from .extremes import Bracket, local_search
from .spectral import spectral
from .time import vertex_extreme

__all__ = ["Ball", "covering_parameters", "envelope", "flange_bound", "with_payload", "worst_point_masses"]

ALTERNATIONS = 8  # rounds of (top eigenvector, farthest point) per configuration: each raises lambda_max
LOCAL_STARTS = 4  # the best sampled configurations refined by local search
LOCAL_ROUNDS = 30
EPS_RANGE = (1e-6, 1e6)  # Young's eps is clipped to this range (any eps > 0 is sound)
SPHERE_POINTS = 2000  # points of the sphere where the observed zeta is sampled


@dataclass(frozen=True)
class Ball:
    """The payload set: every consistent payload of mass at most ``mass`` supported in the ball of ``radius`` around
    ``centre`` (3, body ``body``'s frame; ``body`` counts from 0). Numbers are Fractions, as written."""

    body: int
    mass: Fraction
    centre: tuple
    radius: Fraction

    def __post_init__(self):
        object.__setattr__(self, "mass", Fraction(self.mass))
        object.__setattr__(self, "radius", Fraction(self.radius))
        object.__setattr__(self, "centre", tuple(Fraction(x) for x in self.centre))

    @property
    def floats(self):
        """(m, c, R) as floats."""
        return float(self.mass), np.array([float(x) for x in self.centre]), float(self.radius)

    def with_mass(self, mass):
        return replace(self, mass=Fraction(mass))

    def to_json(self):
        """The certificate's ``payload`` field (body counted from 1)."""
        return {"body": self.body + 1, "mass": str(self.mass), "centre": [str(x) for x in self.centre],
                "radius": str(self.radius)}


def covering_parameters(ball, eps):
    """Phi_U (10,): Z(Phi_p) <= Z(Phi_U) for every Phi_p in the ball's payload set (Young's inequality with ``eps``)."""
    m, c, r = ball.floats
    phi = (1.0 + eps) * point_mass(m, c)
    phi[4:7] += (1.0 + 1.0 / eps) * m * r * r
    return phi


def with_payload(theta, ball, phi):
    """theta (N, 10) with ``phi`` added to the ball's body."""
    out = np.array(theta, float)
    out[ball.body] += phi
    return out


def flange_bound(ball):
    """beta (a Fraction) >= m ((|c| + R)^2 + 1) >= lambda_max(f(Phi_p)) over the payload set, exactly: |c| is bounded
    above by a rational whose square is checked against |c|^2."""
    r2 = sum(x * x for x in ball.centre)
    root = Fraction(math.sqrt(float(r2)))
    while root * root < r2:
        root *= 1 + Fraction(1, 2**50)
    return ball.mass * (r2 + 2 * ball.radius * root + ball.radius**2 + 1)


def _farthest(p, omega, radius):
    """d with |d| = radius maximising |p + omega x d|: omega x d along the part of p across omega (batched)."""
    w2 = np.einsum("ki,ki->k", omega, omega)
    across = p - omega * (np.einsum("ki,ki->k", p, omega) / np.where(w2 > 0, w2, 1.0))[:, None]
    d = np.cross(across, omega)
    size = np.linalg.norm(d, axis=1)
    fallback = np.cross(omega, [1.0, 0, 0])  # any direction across omega where p has no part across it
    fallback[np.linalg.norm(fallback, axis=1) < 1e-12] = [0.0, 1.0, 0]
    d = np.where((size > 1e-300)[:, None], d, fallback)
    return radius * d / np.linalg.norm(d, axis=1)[:, None]


def worst_point_masses(chain, theta, ball, q, rounds=ALTERNATIONS):
    """(values (K,), points (K, 3), eps (K,)): at configurations q (K, n), a point mass m on the ball's sphere that
    lambda_max(M(q, theta + m delta_x)) reaches (attained there: a lower side of the sup over the set), and Young's
    eps = R |omega| / |p| of its top eigenvector, which makes Z(Phi_U) touch it."""
    q = np.atleast_2d(np.asarray(q, float))
    m, c, r = ball.floats
    base = composite.mass_matrix(chain, q, theta)
    qj = chain.body_jacobian(q)[:, 6 * ball.body:6 * ball.body + 6]
    x = np.broadcast_to(c, (len(q), 3)).copy()
    for step in range(rounds + 1):
        a = qj[:, :3] - skew(x) @ qj[:, 3:]  # linear velocity of the point x
        values, vectors = np.linalg.eigh(base + m * np.swapaxes(a, 1, 2) @ a)
        twist = np.einsum("kij,kj->ki", qj, vectors[..., -1])
        omega, p = twist[:, 3:], twist[:, :3] + np.cross(twist[:, 3:], c)
        if step == rounds:
            break
        x = c + _farthest(p, omega, r)
    speed = np.linalg.norm(p, axis=1)
    eps = np.clip(r * np.linalg.norm(omega, axis=1) / np.where(speed > 0, speed, 1.0), *EPS_RANGE)
    return values[:, -1], x, eps


def _worst(chain, theta, ball, samples, rng, extra=()):
    """(value, q, point, eps) of the worst point mass found: sampled configurations, then local search."""
    lo, hi = search_box(chain)
    qs = np.concatenate([lo + (hi - lo) * rng.random((samples, chain.n)), np.reshape(extra, (-1, chain.n))])
    values = worst_point_masses(chain, theta, ball, qs)[0]
    starts = qs[np.argsort(values)[::-1][:LOCAL_STARTS]]
    best, _ = local_search(lambda q: worst_point_masses(chain, theta, ball, q)[0], starts, lo, hi,
                           free_coordinates(chain), sign=-1.0, rounds=LOCAL_ROUNDS)
    values, points, eps = worst_point_masses(chain, theta, ball, best)
    k = int(np.argmax(values))
    return float(values[k]), best[k], points[k], float(eps[k])


def _sup_over_set(chain, theta, ball, quantity, kw, goal=None):
    """The bracket of sup over q and the payload set of lambda_max(M(q, theta + Phi_p)): attained by the worst point
    mass found, certified as the sup with Phi_U (:func:`covering_parameters`) at its eps. A witness found by the
    certifying search is tried as a start too."""
    rng = kw["rng"]
    value, q, point, eps = _worst(chain, theta, ball, kw["samples"], rng)
    covered = with_payload(theta, ball, covering_parameters(ball, eps))[None]
    b = mass_sup(chain, covered, goal=goal, **kw)
    found = _worst(chain, theta, ball, 0, rng, extra=[b.witness, q])
    if found[0] > value:
        value, q, point = found[:3]
    return Bracket(quantity, "max", value, b.certified, np.asarray(q), b.convergence, b.boxes,
                   f"attained by a point mass at {np.round(point, 6).tolist()}; certified with Phi_U (eps {eps:.6g}) at "
                   f"body {ball.body + 1}: {b.note}",
                   PayloadClaim(b.certify, theta[None], ball, "lambda_max", eps), b.proof), point


def _zeta(theta, ball):
    """(observed, certified, certificate) of max_l lambda_max(f(Phi_l)) over the payload set: observed on sphere points."""
    m, c, r = ball.floats
    f = pseudo_inertia(theta)
    k = ball.body
    i = np.arange(SPHERE_POINTS) + 0.5  # a Fibonacci sphere
    z, turn = 1 - 2 * i / SPHERE_POINTS, np.pi * (1 + 5**0.5) * i
    y = np.concatenate([c + r * np.stack([np.sqrt(1 - z * z) * np.cos(turn), np.sqrt(1 - z * z) * np.sin(turn), z], 1),
                        np.ones((SPHERE_POINTS, 1))], 1)
    loaded = spectral(f[k] + m * y[:, :, None] * y[:, None, :], "lmax").max()
    others = spectral(np.delete(f, k, 0), "lmax").max(initial=-np.inf)
    bound = flange_bound(ball)
    certificate = payload_f_certificate(theta[None], ball, bound)
    certified = np.inf if certificate is None else float(Fraction(certificate["claim"]["bound"]))
    return float(max(loaded, others)), certified, certificate


def envelope(chain, theta, ball, *, rate, masses=(), goal=None, samples=2000, refine_s=0.5, rng=None, progress=None):
    """alpha1, alpha2 and chi (Theorems 2-4) over the ball's payload set for an arm of constant parameters ``theta``
    (N, 10) whose payload is taken up at a peak rate ``rate`` (sup |s'|, 1/s): per constant the paper's value and the
    sharpest certified one with their certificates (as :func:`inertiaproof.bounds.constants.lower_constants` and
    ``upper_constants``), the bracket of the true extreme, and the worst payload found (a point mass: mass, CoM and
    inertia about the CoM, zero). ``masses`` (below the ball's): the curve of alpha2 and chi against the payload's
    mass, one row per mass (alpha1 does not depend on it). ``goal``: the ratio to which the pivot ladders narrow the
    sup brackets of the full payload (:func:`inertiaproof.bounds.configuration.mass_sup`); the curve's use the
    default."""
    rng = np.random.default_rng(0) if rng is None else rng
    theta = np.asarray(theta, float)
    kw = dict(samples=samples, refine_s=refine_s, rng=rng, progress=progress)
    gamma, sigma = jacobian_normality(chain, **kw), jacobian_sup(chain, **kw)
    low = mass_inf(chain, theta[None], **kw)
    low.certify = PayloadClaim(low.certify, theta[None], ball, "lambda_min")
    xi, xi_certificate = vertex_extreme(theta[None], "lmin_f", "the bare arm's bodies (a payload only adds f >= 0)")
    z_min, z_certificate = vertex_extreme(theta[None], "lmin_Z", "the bare arm's bodies (a payload only adds Z >= 0)")
    lower = lower_constants(xi, z_min, gamma, low, xi_certificate=xi_certificate, z_certificate=z_certificate)

    high, worst = _sup_over_set(chain, theta, ball, "sup over q and payloads of lambda_max(M)", kw, goal)
    zeta_observed, zeta, zeta_certificate = _zeta(theta, ball)
    upper = upper_constants(zeta, np.inf, sigma, high, zeta_observed, zeta_certificate)
    return {"payload": ball.to_json(), "rate": rate,
            "worst_payload": {"mass": float(ball.mass), "com": worst.tolist(), "inertia_about_com": [[0.0] * 3] * 3,
                              "q": np.asarray(high.witness).tolist()},
            "lower": lower, "upper": upper, "chi": _chi(chain, ball, rate, sigma, kw, goal),
            "brackets": {"inf lambda_min(M)": low.evidence(), "sup lambda_max(M)": high.evidence()},
            "curve": [_curve_row(chain, theta, ball.with_mass(mass), rate, sigma, kw) for mass in masses],
            "ingredients": {"inf_sigma_min_QJ_sq": gamma, "sup_sigma_max_QJ": sigma, "zeta": [zeta_observed, zeta]}}


def _chi(chain, ball, rate, sigma, kw, goal=None):
    """Theorem 4 for the payload's ramp: the paper's chi = sqrt(69 N) mu S^2, mu = rate sup_P lambda_max(f(Phi_p)),
    and the sharpest certified rate sup lambda_max(M(q, Phi_p)) (the payload alone), with the bracket of the true
    sup_t,q sigma_max(M(q, Thetadot))."""
    alone = np.zeros((chain.n, 10))
    b, _ = _sup_over_set(chain, alone, ball, "sup over q and payloads of lambda_max(M(q, Phi_p))", kw, goal)
    exact_rate = Fraction(rate)
    flange = payload_f_certificate(alone[None], ball, flange_bound(ball))
    mu = float(exact_rate * Fraction(flange["claim"]["bound"]))
    statement = "chi = sqrt(69 N) rate sup_P lambda_max(f(Phi_p)) sup_q lambda_max((QJ)^T QJ) >= sup sigma_max(M(q, Thetadot)); <= {bound}"
    paper_value, paper_cert = paper_product(
        "upper", formulas.chi(mu, sigma.upper, chain.n), ("sqrt", 69 * chain.n * exact_rate**2),
        [(flange, 1), (bracket_certificate(sigma), 1)], statement)
    m, c, r = ball.floats
    observed_mu = float(rate) * m * ((np.linalg.norm(c) + r) ** 2 + 1)
    sharp_value, sharp_cert = paper_product(
        "upper", float(exact_rate) * b.upper, exact_rate, [(bracket_certificate(b), 1)],
        "sigma_max(M(q, Thetadot)) = |s'| lambda_max(M(q, Phi_p)) <= rate sup over q and the payload set <= {bound}")
    return {"paper": {"value": formulas.chi(observed_mu, sigma.lower, chain.n), "upper": paper_value,
                      **({"certificate": paper_cert} if paper_cert else {})},
            "certified": {"value": sharp_value, "how": "the payload's rate times the certified sup of lambda_max(M(q, "
                          "Phi_p)) over q and the payload set (the payload alone)",
                          **({"certificate": sharp_cert} if sharp_cert else {})},
            "observed": {"lower": float(rate) * b.observed, "upper": sharp_value, "witness": np.asarray(b.witness).tolist()}}


def _curve_row(chain, theta, ball, rate, sigma, kw):
    high, _ = _sup_over_set(chain, theta, ball, "sup over q and payloads of lambda_max(M)", kw)
    return {"mass": float(ball.mass), "alpha2": {"attained": high.observed, "certified": high.upper,
                                                 "certificate": bracket_certificate(high)},
            "chi": _chi(chain, ball, rate, sigma, kw)}
