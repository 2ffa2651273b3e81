"""How the Section 4 brackets scale: time and peak memory against the number of joints, and width against time.

1. ``inertiaproof audit serial_N.urdf --bounds all --json`` (ci profile) for N in JOINTS, each in a fresh
   process: wall time, peak resident memory (the child's ru_maxrss), and the brackets of inf lambda_min(M) and
   sup lambda_max(M) it reports (certified and sampled sides, their ratio).
2. The configuration brackets of the built-in arms (Panda with 2 kg, UR5, spatial 3R, planar 2R) with growing
   refinement budgets: lower, upper, ratio upper/lower and seconds, per quantity.

Nothing is asserted; timings depend on the machine and its load (recorded). Run:

    python bench/bracket_scaling.py            # writes bench/results/bracket_scaling.json
    python bench/bracket_scaling.py --quick    # JOINTS 6, 12 and one budget
    python bench/bracket_scaling.py --widths-only --budgets 20 800 --samples 2000 50000
                                               # part 2 only (bench/results/bracket_widths.json): the ci
                                               # and deep profiles' budgets and samples

The sup sides include the Perron bound of certified entry sups over the search box (inertiaproof.bounds.fourier),
which grows with the budget (pairs of coordinates from 10 rounds, finer grids from 200).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from serial_urdf import serial_urdf  # noqa: E402

__all__ = ["audit_scaling", "main", "width_against_time"]

JOINTS = (6, 12, 24, 30)
BUDGETS = (4, 20, 80)  # rounds per bracket
RESULTS = Path(__file__).resolve().parent / "results" / "bracket_scaling.json"

_MEASURE = """
import json, resource, subprocess, sys, time
start = time.perf_counter()
done = subprocess.run(sys.argv[1:], capture_output=True, text=True)
print(json.dumps({"seconds": time.perf_counter() - start, "exit": done.returncode,
                  "peak_rss_mib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0,
                  "stdout": done.stdout, "stderr": done.stderr[-2000:]}))
"""


def _measured(command):
    """Run ``command`` in a fresh process: seconds, exit status, peak RSS (MiB) of that process, its output."""
    out = subprocess.run([sys.executable, "-c", _MEASURE, *command], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def audit_scaling(joints=JOINTS):
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in joints:
            path = Path(tmp) / f"serial_{n}.urdf"
            path.write_text(serial_urdf(n))
            run = _measured([sys.executable, "-m", "inertiaproof", "audit", str(path), "--bounds", "all", "--json"])
            row = {"joints": n, "seconds": round(run["seconds"], 3), "exit": run["exit"],
                   "peak_rss_mib": round(run["peak_rss_mib"], 1)}
            try:
                chains = json.loads(run["stdout"])["files"][str(path)]["chains"]
                bounds = next(iter(chains.values()))["bounds"]
                low = (bounds["inf_lambda_min_certified"]["value"], bounds["inf_lambda_min_sampled"]["value"])
                high = (bounds["sup_lambda_max_certified"]["value"], bounds["lambda_max"]["value"])
                row["inf_lambda_min"] = {"lower": low[0], "upper": low[1], "ratio": _ratio(low[1], low[0])}
                row["sup_lambda_max"] = {"lower": high[1], "upper": high[0], "ratio": _ratio(high[0], high[1])}
            except (KeyError, ValueError, StopIteration) as exc:
                row["error"] = f"{type(exc).__name__}: {exc}; stderr: {run['stderr'][-300:]}"
            rows.append(row)
            print(row, flush=True)
    return rows


def _ratio(upper, lower):
    return float(upper / lower) if lower and lower > 0 and np.isfinite(upper) else None


def width_against_time(budgets=BUDGETS, samples=None):
    from inertiaproof.bounds.configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup
    from inertiaproof.bounds.time import parameter_vertices
    from inertiaproof.scene import robots

    rows = []
    for scene in (robots.panda(payload=2.0), robots.ur5(), robots.spatial_3r(), robots.planar_2r(payload=1.0)):
        chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
        rates = parameter_vertices(scene.trajectory)[1]
        for b_index, budget in enumerate(budgets):
            kw = dict(samples=2000 if samples is None else samples[b_index], rounds=budget,
                      rng=np.random.default_rng(0))
            quantities = {
                "inf sigma_min(QJ)^2": lambda: jacobian_normality(chain, **kw),
                "sup sigma_max(QJ)": lambda: jacobian_sup(chain, **kw),
                "inf lambda_min(M)": lambda: mass_inf(chain, thetas, **kw),
                "sup lambda_max(M)": lambda: mass_sup(chain, thetas, **kw),
                "sup sigma_max(M(q, Thetadot))": lambda: mass_sup(chain, rates, kind="absmax", **kw),
            }
            for name, compute in quantities.items():
                start = time.perf_counter()
                b = compute()
                seconds = time.perf_counter() - start
                row = {"chain": scene.name, "quantity": name, "rounds": budget, "samples": kw["samples"],
                       "lower": float(b.lower),
                       "upper": float(b.upper), "ratio": _ratio(b.upper, b.lower), "seconds": round(seconds, 3),
                       "boxes": b.boxes}
                rows.append(row)
                print(row, flush=True)
    return rows


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    quick = "--quick" in argv
    budgets, samples = _floats(argv, "--budgets"), _floats(argv, "--samples")
    budgets = budgets or ((20,) if quick else BUDGETS)
    if samples is not None and len(samples) != len(budgets):
        raise SystemExit("--samples needs one count per budget")
    load = os.getloadavg()
    result = {"machine": {"cpus": os.cpu_count(), "load_average_1_5_15": [round(x, 2) for x in load]},
              "audit_serial_chain": [] if "--widths-only" in argv else audit_scaling((6, 12) if quick else JOINTS),
              "width_against_time": width_against_time(budgets, samples and [int(x) for x in samples])}
    result["machine"]["load_average_after"] = [round(x, 2) for x in os.getloadavg()]
    out = RESULTS.with_name("bracket_widths.json") if "--widths-only" in argv else RESULTS
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(result, indent=1))
    print(out)


def _floats(argv, flag):
    """The numbers after ``flag`` in argv (up to the next option), or None."""
    if flag not in argv:
        return None
    out = []
    for item in argv[argv.index(flag) + 1:]:
        if item.startswith("--"):
            break
        out.append(float(item))
    return tuple(out)


if __name__ == "__main__":
    main()
