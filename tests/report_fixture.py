"""A synthetic but realistic results folder for the report tests.

Every catalog ID, all three verdicts, a VIOLATED result with a saved
counterexample whose strings are hostile to HTML and LaTeX, a crashed check,
every evidence convention of inertiaproof.result (bracket, constants, hunt,
series) and both data files (work precision, stability), the gate, a left-out
check, long check names and long numbers.

``python tests/report_fixture.py DIR`` writes it to DIR for a look by hand.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from inertiaproof.result import Result, Verdict, quantity

HOSTILE = ("</pre></code><script>alert(\"x\")</script> a<b && c>d 'single' \"double\" C:\\path\\to \\end{document} "
           "$x^2$ 100% a_b #1 {brace} ^caret ~tilde `tick` -- --- lambda=λ")
ASCII = "".join(map(chr, range(32, 127)))
LONG_CHECK = "Asm3/Thm5:scene:ur5-with-a-sliding-trolley-and-a-passenger-on-the-forearm-moving-at-2m-per-s"
LONG_EXACT = "340282366920938463463374607431768211457/18446744073709551616000000000000000001"
VIOLATED_FILE = "counterexamples/found/Thm4-3f9c2a1b7e.json"


def _bracket(name, limit, rate, unit=None):
    points = []
    for k in range(8):
        seconds = 0.01 * 2.0 ** k
        width = 0.9 * limit * 10.0 ** (-rate * k)
        lo, up = limit - 0.7 * width, limit + 0.3 * width
        points.append([seconds, lo, up])
    return {"quantity": name,
            "lower": quantity(lo, "lower_bound", "interval bound over all q (branch and bound)", unit),
            "upper": quantity(up, "sampled", "smallest value seen in samples: an upper estimate of the inf", unit),
            "convergence": points}


def _constants(paper, certified, observed, unit=None):
    return {"paper": quantity(paper, "paper_constant", unit=unit),
            "certified": quantity(certified, "certified_constant", "SDP certificate", unit),
            "observed": quantity(observed, "sampled", "worst case over 2000 samples", unit)}


def _hunt(margins, unit=None):
    margins = [float(m) for m in margins]
    return {"examples": quantity(len(margins), "count", "Hypothesis examples"),
            "smallest_margin": quantity(min(margins), "margin", unit=unit),
            "margins": margins}


def _results(rng):
    R = []

    def add(check_id, verdict, summary, evidence, check=None, runtime=0.05, **kw):
        r = Result(check_id, Verdict(verdict), summary, evidence, runtime_s=runtime, seed=0, profile="ci",
                   check=check or check_id, **kw)
        R.append(r)
        return r

    solids = ["box", "ellipsoid", "cylinder", "cone", "tetrahedron", "union box+cone", "mixture 0.3/0.7"]
    add("EQ-moments", "HOLDS", "exact moments of 7 solids agree with 3-D Gauss quadrature to 4e-15", {
        "solids": [{"solid": s, "mass_residual": quantity(float(rng.uniform(0, 4e-15)), "residual"),
                    "inertia_residual": quantity(float(rng.uniform(0, 4e-15)), "residual", unit="kg m^2"),
                    "quadrature_points": 4096} for s in solids],
        "method": "closed-form moments (SymPy integrate) against tensor Gauss-Legendre quadrature"})
    add("EQ-geom", "HOLDS", "S(x)^T S(x) = tr(x x^T) I3 - x x^T: lhs - rhs expands to 0 exactly", {
        "method": "expand lhs - rhs to a canonical polynomial; exact (no sampling, no floats)",
        "entries": quantity(9, "count", "matrix entries compared"),
        "nonzero_entries": quantity(0, "exact", "entries of lhs - rhs that do not vanish")})
    add("EQ-inverse", "HOLDS", "I = tr(Sigma) I3 - Sigma inverts f; the 10x10 matrix of f has rank 10", {
        "rank": quantity(10, "exact", "rank of the matrix of f: R^10 -> sym(4)"),
        "determinant": quantity(LONG_EXACT, "exact", "a long exact rational, printed whole")})
    add("EQ-schur", "HOLDS", "Schur complement identity holds symbolically", {
        "nonzero_entries": quantity(0, "exact")}, check="EQ-schur:symbolic", runtime=1.2)
    add("EQ-schur", "HOLDS", "f > 0 and the Schur test agree on 60 random Phi, 12 near the boundary", {
        "hunt": _hunt(np.abs(rng.normal(0.5, 0.4, 60)) + 1e-3),
        "disagreements": quantity(0, "count")}, check="EQ-schur:numeric")
    add("EQ-translation", "HOLDS", "Sigma_CoM = tr(I_CoM)/2 I3 - I_CoM exactly",
        {"nonzero_entries": quantity(0, "exact")})
    add("EQ-triangle", "INCONCLUSIVE", "boundary case: margin 3.1e-17 is below the resolution 2.2e-16", {
        "margin": quantity(3.1e-17, "margin", "smallest strict-triangle slack over the hunt", "kg m^2"),
        "tolerance": quantity(2.2e-16, "tolerance", "eps * ||I_CoM||"),
        "boundary_cases": ["thin rod", "flat disc", "point mass"]})
    add("Def1/Thm1-suff", "HOLDS", "300 random densities with a 3-D carrier all give f(Phi) > 0", {
        "hunt": _hunt(10.0 ** rng.uniform(-6, 1, 300)),
        "error_probability": quantity(1e-12, "error_probability",
                                      "Schwartz-Zippel: probability the randomised identity test passed "
                                      "although false")},
        runtime=2.4)
    add("Thm1-nec", "HOLDS", "uniform solid ellipsoids reproduce 60 random Phi with f > 0", {
        "moment_residual": quantity(2.7e-15, "residual", "max |Phi(ellipsoid) - Phi|", "kg m^2"),
        "examples": quantity(60, "count")})
    add("Thm1-boundary", "HOLDS", "point, line and planar masses give lambda_min(f) = 0 exactly", {
        "examples": {"point mass": {"lambda_min": quantity(0, "exact"), "triangle_equalities": 3},
                     "line mass": {"lambda_min": quantity(0, "exact"), "triangle_equalities": 1},
                     "planar mass": {"lambda_min": quantity(0, "exact"), "triangle_equalities": 1}}})
    add("Rem2", "HOLDS", "strict triangle inequalities hold on all 300 hunt examples", {
        "hunt": _hunt(rng.uniform(0.02, 0.9, 300))})
    add("GRE", "HOLDS", "Lagrange's equations re-derived for generic n = 1..3", {
        "series": {"title": "symbolic derivation time", "x_label": "degrees of freedom n", "y_label": "time [s]",
                   "x_log": False, "y_log": True,
                   "lines": {"abstract chain": [[1, 0.21], [2, 1.9], [3, 24.0]]}},
        "largest_n": quantity(3, "count")}, check="GRE:abstract", runtime=26.1)
    add("GRE", "HOLDS", "2R and 3R chains: both sides expand to the same polynomials", {
        "chains": ["2R", "3R"], "nonzero_entries": quantity(0, "exact")}, check="GRE:concrete", runtime=3.3)
    add("GRE-F", "HOLDS", "F(q, Theta, Thetadot) = M(q, Thetadot) symbolically",
        {"nonzero_entries": quantity(0, "exact")})
    add("GRE-physics", "HOLDS", "the GRE matches a multibody model with a prescribed moving mass to 3e-9", {
        "max_deviation": quantity(3.2e-9, "residual", "max |qdd(GRE) - qdd(multibody)| over the trajectory", "rad/s^2"),
        "tolerance": quantity(1e-7, "tolerance")},
        artifacts=["data/work_precision.json", "data/stability.json"], runtime=7.9)
    add("Prop1", "HOLDS", "skew-symmetry holds symbolically for n = 1..3", {"nonzero_entries": quantity(0, "exact")},
        check="Prop1:symbolic")
    add("Prop1", "HOLDS", "skew-symmetry holds at 2000 random states of 4 chains", {
        "residual": quantity(4.4e-16, "residual", "max |A + A^T| / |A|"),
        "error_probability": quantity(2.0 ** -60, "error_probability", "randomised identity test at 60 points")},
        check="Prop1:numeric")
    add("Prop2", "HOLDS", "regressors reproduce M a + C v + G and M(q, Thetadot) v", {
        "residual": quantity(8.9e-16, "residual"), "regressor_shape": [7, 10]})
    add("Def2", "HOLDS", "QJ of the 7-DoF arm is normal: inf lambda_min((QJ)^T QJ) in [0.0412, 0.0413]", {
        "bracket": _bracket("inf_q lambda_min((QJ)^T QJ)", 0.04123, 0.45)})
    add("CX-normal", "HOLDS", "Phi_l = (1, 0, I3) gives M = (QJ)^T QJ; inf lambda_min(M) = 0 at q2 = 0", {
        "residual": quantity(0, "exact", "M - (QJ)^T QJ"),
        "lambda_min_at_singularity": quantity(0, "exact")})
    add("CX-sphere", "HOLDS", "consistent at all t, yet lambda_min(M) -> 0 as m(t) -> 0", {
        "series": {"title": "mass matrix of a shrinking sphere", "x_label": "t [s]", "y_label": "lambda_min(M) [kg]",
                   "x_log": False, "y_log": True,
                   "lines": {"lambda_min(M)": [[t, float(np.exp(-t))] for t in range(0, 30, 2)],
                             "m(t)": [[t, float(2 * np.exp(-t))] for t in range(0, 30, 2)]}}})
    add("Def3", "HOLDS", "uniform consistency computed for 5 parameter trajectories", {
        "trajectories": [{"name": n, "inf_lambda_min_f": quantity(v, "lower_bound")}
                         for n, v in [("constant", 0.12), ("linear mass gain", 0.08), ("exp decay", 0.0031),
                                      ("payload pick-up", 0.05), ("sinusoid", 0.11)]]})
    add("Thm2", "HOLDS", "alpha1 = 0.0034 <= inf lambda_min(M) = 0.0051 on the 7-DoF arm", {
        "bracket": _bracket("inf_q lambda_min(M)", 0.0051, 0.3, "kg m^2"),
        "constants": _constants(0.0034, 0.0047, 0.0051, "kg m^2"),
        "key_step": {"certificate": "SDP dual, 4x4", "certificate_size": quantity(10, "count", "free variables"),
                     "residual": quantity(1.1e-12, "residual")}}, runtime=1.4)
    add("Lem1", "HOLDS", "both directions exercised on a normal and a non-normal chain", {
        "normal": quantity(0.21, "lower_bound"), "non_normal": quantity(0, "exact")})
    add("Asm2/Lem2", "HOLDS", "prismatic chain: sup sigma_max(QJ) and sup lambda_max(M) grow together", {
        "series": {"title": "prismatic chain", "x_label": "joint range [m]", "y_label": "sup lambda_max(M)",
                   "x_log": True, "y_log": True,
                   "lines": {"lambda_max(M)": [[10.0 ** k, 10.0 ** (2 * k)] for k in range(6)]}}})
    add("Thm3", "HOLDS", "alpha2 = 214 >= sup lambda_max(M) = 61.3", {
        "bracket": _bracket("sup_q lambda_max(M)", 61.3, 0.5, "kg m^2"),
        "constants": _constants(214.0, 122.6, 61.3, "kg m^2")})
    add("Cor1", "HOLDS", "alpha1 I <= M <= alpha2 I on all 4 chains", {"chains": quantity(4, "count")})
    crash = ("Traceback (most recent call last):\n  File \"checks/bounds.py\", line 88, in cor2\n"
             "    ratio = upper / lower\nZeroDivisionError: float division by zero\n")
    add("Cor2", "INCONCLUSIVE", "the check crashed: ZeroDivisionError: float division by zero",
        {"traceback": crash, "crashed": True})
    add("Thm4", "VIOLATED", "sigma_max(M(q, Thetadot)) = 412.7 exceeds chi = 389.2 at q = (0.3, -1.2, 2.9)", {
        "constants": _constants(389.2, 455.0, 412.7),
        "margin": quantity(-23.5, "margin", "chi - sigma_max(M(q, Thetadot))"),
        "tolerance": quantity(1e-9, "tolerance"),
        "note": HOSTILE,
        "every_ascii_character": ASCII},
        counterexample={"kind": "bound", "file": VIOLATED_FILE,
                        "data": {"id": "Thm4", "q": [0.3, -1.2, 2.9], "t": 1.75, "chain": "3R <planar> & \"friends\"",
                                 "comment": HOSTILE, "ascii": ASCII}})
    add("EQ-acc", "HOLDS", "||J^T Q^T Psidot|| <= dPsi* sup sigma_max(QJ) with ratio 0.62", {
        "constants": _constants(3.1, 2.4, 1.93, "N m")})
    add("Asm3/Thm5", "HOLDS", "sigma_max(H) <= sqrt(6N) Psi* max_p ... with ratio 0.18", {
        "constants": _constants(74.2, 31.0, 13.4), "long_number": quantity(1.2345678901234567e-300, "estimate")},
        check=LONG_CHECK)
    add("gate", "HOLDS", "6 derivations fingerprinted; none changed since the lockfile", {
        "lockfile": "symbolic/derivations.lock.json",
        "derivations": [{"name": n, "fingerprint": f"sha256:{h}", "locked": f"sha256:{h}", "changed": False}
                        for n, h in [("mass_matrix_2R", "9f2c41d0a7b3e6c5"), ("mass_matrix_3R", "07aa5e19c2d84b3f"),
                                     ("coriolis_2R", "c3d1e0f9a8b7c6d5"), ("gre_abstract_n3", "11e2d3c4b5a69788"),
                                     ("regressor_2R", "5a4b3c2d1e0f9a8b"), ("skew_H_2R", "e0d1c2b3a4958677")]],
        "changed": quantity(0, "count")})
    return R


def _work_precision():
    rows = []
    for scene, scale in (("trolley-2R", 1.0), ("payload-7R", 3.0)):
        methods = (("RK45", 5, 1.0), ("DOP853", 8, 1.6), ("Radau", 5, 6.0), ("GRE-symplectic", 2, 0.4))
        for method, order, cost in methods:
            for k, rtol in enumerate([1e-3, 1e-5, 1e-7, 1e-9, 1e-11]):
                seconds = cost * scale * 0.002 * (1e-3 / rtol) ** (1.0 / order)
                rows.append({"scene": scene, "method": method, "rtol": rtol, "seconds": round(seconds, 6),
                             "error": rtol * 3.0 * scale})
    return {"rows": rows}


def _stability():
    rows = []
    for scene in ("stiff-spring-2R", "mass-ratio-1e6", "vanishing-mass", "fast-trolley"):
        for method in ("RK45", "Radau", "LSODA"):
            failed = method == "RK45" and scene in ("stiff-spring-2R", "mass-ratio-1e6")
            rows.append({"scene": scene, "method": method, "status": "step size too small" if failed else "ok",
                         "seconds": 12.0 if failed else 0.05 * (3 if method == "Radau" else 1),
                         "steps": 250000 if failed else 1200, "note": "h < 1e-14 at t = 0.31" if failed else ""})
    return rows


def document():
    rng = np.random.default_rng(20240601)
    results = _results(rng)
    summary = {v.value: sum(r.verdict == v for r in results) for v in Verdict}
    return {
        "schema": "inertiaproof.results/1",
        "profile": "ci",
        "seed": 0,
        "scene": None,
        "runtime_s": 47.31,
        "versions": {"python": "3.11.7", "inertiaproof": "0.1.0", "numpy": "2.4.6", "scipy": "1.18.0",
                     "sympy": "1.14.0", "cvxpy": "1.9.3", "clarabel": "0.11.1", "hypothesis": "6.170.0"},
        "summary": summary,
        "checks": [r.to_json() for r in results],
        "skipped": [{"check": "Thm4:scene", "reason": "needs time-varying parameters (the scene's are constant)"}],
    }


def write(out_dir):
    """Write results.json and its data files into out_dir; returns out_dir."""
    out = Path(out_dir)
    (out / "data").mkdir(parents=True, exist_ok=True)
    (out / "results.json").write_text(json.dumps(document(), indent=1, allow_nan=False))
    (out / "data" / "work_precision.json").write_text(json.dumps(_work_precision(), indent=1, sort_keys=True))
    (out / "data" / "stability.json").write_text(json.dumps(_stability(), indent=1, sort_keys=True))
    return out


if __name__ == "__main__":
    print(write(sys.argv[1] if len(sys.argv) > 1 else "out/fixture"))


_BUILT = {}


def built(tmp_path_factory):
    """The fixture's report, built once per session (with report.pdf when latexmk is installed): (folder, seconds)."""
    if "full" not in _BUILT:
        from inertiaproof.report.cli import build

        out = write(tmp_path_factory.mktemp("report-full"))
        start = time.perf_counter()
        build(out)
        _BUILT["full"] = (out, time.perf_counter() - start)
    return _BUILT["full"]


def artifacts_dir():
    """Where the report tests keep what a person may want to look at ($INERTIAPROOF_ARTIFACTS or artifacts/report)."""
    root = os.environ.get("INERTIAPROOF_ARTIFACTS") or Path(__file__).resolve().parents[1] / "artifacts"
    path = Path(root) / "report"
    path.mkdir(parents=True, exist_ok=True)
    return path
