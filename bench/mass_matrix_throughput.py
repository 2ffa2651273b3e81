"""Batched M(q) per configuration against Pinocchio's crba called once per configuration from Python.

Writes bench/results/mass_matrix_throughput.json (median of repeats; the machine may be shared).
Run: python bench/mass_matrix_throughput.py
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from pinocchio_oracle import joint_variables, pinocchio_model  # noqa: E402

from inertiaproof import robots  # noqa: E402
from inertiaproof.dynamics import mass_matrix  # noqa: E402


def median_time(fn, repeats=7):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main(count=2000):
    import pinocchio as pin

    scene = robots.panda()
    chain, theta = scene.chain, scene.trajectory.base
    model = pinocchio_model(chain, theta)
    data = model.createData()
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(0).random((count, chain.n))
    pin_q = np.array([joint_variables(chain, x) for x in q])
    batched = median_time(lambda: mass_matrix(chain.body_jacobian(q), theta))

    def loop():
        for x in pin_q:
            pin.crba(model, data, x)

    looped = median_time(loop)
    ours = mass_matrix(chain.body_jacobian(q[:5]), theta)
    theirs = []
    for x in pin_q[:5]:
        m = pin.crba(model, data, x)
        theirs.append(np.triu(m) + np.triu(m, 1).T)
    agreement = float(np.abs(ours - np.array(theirs)).max())
    out = {"robot": "panda (7-DoF)", "configurations": count,
           "batched_us_per_configuration": 1e6 * batched / count,
           "pinocchio_crba_loop_us_per_configuration": 1e6 * looped / count,
           "ratio_batched_over_pinocchio": batched / looped, "max_abs_difference": agreement,
           "note": "median of 7 repeats on a shared 2-core machine; batched = body_jacobian + mass_matrix"}
    path = Path(__file__).parent / "results" / "mass_matrix_throughput.json"
    path.write_text(json.dumps(out, indent=1))
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
