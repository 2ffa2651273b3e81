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

from inertiaproof import study
from inertiaproof.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_SCENES = ("planar_2r_payload", "panda_payload_3kg", "passenger_platform", "micro_2r", "giant_2r",
                  "stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "near_singular_cubic",
                  "many_links_24", "extreme_lengths")
STIFF = ("stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "near_singular_cubic", "many_links_24")
TARGETS = (1e-6, 1e-10)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", nargs="+", default=DEFAULT_SCENES)
    p.add_argument("--tolerances", nargs="+", type=float, default=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10))
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--max-evaluations", type=int, default=30_000)
    p.add_argument("--reference-rtol", type=float, default=1e-12)
    p.add_argument("--out", default=str(ROOT / "bench" / "results"))
    args = p.parse_args(argv)
    out = Path(args.out)
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
    (out / "summary.md").write_text(summary(studies, wp))
    references = {n: {"method": st.reference.method, "rtol": st.reference.rtol, "status": st.reference.status,
                      "note": st.reference.note, "seconds": st.reference.seconds, "fastest_rate": st.fastest_rate,
                      "substitute": None if st.substitute is None else [st.substitute.method, st.substitute.rtol]}
                  for n, st in studies.items()}
    (out / "studies.json").write_text(json.dumps(references, indent=1))
    print(out / "summary.md")


def summary(studies, rows):
    lines = ["# Work-precision and stability (solve_ivp on (RoboticEquation))", "",
             "Median wall time of repeated runs on a shared 2-core machine; error = max_t ||q - q_ref|| / range of "
             "q_ref against a reference run (rtol in the table); balance = power-balance residual of Prop1.", ""]
    lines += ["| scene | cheapest at 1e-6 | cheapest at 1e-10 | reference | fastest mode (rad/s) |",
              "|---|---|---|---|---|"]
    for name, st in studies.items():
        cells = []
        for target in TARGETS:
            best = study.cheapest(rows, target, st.scene)
            cells.append("none reached it" if best is None else f"{best[0]} ({best[1]:.3g} s)")
        ref, sub = st.reference, st.substitute
        reference = f"{ref.method} rtol {ref.rtol:g} {ref.status}" + (
            f"; errors against {sub.method} rtol {sub.rtol:g}" if sub is not None else "")
        lines.append(f"| {name}{' (stiff)' if name in STIFF else ''} | {cells[0]} | {cells[1]} | "
                     f"{reference} | {st.fastest_rate:.3g} |")
    for name, st in studies.items():
        lines += ["", f"## {name}", "", "| method | rtol | status | seconds | steps | error | balance | note |",
                  "|---|---|---|---|---|---|---|---|"]
        for run, error in st.runs:
            err = "-" if error is None else f"{error:.1e}"
            lines.append(f"| {run.method} | {run.rtol:g} | {run.status} | {run.seconds:.3g} | {run.steps} | {err} | "
                         f"{run.balance_error:.1e} | {run.note} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
