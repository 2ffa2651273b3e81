"""How much time selecting checks by scene saves: the selected checks against every registered check.

    python bench/scene_selection.py [--scenes NAME ...] [--profile ci] [--mode both|selected|all]

For each scene file: (a) the checks ``inertiaproof run --scene FILE`` selects, (b) every registered check
run on the same scene regardless of what it needs (a check whose needs the scene lacks may stop with an
error; its time counts all the same). Prints per-check CPU and wall seconds and the totals, and writes
``scene_selection.json``. With ``--mode selected`` or ``--mode all`` only one side runs, so that a
whole-process timer can compare the two, e.g. with /usr/bin/time -v. Re-run after new checks land.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from inertiaproof.scene.format import load_scene
from inertiaproof.suite import catalog
from inertiaproof.suite.context import Context
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.runner import select

ROOT = Path(__file__).resolve().parent.parent


def timed_checks(specs, scene, profile):
    out = []
    for spec in specs:
        ctx = Context(PROFILES[profile], scene=scene)
        cpu, wall = time.process_time(), time.perf_counter()
        try:
            verdict = str(spec.fn(ctx).verdict)
        except Exception as exc:  # an inapplicable check may fail; its time still counts
            verdict = f"error: {type(exc).__name__}"
        out.append({"check": spec.name, "verdict": verdict, "cpu_s": time.process_time() - cpu,
                    "wall_s": time.perf_counter() - wall})
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", nargs="+", default=sorted(f.stem for f in (ROOT / "scenes").glob("*.toml")))
    p.add_argument("--profile", default="ci", choices=sorted(PROFILES))
    p.add_argument("--mode", default="both", choices=("both", "selected", "all"))
    p.add_argument("--out", default=str(ROOT / "bench" / "results" / "scene_selection.json"))
    args = p.parse_args(argv)
    checks = load_checks()
    everything = sorted(checks.values(), key=lambda s: (catalog.order(s.id), s.name))
    rows = []
    for name in args.scenes:
        scene = load_scene(ROOT / "scenes" / f"{name}.toml")
        selected, skipped = select(checks, scene=scene)
        row = {"scene": name, "selected": [s.name for s in selected], "left_out": [n for n, _ in skipped]}
        if args.mode in ("both", "selected"):
            row["selected_runs"] = timed_checks(selected, scene, args.profile)
        if args.mode in ("both", "all"):
            row["all_runs"] = timed_checks(everything, scene, args.profile)
        for key in ("selected_runs", "all_runs"):
            if key in row:
                row[key.replace("runs", "cpu_s")] = sum(r["cpu_s"] for r in row[key])
        rows.append(row)
        saved = (f"; selection saves {row['all_cpu_s'] - row['selected_cpu_s']:.2f} s CPU of {row['all_cpu_s']:.2f}"
                 if args.mode == "both" else "")
        print(f"{name}: runs {len(selected)} of {len(everything)} checks{saved}", flush=True)
        for key in ("selected_runs", "all_runs"):
            for r in row.get(key, []):
                print(f"  {key[:-5]:>8} {r['check']:<30} {r['cpu_s']:7.2f} s cpu {r['wall_s']:7.2f} s wall  "
                      f"{r['verdict']}")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"profile": args.profile, "mode": args.mode, "scenes": rows}, indent=1))
    print(out)


if __name__ == "__main__":
    main()
