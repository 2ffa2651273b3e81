"""How the prover's values read as evidence (:mod:`inertiaproof.result`): presentation kept out of the prover.

:func:`bracket_evidence` writes a two-sided bracket (:class:`inertiaproof.bounds.extremes.Bracket`, read by its
attributes: this module imports nothing of the prover) as the ``bracket`` evidence the report plots, its certified
side citing the bracket's certificate by hash (:mod:`inertiaproof.citation`).
"""

from __future__ import annotations

import numpy as np

from inertiaproof.result import quantity

__all__ = ["bracket_evidence"]


def bracket_evidence(b):
    """The ``bracket`` evidence of ``b``: {quantity, lower, upper, witness, convergence}, the certified side a
    lower_bound (of an inf) or upper_bound (of a sup) quantity citing ``b.certificate()`` where it has one, the
    other the sampled value attained at the witness."""
    inf = b.sense == "min"
    sampled = "attained at the witness: an {} estimate of the {}".format(
        "upper" if inf else "lower", "infimum" if inf else "supremum")
    kind = "lower_bound" if inf else "upper_bound"
    if b.certified is None:
        side = quantity(-np.inf if inf else np.inf, kind, "no certified side: " + b.note)
    else:
        side = quantity(b.certified, kind, f"certified by branch and bound over {b.boxes} boxes"
                        + (f"; {b.note}" if b.note else ""), certificate=b.certificate())
    observed = quantity(b.observed, "sampled", sampled)
    lower, upper = (side, observed) if inf else (observed, side)
    return {"quantity": b.quantity, "lower": lower, "upper": upper,
            "witness": np.asarray(b.witness).tolist(), "convergence": b.convergence}
