"""Time per n of the abstract derivation (generic SymPy functions of t), written to a file.

For each size (parameters, rows) and n = 1 .. --max-n, one fresh process
derives the abstract system without any cache (Euler-Lagrange, paper form,
DefF, Prop1, Prop2) and decides GRE exactly; per-stage seconds go to
bench/results/abstract_time_per_n.json. Nothing is asserted.

    python bench/abstract_time_per_n.py [--max-n 5] [--sizes 2x2 10x6] [--timeout 600]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ONE = """
import json, sys, time
from inertiaproof.symbolic.claims import CLAIMS
from inertiaproof.symbolic.derivations import derive
from inertiaproof.symbolic.evidence import run_claim
from inertiaproof.symbolic.systems import SystemKey, build
n, p, r = map(int, sys.argv[1:4])
d = derive(build(SystemKey.abstract(n, p, r)))
start = time.perf_counter()
outcome = run_claim(CLAIMS["GRE"], d, controls=False)
print(json.dumps({"stages": d.seconds, "decide_GRE": time.perf_counter() - start, "holds": outcome.holds,
                  "euler_lagrange_terms": outcome.subject_terms}))
"""


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--max-n", type=int, default=5)
    p.add_argument("--sizes", nargs="+", default=["2x2", "10x6"], help="parameters x rows")
    p.add_argument("--timeout", type=float, default=600.0, help="per n; larger n are skipped after a timeout")
    p.add_argument("--out", default=str(Path(__file__).with_name("results") / "abstract_time_per_n.json"))
    args = p.parse_args(argv)
    rows = []
    for size in args.sizes:
        params, nrows = map(int, size.split("x"))
        for n in range(1, args.max_n + 1):
            start = time.perf_counter()
            try:
                out = subprocess.run([sys.executable, "-c", ONE, str(n), str(params), str(nrows)], capture_output=True,
                                     text=True, timeout=args.timeout, env=dict(os.environ, PYTHONHASHSEED="0"))
            except subprocess.TimeoutExpired:
                rows.append({"n": n, "parameters": params, "rows": nrows, "timeout_s": args.timeout})
                print(f"{size} n={n}: no result within {args.timeout:g} s", flush=True)
                break
            row = {"n": n, "parameters": params, "rows": nrows, "process_s": time.perf_counter() - start,
                   **json.loads(out.stdout)}
            row["derive_s"] = sum(row["stages"].values())
            rows.append(row)
            print(f"{size} n={n}: derive {row['derive_s']:.2f} s (Euler-Lagrange {row['stages']['euler_lagrange']:.2f}"
                  f" s), decide GRE {row['decide_GRE']:.2f} s, holds {row['holds']}", flush=True)
    result = {"what": "abstract derivation time per n (fresh process, no cache)", "rows": rows,
              "machine": {"python": platform.python_version(), "cores": os.cpu_count(),
                          "note": "shared 2-core machine: single runs, noisy"},
              "recorded": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
