"""The ``payload-envelope`` claim: a bound over every consistent payload of a ball, reduced to claims proved elsewhere.

``payload``: body k (from 1), mass m, centre c and radius R in body k's frame. The payloads are the closed convex
hull of the point masses m' delta_x, m' <= m, |x - c| <= R (by the S-lemma, the LMI set f(Phi_p) >= 0, tr(Q
f(Phi_p)) >= 0 of Wensing, Kim and Slotine 2017); each quantity is convex in Phi_p, so the point masses of mass m
decide it. With Z(m delta_x) = m A^T A, A = [I3, -S(x)], and f(m delta_x) = m y y^T, y = (x, 1):

- ``lambda_min`` (of M(q, Theta + Phi_p e_k), >= bound): Z(Phi_p) >= 0 only adds to M: the ``mass-matrix-spectrum``
  claim of the parameters (the rest of the certificate is its data);
- ``lambda_max`` (<= bound): Young's inequality with ``epsilon`` > 0 gives Z(m delta_x) <= Z(Phi_U), Phi_U = (1 + eps)
  Phi(m delta_c) + (1 + 1/eps) m R^2 on I11, I22, I33: the spectrum claim with Phi_U added to body k (exactly, here);
- ``lambda_max_f`` (every body's lambda_max(f(Phi_l + [l = k] Phi_p)) <= bound): m |y|^2 <= beta when beta >= m
  ((|c| + R)^2 + 1) (decided exactly by squaring), then bound I - f(Phi_l) - [l = k] beta I >= 0 exactly per row.
"""

from __future__ import annotations

from flint import fmpq

from . import spectrum
from .bodies import parameter_sets, pseudo_inertia
from .exact import BadCertificate, rational, semidefinite
from .outcome import Outcome

__all__ = ["covering", "prove"]

QUANTITIES = ("lambda_min", "lambda_max", "lambda_max_f")


def _payload(cert, bodies):
    payload = cert.get("payload")
    if not isinstance(payload, dict):
        raise BadCertificate("payload: {body, mass, centre, radius}")
    body = payload.get("body")
    if not isinstance(body, int) or not 1 <= body <= bodies:
        raise BadCertificate(f"payload.body: a body from 1 to {bodies}")
    mass, radius = rational(payload.get("mass"), "payload.mass"), rational(payload.get("radius"), "payload.radius")
    centre = payload.get("centre")
    if not isinstance(centre, list) or len(centre) != 3:
        raise BadCertificate("payload.centre: three numbers")
    centre = [rational(x, f"payload.centre[{i}]") for i, x in enumerate(centre)]
    if mass < 0 or radius < 0:
        raise BadCertificate("payload: mass and radius must be >= 0")
    return body - 1, mass, centre, radius


def covering(mass, centre, radius, eps):
    """Phi_U (10 exact rationals): (1 + eps) Phi(m delta_c) + (1 + 1/eps) m R^2 on I11, I22, I33."""
    c1, c2, c3 = centre
    s, lift = 1 + eps, (1 + 1 / eps) * mass * radius**2
    m = s * mass
    return [m, m * c1, m * c2, m * c3, m * (c2**2 + c3**2) + lift, m * (c1**2 + c3**2) + lift,
            m * (c1**2 + c2**2) + lift, -m * c1 * c2, -m * c2 * c3, -m * c1 * c3]


def _written(sets):
    return [[[str(x) for x in row] for row in rows] for rows in sets]


def prove(cert, budget):
    """The :class:`Outcome` of the claim: ``lambda_min`` and ``lambda_max`` by :func:`.spectrum.prove` (with Phi_U
    for the latter), ``lambda_max_f`` exactly."""
    claim = cert["claim"]
    quantity = claim.get("quantity")
    if quantity not in QUANTITIES:
        raise BadCertificate(f"claim.quantity: one of {list(QUANTITIES)}")
    sets = parameter_sets(cert.get("parameters"))
    k, mass, centre, radius = _payload(cert, len(sets[0]))
    if quantity == "lambda_max_f":
        return _flange(claim, sets, k, mass, centre, radius, cert.get("beta"))
    inner = {**cert, "claim": {**claim, "kind": "mass-matrix-spectrum"}}
    if quantity == "lambda_max":
        eps = rational(cert.get("epsilon"), "epsilon")
        if eps <= 0:
            raise BadCertificate("epsilon: must be > 0")
        extra = covering(mass, centre, radius, eps)
        for rows in sets:
            rows[k] = [a + b for a, b in zip(rows[k], extra)]
        inner["parameters"] = _written(sets)
    return spectrum.prove(inner, budget)


def _flange(claim, sets, k, mass, centre, radius, beta):
    bound, beta = rational(claim.get("bound"), "claim.bound"), rational(beta, "beta")
    c2 = sum(x * x for x in centre)
    base = (beta / mass - 1 - c2 - radius**2) if mass > 0 else fmpq(0)
    if mass > 0 and (base < 0 or base**2 < 4 * radius**2 * c2):
        return Outcome("refuted", f"beta = {beta} is below m ((|c| + R)^2 + 1) (exact arithmetic)", 0)
    lift = beta if mass > 0 else fmpq(0)
    tested = 0
    for v, rows in enumerate(sets):
        for l, row in enumerate(rows):
            tested += 1
            shift = bound - (lift if l == k else 0)
            f = pseudo_inertia(row)
            if not semidefinite([[(shift if i == j else 0) - f[i][j] for j in range(4)] for i in range(4)]):
                return Outcome("refuted", f"parameter set {v}, body {l + 1}: (bound{' - beta' if l == k else ''}) I - "
                               "f(Phi) is not positive semidefinite (exact arithmetic)", tested,
                               {"parameter_set": v, "body": l + 1})
    return Outcome("re-proved", f"beta >= m ((|c| + R)^2 + 1) and {tested} bodies decided exactly", tested)
