"""Error against run time and stability of solve_ivp's methods on the scenes (the deep study).

    python bench/work_precision.py [--scenes NAME ...] [--repeats 3] [--out bench/results]

For every scene, method and tolerance: the median run time over ``--repeats`` runs, the error against a
reference run at rtol 1e-12, the power-balance residual and how the run ended. Writes
``work_precision.json`` and ``stability.json`` (the rows the report plots, as ``inertiaproof run`` writes
them) and ``summary.md`` (per scene: the cheapest method reaching errors 1e-6 and 1e-10). Timings are
wall-clock on whatever machine runs this; they are data, not assertions.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from inertiaproof.scene.format import load_scene
from inertiaproof.sim import study

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_SCENES = ("planar_2r_payload", "panda_payload_3kg", "passenger_platform", "micro_2r", "giant_2r",
                  "stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "near_singular_cubic",
                  "many_links_24", "extreme_lengths")
STIFF = ("stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "near_singular_cubic")
TARGETS = (1e-6, 1e-10)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", nargs="+", default=DEFAULT_SCENES)
    p.add_argument("--tolerances", nargs="+", type=float, default=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10))
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--max-evaluations", type=int, default=30_000)
    p.add_argument("--reference-rtol", type=float, default=1e-12)
    p.add_argument("--out", default=str(ROOT / "bench" / "results"))
    p.add_argument("--summary-only", action="store_true", help="rewrite summary.md from the JSON files in --out")
    args = p.parse_args(argv)
    out = Path(args.out)
    if args.summary_only:
        rows, notes = json.loads((out / "work_precision.json").read_text()), notes_of(out)
        (out / "summary.md").write_text(summary(json.loads((out / "studies.json").read_text()), rows, notes))
        print(out / "summary.md")
        return
    out.mkdir(parents=True, exist_ok=True)
    settings = study.StudySettings(tolerances=tuple(args.tolerances), reference_rtol=args.reference_rtol,
                                   max_evaluations=args.max_evaluations, max_seconds=600.0, repeats=args.repeats)
    wp, stab, studies = [], [], {}
    for name in args.scenes:
        scene = load_scene(ROOT / "scenes" / f"{name}.toml")
        start = time.perf_counter()
        st = study.study(scene, settings, progress=lambda m, n=name: print(f"{n}: {m}", file=sys.stderr, flush=True))
        wp += st.work_precision_rows()
        stab += st.stability_rows()
        studies[name] = st
        print(f"{name}: done in {time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
        (out / "work_precision.json").write_text(json.dumps(wp, indent=1))
        (out / "stability.json").write_text(json.dumps(stab, indent=1))
    references = {n: {"method": st.reference.method, "rtol": st.reference.rtol, "status": st.reference.status,
                      "note": st.reference.note, "seconds": st.reference.seconds, "fastest_rate": st.fastest_rate,
                      "substitute": None if st.substitute is None else [st.substitute.method, st.substitute.rtol]}
                  for n, st in studies.items()}
    (out / "studies.json").write_text(json.dumps(references, indent=1))
    (out / "summary.md").write_text(summary(references, wp, notes_of(out)))
    print(out / "summary.md")


def notes_of(out):
    """How each run ended, from stability.json: {(scene, method, rtol): note}."""
    return {(r["scene"], r["method"], r["rtol"]): r["note"] for r in json.loads((out / "stability.json").read_text())}


def summary(references, rows, notes):
    """Markdown: per scene the cheapest method at each target error (by median time and by right-hand-side
    evaluations), the reference, then every run."""
    lines = ["# Work-precision and stability (solve_ivp on (RoboticEquation))", "",
             "Median wall time of repeated runs (runs under 5 s: three; longer: one) on a shared 2-core machine; "
             "evaluations = right-hand sides (a vectorized Jacobian call of Radau/BDF counts once); error = "
             "max_t ||q - q_ref|| / range of q_ref against the reference run; balance = power-balance residual of "
             "Prop1 (max_t |E - E0 - W| / energy in play).", ""]
    lines += ["| scene | cheapest at 1e-6 (time; evaluations) | cheapest at 1e-10 (time; evaluations) | reference "
              "| fastest mode (rad/s) |", "|---|---|---|---|---|"]
    for name, ref in references.items():
        scene = next((r["scene"] for r in rows if r["scene"].replace("-", "_") == name), name)
        cells = []
        for target in TARGETS:
            by_time = study.cheapest(rows, target, scene)
            by_count = study.cheapest(rows, target, scene, cost="evaluations")
            cells.append("none reached it" if by_time is None else
                         f"{by_time[0]} ({by_time[1]:.3g} s); {by_count[0]} ({by_count[1]:.0f})")
        reference = f"{ref['method']} rtol {ref['rtol']:g} {ref['status']}" + (
            f"; errors against {ref['substitute'][0]} rtol {ref['substitute'][1]:g}" if ref["substitute"] else "")
        lines.append(f"| {name}{' (stiff)' if name in STIFF else ''} | {cells[0]} | {cells[1]} | {reference} | "
                     f"{ref['fastest_rate']:.3g} |")
    for name in references:
        lines += ["", f"## {name}", "", "| method | rtol | status | seconds | steps | evaluations | error | balance "
                  "| note |", "|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            if r["scene"].replace("-", "_") != name:
                continue
            err = "-" if r["error"] is None else f"{r['error']:.1e}"
            lines.append(f"| {r['method']} | {r['rtol']:g} | {r['status']} | {r['seconds']:.3g} | {r['steps']} | "
                         f"{r['evaluations']} | {err} | {r['balance_error']:.1e} | "
                         f"{notes.get((r['scene'], r['method'], r['rtol']), '')} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
