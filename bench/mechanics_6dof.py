"""6-DoF chain: this suite's full symbolic check against deriving the equations with sympy.physics.mechanics.

Both routes run in fresh processes on the same machine. Ours (cold disk cache):
derive the UR5-like chain's generalized robotics equation with symbolic
Phi_l(t), Psi(t) by Euler-Lagrange, assemble the paper's form, build
Prop1's N and Prop2's regressors, and decide GRE, GRE-F, Prop1, Prop2 exactly.
The mechanics route: LagrangesMethod on the same DH chain with CONSTANT symbolic
inertial parameters (10 per body, no Psi): less than our model, so the ratio is
conservative. It is bounded by --timeout; if it does not finish, the ratio is a
lower bound. Results go to bench/results/mechanics_6dof.json; nothing is asserted.

    python bench/mechanics_6dof.py [--timeout 900] [--repeats 3]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

OURS = """
import time, sys
start = time.perf_counter()
from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.systems import SystemKey
from inertiaproof.symbolic.claims import CLAIMS
from inertiaproof.symbolic.evidence import run_claim
d = derivation(SystemKey.chain("6R"))
derived = time.perf_counter()
ok = all(run_claim(CLAIMS[c], d, controls=False).holds for c in ("GRE", "GRE-F", "Prop1", "Prop2"))
decided = time.perf_counter()
print(f"{derived - start} {decided - start} {ok}")
"""

MECHANICS = """
import time
start = time.perf_counter()
import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, Lagrangian, Point, ReferenceFrame, RigidBody, dynamicsymbols, inertia
HALF_PI = sp.pi / 2
R = sp.Rational
DH = ((0, HALF_PI, R('0.089159')), (R('-0.425'), 0, 0), (R('-0.39225'), 0, 0),  # robots.ur5: (a, alpha, d)
      (0, HALF_PI, R('0.10915')), (0, -HALF_PI, R('0.09465')), (0, 0, R('0.0823')))
q = dynamicsymbols('q1:7')
world = ReferenceFrame('N')
base = Point('O0')
base.set_vel(world, 0)
frame, origin, bodies = world, base, []
for l, (a, alpha, d) in enumerate(DH, 1):
    turned = frame.orientnew(f'A{l}', 'Axis', (q[l - 1], frame.z))
    body_frame = turned.orientnew(f'B{l}', 'Axis', (alpha, turned.x))
    joint = origin.locatenew(f'O{l}', d * frame.z + a * turned.x)
    joint.v2pt_theory(origin, world, turned)
    m, c1, c2, c3, i11, i22, i33, i12, i23, i13 = sp.symbols(
        f'm_{l} c1_{l} c2_{l} c3_{l} I11_{l} I22_{l} I33_{l} I12_{l} I23_{l} I13_{l}')
    com = joint.locatenew(f'C{l}', c1 * body_frame.x + c2 * body_frame.y + c3 * body_frame.z)
    com.v2pt_theory(joint, world, body_frame)
    body = RigidBody(f'body{l}', com, body_frame, m, (inertia(body_frame, i11, i22, i33, i12, i23, i13), com))
    body.potential_energy = m * R('9.81') * com.pos_from(base).dot(world.z)
    bodies.append(body)
    frame, origin = body_frame, joint
built = time.perf_counter()
method = LagrangesMethod(Lagrangian(world, *bodies), q)
equations = method.form_lagranges_equations()
done = time.perf_counter()
print(f"{built - start} {done - start} {sp.count_ops(equations[5])}")
"""


def fresh(code, timeout, env=None):
    """(seconds, stdout) of a fresh Python process, or (None, reason) if it did not finish in time."""
    start = time.perf_counter()
    try:
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                             env=dict(os.environ, **(env or {})))
    except subprocess.TimeoutExpired:
        return None, f"did not finish within {timeout} s"
    if out.returncode:
        return None, out.stderr.strip()[-400:]
    return time.perf_counter() - start, out.stdout.strip()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--timeout", type=float, default=900.0, help="bound on the mechanics route (s)")
    p.add_argument("--repeats", type=int, default=3, help="runs of our route (median reported)")
    p.add_argument("--out", default=str(Path(__file__).with_name("results") / "mechanics_6dof.json"))
    args = p.parse_args(argv)
    ours = []
    for i in range(args.repeats):
        with tempfile.TemporaryDirectory() as cache:
            seconds, text = fresh(OURS, args.timeout, {"INERTIAPROOF_CACHE": cache, "PYTHONHASHSEED": "0"})
        if seconds is None:
            raise SystemExit(f"our route failed: {text}")
        derived, decided, ok = text.split()
        ours.append({"process_s": seconds, "derive_s": float(derived), "derive_and_decide_s": float(decided),
                     "all_hold": ok == "True"})
        print(f"ours run {i + 1}: {seconds:.1f} s (derive {float(derived):.1f} s), all hold: {ok}", flush=True)
    ours_median = statistics.median(r["process_s"] for r in ours)
    print(f"mechanics route (bounded by {args.timeout:g} s) ...", flush=True)
    mech_s, mech_text = fresh(MECHANICS, args.timeout)
    if mech_s is None:
        ratio = {"value": args.timeout / ours_median, "kind": "lower bound",
                 "note": f"mechanics {mech_text}; ratio >= timeout / ours"}
    else:
        ratio = {"value": mech_s / ours_median, "kind": "ratio", "note": "mechanics seconds / our median seconds"}
    result = {
        "what": "6-DoF UR5-like chain (robots.ur5): our full symbolic check vs LagrangesMethod",
        "machine": {"python": platform.python_version(), "cores": os.cpu_count(), "note": "shared 2-core machine; "
                    "wall times of whole fresh processes, cold derivation cache"},
        "ours": {"runs": ours, "median_process_s": ours_median,
                 "scope": "derive EL + paper form + Prop1 N + Prop2 regressors, decide GRE, GRE-F, Prop1, Prop2 exactly"},
        "mechanics": {"process_s": mech_s, "output": mech_text,
                      "scope": "LagrangesMethod.form_lagranges_equations, constant symbolic inertial parameters"},
        "ratio_mechanics_over_ours": ratio,
        "recorded": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps(result["ratio_mechanics_over_ours"]))
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
