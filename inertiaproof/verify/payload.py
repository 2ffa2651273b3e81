"""The ``payload-envelope`` claim: a bound over every consistent payload of an ellipsoid, reduced to claims proved
elsewhere.

``payload``: body k (from 1), mass m, centre c and ``radius`` R or ``semi_axes`` (a, b, c) in body k's frame. The
payloads are the closed convex hull of the point masses m' delta_x, m' <= m, x - c = d in the ellipsoid (the S-lemma
LMI set of Wensing, Kim and Slotine 2017); each quantity is convex in Phi_p, so point masses of mass m decide it:

- ``lambda_min`` (of M(q, Theta + Phi_p e_k)): Z(Phi_p) >= 0 only adds to M: the spectrum claim of the parameters;
- ``lambda_max``: Young's inequality with ``epsilon`` > 0, |p + w x d|^2 <= (1 + eps) |p|^2 + (1 + 1/eps) |w x d|^2,
  and |w x d|^2 <= w^T U w, U = diag(max(b, c)^2, max(a, c)^2, max(a, b)^2), give Z(m delta_x) <= Z(Phi_U), Phi_U =
  (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33: the spectrum claim with Phi_U added to body k;
- ``lambda_max_f`` (max_l lambda_max(f(Phi_l + [l = k] Phi_p)) <= bound): m |y|^2 <= beta, y = (x, 1), when beta >=
  m ((|c| + R)^2 + 1) (decided exactly by squaring), then bound I - f(Phi_l) - [l = k] beta I >= 0 exactly.
"""

from flint import fmpq

from . import spectrum
from .bodies import parameter_sets, pseudo_inertia
from .exact import above, need, rational
from .outcome import REFUTED, REPROVED, UNPROVED, Outcome

QUANTITIES = ("lambda_min", "lambda_max", "lambda_max_f")


def _payload(cert, bodies):
    payload = cert.get("payload")
    need(isinstance(payload, dict), "payload: {body, mass, centre, radius or semi_axes}")
    body = payload.get("body")
    need(isinstance(body, int) and 1 <= body <= bodies, f"payload.body: a body from 1 to {bodies}")
    centre, axes = payload.get("centre"), payload.get("semi_axes", [payload.get("radius")] * 3)
    for name, value in (("centre", centre), ("semi_axes", axes)):
        need(isinstance(value, list) and len(value) == 3, f"payload.{name}: three numbers")
    mass = rational(payload.get("mass"), "payload.mass")
    centre, axes = ([rational(x, f"payload.{k}[{i}]") for i, x in enumerate(v)] for k, v in (("centre", centre),
                                                                                              ("semi_axes", axes)))
    need(mass >= 0 and min(axes) >= 0, "payload: mass and radius (semi-axes) must be >= 0")
    return body - 1, mass, centre, axes


def covering(mass, centre, axes, eps):
    """Phi_U (10 exact rationals): (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33."""
    c1, c2, c3 = centre
    sa, sb, sc = (x * x for x in axes)
    u1, u2, u3 = ((1 + 1 / eps) * mass * u for u in (max(sb, sc), max(sa, sc), max(sa, sb)))
    m = (1 + eps) * mass
    return [m, m * c1, m * c2, m * c3, m * (c2**2 + c3**2) + u1, m * (c1**2 + c3**2) + u2, m * (c1**2 + c2**2) + u3,
            -m * c1 * c2, -m * c2 * c3, -m * c1 * c3]


def prove(cert):
    """The :class:`Outcome` of the claim: ``lambda_min`` and ``lambda_max`` by :func:`.spectrum.prove` (with Phi_U
    for the latter, whose refutation refutes only the cover: not re-proved), ``lambda_max_f`` exactly."""
    quantity = cert["claim"].get("quantity")
    need(quantity in QUANTITIES, f"claim.quantity: one of {list(QUANTITIES)}")
    if quantity == "lambda_max_f":
        return _flange(cert)
    out = spectrum.prove(inner_spectrum(cert))
    if quantity == "lambda_max" and out.status == REFUTED:
        return Outcome(UNPROVED, f"the cover Phi_U of Young's epsilon is refuted, not the payloads: {out.why}",
                       out.boxes)
    return out


def inner_spectrum(cert):
    """The spectrum certificate that proves a ``lambda_min`` or ``lambda_max`` payload claim (Phi_U added for the
    latter; the prover completes its tree)."""
    sets = parameter_sets(cert)
    k, mass, centre, axes = _payload(cert, len(sets[0]))
    inner = {key: value for key, value in cert.items() if key not in ("payload", "epsilon", "beta")}
    inner["claim"] = {**cert["claim"], "kind": "mass-matrix-spectrum"}
    if cert["claim"]["quantity"] == "lambda_max":
        inner.pop("formation", None)  # the sets are the formed ones plus the cover
        eps = rational(cert.get("epsilon"), "epsilon")
        need(eps > 0, "epsilon: must be > 0")
        extra = covering(mass, centre, axes, eps)
        for rows in sets:
            rows[k] = [a + b for a, b in zip(rows[k], extra)]
        inner["parameters"] = [[[str(x) for x in row] for row in rows] for rows in sets]
    return inner


def _flange(cert):
    sets = parameter_sets(cert)
    k, mass, centre, axes = _payload(cert, len(sets[0]))
    bound, beta, radius = rational(cert["claim"].get("bound"), "claim.bound"), rational(cert.get("beta"), "beta"), \
        max(axes)
    c2 = sum(x * x for x in centre)
    base = (beta / mass - 1 - c2 - radius**2) if mass > 0 else fmpq(0)
    if mass > 0 and (base < 0 or base**2 < 4 * radius**2 * c2):
        return Outcome(UNPROVED, f"beta = {beta} is below m ((|c| + R)^2 + 1) (exact arithmetic)", 0)
    tested = 0
    for v, rows in enumerate(sets):
        for l, row in enumerate(rows):
            tested += 1
            if not above(pseudo_inertia(row), -1, bound - (beta if l == k and mass > 0 else 0)):
                return Outcome(UNPROVED, f"parameter set {v}, body {l + 1}: (bound{' - beta' if l == k else ''}) I - "
                               "f(Phi) is not positive semidefinite (exact arithmetic)", tested,
                               {"parameter_set": v, "body": l + 1})
    return Outcome(REPROVED, f"beta >= m ((|c| + R)^2 + 1) and {tested} bodies decided exactly", tested)
