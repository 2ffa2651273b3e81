"""The ``product`` claim: a constant built by formula from certified ingredients, factor * prod_i x_i^p_i.

Ingredient i: an embedded certificate (``of``, re-proved by :func:`.claims.prove`, passed in; products nest
at most ``DEPTH`` deep) whose claim bounds its quantity x_i (an extreme over its domain) by b_i, and a power p_i
(an integer, 1..16, or a half "k/2" of a nonnegative x_i: sup_q sigma_max(QJ) from its claim on (QJ)^T QJ);
the factor f >= 0 is a rational or {"sqrt": r}. ``>=``: every claim x_i >= b_i (``lambda_min``, a ``>=``
product) with b_i >= 0, so x_i^p_i >= b_i^p_i and f prod x_i^p_i >= f prod b_i^p_i. ``<=``: every claim x_i <=
b_i (``lambda_max``, ``sigma_max``, a ``<=`` product); where x_i >= 0, x_i^p_i <= b_i^p_i. Nonnegative by kind:
the norms (a body-spectrum ``sigma_max``, a max |eigenvalue|; a moving-mass rate or Psi; a skew-partials
sigma_max), a mass-matrix-spectrum or payload-envelope ``lambda_max`` with a
parameter set whose Z(Phi_l) are all positive semidefinite (decided exactly; then M >= 0: unit bodies Z = I for
(QJ)^T QJ; a payload adds Z(Phi_p) >= 0), a payload-envelope ``lambda_max_f`` with a set whose f(Phi_l) all are.
At most ONE other x_k (e.g. a body-spectrum ``lambda_max`` of f(Phi), possibly negative), of odd p_k: t -> t^p_k
is nondecreasing, so x_k^p_k <= max(x_k, 0)^p_k <= max(b_k, 0)^p_k, and, the factor and the other powers being
nonnegative, f prod x_i^p_i <= f max(b_k, 0)^p_k prod_(i != k) b_i^p_i (two could both be negative, their product
positive and unbounded). The claim holds when its ingredients' do and f prod c_i^p_i >= (<=) bound, c_i = b_i
(clamped at 0 for ``<=``): with P = prod c_i^p_i >= 0 and f = sqrt(r), f P - bound has the sign of r P^2 -
bound^2 where bound >= 0 (P^2 = prod c_i^(2 p_i) decided exactly). Where that fails the claim is refuted (the
ingredients give no more); else an ingredient refuted refutes it, and one not decided leaves it not decided.

The ``sum`` claim: sum_i x_i ``relation`` bound from ``terms`` (certificates: upper claims for ``<=``, lower for
``>=``) bounding x_i by b_i: x_i <= b_i for all i gives sum x_i <= sum b_i whatever their signs, so it holds when
sum b_i <= bound (>= for ``>=``, decided exactly) and every term is re-proved.
"""

from __future__ import annotations

from flint import arb, fmpq

from .bodies import parameter_sets, pseudo_inertia, spatial_inertia
from .exact import BadCertificate, rational, semidefinite
from .outcome import Outcome

__all__ = ["prove", "prove_sum"]

DEPTH = 4  # products nested in products
NORMS = {("body-spectrum", "sigma_max"), ("moving-mass", "sigma_max_fdot"), ("moving-mass", "sigma_max_Zdot"),
         ("moving-mass", "psi"), ("moving-mass", "psi_dot"), ("skew-partials", "max_sigma"),
         ("skew-partials", "rss_sigma")}  # upper claims of norms: nonnegative quantities
LOWER = {("mass-matrix-spectrum", "lambda_min"), ("body-spectrum", "lambda_min"), ("payload-envelope", "lambda_min"),
         ("moving-mass", "lambda_min_f"), ("moving-mass", "lambda_min_Z"), ("product", ">="), ("sum", ">=")}
UPPER = {("mass-matrix-spectrum", "lambda_max"), ("body-spectrum", "lambda_max"), ("payload-envelope", "lambda_max"),
         ("payload-envelope", "lambda_max_f"), ("moving-mass", "lambda_max_f"), ("moving-mass", "lambda_max_Z"),
         ("product", "<="), ("sum", "<=")} | NORMS


def _nonnegative(sub, key):
    if key in NORMS:
        return True
    matrix = {("mass-matrix-spectrum", "lambda_max"): spatial_inertia, ("payload-envelope", "lambda_max"): spatial_inertia,
              ("payload-envelope", "lambda_max_f"): pseudo_inertia}.get(key)
    return matrix is not None and any(
        all(semidefinite(matrix(row)) for row in rows) for rows in parameter_sets(sub.get("parameters")))


def _key(sub):
    kind = sub["claim"].get("kind")
    return kind, sub["claim"].get("relation" if kind in ("product", "sum") else "quantity")


def _parse(cert):
    claim = cert["claim"]
    relation, bound = claim.get("relation"), rational(claim.get("bound"), "claim.bound")
    if relation not in (">=", "<="):
        raise BadCertificate("claim.relation: '>=' or '<='")
    factor = claim.get("factor")
    r = rational(factor.get("sqrt"), "claim.factor.sqrt") if isinstance(factor, dict) else rational(factor, "claim.factor")
    if r < 0:
        raise BadCertificate("claim.factor: must be >= 0")
    r = r if isinstance(factor, dict) else r * r  # f = sqrt(r)
    items = cert.get("ingredients")
    if not isinstance(items, list) or not items:
        raise BadCertificate("ingredients: a nonempty list of {power, of}")
    parsed, loose = [], 0
    for i, item in enumerate(items):
        where, (sub, power) = f"ingredients[{i}]", (item.get("of"), item.get("power")) if isinstance(item, dict) else (0, 0)
        if not isinstance(sub, dict) or not isinstance(sub.get("claim"), dict):
            raise BadCertificate(f"{where}.of: a certificate")
        twice = 2 * power if type(power) is int else {f"{k}/2": k for k in range(1, 32, 2)}.get(power, 0)
        if not 1 <= twice <= 32:
            raise BadCertificate(f"{where}.power: an integer from 1 to 16 or a half \"k/2\" (k odd, below 32)")
        key = _key(sub)
        if key not in (LOWER if relation == ">=" else UPPER):
            raise BadCertificate(f"{where}: a {'lower' if relation == '>=' else 'upper'} claim expected, not {key}")
        b = rational(sub["claim"].get("bound"), f"{where}.of.claim.bound")
        if relation == ">=" and b < 0:
            raise BadCertificate(f"{where}: lower bound {b} < 0 says nothing of x^p (x >= b < 0 allows x^p below b^p)")
        if relation == "<=" and not _nonnegative(sub, key):
            loose += 1
            if loose > 1 or twice % 4 != 2:
                raise BadCertificate(f"{where}: a quantity that may be negative: only one such, of odd power")
            b = max(b, fmpq(0))
        elif b < 0:
            raise BadCertificate(f"{where}: upper bound {b} < 0 of a nonnegative quantity")
        parsed.append((sub, twice, b))
    return relation, bound, r, parsed


def prove(cert, budget, prove_any, depth=0):
    """The :class:`Outcome` of the product claim: the arithmetic decided exactly, then each ingredient re-proved by
    ``prove_any`` (:func:`.claims.prove`, passed in: this module does not import it back)."""
    if depth > DEPTH:
        raise BadCertificate(f"ingredients: products nested deeper than {DEPTH}")
    relation, bound, r, parsed = _parse(cert)
    square = fmpq(1)  # (prod b_i^p_i)^2, exact for half powers too
    for _, twice, b in parsed:
        square *= b ** twice
    holds = (bound <= 0 or r * square >= bound**2) if relation == ">=" else (bound >= 0 and r * square <= bound**2)
    if not holds:
        value = (arb(r * square).sqrt()).str(10, radius=False)
        return Outcome("refuted", f"the ingredients' bounds give factor * prod b_i^p_i = {value}, not {relation} "
                       f"{float(bound):.10g} (exact rational arithmetic)", 0, {"product": value})
    return _prove_parts(cert, [sub for sub, _, _ in parsed], "ingredient", budget, prove_any, depth,
                        f"{len(parsed)} ingredient(s) re-proved; factor * prod b_i^p_i {relation} bound decided "
                        "exactly")


def _prove_parts(cert, parts, label, budget, prove_any, depth, done):
    """Each part (``label``: ingredient or term) re-proved, products and sums here (nested ``depth`` deep), the rest
    by ``prove_any``: the first refuted refutes the claim, any not decided leaves it not decided."""
    boxes, undecided = 0, []
    nested = {"product": prove, "sum": prove_sum}
    for i, sub in enumerate(parts):
        try:
            own = sub.get("schema") == cert["schema"] and sub["claim"].get("kind") in nested
            out = nested[sub["claim"]["kind"]](sub, budget, prove_any, depth + 1) if own else prove_any(sub, budget)
        except BadCertificate as exc:
            raise BadCertificate(f"{label}s[{i}]: {exc}") from None
        boxes += out.boxes
        if out.status == "refuted":
            return Outcome("refuted", f"{label} {i} ({sub['claim'].get('statement', '')}): {out.why}", boxes,
                           {label: i, "where": out.where})
        if out.status != "re-proved":
            undecided.append(f"{label} {i}: {out.why}")
    if undecided:
        return Outcome("not decided", "; ".join(undecided), boxes)
    return Outcome("re-proved", done, boxes)


def prove_sum(cert, budget, prove_any, depth=0):
    """The :class:`Outcome` of the sum claim: sum b_i ``relation`` bound decided exactly, then each term re-proved."""
    if depth > DEPTH:
        raise BadCertificate(f"terms: claims nested deeper than {DEPTH}")
    claim = cert["claim"]
    relation, bound = claim.get("relation"), rational(claim.get("bound"), "claim.bound")
    if relation not in (">=", "<="):
        raise BadCertificate("claim.relation: '>=' or '<='")
    terms = cert.get("terms")
    if not isinstance(terms, list) or not terms:
        raise BadCertificate("terms: a nonempty list of certificates")
    total = fmpq(0)
    for i, sub in enumerate(terms):
        if not isinstance(sub, dict) or not isinstance(sub.get("claim"), dict):
            raise BadCertificate(f"terms[{i}]: a certificate")
        if _key(sub) not in (LOWER if relation == ">=" else UPPER):
            raise BadCertificate(f"terms[{i}]: a {'lower' if relation == '>=' else 'upper'} claim expected, not "
                                 f"{_key(sub)}")
        total += rational(sub["claim"].get("bound"), f"terms[{i}].claim.bound")
    if not (total >= bound if relation == ">=" else total <= bound):
        return Outcome("refuted", f"the terms' bounds sum to {float(total):.10g}, not {relation} {float(bound):.10g} "
                       "(exact rational arithmetic)", 0, {"sum": str(total)})
    return _prove_parts(cert, terms, "term", budget, prove_any, depth,
                        f"{len(terms)} term(s) re-proved; sum b_i {relation} bound decided exactly")
