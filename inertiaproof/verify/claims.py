"""What a certificate claims: its schema and kinds, each kind proved by its own module, and the statement the
checker writes from the claim (it never reads one).

Every certificate is a JSON object with ``schema`` (:data:`SCHEMA`) and a ``claim`` whose ``kind`` names the module
that proves it; the rest of the certificate is that kind's data (README: "Certificates").
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


def prove(cert):
    """The :class:`.outcome.Outcome` of the certificate's claim."""
    need(isinstance(cert, dict) and cert.get("schema") == SCHEMA, f"schema: {SCHEMA!r} expected")
    claim = cert.get("claim")
    need(isinstance(claim, dict) and claim.get("kind") in KINDS, f"claim.kind: one of {sorted(KINDS)}")
    need(set(claim) <= CLAIM_KEYS, f"claim: unknown field(s) {sorted(set(claim) - CLAIM_KEYS)} (the checker writes "
         "the statement itself)")
    digest = hashlib.sha256(json.dumps(cert, sort_keys=True).encode()).hexdigest()
    if digest not in PROVED:
        PROVED[digest] = KINDS[claim["kind"]](cert)
    return PROVED[digest]


def decimal(x, up):
    """The rational ``x`` as a decimal of 10 significant digits, rounded up (or down): a statement never claims
    more than its exact bound. Plain from 1e-10 to below 1e15, else d.ddde(exponent)."""
    x = Fraction(str(x))
    context = Context(prec=10, rounding=ROUND_CEILING if up else ROUND_FLOOR, Emax=MAX_EMAX, Emin=MIN_EMIN)
    d = context.divide(Decimal(x.numerator), Decimal(x.denominator)).normalize(context)
    return f"{d:f}" if -10 <= d.adjusted() < 15 else f"{d:e}".replace("e+", "e")


def _side(claim, lower):
    return f"{'>=' if lower else '<='} {decimal(rational(claim['bound'], 'claim.bound'), not lower)}"


def _sets(cert):
    formation = cert.get("formation")
    if formation is None:
        return f"{len(cert['parameters'])} parameter set(s) as listed"
    ends = lambda load: (f"[{decimal(rational(load['range'][0], 'formation'), False)}, "  # noqa: E731
                         f"{decimal(rational(load['range'][1], 'formation'), True)}], |s'| <= "
                         f"{decimal(rational(load['rate'], 'formation'), True)}")
    loads = "; ".join(f"{load['kind']} on body {load['body']}, s in {ends(load)}" for load in formation["loads"])
    what = "Thetadot(t)" if formation["of"] == "rate" else "Theta(t)"
    return f"the {len(cert['parameters'])} vertex set(s) of {what} formed from its base and loads ({loads or 'none'})"


def _where(cert):
    """For all q in the domain's box (rounded outward) of the chain (its name, source and digest)."""
    chain, source = cert["chain"], cert["chain"].get("source")
    box = ", ".join(f"[{decimal(rational(lo, 'domain'), False)}, {decimal(rational(hi, 'domain'), True)}]"
                    for lo, hi in cert["domain"])
    return (f"for all q in [{box}] (every joint's limits; a full turn where a revolute joint has none) of "
            + _chain(chain, source))


def _chain(chain, source):
    digest = hashlib.sha256(json.dumps(chain, sort_keys=True).encode()).hexdigest()[:12]
    where = f" of {source['path']} (SHA-256 {source['sha256'][:12]})" if source else ""
    return f"chain {chain.get('name', 'chain')!r}{where} ({len(chain['joints'])} joints, {digest})"


def _spectrum(cert):
    claim = cert["claim"]
    unit = cert["parameters"] == [[product.UNIT] * len(cert["chain"]["joints"])]
    return (_where(cert) + ("" if unit else f" and Theta in the hull of {_sets(cert)}") + f": {claim['quantity']}"
            + ("((QJ)^T QJ) " if unit else "(M(q, Theta)) ") + _side(claim, claim["quantity"] == "lambda_min"))


def _body(cert):
    claim = cert["claim"]
    f = "f" if claim["matrix"] == "pseudo_inertia" else "Z"
    return (f"for every body l and Phi_l in the hull of its rows in {_sets(cert)}"
            + (" plus its growth direction" if "directions" in cert else "")
            + f": {claim['quantity']}({f}(Phi_l)) " + _side(claim, claim["quantity"] == "lambda_min"))


def _payload(cert):
    p, claim = cert["payload"], cert["claim"]
    shape = f"radius {p['radius']}" if "radius" in p else f"semi-axes {p['semi_axes']}"
    what = (f"every consistent payload of mass <= {p['mass']} in the ellipsoid of centre {p['centre']} and {shape} "
            f"on body {p['body']} (Phi_p)")
    if claim["quantity"] == "lambda_max_f":
        return (f"for every body l, Theta in the hull of {_sets(cert)} and {what}: lambda_max(f(Phi_l + Phi_p)) "
                + _side(claim, False))
    return (f"{_where(cert)}, Theta in the hull of {_sets(cert)} and {what}: {claim['quantity']}(M(q, Theta + "
            "Phi_p)) " + _side(claim, claim["quantity"] == "lambda_min"))


def _moving(cert):
    claim = cert["claim"]
    return (f"for every t, the bodies' rows in the hull of {_sets(cert)} carrying {len(cert['loads'])} moving "
            f"load(s): {claim['quantity']} " + _side(claim, claim["quantity"].startswith("lambda_min")))


def _skew(cert):
    what = {"max_sigma": "max_p sigma_max(Y_p(q))", "rss_sigma": "(sum_p sigma_max(Y_p(q))^2)^(1/2)"}
    return (f"{_where(cert)}, Y_p = dK_p/dq - (dK_p/dq)^T: {what[cert['claim']['quantity']]} "
            + _side(cert["claim"], False))


def _product(cert):
    claim = cert["claim"]
    declared = f" (r = {claim['declared']})" if "declared" in claim else ""
    chains = [_chain(sub["chain"], sub["chain"].get("source")) for sub in cert["ingredients"] if "chain" in sub][:1]
    return (product.FORMULAS[claim["formula"]][3] + declared + (f" of {chains[0]}" if chains else "") + " "
            + _side(claim, claim["relation"] == ">="))


def _sum(cert):
    return (f"the sum of {len(cert['terms'])} term(s) (" + "; ".join(statement(t) for t in cert["terms"]) + ") "
            + _side(cert["claim"], cert["claim"]["relation"] == ">="))


def _key_step(cert):
    lo, hi = (decimal(rational(cert["claim"][k], f"claim.{k}"), k == "upper") for k in ("lower", "upper"))
    return (f"L(F) = Z(f^-1(F)) is a positive map and {lo} I6 <= L(I4) <= {hi} I6: for s >= 0, f(Phi) >= s I4 "
            f"implies Z(Phi) >= {lo} s I6, f(Phi) <= s I4 implies Z(Phi) <= {hi} s I6")


STATEMENTS = {"mass-matrix-spectrum": _spectrum, "body-spectrum": _body,
              "payload-envelope": _payload, "moving-mass": _moving, "skew-partials": _skew, "product": _product,
              "sum": _sum, "key-step": _key_step,
              "residual-bound": lambda cert: residual.statement(cert, decimal)}


def statement(cert):
    """The claim in words, written from its fields (the checker's own; bounds rounded outward)."""
    return STATEMENTS[cert["claim"]["kind"]](cert)
