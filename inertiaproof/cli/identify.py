"""``inertiaproof identify ROBOT DATA [--payload LINK [--pickup T [--ramp R]]] [--friction] [--ols]
[--geometry grown|strict|off] [--trace-factor F] [--out DIR] [--json] [--report]``: which inertial parameters explain
measured torques (:mod:`inertiaproof.identify`).

ROBOT is a URDF, MJCF or xacro file or a scene; DATA a CSV of samples (:mod:`inertiaproof.identify.data`). Prints
what the data excite (null directions in parameter names), ordinary least squares with its base parameters and
each body's consistency, the consistent fit with its certificates and the set they cover (which bodies got a
bounding ellipsoid from their geometry and why the others did not; the trace bounds), and a table per body
(identified, the file's, the difference). ``--payload LINK``: the robot's parameters fixed to the file's, the payload's Phi about LINK's
frame identified, and the `inertiaproof envelope` command for every payload within its confidence (run with
``--envelope``; the exit status is then the graver of the two). ``--out DIR``:
DIR/identify.json, DIR/certificates/ (re-proved by ``inertiaproof verify DIR/certificates``), DIR/repaired.urdf (a
URDF robot with the identified inertials; robot mode) and, with ``--report``, DIR/identify.html (residuals against
time, fitted against measured torque per joint).

Exit status: 0 the fit shown is certified (or, without the consistent fit, every identified body is consistent);
1 the data demand inconsistent inertia (certified), or some identified body is inconsistent, or a crash; 2 bad usage
or input (one line naming file and line); 3 the consistent fit not certified.
"""

from __future__ import annotations

import html
import json
import sys
from pathlib import Path

from inertiaproof.errors import InputError

from .status import HOLDS, INCONCLUSIVE, VIOLATED

__all__ = ["configure", "exit_code", "main"]


def configure(parser):
    parser.add_argument("robot", metavar="ROBOT", help="a URDF, MJCF or xacro file, or a scene (*.toml)")
    parser.add_argument("data", metavar="DATA", help="CSV: t, q_J, [qd_J, qdd_J,] tau_J per joint J (SI units)")
    parser.add_argument("--payload", metavar="LINK", help="identify a payload on LINK, the robot's parameters fixed")
    parser.add_argument("--pickup", type=float, metavar="T", help="the payload is taken up at time T (s): fit the "
                        "windows before T and after T + ramp")
    parser.add_argument("--ramp", type=float, metavar="R", help="... over R seconds (smootherstep): also fit the whole "
                        "run with the generalized equation (Thetadot)")
    parser.add_argument("--friction", action="store_true", help="viscous and Coulomb friction per joint as unknowns")
    parser.add_argument("--cutoff", type=float, default=10.0, metavar="HZ", help="cut-off of the zero-phase low-pass "
                        "filter used where qd and qdd are not given (default %(default)s Hz)")
    parser.add_argument("--ols", action="store_true", help="ordinary least squares only (no consistent fit)")
    parser.add_argument("--eps", type=float, default=1e-6, help="the consistent fit's f(Phi_l) >= eps I (default "
                        "%(default)s)")
    parser.add_argument("--prior-weight", type=float, default=0.0, metavar="W", help="weight of the file's values "
                        "as a prior in the consistent fit (log-det divergence; default 0: none)")
    parser.add_argument("--geometry", choices=("grown", "strict", "off"), default="grown", help="each body's bounding "
                        "ellipsoid from its links' geometry (URDF) as a condition of the consistent fit: 'grown' "
                        "(default) grows it about its centre where the file's own values lie outside, 'strict' skips "
                        "such bodies, 'off' none")
    parser.add_argument("--trace-factor", type=float, default=10.0, metavar="F", help="the certified set's trace "
                        "bounds: m_l + tr(I_l)/2 <= F times the file's (default %(default)s)")
    parser.add_argument("--envelope", action="store_true", help="with --payload: also run `inertiaproof envelope` on "
                        "the payload found (its confidence set; into DIR/envelope with --out)")
    parser.add_argument("--out", metavar="DIR", help="write identify.json, certificates/, repaired.urdf there")
    parser.add_argument("--json", action="store_true", help="print the document as JSON")
    parser.add_argument("--report", action="store_true", help="also write DIR/identify.html (needs --out)")


def exit_code(doc):
    """The exit status of an identify document (module docstring)."""
    fits = [doc] if "payload" not in doc else doc["payload"]["fits"]
    statuses = [f.get("consistent", {}).get("status", "not run") for f in fits]
    if "inconsistent data" in statuses:
        return VIOLATED
    if any(s == "not certified" for s in statuses):
        return INCONCLUSIVE
    if all(s == "certified" for s in statuses):
        return HOLDS
    verdicts = [b["verdict"] for b in doc.get("ols", {}).get("bodies", [])] + \
        [f["ols"]["verdict"]["verdict"] for f in fits if "ols" in f and "verdict" in f.get("ols", {})]
    return HOLDS if all(v == "consistent" for v in verdicts) else VIOLATED


def _print(doc):
    d = doc["data"]
    rates = d["velocities"] if isinstance(d["velocities"], str) else (
        f"derived: {d['velocities']['filter']}, cut-off {d['velocities']['cutoff_hz']:g} Hz, "
        f"{d['velocities']['trimmed_each_end']} samples dropped at each end")
    print(f"inertiaproof identify: {doc['chain']} ({len(doc['joints'])} joints"
          f"{', locked: ' + ', '.join(doc['locked_joints']) if doc['locked_joints'] else ''}); {d['samples']} samples, "
          f"t in [{d['t'][0]:g}, {d['t'][1]:g}] s; velocities {rates}")
    if "payload" in doc:
        return _print_payload(doc)
    ex = doc["excitation"]
    print(f"excitation: rank {ex['rank']} of {ex['parameters']} parameters, condition {ex['condition']:.4g}"
          + (f"; joints that do not move: {', '.join(ex['still_joints'])}" if ex["still_joints"] else ""))
    for line in ex["null_directions"]:
        print(f"  not excited: {line}")
    o = doc["ols"]
    print(f"ordinary least squares: residual {o['residual']:.6g}, torque noise {o['torque_noise']:.4g} (N m per "
          f"sample and joint); {len(o['base_parameters'])} base parameters")
    bad = [b for b in o["bodies"] if b["verdict"] != "consistent"]
    print(f"  bodies: {len(o['bodies']) - len(bad)} consistent" + "".join(
        f"; {b['body']} {b['verdict']}: {b['reason']}" for b in bad))
    _print_consistent(doc["consistent"])
    print(f"{'body':<20} {'quantity':<6} {'identified':>13} {'file':>13} {'difference':>13}   ({doc['shown']} fit)")
    for r in doc["table"]:
        print(f"{r['body']:<20} {r['quantity']:<6} {r['identified']:>13.6g} {r['file']:>13.6g} {r['difference']:>13.4g}")


def _print_consistent(c):
    if c["status"] == "not run":
        print(f"consistent fit: not run ({c['reason']})")
        return
    lb = "none certified" if c.get("lower_bound") is None else f"{c['lower_bound']:.6g}"
    print(f"consistent fit: {c['status']}: {c['reason']}; residual {c['residual']:.6g}, certified lower bound {lb}")
    g = c.get("geometry")
    if g is not None:
        print(f"  bounding ellipsoids (--geometry {g['mode']}): {', '.join(g['with_ellipsoid']) or 'none'}")
        for body, note in g["bodies"].items():
            print(f"    {body}: {note}")
    t = c.get("trace_bounds")
    if t is not None:
        print(f"  trace bounds: m_l + tr(I_l)/2 <= {t['factor']:g} times the file's")


def _print_payload(doc):
    p = doc["payload"]
    for f in p["fits"]:
        o = f["ols"]
        phi, se = o["phi"], o["standard_errors"]
        print(f"payload on {p['link']} ({f['window']}, {f['samples']} samples): m = {phi[0]:.5g} +- {se[0]:.2g} kg, "
              f"h = [{phi[1]:.5g}, {phi[2]:.5g}, {phi[3]:.5g}], I = [{', '.join(f'{x:.4g}' for x in phi[4:])}] "
              f"(ols; torque noise {o['torque_noise']:.4g}; {o['verdict']['verdict']})")
        if "consistent" in f:
            _print_consistent(f["consistent"])
        env = f["envelope"]
        if "command" in env:
            print(f"  envelope of every payload within {env['sigmas']:g} standard errors: {env['command']}")
        else:
            print(f"  {env['note']}")


def _write_report(out, ident):
    from inertiaproof.report import plots
    from inertiaproof.report.model import Figure

    s, fitted = ident.samples, ident.fitted
    t = s.t.tolist()
    figures = []
    for k, joint in enumerate(ident.robot.joints):
        lines = {"measured": [[a, b] for a, b in zip(t, s.tau[:, k].tolist())],
                 "fitted": [[a, b] for a, b in zip(t, fitted[:, k].tolist())]}
        figures.append(Figure(f"torque-{k}", 2 * k + 1, "series", {"title": f"{joint}: torque", "x_label": "t (s)",
                                                                  "y_label": "tau (N m or N)", "lines": lines},
                              f"{joint}: fitted and measured torque"))
        res = (s.tau[:, k] - fitted[:, k]).tolist()
        figures.append(Figure(f"residual-{k}", 2 * k + 2, "series", {"title": f"{joint}: residual", "x_label": "t (s)",
                                                                    "y_label": "measured - fitted",
                                                                    "lines": {"residual": [[a, b] for a, b in
                                                                                           zip(t, res)]}},
                              f"{joint}: residual"))
    svgs = plots.render(figures, out / "identify-figures.pdf")
    doc = ident.document
    rows = "".join(f"<tr><td>{html.escape(r['body'])}</td><td>{r['quantity']}</td><td>{r['identified']:.6g}</td>"
                   f"<td>{r['file']:.6g}</td><td>{r['difference']:.4g}</td></tr>" for r in doc.get("table", []))
    table = (f"<table border=1><tr><th>body</th><th>quantity</th><th>identified</th><th>file</th><th>difference</th>"
             f"</tr>{rows}</table>") if rows else ""
    plots_html = "".join(f"<figure>{svgs[f.key]}<figcaption>{html.escape(f.caption)}</figcaption></figure>"
                         for f in figures)
    (out / "identify.html").write_text(
        "<!doctype html><meta charset=utf-8><title>identification</title><h1>Identification</h1>"
        f"<p>{html.escape(doc['chain'])} from {html.escape(doc['data']['path'])}: {doc['data']['samples']} samples"
        f"</p>{table}{plots_html}")


def _write(out, ident, args):
    out.mkdir(parents=True, exist_ok=True)
    written = []
    if ident.certificates:
        folder = out / "certificates"
        folder.mkdir(exist_ok=True)
        for k, cert in enumerate(ident.certificates):
            name = cert.get("id", f"identify-{k + 1}") if isinstance(cert, dict) else f"identify-{k + 1}"
            path = folder / f"{Path(str(name)).name}.json"
            path.write_text(json.dumps(cert, indent=1))
        written.append(f"{folder}/ ({len(ident.certificates)} certificates; inertiaproof verify {folder})")
        ident.document["certificates"] = sorted(p.name for p in folder.glob("*.json"))
    if ident.theta is not None:
        robot = ident.robot.robot
        if robot is not None and robot.format == "urdf":
            from inertiaproof.identify.repaired import repaired_urdf

            text, notes = repaired_urdf(ident.robot, ident.theta)
            (out / "repaired.urdf").write_text(text)
            ident.document["repaired"] = {"path": str(out / "repaired.urdf"), "notes": notes}
            written.append(str(out / "repaired.urdf"))
        else:
            ident.document["repaired"] = {"path": None, "notes": ["a repaired copy is written for URDF files only"]}
    if args.report:
        _write_report(out, ident)
        written.append(str(out / "identify.html"))
    (out / "identify.json").write_text(json.dumps(ident.document, indent=1))
    written.insert(0, str(out / "identify.json"))
    return written


def main(args):
    from inertiaproof.identify.session import identify

    if args.report and not args.out:
        raise InputError("--report needs --out DIR")
    if args.ramp is not None and (args.pickup is None or not args.ramp > 0):
        raise InputError("--ramp R needs --pickup T and R > 0")
    if not args.trace_factor > 0:
        raise InputError(f"--trace-factor must be > 0, got {args.trace_factor}")
    if not args.cutoff > 0:
        raise InputError(f"--cutoff must be > 0 Hz, got {args.cutoff}")
    ident = identify(args.robot, args.data, payload=args.payload, pickup=args.pickup, ramp=args.ramp,
                     friction=args.friction, cutoff=args.cutoff, consistent=not args.ols, eps=args.eps,
                     prior_weight=args.prior_weight, geometry=args.geometry, trace_factor=args.trace_factor)
    written = _write(Path(args.out), ident, args) if args.out else []
    if args.json:
        print(json.dumps(ident.document))
    else:
        _print(ident.document)
        for w in written:
            print(f"wrote {w}")
    sys.stdout.flush()
    code = exit_code(ident.document)
    if args.envelope:
        code = _combined(code, _envelope(args, ident.document))
    return code


def _combined(a, b):
    """The graver of two exit statuses: 1 over 3 over 0."""
    return max((a, b), key=lambda c: {VIOLATED: 3, INCONCLUSIVE: 2, HOLDS: 1}.get(c, 0))


def _envelope(args, doc):
    """`inertiaproof envelope` on the last payload fit's confidence set; its exit status."""
    if "payload" not in doc:
        raise InputError("--envelope needs --payload LINK")
    env = doc["payload"]["fits"][-1]["envelope"]
    if "command" not in env:
        print(f"envelope: not run: {env['note']}")
        return HOLDS
    from . import parser  # noqa: PLC0415

    argv = list(env["argv"])
    if args.out:
        argv += ["--out", str(Path(args.out) / "envelope")]
    chosen = parser("envelope").parse_args(argv)
    return chosen.func(chosen)

