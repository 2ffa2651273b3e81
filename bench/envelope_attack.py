"""The payload envelope's Hypothesis attack at a chosen size against the constants a run certified:

    python bench/envelope_attack.py OUT [--examples 100000] [--seed 0]

Reads OUT/results.json of a run with APP-payload-envelope (deep: the built-in Panda and UR5 with 0..5 kg within
0.1 m of the flange), draws ``--examples`` payloads of each case's set with a configuration each
(``checks.payload_envelope.attack``, the check's own attack) against that case's certified alpha1, alpha2, chi
and zeta, and prints per case the examples, the smallest relative margin, any payload beyond a constant, and the
seconds. A deep run draws the profile's hunt size (``Profile.examples``); the issue asks for 100,000.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from inertiaproof.bounds.payload import PayloadSet, zeta_over_set
from inertiaproof.checks import payload_envelope as check
from inertiaproof.scene import robots


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--examples", type=int, default=100_000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    results = json.loads((args.out / "results.json").read_text())
    (found,) = [c for c in results["checks"] if c["id"] == check.ID]
    for name, case in found["evidence"]["cases"].items():
        scene = getattr(robots, name)()
        pset = PayloadSet.from_json(case["payload_set"])
        c = case["constants"]
        bounds = (c["alpha1"]["certified"]["value"], c["alpha2"]["certified"]["value"], c["chi"]["certified"]["value"],
                  zeta_over_set(np.asarray(scene.trajectory.base, float), pset)[1])
        start = time.perf_counter()
        seen = check.attack(scene.chain, scene.trajectory.base, pset, bounds, check.ramp_rate(check.RAMP_S),
                            examples=args.examples, seed_value=args.seed, witnesses=np.zeros((0, scene.chain.n)))
        print(f"{name}: {seen['examples']} payloads, smallest relative margin {seen['smallest']:.3g}, beyond a "
              f"constant: {seen['violation'] or 'none'} ({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
