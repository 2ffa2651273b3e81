"""The inf sides of Section 4 on the built-in arms (issue 12): brackets of inf sigma_min(QJ)^2 (Definition 2) and
inf lambda_min(M) (Theorem 2) for Panda with its 2 kg payload ramp and UR5, at the ci budget (20 rounds,
2000 samples) and, with --deep, at the deep budget (800 rounds, 50000 samples): lower (certified), upper (attained),
ratio and seconds per bracket, with the load average. Nothing is asserted; timings depend on the load.

    python bench/inf_brackets.py            # ci budget -> bench/results/inf_brackets.json
    python bench/inf_brackets.py --deep     # both budgets (about 6 minutes on 2 loaded cores)
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np

__all__ = ["brackets", "main"]

RESULTS = Path(__file__).resolve().parent / "results" / "inf_brackets.json"


def brackets(rounds, samples):
    from inertiaproof.bounds.configuration import jacobian_normality, mass_inf
    from inertiaproof.bounds.time import parameter_vertices
    from inertiaproof.scene import robots

    rows = []
    for name, scene in (("panda +2 kg", robots.panda(payload=2.0)), ("ur5", robots.ur5())):
        chain, stack = scene.chain, parameter_vertices(scene.trajectory)[0]
        for quantity, compute in (
                ("inf sigma_min(QJ)^2", lambda: jacobian_normality(chain, samples=samples, rounds=rounds,
                                                                   rng=np.random.default_rng(0))),
                ("inf lambda_min(M)", lambda: mass_inf(chain, stack, samples=samples, rounds=rounds,
                                                       rng=np.random.default_rng(0)))):
            start = time.perf_counter()
            b = compute()
            rows.append({"chain": name, "quantity": quantity, "rounds": rounds, "lower": b.lower,
                         "upper": b.upper, "ratio": b.upper / b.lower if b.lower > 0 else None,
                         "seconds": round(time.perf_counter() - start, 2), "load": os.getloadavg()[0],
                         "note": b.note})
            print({k: v for k, v in rows[-1].items() if k != "note"}, flush=True)
    return rows


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    rows = brackets(20, 2000)
    if "--deep" in argv:
        rows += brackets(800, 50000)
    RESULTS.parent.mkdir(exist_ok=True)
    RESULTS.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
