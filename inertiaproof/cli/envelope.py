"""``inertiaproof envelope ROBOT --link NAME --mass M [--radius R | --ellipsoid A B C] [--centre X Y Z] [--ramp T]``:
certified alpha1, alpha2 and chi for every consistent payload of mass at most M within R of a point of a link (or in
the ellipsoid with semi-axes A, B, C along the link's axes; Theorems 2-4 over the payload set:
:mod:`inertiaproof.bounds.payload`), the bracket of each true extreme, the worst payload found, the
constants against the payload's mass, and a Hypothesis attack of payloads drawn from the set.

ROBOT is a URDF, MJCF or xacro file (the link's body: the child of its movable joint with the links fixed to it;
the centre is given in the link's frame) or a scene (``*.toml``; ``--link`` names a body). With ``--out DIR``:
DIR/envelope.json (the result), DIR/envelope.csv (the curve), DIR/envelope.html and DIR/envelope.pdf (table and
figure) and DIR/certificates/, which ``inertiaproof verify DIR`` re-proves; the command re-proves them itself, as a
run does, unless ``--no-verify``: a certificate whose tree the prover could not complete within the profile's
``tree_boxes`` is not re-proved and leaves exit 3.

Exit status: 0 every constant certified (and re-proved) and no payload of the set beyond one; 1 a payload of the
set beyond a certified constant, or a certificate refuted; 2 bad usage or input; 3 something not certified or not
re-proved.
"""

from __future__ import annotations

import csv
import html
import json
import sys
from pathlib import Path

import numpy as np

from inertiaproof.errors import InputError
from inertiaproof.model.exact import written_fraction
from inertiaproof.suite.profiles import PROFILES

from .status import exit_status

__all__ = ["configure", "main", "payload_envelope", "robot_arm"]

CURVE_FIELDS = ("mass", "alpha1", "alpha2_attained", "alpha2_certified", "chi_certified")


def _decimal(text, name, least=None):
    """The exact number a decimal ``text`` writes (a plain decimal of moderate size: "1e999999999" would not fit in
    memory); ``least``: ">= 0" or "> 0"."""
    value = written_fraction(str(text))
    if value is None:
        raise InputError(f"{name}: {text!r} is not a number (a plain decimal: 3, 2.5, 1e-3)")
    if (least == ">= 0" and value < 0) or (least == "> 0" and value <= 0):
        raise InputError(f"{name}: must be {least}, got {text}")
    return value


def configure(parser):
    parser.add_argument("robot", metavar="ROBOT", help="a URDF, MJCF or xacro file, or a scene (*.toml)")
    parser.add_argument("--link", required=True, help="the link (a scene: the body's number) that carries the payload")
    parser.add_argument("--mass", required=True, help="the heaviest payload (kg, as written: 3 or 2.5)")
    shape = parser.add_mutually_exclusive_group()
    shape.add_argument("--radius", default="0.1", help="the payload lies within this distance (m) of the centre "
                       "(default %(default)s)")
    shape.add_argument("--ellipsoid", nargs=3, metavar=("A", "B", "C"),
                       help="the payload lies in the ellipsoid around the centre with these semi-axes (m) along the "
                       "link's x, y and z axes")
    parser.add_argument("--centre", nargs=3, default=("0", "0", "0"), metavar=("X", "Y", "Z"),
                        help="the centre in the link's frame (m; default its origin)")
    parser.add_argument("--ramp", default="1", help="the payload is taken up over this many seconds with the scenes' "
                        "smootherstep profile, peak rate 15/8 per ramp (default %(default)s)")
    parser.add_argument("--moving", metavar="V", help="the payload's particles move inside the set at speeds up to V "
                        "(m/s) relative to the link (a liquid, a sliding part): chi includes it, and Theorem 5's "
                        "bounds of H(q, Psi) are reported")
    parser.add_argument("--profile", choices=sorted(PROFILES), default="ci")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", metavar="DIR", help="write envelope.json, .csv, .html, .pdf and certificates/ there")
    parser.add_argument("--no-verify", action="store_true", help="do not re-prove the certificates")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")


def robot_arm(path, link):
    """(name, chain, theta, body index, pose of the link in the body's frame) of the serial chain of a robot file or
    scene that moves ``link``."""
    path = Path(path)
    if path.suffix.lower() == ".toml":
        from inertiaproof.scene.format import load_scene  # noqa: PLC0415 (a command imports what it reads)

        scene = load_scene(path)
        number = link.removeprefix("body ").strip()
        if not number.isdigit() or not 1 <= int(number) <= scene.chain.n:
            raise InputError(f"{path}: --link {link!r}: a scene's body is named by its number, 1 to {scene.chain.n}")
        return scene.name, scene.chain, scene.trajectory.base, int(number) - 1, np.eye(4)
    from inertiaproof.audit.document import read_robot  # noqa: PLC0415
    from inertiaproof.audit.kinematic_tree import kinematic_tree  # noqa: PLC0415

    tree = kinematic_tree(read_robot(path))
    if link not in tree.group_of:
        raise InputError(f"{path}: --link {link!r}: no such link")
    anchor = tree.group_of[link]
    for serial in tree.chains:
        anchors = [g.anchor for g in serial.bodies]
        if anchor in anchors:
            group = tree.groups[anchor]
            return serial.name, serial.chain, serial.theta, anchors.index(anchor), group.poses[group.links.index(link)]
    raise InputError(f"{path}: --link {link!r}: not moved by a revolute or prismatic joint (a fixed base)")


def _semi_axes_in_body(axes, turn, link):
    """The semi-axes along the body's axes of an ellipsoid with ``axes`` along the link's, whose frame is turned by
    ``turn`` (3, 3) against the body's: a ball, or a turn that maps axes onto axes."""
    if len(set(axes)) == 1:
        return tuple(axes)
    onto = np.abs(turn) > 1 - 1e-12
    if not (onto.sum(0) == 1).all() or not np.allclose(np.abs(turn), onto, atol=1e-12):
        raise InputError(f"--link {link!r}: its frame is turned against its body's by other than a quarter turn; "
                         "an --ellipsoid's axes would not be the body's (give a ball, --radius)")
    return tuple(axes[int(np.argmax(onto[i]))] for i in range(3))


def payload_envelope(robot, link, mass, *, radius="0.1", ellipsoid=None, centre=("0", "0", "0"), ramp="1",
                     moving=None, profile="ci", seed=0, progress=None):
    """The :class:`~inertiaproof.result.Result` of the payload envelope (the Python API of the command):
    ``ellipsoid`` (three semi-axes along the link's axes) in place of the ball of ``radius``; ``moving``: the
    particles' speed inside the set (m/s)."""
    from inertiaproof.bounds.payload import PayloadSet  # noqa: PLC0415
    from inertiaproof.checks.payload_envelope import envelope_result  # noqa: PLC0415

    mass, ramp = _decimal(mass, "--mass", "> 0"), _decimal(ramp, "--ramp", "> 0")
    if ellipsoid is None:
        axes = [_decimal(radius, "--radius", ">= 0")] * 3
    elif len(ellipsoid) != 3:
        raise InputError(f"--ellipsoid: three semi-axes, got {len(ellipsoid)}")
    else:
        axes = [_decimal(x, "--ellipsoid", ">= 0") for x in ellipsoid]
    centre = [_decimal(x, "--centre") for x in centre]
    speed = None if moving is None else _decimal(moving, "--moving", ">= 0")
    name, chain, theta, body, pose = robot_arm(robot, link)
    in_body = pose[:3, :3] @ np.array([float(x) for x in centre]) + pose[:3, 3]
    exact_centre = centre if np.allclose(pose, np.eye(4), atol=0) else tuple(map(float, in_body))
    pset = PayloadSet(body, mass, exact_centre, _semi_axes_in_body(axes, pose[:3, :3], link))
    chosen = PROFILES[profile]
    return envelope_result(f"{name} ({link})", chain, theta, pset, ramp_s=float(ramp), profile=chosen,
                           examples=chosen.envelope_examples, points=chosen.envelope_points, goal=chosen.envelope_goal,
                           speed=speed, seed_value=seed, progress=progress)


def _print(result, verified):
    ev = result.evidence
    print(f"inertiaproof envelope: {result.summary}")
    print(f"{'constant':<8} {'certified':>12}  {'paper (certified side)':>22}  true extreme in")
    for name, c in ev["constants"].items():
        lo, hi = (c["true_extreme"][side]["value"] for side in ("lower", "upper"))
        print(f"{name:<8} {c['certified']['value']:>12.6g}  {c['paper']['value']:>22.6g}  [{lo:.6g}, {hi:.6g}] "
              f"({hi / lo if lo > 0 else float('inf'):.3f}x)")
    worst = ev["worst_payload"]
    print(f"worst payload: a point mass of {worst['mass']:g} kg at {np.round(worst['com'], 5).tolist()} (body frame), "
          f"q = {np.round(worst['q'], 4).tolist()}")
    print("curve (kg: alpha2 certified, chi certified): " + "; ".join(
        f"{r['mass']:g}: {'-' if r['alpha2_certified'] is None else format(r['alpha2_certified'], '.6g')}, "
        f"{r['chi_certified']:.6g}" for r in ev["curve"]))
    if "theorem5" in ev:
        t5 = ev["theorem5"]
        print(f"Theorem 5 (particles at <= {t5['speed']['value']:g} m/s): Psi* <= {t5['psi_star']['value']:.6g}, "
              f"sigma_max(H(q, Psi)) <= {t5['sharp']['value']:.6g} (paper {t5['paper']['value']:.6g}; the prover's "
              "bounds of sup sigma_max(Y_p), not re-proved)")
    attack = ev["attack"]
    print(f"attack: {attack['examples']['value']} Hypothesis payloads of the set, smallest margin "
          f"{attack['smallest_margin']['value']:.3g}; beyond the set: {_beyond_text(ev['beyond_the_set'])}")
    if verified:
        print(f"certificates: {verified}")


def _beyond_text(beyond):
    if isinstance(beyond, str):
        return beyond
    return (f"a point mass of {beyond['mass']['value']:g} kg reaches lambda_max {beyond['lambda_max']['value']:.6g} > "
            f"alpha2 {beyond['alpha2']['value']:.6g}")


def _write(out, result):
    from inertiaproof.report import plots  # noqa: PLC0415
    from inertiaproof.report.model import Figure  # noqa: PLC0415

    out.mkdir(parents=True, exist_ok=True)
    (out / "envelope.json").write_text(json.dumps(result.to_json(), indent=1))
    with open(out / "envelope.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, CURVE_FIELDS)
        writer.writeheader()
        writer.writerows(result.evidence["curve"])
    (key, spec), = result.evidence["figures"].items()
    svgs = plots.render([Figure(key, 1, "series", spec["series"], key)], out / "envelope.pdf")
    rows = "".join(f"<tr><td>{html.escape(n)}</td><td>{c['certified']['value']:.6g}</td><td>{c['paper']['value']:.6g}"
                   f"</td><td>[{c['true_extreme']['lower']['value']:.6g}, {c['true_extreme']['upper']['value']:.6g}]"
                   "</td></tr>" for n, c in result.evidence["constants"].items())
    (out / "envelope.html").write_text(
        f"<!doctype html><meta charset=utf-8><title>payload envelope</title><h1>Payload envelope</h1>"
        f"<p>{html.escape(result.verdict.value)}: {html.escape(result.summary)}</p><table border=1><tr><th>constant"
        f"</th><th>certified</th><th>paper</th><th>true extreme in</th></tr>{rows}</table>{svgs[key]}")


def main(args):
    if args.seed < 0:
        raise InputError(f"--seed must be a nonnegative integer, got {args.seed}")
    from inertiaproof.suite.certificates import certificate_tally, settle  # noqa: PLC0415
    from inertiaproof.suite.execution import Executor  # noqa: PLC0415

    def say(message):
        print(message, file=sys.stderr)

    result = payload_envelope(args.robot, args.link, args.mass, radius=args.radius, ellipsoid=args.ellipsoid,
                              centre=args.centre, ramp=args.ramp, moving=args.moving, profile=args.profile,
                              seed=args.seed, progress=say)
    out = Path(args.out) if args.out else None
    executor = Executor()
    executor.say = say  # the re-proof's progress ("certificates: k/N tasks, ETA")
    result = settle(result, out_dir=out, boxes=PROFILES[args.profile].tree_boxes, verify=not args.no_verify, memo={},
                    executor=executor)
    if out is not None:
        _write(out, result)
    if args.json:
        print(json.dumps(result.to_json()))
    else:
        _print(result, certificate_tally([result])[1])
    return exit_status([result])

