"""The ``product`` claim: a constant of the paper built by a named formula from certified ingredients; and the
``sum`` claim of certified terms.

A product names its ``formula`` from the closed list :data:`FORMULAS`: the relation, the factor r of sqrt(r) (from
the chain's N, or the claim's ``declared`` r) and, in order, what each ingredient must bound (:data:`SLOTS`) and to
which power. Every ingredient that concerns a chain concerns the same chain and domain, every parameter set has one
row per joint of it, and (QJ)^T QJ is M of unit bodies (Z = I6). ``>=``: every ingredient x_i >= b_i >= 0, so
sqrt(r) prod x_i^p_i >= sqrt(r) prod b_i^p_i. ``<=``: every x_i <= b_i, x_i >= 0 by its kind except lambda_max of f
or Z (power 1 inside the square, clamped at 0: t -> max(t, 0) is nondecreasing). The arithmetic is decided exactly:
sqrt(r) P - bound has the sign of r P^2 - bound^2 where bound >= 0. Short of it: not re-proved; an ingredient refuted
refutes the certificate. ``sum``: sum_i x_i ``relation`` bound from ``terms`` bounding x_i by b_i.
"""

from math import prod

from flint import arb, fmpq

from .exact import BadCertificate, known, need, rational
from .outcome import REFUTED, REPROVED, UNPROVED, Outcome

UNIT = ["1", "0", "0", "0", "1", "1", "1", "0", "0", "0"]  # Z(Phi) = I6: M = (QJ)^T QJ
SLOTS = {  # what an ingredient may bound: its (kind, quantity[, matrix]), and whether it is >= 0 by its kind
    slot: ({tuple(k.split()) for k in keys.split(", ")}, nonnegative) for slot, keys, nonnegative in (
        ("f_min", "body-spectrum lambda_min pseudo_inertia, moving-mass lambda_min_f", True),
        ("Z_min", "body-spectrum lambda_min spatial_inertia, moving-mass lambda_min_Z", True),
        ("f_max", "body-spectrum lambda_max pseudo_inertia, moving-mass lambda_max_f, payload-envelope lambda_max_f",
         False),
        ("Z_max", "body-spectrum lambda_max spatial_inertia, moving-mass lambda_max_Z", False),
        ("fdot_max", "body-spectrum sigma_max pseudo_inertia, moving-mass sigma_max_fdot", True),
        ("Zdot_max", "body-spectrum sigma_max spatial_inertia, moving-mass sigma_max_Zdot", True),
        ("QJ_min", "mass-matrix-spectrum lambda_min", True), ("QJ_max", "mass-matrix-spectrum lambda_max", True),
        ("payload_max", "payload-envelope lambda_max", True), ("psi", "moving-mass psi", True),
        ("psi_dot", "moving-mass psi_dot", True), ("Y_max", "skew-partials max_sigma", True),
        ("Y_rss", "skew-partials rss_sigma", True))}
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


def key(sub):
    """(kind, quantity[, matrix]) of an embedded certificate's claim (kind, relation of a product or sum)."""
    claim = sub.get("claim") if isinstance(sub, dict) else None
    need(isinstance(claim, dict), "an ingredient or term is a certificate with a claim")
    kind = claim.get("kind")
    base = (kind, claim.get("relation" if kind in ("product", "sum") else "quantity"))
    return base + (claim.get("matrix"),) if kind == "body-spectrum" else base


def _joints(subs):
    """N, the joints of the one chain (and domain) that every ingredient concerning a chain concerns."""
    chains = [(sub.get("chain"), sub.get("domain")) for sub in subs if "chain" in sub]
    joints = chains[0][0].get("joints") if chains and isinstance(chains[0][0], dict) else None
    need(isinstance(joints, list) and all(c == chains[0] for c in chains),
         "ingredients: of one chain (with a list of joints) and one domain")
    return len(joints)


def _bounds(cert):
    """The claim's relation and bound, r, and each ingredient's twice-power and bound b_i (clamped at 0), checked
    against the formula."""
    known(cert, ("schema", "claim", "ingredients", "provenance"))
    claim = cert["claim"]
    need(claim.get("formula") in FORMULAS, f"claim.formula: one of {sorted(FORMULAS)}")
    relation, factor, slots, _ = FORMULAS[claim["formula"]]
    need(claim.get("relation") == relation, f"claim.relation: {claim['formula']} is a {relation!r} claim")
    rate = rational(claim.get("declared", "0"), "claim.declared")
    need(("declared" in claim) == (claim["formula"] in DECLARED) and rate >= 0,
         f"claim.declared: the r >= 0 of {sorted(DECLARED)}, and only theirs")
    subs = cert.get("ingredients")
    need(isinstance(subs, list) and len(subs) == len(slots),
         f"ingredients: {len(slots)} certificates, of {', '.join(s for s, _ in slots)}")
    powers = []
    for i, (sub, (slot, twice)) in enumerate(zip(subs, slots)):
        kinds, nonnegative = SLOTS[slot]
        need(key(sub) in kinds, f"ingredients[{i}]: {slot} is bounded by one of {sorted(kinds)}, not {key(sub)}")
        b = rational(sub["claim"].get("bound"), f"ingredients[{i}].claim.bound")
        need(b >= 0 or relation == "<=" and not nonnegative, f"ingredients[{i}]: bound {b} < 0 of {slot}, which the "
             "formula needs >= 0")
        powers.append((twice, max(b, fmpq(0))))
    n = _joints(subs)
    for i, (sub, (slot, _)) in enumerate(zip(subs, slots)):
        sets = sub.get("parameters", [])
        of_chain = isinstance(sets, list) and all(isinstance(rows, list) and len(rows) == n for rows in sets)
        need(sets == [[UNIT] * n] if slot.startswith("QJ") else of_chain, f"ingredients[{i}]: parameter sets of "
             f"the chain's {n} bodies; of (QJ)^T QJ, one set of unit bodies (Z = I6)")
    return relation, rational(claim.get("bound"), "claim.bound"), fmpq(factor(n, rate)), powers


def prove(cert, prove_any):
    """The :class:`Outcome` of the product claim: the arithmetic decided exactly, then each ingredient re-proved by
    ``prove_any`` (:func:`.claims.prove`, passed in: this module does not import it back)."""
    relation, bound, r, powers = _bounds(cert)
    square = r * prod(b**twice for twice, b in powers)  # r (prod b_i^p_i)^2: exact for half powers too
    holds = (bound <= 0 or square >= bound**2) if relation == ">=" else (bound >= 0 and square <= bound**2)
    return _parts(cert, holds, "factor * prod b_i^p_i", arb(square).sqrt().str(10, radius=False), prove_any)


def prove_sum(cert, prove_any):
    """The :class:`Outcome` of the sum claim: sum b_i ``relation`` bound decided exactly, then each term re-proved."""
    known(cert, ("schema", "claim", "terms", "provenance"))
    relation, bound = cert["claim"].get("relation"), rational(cert["claim"].get("bound"), "claim.bound")
    need(relation in (">=", "<="), "claim.relation: '>=' or '<='")
    terms = cert.get("terms")
    need(isinstance(terms, list) and terms, "terms: a nonempty list of certificates")
    total = fmpq(0)
    for i, sub in enumerate(terms):
        need(key(sub) in (("product", relation), ("sum", relation)), f"terms[{i}]: a {relation} product or sum, "
             f"not {key(sub)}")
        total += rational(sub["claim"].get("bound"), f"terms[{i}].claim.bound")
    return _parts(cert, total >= bound if relation == ">=" else total <= bound, "sum b_i", str(total), prove_any)


def _parts(cert, holds, what, value, prove_any):
    """The outcome of a product (sum) whose bounds give ``what`` = ``value``: not re-proved unless that ``holds``,
    then each ingredient (term) re-proved by ``prove_any``: one refuted refutes the certificate, one not re-proved
    leaves it so, ``where`` naming it by its index with its own ``where`` (for the prover to complete only it)."""
    kind, relation = cert["claim"]["kind"], cert["claim"]["relation"]
    label = "ingredient" if kind == "product" else "term"
    if not holds:
        return Outcome(UNPROVED, f"the {label}s' bounds give {what} = {value}, not {relation} the bound (exact "
                       "arithmetic)", 0, {kind: value})
    boxes, unproved, where = 0, [], {}
    for i, sub in enumerate(cert[label + "s"]):
        try:
            out = prove_any(sub)
        except BadCertificate as exc:
            raise BadCertificate(f"{label}s[{i}]: {exc}") from None
        boxes += out.boxes
        if out.status == REFUTED:
            return Outcome(REFUTED, f"the claim of {label} {i} is refuted: {out.why}", boxes, out.where)
        if out.status != REPROVED:
            unproved.append(f"{label} {i}: {out.why}")
            where[str(i)] = out.where
    done = f"{len(cert[label + 's'])} {label}(s) re-proved; {what} {relation} bound decided exactly"
    if unproved:
        return Outcome(UNPROVED, "; ".join(unproved), boxes, {label + "s": where})
    return Outcome(REPROVED, done, boxes)
