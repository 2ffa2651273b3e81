"""Writes the golden certificates of format 2 beside this file from a run's OUT folder: for each kind of claim,
the smallest certificate the run wrote (``*.reproved.json``), an altered copy whose claim is false at its witness
(``*.refuted.json``) or whose proof no longer goes through (``*.unproved.json``), and a malformed one
(``*.bad.json``). Run it only when the format changes: ``python tests/golden/make_golden.py OUT``."""

import json
import sys
from fractions import Fraction
from pathlib import Path

HERE = Path(__file__).parent


def key(cert):
    claim = cert["claim"]
    return f"{claim['kind']}-{claim.get('quantity') or {'>=': 'lower', '<=': 'upper'}.get(claim.get('relation'), 'map')}"


def scaled(cert, factor):
    out = json.loads(json.dumps(cert))
    bound = Fraction(out["claim"]["bound"])
    out["claim"]["bound"] = str(bound * Fraction(factor) if bound else Fraction(1000))
    return out


def main(out):
    found = {}
    for path in sorted(Path(out, "certificates").glob("*.json")):
        cert = json.loads(path.read_text())
        k = key(cert)
        if ("witness" in cert or k.split("-")[0] not in ("mass-matrix", "skew", "payload")) and (
                k not in found or len(path.read_text()) < len(json.dumps(found[k]))):
            found[k] = cert
    for k, cert in found.items():
        write(k, "reproved", cert)
        kind, quantity = cert["claim"]["kind"], k.split("-")[-1]
        if kind == "key-step":
            write(k, "refuted", {**cert, "claim": {**cert["claim"], "upper": "1"}})
        elif kind in ("mass-matrix-spectrum", "body-spectrum", "skew-partials") or k == "payload-envelope-lambda_min":
            write(k, "refuted", scaled(cert, 2 if "min" in quantity else Fraction(1, 2)))
        else:
            write(k, "unproved", scaled(cert, 2 if cert["claim"].get("relation") == ">=" or "min" in quantity
                                        else Fraction(1, 2)))
        write(k, "bad", {**cert, "claim": {**cert["claim"], "statement": "a statement the checker never reads"}})
    upper = [c for c in found.values() if c["claim"].get("relation") == "<="]
    total = sum(Fraction(c["claim"]["bound"]) for c in upper[:2])
    write("sum-upper", "reproved", {"schema": "inertiaproof.certificate/2", "claim": {
        "kind": "sum", "relation": "<=", "bound": str(total)}, "terms": upper[:2]})


def write(name, expect, cert):
    (HERE / f"{name}.{expect}.json").write_text(json.dumps(cert, sort_keys=True) + "\n")


def identify():
    """The ``residual-bound`` goldens (issue 50), from consistent fits of the spatial 3R arm's torques (a consistent
    truth; one whose body 3 has a negative mass): ``python tests/golden/make_golden.py --identify``."""
    import numpy as np

    from inertiaproof.dynamics import motion, regressors
    from inertiaproof.identify.consistent import consistent_fit
    from inertiaproof.identify.problem import NormalEquations
    from inertiaproof.scene import robots

    scene = robots.spatial_3r()
    rng = np.random.default_rng(0)
    q, qd, qdd = rng.uniform(-np.pi, np.pi, (60, 3)), rng.normal(0, 1.5, (60, 3)), rng.normal(0, 3, (60, 3))
    kin = motion.kinematics(scene.chain, q)
    a = np.moveaxis(regressors.regressor(kin.qj, kin.dqj, kin.rotations, scene.chain.gravity, qd, qd, qdd), 2, 1)
    a = a.reshape(180, 30)
    base = np.asarray(scene.trajectory.base, float)
    for name, mass in (("lower", base[2, 0]), ("excess", -1.0)):
        truth = base.copy()
        truth[2, 0] = mass
        ne = NormalEquations.of_rows(a, a @ truth.ravel() + rng.normal(0, 0.05, 180), ("link1", "link2", "link3"))
        fit = consistent_fit(ne, trace_bounds=[50.0] * 3)
        cert = next(c for c in fit.certificates if c["claim"].get("quantity") == name)
        write(f"residual-bound-{name}", "reproved", cert)
        if name == "lower":
            write("residual-bound-lower", "refuted", {**cert, "claim": {**cert["claim"], "bound": str(
                Fraction(fit.residual) * 2)}, "dual": {**cert["dual"], "theta": [str(Fraction(x)) for x in fit.theta]}})
        else:
            write("residual-bound-excess", "refuted", scaled(cert, 10**6))
        zero = [[["0"] * 4] * 4] * 3  # no dual: the Lagrangian bound falls far below, no point refutes the claim
        write(f"residual-bound-{name}", "unproved", {**cert, "dual": {**cert["dual"], "Z": zero}})
        write(f"residual-bound-{name}", "bad", {**cert, "claim": {**cert["claim"], "statement": "better than L"}})


if __name__ == "__main__":
    identify() if sys.argv[1] == "--identify" else main(sys.argv[1])
