"""The consistent fit's and its certificates' seconds on a 7-body chain with friction (84 parameters), from the
normal equations (the rows already summed): the Panda scene's chain, Property 2's regressors at random states,
the scene's Theta and viscous/Coulomb friction as the truth, Gaussian torque noise.

    python bench/consistent_fit.py [--samples 10000] [--repeats 3] [--noise 0.05] [--out bench/results/consistent_fit.json]

Reports per repeat the seconds of consistent_fit (SDP, polish, body and residual certificates, each re-proved by
the checker in process) and of the checker alone on the residual certificate, the certified lower bound L against
the fit's residual and the truth's, and the status.
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path

import numpy as np

from inertiaproof.dynamics import motion, regressors
from inertiaproof.identify.consistent import consistent_fit
from inertiaproof.identify.problem import NormalEquations
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.scene import robots
from inertiaproof.verify.cli import check


def normal_equations(samples, noise, seed=0):
    scene = robots.panda()
    chain, n = scene.chain, scene.chain.n
    rng = np.random.default_rng(seed)
    base = np.asarray(scene.trajectory.base, float)
    truth = np.concatenate([base.ravel(), np.tile([0.3, 0.5], n)])
    h, g, c = np.zeros((truth.size,) * 2), np.zeros(truth.size), 0.0
    for start in range(0, samples, 1000):  # in blocks: the regressors of 1000 states at a time
        count = min(1000, samples - start)
        q, qd, qdd = rng.uniform(-2, 2, (count, n)), rng.normal(0, 1.5, (count, n)), rng.normal(0, 3, (count, n))
        kin = motion.kinematics(chain, q)
        r = regressors.regressor(kin.qj, kin.dqj, kin.rotations, chain.gravity, qd, qd, qdd)
        friction = np.zeros((count, n, 2 * n))
        for k in range(n):
            friction[:, k, 2 * k], friction[:, k, 2 * k + 1] = qd[:, k], np.sign(qd[:, k])
        a = np.hstack([np.moveaxis(r, 2, 1).reshape(count * n, -1), friction.reshape(count * n, -1)])
        b = a @ truth + rng.normal(0, noise, count * n)
        h, g, c = h + a.T @ a, g + a.T @ b, c + float(b @ b)
    bodies = tuple(f"link{k + 1}" for k in range(n))
    extra = tuple(f"joint{k + 1}.{w}" for k in range(n) for w in ("viscous", "coulomb"))
    trace = 10 * float(np.max(np.trace(pseudo_inertia(base), axis1=1, axis2=2)))
    return NormalEquations(h, g, c, bodies, extra, samples * n, {"path": "synthetic panda"}), truth, [trace] * n


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--noise", type=float, default=0.05)
    parser.add_argument("--out", type=Path, default=Path("bench/results/consistent_fit.json"))
    args = parser.parse_args(argv)
    ne, truth, traces = normal_equations(args.samples, args.noise)
    runs = []
    for _ in range(args.repeats):
        start = time.perf_counter()
        fit = consistent_fit(ne, trace_bounds=traces)
        fit_s = time.perf_counter() - start
        cert = next(c for c in fit.certificates if c["claim"]["kind"] == "residual-bound")
        start = time.perf_counter()
        status = check(cert)["status"]
        runs.append({"fit_and_certify_s": fit_s, "checker_s": time.perf_counter() - start, "checker": status})
    out = {"parameters": ne.size, "rows": ne.rows, "noise": args.noise, "status": fit.status, "reason": fit.reason,
           "lower_bound": fit.lower_bound, "residual": fit.residual, "truth_residual": ne.residual(truth),
           "gap_percent": 100 * (fit.residual - fit.lower_bound) / fit.residual if fit.lower_bound else None,
           "median_fit_and_certify_s": float(np.median([r["fit_and_certify_s"] for r in runs])),
           "median_checker_s": float(np.median([r["checker_s"] for r in runs])), "runs": runs,
           "machine": {"python": platform.python_version(), "note": "shared 2-core machine; quote medians"}}
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: v for k, v in out.items() if k != "runs"}, indent=1))


if __name__ == "__main__":
    main()
