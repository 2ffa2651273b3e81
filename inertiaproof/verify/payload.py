"""The ``payload-envelope`` claim: a bound over every consistent payload of an ellipsoid, reduced to claims proved
elsewhere.

``payload``: body k (from 1), mass m, centre c and ``radius`` R (a ball) or ``semi_axes`` (a, b, c) along body k's
axes, in body k's frame. The payloads are the closed convex hull of the point masses m' delta_x, m' <= m, x - c = d
in the ellipsoid (by the S-lemma, the LMI set f(Phi_p) >= 0, tr(Q f(Phi_p)) >= 0 of Wensing, Kim and Slotine 2017);
each quantity is convex in Phi_p, so the point masses of mass m decide it. With Z(m delta_x) = m A^T A, A = [I3,
-S(x)], and f(m delta_x) = m y y^T, y = (x, 1):

- ``lambda_min`` (of M(q, Theta + Phi_p e_k), >= bound): Z(Phi_p) >= 0 only adds to M: the ``mass-matrix-spectrum``
  claim of the parameters (the rest of the certificate is its data);
- ``lambda_max`` (<= bound): Young's inequality with ``epsilon`` > 0, |p + w x d|^2 <= (1 + eps) |p|^2 + (1 + 1/eps)
  |w x d|^2, and |w x d|^2 <= w^T U w for U = diag(max(b, c)^2, max(a, c)^2, max(a, b)^2) (by the determinant
  lemma: for a >= b >= c, U - |d|^2 I + d d^T >= 0 reduces to d_1^2/a^2 + (d_2^2 + d_3^2)/b^2 <= 1) give Z(m
  delta_x) <= Z(Phi_U), Phi_U = (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33: the spectrum claim
  with Phi_U added to body k (exactly, here);
- ``lambda_max_f`` (every body's lambda_max(f(Phi_l + [l = k] Phi_p)) <= bound): m |y|^2 <= beta when beta >= m
  ((|c| + R)^2 + 1), R the largest semi-axis (decided exactly by squaring), then bound I - f(Phi_l) - [l = k] beta I
  >= 0 exactly per row.
"""

from __future__ import annotations

from flint import fmpq

from . import spectrum
from .bodies import parameter_sets, pseudo_inertia
from .exact import BadCertificate, rational, semidefinite
from .outcome import REFUTED, REPROVED, UNPROVED, Outcome

__all__ = ["covering", "inner_spectrum", "prove"]

QUANTITIES = ("lambda_min", "lambda_max", "lambda_max_f")


def _payload(cert, bodies):
    payload = cert.get("payload")
    if not isinstance(payload, dict):
        raise BadCertificate("payload: {body, mass, centre, radius or semi_axes}")
    body = payload.get("body")
    if not isinstance(body, int) or not 1 <= body <= bodies:
        raise BadCertificate(f"payload.body: a body from 1 to {bodies}")
    mass = rational(payload.get("mass"), "payload.mass")
    centre, axes = payload.get("centre"), payload.get("semi_axes", [payload.get("radius")] * 3)
    for name, value in (("centre", centre), ("semi_axes", axes)):
        if not isinstance(value, list) or len(value) != 3:
            raise BadCertificate(f"payload.{name}: three numbers")
    centre = [rational(x, f"payload.centre[{i}]") for i, x in enumerate(centre)]
    axes = [rational(x, f"payload.semi_axes[{i}]") for i, x in enumerate(axes)]
    if mass < 0 or min(axes) < 0:
        raise BadCertificate("payload: mass and radius (semi-axes) must be >= 0")
    return body - 1, mass, centre, axes


def covering(mass, centre, axes, eps):
    """Phi_U (10 exact rationals): (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33."""
    c1, c2, c3 = centre
    sa, sb, sc = (x * x for x in axes)
    u1, u2, u3 = ((1 + 1 / eps) * mass * u for u in (max(sb, sc), max(sa, sc), max(sa, sb)))
    m = (1 + eps) * mass
    return [m, m * c1, m * c2, m * c3, m * (c2**2 + c3**2) + u1, m * (c1**2 + c3**2) + u2, m * (c1**2 + c2**2) + u3,
            -m * c1 * c2, -m * c2 * c3, -m * c1 * c3]


def _written(sets):
    return [[[str(x) for x in row] for row in rows] for rows in sets]


def prove(cert):
    """The :class:`Outcome` of the claim: ``lambda_min`` and ``lambda_max`` by :func:`.spectrum.prove` (with Phi_U
    for the latter, whose refutation refutes only the cover: not re-proved), ``lambda_max_f`` exactly."""
    claim = cert["claim"]
    quantity = claim.get("quantity")
    if quantity not in QUANTITIES:
        raise BadCertificate(f"claim.quantity: one of {list(QUANTITIES)}")
    sets = parameter_sets(cert)
    k, mass, centre, axes = _payload(cert, len(sets[0]))
    if quantity == "lambda_max_f":
        return _flange(claim, sets, k, mass, centre, max(axes), cert.get("beta"))
    out = spectrum.prove(spectrum_of(cert, quantity, sets, k, mass, centre, axes))
    if quantity == "lambda_max" and out.status == REFUTED:
        return Outcome(UNPROVED, f"the cover Phi_U of Young's epsilon is refuted, not the payloads: {out.why}",
                       out.boxes)
    return out


def spectrum_of(cert, quantity, sets, k, mass, centre, axes):
    """The spectrum claim that proves a ``lambda_min`` or ``lambda_max`` payload claim (Phi_U added for the latter)."""
    claim = cert["claim"]
    inner = {key: value for key, value in cert.items() if key not in ("payload", "epsilon", "beta")}
    inner["claim"] = {**claim, "kind": "mass-matrix-spectrum"}
    if quantity == "lambda_max":
        inner.pop("formation", None)  # the sets are the formed ones plus the cover
        eps = rational(cert.get("epsilon"), "epsilon")
        if eps <= 0:
            raise BadCertificate("epsilon: must be > 0")
        extra = covering(mass, centre, axes, eps)
        for rows in sets:
            rows[k] = [a + b for a, b in zip(rows[k], extra)]
        inner["parameters"] = _written(sets)
    return inner


def inner_spectrum(cert):
    """The spectrum certificate the checker proves for the payload certificate ``cert`` (for the prover's tree)."""
    sets = parameter_sets(cert)
    return spectrum_of(cert, cert["claim"]["quantity"], sets, *_payload(cert, len(sets[0])))


def _flange(claim, sets, k, mass, centre, radius, beta):
    bound, beta = rational(claim.get("bound"), "claim.bound"), rational(beta, "beta")
    c2 = sum(x * x for x in centre)
    base = (beta / mass - 1 - c2 - radius**2) if mass > 0 else fmpq(0)
    if mass > 0 and (base < 0 or base**2 < 4 * radius**2 * c2):
        return Outcome(UNPROVED, f"beta = {beta} is below m ((|c| + R)^2 + 1) (exact arithmetic)", 0)
    lift = beta if mass > 0 else fmpq(0)
    tested = 0
    for v, rows in enumerate(sets):
        for l, row in enumerate(rows):
            tested += 1
            shift = bound - (lift if l == k else 0)
            f = pseudo_inertia(row)
            if not semidefinite([[(shift if i == j else 0) - f[i][j] for j in range(4)] for i in range(4)]):
                return Outcome(UNPROVED, f"parameter set {v}, body {l + 1}: (bound{' - beta' if l == k else ''}) I - "
                               "f(Phi) is not positive semidefinite (exact arithmetic)", tested,
                               {"parameter_set": v, "body": l + 1})
    return Outcome(REPROVED, f"beta >= m ((|c| + R)^2 + 1) and {tested} bodies decided exactly", tested)
