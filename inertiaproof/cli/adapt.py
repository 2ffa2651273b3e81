"""``inertiaproof adapt``: adaptive tracking of a scene's reference motion, written as time series.

The scene's ``[control]`` table gives the reference, its ``[adaptive]`` table (or ``--gains FILE`` with the same
keys) the gains; its loads change the parameters as the scene says. DIR/adapt.json (``inertiaproof.adapt/1``) and
DIR/series.csv hold, per sample time: the tracking error, the parameter error, lambda_min and lambda_max of each
f(Phi_hat_l) and of M(q, Theta_hat) at the run's configuration and over sampled configurations. ``--report``
also writes DIR/adapt.html (and .tex, .pdf) with the plots. Exit status 0 when the run reached its horizon, 1 when
it stopped early (budget, non-finite state, step collapse, a barrier stepped over).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from inertiaproof.errors import InputError
from inertiaproof.scene.format import load_gains, load_scene
from inertiaproof.sim import estimates, tracking
from inertiaproof.sim.adaptive import LAWS

__all__ = ["configure", "document", "main", "SCHEMA"]

SCHEMA = "inertiaproof.adapt/1"


def configure(parser):
    parser.add_argument("--scene", required=True, metavar="FILE", help="the scene (TOML)")
    parser.add_argument("--law", required=True, choices=sorted(LAWS), help="the adaptive law")
    parser.add_argument("--gains", metavar="FILE", help="TOML with the keys of the scene's [adaptive] table")
    parser.add_argument("--plant", choices=tracking.PLANTS, default="gre",
                        help="gre: the generalized equation; pagilla: Eq. (2); classical: Eq. (1) (default: gre)")
    parser.add_argument("--out", default="out/adapt", metavar="DIR", help="output folder (default: out/adapt)")
    parser.add_argument("--horizon", type=float, metavar="S", help="seconds simulated (default: the scene's)")
    parser.add_argument("--samples", type=int, default=201, help="sample times written (default: 201)")
    parser.add_argument("--rtol", type=float, default=1e-6, help="relative tolerance of RK45 (default: 1e-6)")
    parser.add_argument("--configurations", type=int, default=256,
                        help="random configurations for the extremes of M(q, Theta_hat) over q (default: 256)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--report", action="store_true", help="also write DIR/adapt.html, .tex (and .pdf)")


def document(scene, run, batch, settings, q_samples):
    """The adapt.json document of a finished or stopped run."""
    x = estimates.series(scene.chain, run, batch, q_samples)
    spec = run.spec
    summary = {
        "rms_tracking_error": float(np.sqrt(np.mean(x["tracking_error"] ** 2))),
        "max_tracking_error": float(x["tracking_error"].max()),
        "final_parameter_error": float(x["parameter_error"][-1]),
        "min_lambda_min_f_hat": x["lambda_min_f_hat"].min(0), "max_lambda_max_f_hat": x["lambda_max_f_hat"].max(0),
        "min_lambda_min_M_hat": float(x["lambda_min_M_hat"].min()),
        "max_lambda_max_M_hat": float(x["lambda_max_M_hat"].max()),
        "consistent": bool(x["lambda_min_f_hat"].min() > 0),
    }
    if "inf_lambda_min_M_hat" in x:
        summary["sampled_inf_lambda_min_M_hat"] = float(x["inf_lambda_min_M_hat"].min())
        summary["sampled_sup_lambda_max_M_hat"] = float(x["sup_lambda_max_M_hat"].max())
    return {
        "schema": SCHEMA, "scene": {"source": scene.source, "name": scene.name, "description": scene.description},
        "law": spec.law.name, "gain": spec.law.gain, "plant": spec.plant,
        "gains": {"lambda": spec.gains.lam, "kd": spec.gains.kd, "estimate": list(settings.estimate)},
        "reference": {"home": spec.reference.home, "amplitude": spec.reference.amplitude,
                      "frequency": spec.reference.frequency},
        "status": run.status, "note": run.note, "seconds": run.seconds, "evaluations": run.evaluations,
        "balance_error": run.balance_error, "configurations": len(q_samples), "summary": summary, "series": x,
    }


def _json(x):
    """numpy arrays and scalars as JSON."""
    return x.tolist() if hasattr(x, "tolist") else str(x)


def _csv(path, series):
    columns = {}
    for name, values in series.items():
        values = np.asarray(values, float)
        if values.ndim == 1:
            columns[name] = values
        else:
            columns.update({f"{name}_{k + 1}": values[:, k] for k in range(values.shape[1])})
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(columns)
        writer.writerows(np.column_stack(list(columns.values())).tolist())


def main(args):
    for name in ("horizon", "rtol", "samples"):
        value = getattr(args, name)
        if value is not None and not value > 0:
            raise InputError(f"--{name}: must be > 0, got {value:g}")
    scene = load_scene(args.scene)
    settings = load_gains(args.gains, scene) if args.gains else scene.adaptive
    if settings.gain(args.law) is None:
        raise InputError(f"{args.gains or args.scene}: gamma: no gain for law {args.law!r}")
    spec = tracking.scene_specs(scene, [args.law], [args.plant], settings)[0]
    horizon = args.horizon or scene.horizon()
    (run,), batch = tracking.simulate(scene.chain, [spec], horizon, samples=args.samples, rtol=args.rtol,
                                      method=settings.integrator)
    q_samples = estimates.configurations(scene.chain, args.configurations, np.random.default_rng(args.seed))
    doc = document(scene, run, batch, settings, q_samples)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "adapt.json").write_text(json.dumps(doc, indent=1, default=_json))
    _csv(out / "series.csv", doc["series"])
    s = doc["summary"]
    print(f"{scene.name}, {args.law} on {args.plant}: {run.status} at t = {run.t[-1]:g} s after {run.evaluations} "
          f"evaluations; RMS tracking error {s['rms_tracking_error']:.3g} rad, parameter error "
          f"{s['final_parameter_error']:.3g}, min lambda_min(f(Phi_hat)) {min(s['min_lambda_min_f_hat']):.3g}, "
          f"lambda(M_hat) in [{s['min_lambda_min_M_hat']:.3g}, {s['max_lambda_max_M_hat']:.3g}]; "
          f"Lyapunov balance error {run.balance_error:.1e}")
    if run.note:
        print(f"note: {run.note}")
    print(f"series: {out / 'adapt.json'}, {out / 'series.csv'}")
    if args.report:
        from inertiaproof.report.cli import build

        for written in build(out, only=("adapt",)):
            print(f"report: {written}")
    return 0 if run.finished else 1
