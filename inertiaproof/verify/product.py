"""The ``product`` claim: a constant of the paper built by a named formula from certified ingredients, and the
``sum`` claim of certified terms.

A product names its ``formula`` from the closed list :data:`FORMULAS`: the relation, the factor (derived here from
the chain's N, or from the claim's ``declared`` r) and, in order, what each ingredient must bound (its kind and
quantity) and to which power. Every ingredient that concerns a chain concerns the same chain and domain, every parameter set
has one row per joint of it, and the ingredients of (QJ)^T QJ are claims on unit bodies (Z = I6). ``>=``: every
ingredient x_i >= b_i with b_i >= 0, so factor * prod x_i^p_i >= factor * prod b_i^p_i. ``<=``: every x_i <= b_i;
x_i >= 0 by its kind (norms, Gram matrices, a payload's M) except at most one, of power 1 (lambda_max of f or Z,
clamped at 0: t -> max(t, 0) is nondecreasing and the rest is nonnegative). The claim holds when its ingredients do
and factor * prod c_i^p_i >= (<=) bound, decided exactly: f = sqrt(r), P = prod c_i^p_i >= 0, f P - bound has the
sign of r P^2 - bound^2 where bound >= 0. Where that fails, the proof does not go through (not re-proved); an
ingredient refuted refutes the certificate that embeds it.

The ``sum`` claim: sum_i x_i ``relation`` bound from ``terms`` bounding x_i by b_i (upper claims for ``<=``, lower
for ``>=``): it holds when sum b_i <= bound (>= for ``>=``) and every term is re-proved.
"""

from __future__ import annotations

from flint import arb, fmpq

from .exact import BadCertificate, rational
from .outcome import REFUTED, REPROVED, UNPROVED, Outcome

__all__ = ["FORMULAS", "SLOTS", "prove", "prove_sum"]

UNIT = ["1", "0", "0", "0", "1", "1", "1", "0", "0", "0"]  # Z(Phi) = I6: M = (QJ)^T QJ
SLOTS = {  # what an ingredient may bound: the (kind, quantity) keys it may have, and whether it is >= 0 by its kind
    "f_min": ({("body-spectrum", "lambda_min", "pseudo_inertia"), ("moving-mass", "lambda_min_f")}, True),
    "Z_min": ({("body-spectrum", "lambda_min", "spatial_inertia"), ("moving-mass", "lambda_min_Z")}, True),
    "f_max": ({("body-spectrum", "lambda_max", "pseudo_inertia"), ("moving-mass", "lambda_max_f"),
               ("payload-envelope", "lambda_max_f")}, False),
    "Z_max": ({("body-spectrum", "lambda_max", "spatial_inertia"), ("moving-mass", "lambda_max_Z")}, False),
    "fdot_max": ({("body-spectrum", "sigma_max", "pseudo_inertia"), ("moving-mass", "sigma_max_fdot")}, True),
    "Zdot_max": ({("body-spectrum", "sigma_max", "spatial_inertia"), ("moving-mass", "sigma_max_Zdot")}, True),
    "QJ_min": ({("mass-matrix-spectrum", "lambda_min")}, True),
    "QJ_max": ({("mass-matrix-spectrum", "lambda_max")}, True),
    "payload_max": ({("payload-envelope", "lambda_max")}, True),
    "psi": ({("moving-mass", "psi")}, True),
    "psi_dot": ({("moving-mass", "psi_dot")}, True),
    "Y_max": ({("skew-partials", "max_sigma")}, True),
    "Y_rss": ({("skew-partials", "rss_sigma")}, True),
}
FORMULAS = {  # name: (relation, factor as r of sqrt(r) from (N, rate), [(slot, twice the power)], in words)
    "alpha1": (">=", lambda n, rate: 1, [("f_min", 2), ("QJ_min", 2)],
               "Theorem 2's alpha1 = min_l inf lambda_min(f(Phi_l)) inf_q lambda_min((QJ)^T QJ)"),
    "alpha1_z": (">=", lambda n, rate: 1, [("Z_min", 2), ("QJ_min", 2)],
                 "Theorem 2 at the level of Z: min_l inf lambda_min(Z(Phi_l)) inf_q lambda_min((QJ)^T QJ)"),
    "alpha2": ("<=", lambda n, rate: 4, [("f_max", 2), ("QJ_max", 2)],
               "Theorem 3's alpha2 = 2 max_l sup lambda_max(f(Phi_l)) sup_q lambda_max((QJ)^T QJ)"),
    "alpha2_z": ("<=", lambda n, rate: 1, [("Z_max", 2), ("QJ_max", 2)],
                 "Theorem 3 at the level of Z: max_l sup lambda_max(Z(Phi_l)) sup_q lambda_max((QJ)^T QJ)"),
    "chi": ("<=", lambda n, rate: 69 * n, [("fdot_max", 2), ("QJ_max", 2)],
            "Theorem 4's chi = sqrt(69 N) max_l sup sigma_max(f(Phidot_l)) sup_q lambda_max((QJ)^T QJ)"),
    "chi_sharp": ("<=", lambda n, rate: 4, [("fdot_max", 2), ("QJ_max", 2)],
                  "Theorem 4 with the key step's factor: 2 max_l sup sigma_max(f(Phidot_l)) "
                  "sup_q lambda_max((QJ)^T QJ)"),
    "chi_z": ("<=", lambda n, rate: 1, [("Zdot_max", 2), ("QJ_max", 2)],
              "Theorem 4 at the level of Z: max_l sup sigma_max(Z(Phidot_l)) sup_q lambda_max((QJ)^T QJ)"),
    "chi_ramp": ("<=", lambda n, rate: 69 * n * rate**2, [("f_max", 2), ("QJ_max", 2)],
                 "Theorem 4's chi of a payload ramp of rate r: sqrt(69 N) r sup_P lambda_max(f(Phi_p)) "
                 "sup_q lambda_max((QJ)^T QJ)"),
    "chi_ramp_sharp": ("<=", lambda n, rate: rate**2, [("payload_max", 2)],
                       "sigma_max(M(q, Thetadot)) of a payload ramp of rate r: r sup_(q, P) lambda_max(M(q, Phi_p))"),
    "eq_acc": ("<=", lambda n, rate: 1, [("psi_dot", 2), ("QJ_max", 1)],
               "EQ-acc's sup ||Psidot|| sup_q sigma_max(QJ)"),
    "thm5": ("<=", lambda n, rate: 6 * n, [("psi", 2), ("Y_max", 2)],
             "Theorem 5's sqrt(6 N) sup ||Psi|| max_p sup_q sigma_max(Y_p)"),
    "thm5_sharp": ("<=", lambda n, rate: 1, [("psi", 2), ("Y_rss", 2)],
                   "Theorem 5 with Cauchy-Schwarz first: sup ||Psi|| sup_q (sum_p sigma_max(Y_p)^2)^(1/2)"),
    "moving_share": ("<=", lambda n, rate: rate, [("QJ_max", 2)],
                     "the moving particles' share sqrt(r) sup_q lambda_max((QJ)^T QJ), r as declared (4 Psi*^2 times "
                     "the formula's factor, not re-derived)"),
}
DECLARED = {"chi_ramp", "chi_ramp_sharp", "moving_share"}  # the formulas with a declared r
KEYS = {"schema", "claim", "ingredients", "provenance"}


def key(sub):
    """(kind, quantity[, matrix]) of an embedded certificate's claim."""
    claim = sub.get("claim") if isinstance(sub, dict) else None
    if not isinstance(claim, dict):
        raise BadCertificate("an ingredient or term is a certificate with a claim")
    kind = claim.get("kind")
    base = (kind, claim.get("relation" if kind in ("product", "sum") else "quantity"))
    return base + (claim.get("matrix"),) if kind == "body-spectrum" else base


def _chain_of(sub):
    """(chain, domain) of an ingredient that concerns a chain, else None."""
    return (sub.get("chain"), sub.get("domain")) if "chain" in sub else None


def _consistent(subs, slots):
    """N, the joints of the one chain the ingredients concern (checked the same chain and domain, every parameter
    set one row per joint, (QJ)^T QJ of unit bodies)."""
    chains = [c for c in map(_chain_of, subs) if c is not None]
    if not chains or any(c != chains[0] for c in chains):
        raise BadCertificate("ingredients: not all of one chain and one domain")
    joints = chains[0][0].get("joints") if isinstance(chains[0][0], dict) else None
    n = len(joints) if isinstance(joints, list) else 0
    for i, (sub, slot) in enumerate(zip(subs, slots)):
        if slot.startswith("QJ") and sub.get("parameters") != [[UNIT] * n]:
            raise BadCertificate(f"ingredients[{i}]: (QJ)^T QJ is M of one set of unit bodies (Z = I6)")
        sets = sub.get("parameters", [])
        if not isinstance(sets, list) or any(not isinstance(rows, list) or len(rows) != n for rows in sets):
            raise BadCertificate(f"ingredients[{i}]: its parameter sets are not of the chain's {n} bodies")
    return n


def _parse(cert):
    if not set(cert) <= KEYS:
        raise BadCertificate(f"unknown field(s) {sorted(set(cert) - KEYS)}")
    claim = cert["claim"]
    if claim.get("formula") not in FORMULAS:
        raise BadCertificate(f"claim.formula: one of {sorted(FORMULAS)}")
    relation, factor, slots, _ = FORMULAS[claim["formula"]]
    if claim.get("relation") != relation:
        raise BadCertificate(f"claim.relation: {claim['formula']} is a {relation!r} claim")
    bound = rational(claim.get("bound"), "claim.bound")
    if ("declared" in claim) != (claim["formula"] in DECLARED):
        raise BadCertificate(f"claim.declared: the r of {sorted(DECLARED)}, and only theirs")
    rate = rational(claim.get("declared", "0"), "claim.declared")
    if rate < 0:
        raise BadCertificate("claim.declared: must be >= 0")
    subs = cert.get("ingredients")
    if not isinstance(subs, list) or len(subs) != len(slots):
        raise BadCertificate(f"ingredients: {len(slots)} certificates, of {', '.join(s for s, _ in slots)}")
    parsed = []
    for i, (sub, (slot, twice)) in enumerate(zip(subs, slots)):
        keys, nonnegative = SLOTS[slot]
        if key(sub) not in keys:
            raise BadCertificate(f"ingredients[{i}]: {slot} is bounded by one of {sorted(keys)}, not {key(sub)}")
        b = rational(sub["claim"].get("bound"), f"ingredients[{i}].claim.bound")
        if relation == ">=" and b < 0:
            raise BadCertificate(f"ingredients[{i}]: lower bound {b} < 0 says nothing of x^p")
        if relation == "<=" and not nonnegative:
            b = max(b, fmpq(0))
        elif b < 0:
            raise BadCertificate(f"ingredients[{i}]: upper bound {b} < 0 of a nonnegative quantity")
        parsed.append((sub, twice, b))
    n = _consistent(subs, [s for s, _ in slots]) if any("chain" in s for s in subs) else 0
    return relation, bound, fmpq(factor(n, rate)), parsed


def prove(cert, prove_any):
    """The :class:`Outcome` of the product claim: the arithmetic decided exactly, then each ingredient re-proved by
    ``prove_any`` (:func:`.claims.prove`, passed in: this module does not import it back)."""
    relation, bound, r, parsed = _parse(cert)
    square = fmpq(1)  # (prod b_i^p_i)^2, exact for half powers too
    for _, twice, b in parsed:
        square *= b ** twice
    holds = (bound <= 0 or r * square >= bound**2) if relation == ">=" else (bound >= 0 and r * square <= bound**2)
    if not holds:
        value = arb(r * square).sqrt().str(10, radius=False)
        return Outcome(UNPROVED, f"the ingredients' bounds give factor * prod b_i^p_i = {value}, not {relation} the "
                       "bound (exact arithmetic)", 0, {"product": value})
    return _parts([sub for sub, _, _ in parsed], "ingredient", prove_any,
                  f"{len(parsed)} ingredient(s) re-proved; factor * prod b_i^p_i {relation} bound decided exactly")


def _parts(parts, label, prove_any, done):
    """Each part re-proved by ``prove_any``: one refuted refutes the certificate, one not re-proved leaves it so."""
    boxes, unproved = 0, []
    for i, sub in enumerate(parts):
        try:
            out = prove_any(sub)
        except BadCertificate as exc:
            raise BadCertificate(f"{label}s[{i}]: {exc}") from None
        boxes += out.boxes
        if out.status == REFUTED:
            return Outcome(REFUTED, f"the claim of {label} {i} is refuted: {out.why}", boxes, out.where)
        if out.status != REPROVED:
            unproved.append(f"{label} {i}: {out.why}")
    if unproved:
        return Outcome(UNPROVED, "; ".join(unproved), boxes)
    return Outcome(REPROVED, done, boxes)


def prove_sum(cert, prove_any):
    """The :class:`Outcome` of the sum claim: sum b_i ``relation`` bound decided exactly, then each term re-proved."""
    if not set(cert) <= {"schema", "claim", "terms", "provenance"}:
        raise BadCertificate(f"unknown field(s) {sorted(set(cert) - {'schema', 'claim', 'terms', 'provenance'})}")
    claim = cert["claim"]
    relation, bound = claim.get("relation"), rational(claim.get("bound"), "claim.bound")
    if relation not in (">=", "<="):
        raise BadCertificate("claim.relation: '>=' or '<='")
    terms = cert.get("terms")
    if not isinstance(terms, list) or not terms:
        raise BadCertificate("terms: a nonempty list of certificates")
    total = fmpq(0)
    for i, sub in enumerate(terms):
        if key(sub)[0] not in ("product", "sum") or key(sub)[1] != relation:
            raise BadCertificate(f"terms[{i}]: a {relation} product or sum, not {key(sub)}")
        total += rational(sub["claim"].get("bound"), f"terms[{i}].claim.bound")
    if not (total >= bound if relation == ">=" else total <= bound):
        return Outcome(UNPROVED, f"the terms' bounds sum to {float(total):.10g}, not {relation} the bound (exact "
                       "arithmetic)", 0, {"sum": str(total)})
    return _parts(terms, "term", prove_any, f"{len(terms)} term(s) re-proved; sum b_i {relation} bound decided exactly")
