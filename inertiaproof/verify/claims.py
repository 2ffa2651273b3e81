"""What a certificate claims: a JSON object with ``schema`` (:data:`SCHEMA`) and a ``claim`` whose ``kind`` names the
module that proves it (the rest is that kind's data; README: "Certificates"), and the statement the checker writes
from the claim's fields (it never reads one), its bounds rounded outward.
"""

import hashlib
import json
from decimal import MAX_EMAX, MIN_EMIN, ROUND_CEILING, ROUND_FLOOR, Context, Decimal
from fractions import Fraction

from . import bodies, key_step, moving, payload, product, residual, skew, spectrum
from .exact import need, rational

SCHEMA = "inertiaproof.certificate/2"
KINDS = {"mass-matrix-spectrum": spectrum.prove, "body-spectrum": bodies.prove, "key-step": key_step.prove,
         "payload-envelope": payload.prove, "moving-mass": moving.prove, "skew-partials": skew.prove,
         "product": lambda cert: product.prove(cert, prove), "sum": lambda cert: product.prove_sum(cert, prove),
         "residual-bound": residual.prove}
CLAIM_KEYS = {"kind", "quantity", "relation", "bound", "matrix", "formula", "declared", "lower", "upper"}
PROVED = {}  # outcomes by the certificate's SHA-256: an ingredient embedded in several products is proved once


def sha256(obj):
    """The SHA-256 (hex) of ``obj`` written as JSON with sorted keys."""
    return hashlib.sha256(json.dumps(obj, sort_keys=True).encode()).hexdigest()


def prove(cert):
    """The :class:`.outcome.Outcome` of the certificate's claim."""
    need(isinstance(cert, dict) and cert.get("schema") == SCHEMA, f"schema: {SCHEMA!r} expected")
    claim = cert.get("claim")
    need(isinstance(claim, dict) and claim.get("kind") in KINDS, f"claim.kind: one of {sorted(KINDS)}")
    need(set(claim) <= CLAIM_KEYS, f"claim: unknown field(s) {sorted(set(claim) - CLAIM_KEYS)} (the checker writes "
         "the statement itself)")
    digest = sha256(cert)
    if digest not in PROVED:
        PROVED[digest] = KINDS[claim["kind"]](cert)
    return PROVED[digest]


def side(claim):
    """The relation of a claim: a product's or sum's own; ``>=`` of a lambda_min and of a residual bound; ``<=``
    of every other bound (the key step's upper one among them)."""
    kind = claim["kind"]
    if kind in ("product", "sum"):
        return claim["relation"]
    lower = kind == "residual-bound" or kind != "key-step" and str(claim.get("quantity")).startswith("lambda_min")
    return ">=" if lower else "<="


def decimal(x, up):
    """The rational ``x`` as a decimal of 10 significant digits, rounded up (or down): a statement never claims more
    than its exact bound. Plain from 1e-10 to below 1e15, else d.ddde(exponent)."""
    x = Fraction(str(x))
    context = Context(prec=10, rounding=ROUND_CEILING if up else ROUND_FLOOR, Emax=MAX_EMAX, Emin=MIN_EMIN)
    d = context.divide(Decimal(x.numerator), Decimal(x.denominator)).normalize(context)
    return f"{d:f}" if -10 <= d.adjusted() < 15 else f"{d:e}".replace("e+", "e")


def _written(text, up):
    """:func:`decimal` of a number as the certificate writes it."""
    return decimal(rational(text, "a number of the claim"), up)


def _interval(lo, hi):
    return f"[{_written(lo, False)}, {_written(hi, True)}]"


def _sets(cert):
    formation, n = cert.get("formation"), len(cert["parameters"])
    if formation is None:
        return f"{n} parameter set(s) as listed"
    loads = "; ".join(f"{load['kind']} on body {load['body']}, s in {_interval(*load['range'])}, |s'| <= "
                      f"{_written(load['rate'], True)}" for load in formation["loads"])
    what = "Thetadot(t)" if formation["of"] == "rate" else "Theta(t)"
    return f"the {n} vertex set(s) of {what} formed from its base and loads ({loads or 'none'})"


def _chain(chain):
    source = chain.get("source")
    where = f" of {source['path']} (SHA-256 {source['sha256'][:12]})" if source else ""
    return f"chain {chain.get('name', 'chain')!r}{where} ({len(chain['joints'])} joints, {sha256(chain)[:12]})"


def _where(cert):
    box = ", ".join(_interval(lo, hi) for lo, hi in cert["domain"])
    return (f"for all q in [{box}] (every joint's limits; a full turn where a revolute joint has none) of "
            + _chain(cert["chain"]))


def _spectrum(cert, claim):
    if cert["parameters"] == [[product.UNIT] * len(cert["chain"]["joints"])]:
        return f"{_where(cert)}: {claim['quantity']}((QJ)^T QJ)"
    return f"{_where(cert)} and Theta in the hull of {_sets(cert)}: {claim['quantity']}(M(q, Theta))"


def _body(cert, claim):
    growth = " plus its growth direction" if "directions" in cert else ""
    matrix = "f(Phi_l)" if claim["matrix"] == "pseudo_inertia" else "Z(Phi_l)"
    return f"for every body l and Phi_l in the hull of its rows in {_sets(cert)}{growth}: {claim['quantity']}({matrix})"


def _payload(cert, claim):
    p = cert["payload"]
    shape = f"radius {p['radius']}" if "radius" in p else f"semi-axes {p['semi_axes']}"
    hull = (f"Theta in the hull of {_sets(cert)} and every consistent payload of mass <= {p['mass']} in the ellipsoid "
            f"of centre {p['centre']} and {shape} on body {p['body']} (Phi_p)")
    if claim["quantity"] == "lambda_max_f":
        return f"for every body l, {hull}: lambda_max(f(Phi_l + Phi_p))"
    return f"{_where(cert)}, {hull}: {claim['quantity']}(M(q, Theta + Phi_p))"


def _moving(cert, claim):
    return (f"for every t, the bodies' rows in the hull of {_sets(cert)} carrying {len(cert['loads'])} moving "
            f"load(s): {claim['quantity']}")


def _skew(cert, claim):
    what = {"max_sigma": "max_p sigma_max(Y_p(q))", "rss_sigma": "(sum_p sigma_max(Y_p(q))^2)^(1/2)"}
    return f"{_where(cert)}, Y_p = dK_p/dq - (dK_p/dq)^T: {what[claim['quantity']]}"


def _product(cert, claim):
    declared = f" (r = {claim['declared']})" if "declared" in claim else ""
    chain = next((f" of {_chain(sub['chain'])}" for sub in cert["ingredients"] if "chain" in sub), "")
    return f"{product.FORMULAS[claim['formula']][3]}{declared}{chain}"


def _sum(cert, claim):
    return f"the sum of {len(cert['terms'])} term(s) ({'; '.join(map(statement, cert['terms']))})"


def _key_step(cert, claim):
    lo, hi = _written(claim["lower"], False), _written(claim["upper"], True)
    return (f"L(F) = Z(f^-1(F)) is a positive map and {lo} I6 <= L(I4) <= {hi} I6: for s >= 0, f(Phi) >= s I4 "
            f"implies Z(Phi) >= {lo} s I6, f(Phi) <= s I4 implies Z(Phi) <= {hi} s I6")


STATEMENTS = {"mass-matrix-spectrum": _spectrum, "body-spectrum": _body, "payload-envelope": _payload,
              "moving-mass": _moving, "skew-partials": _skew, "product": _product, "sum": _sum, "key-step": _key_step,
              "residual-bound": lambda cert, claim: residual.statement(cert, decimal)}


def statement(cert):
    """The claim in words, written from its fields (the checker's own): but for the key step's and a residual
    bound's, it ends with the claim's side, its bound rounded outward."""
    claim = cert["claim"]
    text = STATEMENTS[claim["kind"]](cert, claim)
    if claim["kind"] in ("key-step", "residual-bound"):
        return text
    return f"{text} {side(claim)} {_written(claim['bound'], side(claim) == '<=')}"
