"""What a certificate claims: its schema and kinds, each kind proved by its own module.

Every certificate is a JSON object with ``schema`` (:data:`SCHEMA`) and a ``claim`` whose ``kind`` names the module
that proves it; the rest of the certificate is that kind's data (README: "Certificates").
"""

from __future__ import annotations

from . import bodies, product, spectrum
from .exact import BadCertificate

__all__ = ["KINDS", "SCHEMA", "prove"]

SCHEMA = "inertiaproof.certificate/1"
KINDS = {"mass-matrix-spectrum": spectrum.prove, "body-spectrum": bodies.prove,
         "product": lambda cert, budget: product.prove(cert, budget, prove)}  # its ingredients re-proved by prove


def prove(cert, budget):
    """The :class:`.outcome.Outcome` of the certificate's claim (``budget``: the work it may spend beyond its tree)."""
    if not isinstance(cert, dict) or cert.get("schema") != SCHEMA:
        raise BadCertificate(f"schema: {SCHEMA!r} expected")
    claim = cert.get("claim")
    if not isinstance(claim, dict) or claim.get("kind") not in KINDS:
        raise BadCertificate(f"claim.kind: one of {sorted(KINDS)}")
    return KINDS[claim["kind"]](cert, budget)
