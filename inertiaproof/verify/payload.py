"""The ``payload-envelope`` claim: a bound over every consistent payload of an ellipsoid, reduced to claims proved
elsewhere.

``payload``: body k (from 1), mass m, centre c and ``radius`` R or ``semi_axes`` (a, b, c) in body k's frame. The
payloads are the closed convex hull of the point masses m' delta_x, m' <= m, x - c = d in the ellipsoid (the S-lemma
LMI set of Wensing, Kim and Slotine 2017); each quantity is convex in Phi_p, so point masses of mass m decide it:

- ``lambda_min`` (of M(q, Theta + Phi_p e_k)): Z(Phi_p) >= 0 only adds to M: the spectrum claim of the parameters;
- ``lambda_max``: Young's inequality with ``epsilon`` > 0, |p + w x d|^2 <= (1 + eps) |p|^2 + (1 + 1/eps) |w x d|^2,
  and |w x d|^2 <= w^T U w, U = diag(max(b, c)^2, max(a, c)^2, max(a, b)^2), give Z(m delta_x) <= Z(Phi_U), Phi_U =
  (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33: the spectrum claim with Phi_U added to body k;
- ``lambda_max_f`` (max_l lambda_max(f(Phi_l + [l = k] Phi_p)) <= bound): f(m delta_x) = m y y^T <= m |y|^2 I4 <=
  beta I4, y = (x, 1), when beta >= m ((|c| + R)^2 + 1) (decided exactly by squaring): the ``body-spectrum`` claim
  with Phi_beta, f(Phi_beta) = beta I4, added to body k.

A refutation of a claim with a cover added refutes only the cover (the payload claim is then not re-proved); one at a
body without it (``lambda_max_f``) refutes the claim.
"""

from . import bodies, spectrum
from .exact import need, rational, vector
from .outcome import REFUTED, UNPROVED, Outcome

QUANTITIES = ("lambda_min", "lambda_max", "lambda_max_f")


def _payload(cert, n):
    """(k, m, c, (a, b, c)): body k from 0, the ellipsoid's semi-axes (a ball's: R thrice)."""
    payload = cert.get("payload")
    need(isinstance(payload, dict) and type(payload.get("body")) is int and 1 <= payload["body"] <= n,
         f"payload: {{body from 1 to {n}, mass, centre, radius or semi_axes}}")
    mass, centre = rational(payload.get("mass"), "payload.mass"), vector(payload.get("centre"), 3, "payload.centre")
    axes = vector(payload.get("semi_axes", [payload.get("radius")] * 3), 3, "payload.semi_axes")
    need(mass >= 0 and min(axes) >= 0, "payload: mass and radius (semi-axes) must be >= 0")
    return payload["body"] - 1, mass, centre, axes


def covering(mass, centre, axes, eps):
    """Phi_U (10 exact rationals): (1 + eps) Phi(m delta_c) + (1 + 1/eps) m U on I11, I22, I33."""
    c1, c2, c3 = centre
    sa, sb, sc = (x * x for x in axes)
    u1, u2, u3 = ((1 + 1 / eps) * mass * u for u in (max(sb, sc), max(sa, sc), max(sa, sb)))
    m = (1 + eps) * mass
    return [m, m * c1, m * c2, m * c3, m * (c2**2 + c3**2) + u1, m * (c1**2 + c3**2) + u2, m * (c1**2 + c2**2) + u3,
            -m * c1 * c2, -m * c2 * c3, -m * c1 * c3]


def prove(cert):
    """The :class:`Outcome` of the claim, that of the claim that proves it (:func:`inner_spectrum`)."""
    quantity = cert["claim"].get("quantity")
    need(quantity in QUANTITIES, f"claim.quantity: one of {list(QUANTITIES)}")
    inner = inner_spectrum(cert)
    if inner is None:
        return Outcome(UNPROVED, f"beta = {cert['beta']} is below m ((|c| + R)^2 + 1) (exact arithmetic)", 0)
    out = (bodies.prove if quantity == "lambda_max_f" else spectrum.prove)(inner)
    witness = (out.where or {}).get("witness") or {}
    carries = quantity == "lambda_max" or witness.get("body") == cert["payload"]["body"]
    if quantity != "lambda_min" and out.status == REFUTED and carries:
        return Outcome(UNPROVED, f"the cover is refuted, not the payloads: {out.why}", out.boxes, witness)
    return out


def inner_spectrum(cert):
    """The certificate of the claim that proves the payload claim (the prover completes its tree), for the upper
    bounds with a cover added to body k's rows; None where beta is below m ((|c| + R)^2 + 1)."""
    sets, quantity = bodies.parameter_sets(cert), cert["claim"]["quantity"]
    k, mass, centre, axes = _payload(cert, len(sets[0]))
    inner = {key: value for key, value in cert.items() if key not in ("payload", "epsilon", "beta")}
    inner["claim"] = {**cert["claim"], "kind": "mass-matrix-spectrum"}
    if quantity == "lambda_min":
        return inner
    if quantity == "lambda_max":
        eps = rational(cert.get("epsilon"), "epsilon")
        need(eps > 0, "epsilon: must be > 0")
        cover = covering(mass, centre, axes, eps)
    else:
        beta, c2, r2 = rational(cert.get("beta"), "beta"), sum(x * x for x in centre), max(axes) ** 2
        gap = beta / mass - 1 - c2 - r2 if mass > 0 else None  # beta >= m ((|c| + R)^2 + 1): gap >= 2 |c| R
        if gap is not None and (gap < 0 or gap**2 < 4 * r2 * c2):
            return None
        cover = [(beta if mass > 0 else 0) * x for x in (1, 0, 0, 0, 2, 2, 2, 0, 0, 0)]  # f(cover) = beta I4
        inner = {"schema": cert["schema"], "claim": {"kind": "body-spectrum", "matrix": "pseudo_inertia",
                                                     "quantity": "lambda_max", "bound": cert["claim"].get("bound")}}
    for rows in sets:
        rows[k] = [a + b for a, b in zip(rows[k], cover)]
    inner.pop("formation", None)  # the sets are the formed ones plus the cover
    return {**inner, "parameters": [[[str(x) for x in row] for row in rows] for rows in sets]}
