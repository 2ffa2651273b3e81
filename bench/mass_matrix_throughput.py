"""Batched M(q) per configuration against Pinocchio's crba called once per configuration from Python (7-DoF Panda).

Both are timed the same way: one call over a batch of K configurations
(ours: one batched call; Pinocchio: a Python loop of crba calls), wall
clock and process CPU time, the two taken in turn (A B A B ...) so that a
drift of the machine's speed hits both, median over repeats. Reported per
configuration, with the ratio ours / Pinocchio per pair (median). The
machine may be shared: absolute figures are inflated, ratios much less.

Ours:
- composite: inertiaproof.dynamics.composite.mass_matrix(chain, q, theta) (composite rigid bodies);
- jacobian+formula: dynamics.mass_matrix(chain.body_jacobian(q), theta) ((MassMatrix) as written);
- body_jacobian alone, and dQJ/dq by complex steps (per configuration, n complex evaluations).

Writes bench/results/mass_matrix_throughput.json. Run: python bench/mass_matrix_throughput.py [--repeats R]
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from pinocchio_oracle import joint_variables, pinocchio_model  # noqa: E402

from inertiaproof.dynamics import composite
from inertiaproof.dynamics.terms import mass_matrix
from inertiaproof.scene import robots


def timed(fn):
    """(wall seconds, CPU seconds) of one call."""
    wall, cpu = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - wall, time.process_time() - cpu


def paired(ours, theirs, count, repeats):
    """Per-configuration wall and CPU microseconds of both (medians) and the median of the pairwise ratios."""
    rows = np.array([timed(ours) + timed(theirs) for _ in range(repeats)])  # wall_a, cpu_a, wall_b, cpu_b
    per = 1e6 * rows / count
    return {"ours_wall_us": float(np.median(per[:, 0])), "ours_cpu_us": float(np.median(per[:, 1])),
            "pinocchio_wall_us": float(np.median(per[:, 2])), "pinocchio_cpu_us": float(np.median(per[:, 3])),
            "ratio_wall": float(np.median(rows[:, 0] / rows[:, 2])),
            "ratio_cpu": float(np.median(rows[:, 1] / rows[:, 3])),
            "ratio_wall_range": [float(np.min(rows[:, 0] / rows[:, 2])), float(np.max(rows[:, 0] / rows[:, 2]))]}


def main(counts=(100, 1000, 10000), repeats=9):
    import pinocchio as pin

    scene = robots.panda()
    chain, theta = scene.chain, scene.trajectory.base
    model = pinocchio_model(chain, theta)
    data = model.createData()
    lo, hi = chain.coordinate_box()
    rng = np.random.default_rng(0)
    results = []
    for count in counts:
        q = lo + (hi - lo) * rng.random((count, chain.n))
        pin_q = [joint_variables(chain, x) for x in q]

        def crba_loop():
            for x in pin_q:
                pin.crba(model, data, x)

        ours = {
            "composite": lambda: composite.mass_matrix(chain, q, theta),
            "jacobian+formula": lambda: mass_matrix(chain.body_jacobian(q), theta),
            "body_jacobian": lambda: chain.body_jacobian(q),
            "body_jacobian_derivative": lambda: chain.body_jacobian_derivative(q),
        }
        crba_loop()
        for name, fn in ours.items():
            fn()
            results.append({"configurations": count, "ours": name, **paired(fn, crba_loop, count, repeats)})
            print(json.dumps(results[-1]))
    reference = np.array([pin.crba(model, data, x) for x in [joint_variables(chain, x) for x in q[:50]]])
    reference = np.triu(reference) + np.swapaxes(np.triu(reference, 1), -1, -2)
    agreement = {
        "composite": float(np.abs(composite.mass_matrix(chain, q[:50], theta) - reference).max()),
        "jacobian+formula": float(np.abs(mass_matrix(chain.body_jacobian(q[:50]), theta) - reference).max()),
    }
    out = {"robot": "panda (7-DoF)", "repeats": repeats, "results": results,
           "max_abs_difference_to_crba": agreement, "python": platform.python_version(),
           "pinocchio": pin.__version__, "numpy": np.__version__,
           "note": "medians of paired runs (ours, crba loop, ours, ...); ratio < 1: ours is faster per configuration. "
                   "The machine had 2 cores shared with other jobs."}
    path = Path(__file__).parent / "results" / "mass_matrix_throughput.json"
    path.parent.mkdir(exist_ok=True)
    path.write_text(json.dumps(out, indent=1))
    print(path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=9)
    main(repeats=parser.parse_args().repeats)
