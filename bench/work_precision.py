"""Error against run time and stability of solve_ivp's methods on the scenes (the deep study).

    python bench/work_precision.py [--scenes NAME ...] [--repeats 3] [--out bench/results/main]
    python bench/work_precision.py --stiff          # the stiff scenes, into bench/results/stiff

For every scene, method (RK45, DOP853 explicit; Radau, BDF, LSODA implicit) and tolerance: the median run time
over ``--repeats`` runs, the counted work (right-hand sides, Jacobians, LU factorizations), the error against a
reference run at rtol 1e-12 (Radau on a stiff scene, DOP853 otherwise), the power-balance residual and how the
run ended. An explicit method that the scene's fastest closed-loop mode would hold to more than 10 x its budget
of right-hand sides is not run; its row says so with the prediction. Every run stops at a counted budget
(``--max-evaluations`` right-hand sides; the reference three times as many), so the bench always ends; a
wall-clock safety net per scene (``--scene-seconds``) marks what it stops as ``clock``. ``many_links_24`` runs
over 0.3 s of its 0.6 s horizon (the whole takes over 4 minutes here; ``--horizon many_links_24=0`` for all of it);
the summary says so. Every tolerance is run even after a looser one failed (``--give-up`` to skip them).

Writes into ``--out``: ``work_precision.json`` and ``stability.json`` (the rows the report plots, as
``inertiaproof run`` writes them), ``work_precision.csv`` (the same rows), ``studies.json`` (the references),
``summary.md`` (per scene: which method to use per error, each method's best error with its seconds and work
or why it has none, then every run) and ``work_precision-SCENE.png`` (error against seconds, log-log, one line
per method, drawn as the report draws it). Timings are wall-clock on whatever machine runs this; they are data,
not assertions.
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

from inertiaproof.budget import Budget
from inertiaproof.scene.format import load_scene
from inertiaproof.sim import study

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_SCENES = ("planar_2r_payload", "panda_payload_3kg", "passenger_platform", "micro_2r", "giant_2r",
                  "stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "near_singular_cubic",
                  "many_links_24", "extreme_lengths")
STIFF_SCENES = ("stiff_payload_1ms", "stiff_mass_ratio_1e6", "stiff_thin_rod", "many_links_24")
SHORTER = {"many_links_24": 0.3}  # s: its full 0.6 s takes over 4 min here (a 24-link right-hand side is slow)
TARGETS = (1e-6, 1e-10)
COLUMNS = ("scene", "method", "implicit", "rtol", "status", "seconds", "steps", "evaluations", "jacobians", "lus",
           "work", "predicted", "error", "balance_error", "note")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", nargs="+", default=None, help=f"default: {' '.join(DEFAULT_SCENES)}")
    p.add_argument("--stiff", action="store_true", help=f"the stiff scenes: {' '.join(STIFF_SCENES)}")
    p.add_argument("--tolerances", nargs="+", type=float, default=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10))
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--max-evaluations", type=int, default=30_000, help="right-hand sides per run (a count)")
    p.add_argument("--reference-rtol", type=float, default=1e-12)
    p.add_argument("--horizon", action="append", default=[], metavar="SCENE=SECONDS",
                   help="a shorter horizon for one scene (default: the scene's own; many_links_24: "
                        f"{SHORTER['many_links_24']:g} s); SCENE=0 for the scene's own")
    p.add_argument("--give-up", action="store_true",
                   help="skip a method's tighter tolerances once it failed at a looser one (default: run them all; "
                        "the counted budgets bound them)")
    p.add_argument("--scene-seconds", type=float, default=300.0,
                   help="wall-clock safety net per scene; runs it stops (or never starts) are status clock")
    p.add_argument("--out", default=None, help="default: bench/results/stiff with --stiff, else bench/results/main")
    p.add_argument("--summary-only", action="store_true", help="rewrite summary.md, CSV and figures from --out")
    args = p.parse_args(argv)
    names = args.scenes or (STIFF_SCENES if args.stiff else DEFAULT_SCENES)
    out = Path(args.out or ROOT / "bench" / "results" / ("stiff" if args.stiff else "main"))
    if args.summary_only:
        rows = json.loads((out / "work_precision.json").read_text())
        write_outputs(out, json.loads((out / "studies.json").read_text()), rows)
        return
    horizons = {**SHORTER, **{k: float(v) or None for k, v in (h.split("=", 1) for h in args.horizon)}}
    out.mkdir(parents=True, exist_ok=True)
    wp, stab, studies = [], [], {}
    for name in names:
        scene = load_scene(ROOT / "scenes" / f"{name}.toml")
        settings = study.StudySettings(tolerances=tuple(args.tolerances), reference_rtol=args.reference_rtol,
                                       max_evaluations=args.max_evaluations, max_seconds=args.scene_seconds,
                                       repeats=args.repeats, horizon=horizons.get(name), give_up=args.give_up)
        if horizons.get(name):
            print(f"{name}: horizon {horizons[name]:g} s instead of the scene's {scene.horizon():g} s (bounded run)",
                  file=sys.stderr, flush=True)
        start = time.perf_counter()
        st = study.study(scene, settings, progress=lambda m, n=name: print(f"{n}: {m}", file=sys.stderr, flush=True),
                         budget=Budget.of(args.scene_seconds))
        seconds = time.perf_counter() - start
        wp += st.work_precision_rows()
        stab += st.stability_rows()
        own = scene.horizon()
        studies[name] = {
            "scene": st.scene, "method": st.reference.method, "rtol": st.reference.rtol,
            "status": st.reference.status, "note": st.reference.note, "seconds": st.reference.seconds,
            "work": st.reference.work, "fastest_rate": st.fastest_rate, "horizon": st.horizon,
            "scene_horizon": own, "stiff": bool(st.fastest_rate * st.horizon > study.STIFF), "study_seconds": seconds,
            "substitute": None if st.substitute is None else [st.substitute.method, st.substitute.rtol]}
        print(f"{name}: done in {seconds:.0f} s", file=sys.stderr, flush=True)
        (out / "work_precision.json").write_text(json.dumps(wp, indent=1))
        (out / "stability.json").write_text(json.dumps(stab, indent=1))
        (out / "studies.json").write_text(json.dumps(studies, indent=1))
    write_outputs(out, studies, wp)


def write_outputs(out, studies, rows):
    """summary.md, work_precision.csv and one figure per scene from the rows and the studies' references."""
    studies, rows = _upgrade(studies, rows)
    with open(out / "work_precision.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)
    for name, ref in studies.items():
        figure(out / f"work_precision-{name}.png", [r for r in rows if r["scene"] == ref["scene"]])
    (out / "summary.md").write_text(summary(studies, rows))
    print(out / "summary.md")


def _upgrade(studies, rows):
    """Files written before work was counted (no Jacobians, LUs, scene names or horizons): fill what is known."""
    rows = [{"jacobians": 0, "lus": 0, "work": r.get("evaluations", 0), "predicted": None,
             "implicit": r["method"] in study.IMPLICIT, **r} for r in rows]
    scenes = {r["scene"].replace("-", "_"): r["scene"] for r in rows}
    studies = {name: {"scene": scenes.get(name, name), "work": "?", "horizon": float("nan"),
                      "scene_horizon": float("nan"), "study_seconds": float("nan"),
                      "stiff": ref.get("fastest_rate", 0) * ref.get("horizon", 1.0) > study.STIFF, **ref}
               for name, ref in studies.items()}
    return studies, rows


def figure(path, rows):
    """Error against seconds, log-log, one line per method, as the report draws a run's work-precision rows."""
    import matplotlib

    matplotlib.use("Agg")
    from inertiaproof.report import datafiles, plots
    from inertiaproof.report.model import Figure

    data = datafiles.work_precision_data(rows)
    if not data["scenes"]:
        return
    with matplotlib.rc_context(plots.STYLE):
        plots.draw(Figure("wp", 1, "work_precision", data, "")).savefig(path, dpi=150)


def horizon_note(ref):
    if ref["horizon"] != ref["horizon"]:
        return "not recorded"
    if ref["horizon"] < ref["scene_horizon"]:
        return f"{ref['horizon']:g} s (shortened from the scene's {ref['scene_horizon']:g} s to bound the run)"
    return f"{ref['horizon']:g} s (the scene's)"


def best_runs(rows, scene):
    """Per method: its most accurate finished run (row), or why it has none (str)."""
    from inertiaproof.report import datafiles

    out = {}
    for row in rows:
        if row["scene"] != scene:
            continue
        method = row["method"]
        if row["status"] in ("ok", "wrong energy") and row["error"]:
            if not isinstance(out.get(method), dict) or row["error"] < out[method]["error"]:
                out[method] = row
        else:
            out.setdefault(method, [])
            if isinstance(out[method], list):
                out[method].append(row)
    return {m: r if isinstance(r, dict) else datafiles.why_none(r) + _detail(r) for m, r in out.items()}


def _detail(rows):
    first = rows[0]
    return "" if first.get("predicted") else f" ({first['note']})" if first.get("note") else ""


def summary(studies, rows):
    """Markdown: per scene which method to use per error (by seconds and by counted work), the reference, each
    method's best error with its seconds and work (or why none), then every run."""
    lines = ["# Work-precision and stability (solve_ivp on (RoboticEquation))", "",
             "Median wall time of repeated runs (runs under 5 s: three; longer: one) on a shared 2-core machine; "
             "work = right-hand sides + Jacobians + LU factorizations, each counted as one (the study's Radau and "
             "BDF take finite-difference Jacobians in one vectorized call, counted once among the right-hand "
             "sides and once as a Jacobian; LSODA's own finite differences are right-hand sides); error = "
             "max_t ||q - q_ref|| / range of q_ref against the reference run; balance = power-balance residual of "
             "Prop1 (max_t |E - E0 - W| / energy in play). An explicit method whose stability would need more than "
             f"{study.PREDICTED_BEYOND:g} x its budget of right-hand sides on the scene's fastest closed-loop mode is "
             "not run (its row gives the prediction). LSODA switches between Adams (explicit) and BDF: 0 "
             "Jacobians means it stayed explicit. Use = the cheapest method (by time, interpolated log-log between "
             "tolerances) reaching each error.", ""]
    lines += ["| scene | horizon | fastest mode (rad/s) | rate x horizon | " +
              " | ".join(f"cheapest at {t:g}: by time; by work" for t in TARGETS) + " | reference | study time |",
              "|---|---|---|---|" + "---|" * len(TARGETS) + "---|---|"]
    for name, ref in studies.items():
        cells = []
        for target in TARGETS:
            by_time = study.cheapest(rows, target, ref["scene"])
            by_work = study.cheapest(rows, target, ref["scene"], cost="work")
            cells.append("none reached it" if by_time is None else
                         f"{by_time[0]} ({by_time[1]:.3g} s); {by_work[0]} ({by_work[1]:.0f})")
        reference = f"{ref['method']} rtol {ref['rtol']:g} {ref['status']}" + (
            f"; errors against {ref['substitute'][0]} rtol {ref['substitute'][1]:g}" if ref["substitute"] else "")
        lines.append(f"| {name}{' (stiff)' if ref['stiff'] else ''} | {horizon_note(ref)} | "
                     f"{ref['fastest_rate']:.3g} | {ref['fastest_rate'] * ref['horizon']:.2g} | {' | '.join(cells)} | "
                     f"{reference} | {ref['study_seconds']:.0f} s |")
    from inertiaproof.report import datafiles

    use = datafiles.work_precision_data(rows)["use"]
    for name, ref in studies.items():
        lines += ["", f"## {name}", "", f"Horizon {horizon_note(ref)}; reference {ref['method']} rtol "
                  f"{ref['rtol']:g} ({ref['status']}, {ref['seconds']:.3g} s, work {ref['work']}).", "",
                  f"Use: {use[ref['scene']]}.", ""]
        lines += ["| method | kind | best error | at rtol | seconds | right-hand sides | Jacobians | LUs | work |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for method, best in best_runs(rows, ref["scene"]).items():
            kind = "implicit" if method in study.IMPLICIT else "explicit"
            if isinstance(best, str):
                lines.append(f"| {method} | {kind} | {best} | | | | | | |")
            else:
                lines.append(f"| {method} | {kind} | {best['error']:.1e} | {best['rtol']:g} | {best['seconds']:.3g} | "
                             f"{best['evaluations']} | {best['jacobians']} | {best['lus']} | {best['work']} |")
        lines += ["", "| method | rtol | status | seconds | steps | rhs | Jacobians | LUs | work | error | balance "
                  "| note |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            if r["scene"] != ref["scene"]:
                continue
            err = "-" if r["error"] is None else f"{r['error']:.1e}"
            note = r["note"] if not r.get("predicted") else f"not run: predicted {r['predicted']:.2g} right-hand sides"
            lines.append(f"| {r['method']} | {r['rtol']:g} | {r['status']} | {r['seconds']:.3g} | {r['steps']} | "
                         f"{r['evaluations']} | {r['jacobians']} | {r['lus']} | {r['work']} | {err} | "
                         f"{r['balance_error']:.1e} | {note} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
