"""How the Section 4 brackets narrow with run time: read a run's results.json, fit width against seconds.

Every ``bracket`` evidence records [seconds, lower, upper] as branch and bound
refines. For each distinct bracket this writes its final sides, its width
against time and, where the width shrinks geometrically over at least three
points, the fitted rate (log10 width per second and per refinement point).

Run: inertiaproof run --profile deep --out out/deep; python bench/bracket_narrowing.py out/deep/results.json
Writes bench/results/bracket_narrowing.json.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np


def brackets(node, path=()):
    """(path, bracket) for every bracket evidence at any depth."""
    if isinstance(node, dict):
        if {"quantity", "lower", "upper", "convergence"} <= node.keys():
            yield path, node
        for key, value in node.items():
            yield from brackets(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from brackets(value, path + (str(i),))


def side(q):
    """A bracket side as a float ("inf" strings included)."""
    return float(q["value"] if isinstance(q, dict) else q)


def tail_exponent(convergence):
    """p in width ~ seconds^p fitted (log-log) to the points after the first tenth of the run time, or None."""
    points = [(t, hi - lo) for t, lo, hi in convergence if lo is not None and hi is not None and hi - lo > 0 and t > 0]
    if len(points) < 4:
        return None
    t, w = np.array(points).T
    tail = t >= t[0] + 0.1 * (t[-1] - t[0])
    if tail.sum() < 3 or t[tail][-1] < 2 * t[tail][0]:
        return None
    return float(np.polyfit(np.log10(t[tail]), np.log10(w[tail]), 1)[0])


def rate(convergence):
    """(log10 width per second, log10 width per point, points used) of the finite, shrinking part, or None."""
    points = [(t, hi - lo) for t, lo, hi in convergence if lo is not None and hi is not None and hi - lo > 0]
    if len(points) < 3:
        return None
    t, w = np.array(points).T
    keep = np.r_[True, np.diff(w) < 0]
    t, w = t[keep], w[keep]
    if len(t) < 3 or t[-1] <= t[0]:
        return None
    per_second = np.polyfit(t, np.log10(w), 1)[0]
    per_point = np.polyfit(np.arange(len(w)), np.log10(w), 1)[0]
    return float(per_second), float(per_point), int(len(t))


def main(results_path):
    run = json.loads(Path(results_path).read_text())
    rows, seen = [], set()
    for result in run["checks"]:
        found = sorted(brackets(result["evidence"], (result["id"],)), key=lambda pb: -len(pb[0]))  # scene copies first
        for path, b in found:
            scene = next((p for p in path if p not in ("scenes", "chains", "bracket", "ingredients", result["id"])), "")
            lower, upper = side(b["lower"]), side(b["upper"])
            key = (b["quantity"], round(lower, 12), round(upper, 12))
            if key in seen:
                continue
            seen.add(key)
            conv = b.get("convergence") or []
            fit = rate(conv)
            rows.append({"check": result["id"], "where": "/".join(path[1:]), "scene_or_ingredient": scene,
                         "quantity": b["quantity"], "lower": lower, "upper": upper,
                         "width": upper - lower if np.isfinite(upper - lower) else None,
                         "relative_width": (upper - lower) / max(abs(upper), abs(lower), 1e-300)
                         if np.isfinite(upper - lower) else None,
                         "seconds": conv[-1][0] if conv else None,
                         "width_against_seconds": [[t, hi - lo] for t, lo, hi in conv if lo is not None and hi is not None],
                         "log10_width_per_second": None if fit is None else fit[0],
                         "log10_width_per_point": None if fit is None else fit[1],
                         "tail_power_law_exponent": tail_exponent(conv)})
    out = {"profile": run.get("profile"), "runtime_s": run.get("runtime_s"), "brackets": rows,
           "note": "a rate is fitted only to the shrinking, finite part of a bracket's convergence; brackets whose "
                   "certified side comes from a structural bound (no branch and bound) have no convergence to fit"}
    target = Path(__file__).parent / "results" / "bracket_narrowing.json"
    target.parent.mkdir(exist_ok=True)
    target.write_text(json.dumps(out, indent=1))
    for r in rows:
        rate_text = "" if r["log10_width_per_point"] is None else f"  {r['log10_width_per_point']:+.2f} decades/point"
        if r["tail_power_law_exponent"] is not None:
            rate_text += f", width ~ t^{r['tail_power_law_exponent']:.2f} in the tail"
        print(f"{r['check']:10s} {r['where'][:44]:44s} [{r['lower']:.10g}, {r['upper']:.10g}] "
              f"t={r['seconds']}{rate_text}")
    print(target)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/results.json")
