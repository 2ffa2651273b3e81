"""The deep envelope's alpha2 bracket alone, and the checker's re-proof of its certificate:

    python bench/envelope_alpha2.py [panda ur5] [--profile deep] [--out bench/results/envelope_alpha2.json]

Per built-in robot, the bracket of sup over q and the payload set (5 kg within 0.1 m of the flange, as the deep
APP-payload-envelope) of lambda_max(M) with the profile's envelope_goal and envelope_boxes, its ratio, the ladder's
note and seconds, the seconds making its certificate (its trees pruned: inertiaproof.bounds.completion.pruned), then
the independent checker on it (on its completion, the profile's tree_boxes, where the checker named leaves it does not
prove, as the suite does): status, boxes, seconds. Written to ``--out`` as JSON.
"""

from __future__ import annotations

import argparse
import json
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

from inertiaproof.bounds import payload
from inertiaproof.bounds.completion import complete
from inertiaproof.bounds.constants import bracket_certificate
from inertiaproof.scene import robots
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.verify.cli import check


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=["panda", "ur5"])
    parser.add_argument("--profile", default="deep", choices=sorted(PROFILES))
    parser.add_argument("--out", type=Path, default=Path("bench/results/envelope_alpha2.json"))
    args = parser.parse_args()
    profile, rows = PROFILES[args.profile], []
    for name in args.robots:
        scene = getattr(robots, name)()
        pset = payload.PayloadSet.ball(scene.chain.n - 1, 5, (0, 0, 0), Fraction(1, 10))
        kw = dict(samples=profile.samples, rounds=profile.rounds, rng=np.random.default_rng(0), progress=None)
        start = time.perf_counter()
        b, _ = payload._sup_over_set(scene.chain, scene.trajectory.base, pset, "sup", kw, profile.envelope_goal,
                                     profile.envelope_boxes or None)
        row = {"robot": name, "attained": b.observed, "certified": b.certified, "ratio": b.certified / b.observed,
               "seconds": round(time.perf_counter() - start, 1), "note": b.note}
        print(json.dumps(row), flush=True)
        start = time.perf_counter()
        cert = json.loads(bracket_certificate(b).text)
        row["certificate_s"] = round(time.perf_counter() - start, 1)
        verdict = check(cert)
        if verdict["status"] == "not re-proved":  # as the suite does: complete the leaves the checker named
            start = time.perf_counter()
            cert = complete(cert, profile.tree_boxes, verdict["where"])
            row["completion_s"] = round(time.perf_counter() - start, 1)
            verdict = check(cert)
        row["checker"] = {k: verdict[k] for k in ("status", "boxes", "seconds")}
        print(json.dumps(row["checker"]), flush=True)
        rows.append(row)
    args.out.write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
