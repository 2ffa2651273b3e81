"""Section 4 on real arms: the brackets ``inertiaproof audit --bounds all`` gives for example-robot-data arms.

For each arm and profile (ci, deep), ``inertiaproof audit FILE --bounds all --json --profile P`` runs in a fresh
process; recorded per chain: inf lambda_min(M) (certified lower side, smallest sampled value) and
sup lambda_max(M) (largest sampled value, certified upper side), the ratio upper/lower of each, the seconds and
the peak resident memory of the audit. Nothing is asserted; timings depend on the machine and its load
(recorded). Needs example-robot-data (the test extra). Run:

    python bench/arm_brackets.py               # ci and deep: writes bench/results/arm_brackets.json
    python bench/arm_brackets.py --ci          # the ci profile only (--deep: deep only; the other profile's rows kept)
"""

from __future__ import annotations

import json
import os
import sys
from importlib import metadata
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bracket_scaling import _measured, _ratio  # noqa: E402

__all__ = ["ARMS", "arm_brackets", "main"]

ARMS = (
    "panda_description/urdf/panda.urdf", "ur_description/urdf/ur5_robot.urdf",
    "ur_description/urdf/ur10_robot.urdf", "kinova_description/robots/kinova.urdf", "z1_description/urdf/z1.urdf",
    "xarm_description/urdf/xarm7.urdf", "so_arm_description/urdf/so101.urdf",
)
RESULTS = Path(__file__).resolve().parent / "results" / "arm_brackets.json"


def _robots():
    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        raise SystemExit("bench/arm_brackets.py: example-robot-data is not installed (pip install -e '.[test]')") from None
    return Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots"))


def arm_brackets(profile, arms=ARMS):
    rows = []
    for arm in arms:
        path = _robots() / arm
        run = _measured([sys.executable, "-m", "inertiaproof", "audit", str(path), "--bounds", "all", "--json",
                         "--profile", profile, "--workers", "1"])
        base = {"arm": Path(arm).stem, "profile": profile, "audit_seconds": round(run["seconds"], 2),
                "peak_rss_mib": round(run["peak_rss_mib"], 1)}
        try:
            chains = json.loads(run["stdout"])["files"][str(path)]["chains"]
        except (KeyError, ValueError) as exc:
            rows.append({**base, "error": f"{type(exc).__name__}: {exc}; stderr: {run['stderr'][-300:]}"})
            continue
        for end, chain in chains.items():
            b = chain["bounds"]
            low = (b["inf_lambda_min_certified"]["value"], b["inf_lambda_min_sampled"]["value"])
            high = (b["lambda_max"]["value"], b["sup_lambda_max_certified"]["value"])
            row = {**base, "chain": end, "joints": len(chain["joints"]),
                   "inf lambda_min(M)": {"lower": low[0], "upper": low[1], "ratio": _ratio(low[1], low[0])},
                   "sup lambda_max(M)": {"lower": high[0], "upper": high[1], "ratio": _ratio(high[1], high[0])}}
            rows.append(row)
            print(json.dumps(row), flush=True)
    return rows


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    profiles = ("ci",) if "--ci" in argv else ("deep",) if "--deep" in argv else ("ci", "deep")
    result = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    for profile in profiles:
        load = [round(x, 2) for x in os.getloadavg()]
        rows = arm_brackets(profile)
        result[profile] = {"load_average_1_5_15": {"before": load, "after": [round(x, 2) for x in os.getloadavg()]},
                           "cpus": os.cpu_count(), "rows": rows}
        RESULTS.parent.mkdir(parents=True, exist_ok=True)
        RESULTS.write_text(json.dumps(result, indent=1))
    print(RESULTS)


if __name__ == "__main__":
    main()
