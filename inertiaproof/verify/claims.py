"""What a certificate claims: its schema and kinds, each kind proved by its own module.

Every certificate is a JSON object with ``schema`` (:data:`SCHEMA`) and a ``claim`` whose ``kind`` names the module
that proves it; the rest of the certificate is that kind's data (README: "Certificates").
"""

from __future__ import annotations

import hashlib
import json

from . import bodies, key_step, moving, payload, product, skew, spectrum
from .exact import BadCertificate

__all__ = ["KINDS", "SCHEMA", "prove"]

SCHEMA = "inertiaproof.certificate/1"
KINDS = {"mass-matrix-spectrum": spectrum.prove, "body-spectrum": bodies.prove, "key-step": key_step.prove,
         "payload-envelope": payload.prove, "moving-mass": moving.prove,
         "skew-partials": skew.prove,
         "product": lambda cert, budget: product.prove(cert, budget, prove),
         "sum": lambda cert, budget: product.prove_sum(cert, budget, prove)}  # its ingredients re-proved by prove
PROVED = {}  # outcomes by the certificate's SHA-256 and the budget: a certificate a product embeds, and that a run
# also cites on its own, is proved once per process (Panda's deep alpha1 embeds its 93 s Def2 bracket)


def prove(cert, budget):
    """The :class:`.outcome.Outcome` of the certificate's claim (``budget``: the work it may spend beyond its tree)."""
    if not isinstance(cert, dict) or cert.get("schema") != SCHEMA:
        raise BadCertificate(f"schema: {SCHEMA!r} expected")
    claim = cert.get("claim")
    if not isinstance(claim, dict) or claim.get("kind") not in KINDS:
        raise BadCertificate(f"claim.kind: one of {sorted(KINDS)}")
    key = (hashlib.sha256(json.dumps(cert, sort_keys=True).encode()).hexdigest(), budget)
    if key not in PROVED:
        PROVED[key] = KINDS[claim["kind"]](cert, budget)
    return PROVED[key]
