"""Can a chain's mass matrix M(q) become singular? A structural answer where one exists.

M(q) = sum_l (QJ_l)^T Z(Phi_l) QJ_l (MassMatrix), QJ_l the rows of body l.
In a serial chain joint k moves bodies k..N and no body before k, and moves
body k by its unit axis, so QJ(q) has full column rank at every q (its block
column k starts with a nonzero block in block row k).

- ``never``: every body has f(Phi_l) > 0; then Z(Phi_l) >= lambda_min(f(Phi_l)) I6 > 0
  (Theorem 2, key step) and M(q) >= min_l lambda_min(Z_l) (QJ)^T QJ > 0 for every q.
- ``everywhere``: bodies k..N are all massless (Phi = 0); then QJ_l e_k = 0
  for l < k and Z_l = 0 for l >= k, so M(q) e_k = 0 for every q: exact.
- otherwise the structure decides nothing: a massless or degenerate body
  between massive ones leaves M(q) singular where the massive bodies' rows of
  QJ lose rank (kinematic singularities), and an inconsistent body can make
  M(q) indefinite. The chain's eigenvalue extremes then speak: a sampled
  negative lambda_min beyond rounding is a witness of indefiniteness at that q.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.consistency import CONSISTENT
from inertiaproof.result import quantity

__all__ = ["singularity"]


def singularity(chain, theta, body_verdicts, body_names, bounds=None):
    """The verdict and its argument; ``bounds`` is :func:`inertiaproof.audit.chain_bounds`' answer, if any."""
    theta = np.asarray(theta, dtype=float)
    massless = np.all(theta == 0, axis=1)
    suffix = len(massless)
    while suffix > 0 and massless[suffix - 1]:
        suffix -= 1
    if suffix < chain.n:
        joints = [j.name for j in chain.joints[suffix:]]
        return {"verdict": "everywhere", "rank_at_most": quantity(suffix, "exact"),
                "argument": f"joint{'s' * (len(joints) > 1)} {', '.join(joints)} move{'s' * (len(joints) == 1)} only "
                            f"massless bodies ({', '.join(body_names[suffix:])}): those columns of M(q) vanish for every q"}
    bad = [name for name, v in zip(body_names, body_verdicts) if v != CONSISTENT]
    if not bad:
        return {"verdict": "never",
                "argument": "every body has f(Phi) > 0, so Z(Phi) >= lambda_min(f) I (Theorem 2, key step), and QJ(q) "
                            "has full column rank at every q: M(q) > 0 for all q"}
    answer = {"verdict": "not_excluded", "bodies_not_consistent": bad,
              "argument": f"bodies {', '.join(bad)} are not consistent, so the structural argument does not apply"}
    low = (bounds or {}).get("lambda_min")
    tolerance = (bounds or {}).get("resolution", {}).get("value")
    if low is None or not isinstance(low["value"], float) or not isinstance(tolerance, float):
        return answer
    if low["kind"] == "lower_bound" and low["value"] > 0:
        answer.update(verdict="never", argument=f"certified lambda_min(M) >= {low['value']:.3g} > 0 over the limits")
    elif low["value"] < -tolerance:
        answer.update(verdict="indefinite", at_q=bounds.get("lambda_min_q"),
                      argument=f"lambda_min(M(q)) = {low['value']:.3g} < 0 beyond rounding ({tolerance:.1g}) at a "
                               f"{'sampled ' if low['kind'] == 'sampled' else ''}configuration: negative kinetic energy")
    elif low["value"] <= tolerance:
        answer.update(verdict="singular", at_q=bounds.get("lambda_min_q"),
                      argument=f"lambda_min(M(q)) = {low['value']:.3g} is zero to rounding ({tolerance:.1g}) at a "
                               f"{'sampled ' if low['kind'] == 'sampled' else ''}configuration")
    return answer
