"""Attacks on certificate format 2 and its checker (issue 47), each answered: a false claim is never re-proved, a
malformed certificate is a one-line bad certificate, a proof aid that falls short is "not re-proved" (the check
INCONCLUSIVE, never VIOLATED), and results.json is held to the certificates it cites.

The truth of each altered claim is judged with the prover's model of M(q) (which agrees with Pinocchio's CRBA,
tests/test_real_robots.py), not with the checker."""

from __future__ import annotations

import copy
import json
import shutil
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from inertiaproof.bounds.certificate import spectrum_certificate
from inertiaproof.bounds.completion import complete
from inertiaproof.citation import cite
from inertiaproof.dynamics import composite
from inertiaproof.dynamics.chain import Chain, origin
from inertiaproof.result import Result, Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.certificates import certificate_name, settle
from inertiaproof.verify import claims
from inertiaproof.verify.cli import check, results_problems, verify_file

REJECTED = ("not re-proved", "refuted", "bad certificate")


def _sup(chain, thetas, count=20000):
    """The largest lambda_max(M(q, Theta)) seen over random q and the parameter sets (a lower estimate of the sup)."""
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(1).random((count, chain.n))
    values = [np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], np.asarray(t)[None]))[..., -1].max()
              for t in thetas]
    return float(max(values))


@pytest.fixture(scope="module")
def arm():
    scene = robots.planar_2r()
    return scene.chain, scene.trajectory.theta(np.array([0.0]))[0][0]


@pytest.fixture(scope="module")
def run_out(tmp_path_factory):
    """A run's OUT folder: Thm3 on Panda and the planar 2R arm (alpha2 products, their ingredients)."""
    out = tmp_path_factory.mktemp("thm3")
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--only", "Thm3", "--out", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    return out


def _certs(out):
    return {p: json.loads(p.read_text()) for p in sorted((out / "certificates").glob("*.json"))}


def _verify(*args):
    return subprocess.run([sys.executable, "-m", "inertiaproof", "verify", *map(str, args)], capture_output=True,
                          text=True)


def test_a_non_finite_side_hides_no_parameter_set(arm):
    """The 2R arm's lambda_max claim with a second, consistent set whose body 2 (100/3 kg) has its centre on joint
    2's axis: an exact zero computed from inexact balls, whose square root was NaN. Neither the lengths nor the tree
    re-prove the first set's bound for both."""
    chain, theta = arm
    heavy, m = theta.copy(), 100 / 3  # body 2's frame sits at the tip, 0.8 m beyond joint 2: c = (-0.8, 0, 0)
    heavy[1] = [m, -0.8 * m, 0, 0, 0.01, 0.01 + 0.64 * m, 0.01 + 0.64 * m, 0, 0, 0]
    bound = 1.001 * _sup(chain, [theta])
    assert _sup(chain, [theta, heavy]) > 4 * bound  # the claim is false for the hull of both
    cert = spectrum_certificate(chain, np.stack([theta, heavy]), "lambda_max", bound)
    assert check(cert)["status"] in REJECTED
    assert check({**cert, "method": "lengths"})["status"] in REJECTED
    assert check(complete(cert, boxes=2000))["status"] in REJECTED


def test_a_transform_is_an_origin_the_checker_builds_rigid(arm):
    """A 4x4 matrix is no longer accepted, and an origin's rpy changed makes another rigid chain, whose own sup
    the checker does not certify below."""
    chain, theta = arm
    cert = spectrum_certificate(chain, theta[None], "lambda_max", 1.001 * _sup(chain, [theta]))
    assert check(complete(cert, boxes=2000))["status"] == "re-proved"
    matrix = copy.deepcopy(cert)
    matrix["chain"]["joints"][1]["before"] = [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"],
                                              ["0", "0", "0", "1"]]
    out = check(matrix)
    assert out["status"] == "bad certificate" and "before" in out["why"], out
    flipped = copy.deepcopy(cert)
    flipped["chain"]["joints"][0]["after"] = [{"xyz": ["1/2", "0", "0"], "rpy": ["3", "0", "0"]}]
    joints = list(chain.joints)
    joints[0] = type(joints[0])(joints[0].kind, joints[0].axis, joints[0].before, origin((0.5, 0, 0), (3.0, 0, 0)),
                                limits=joints[0].limits)
    truth = _sup(Chain(tuple(joints)), [theta])
    flipped["claim"]["bound"] = str(Fraction(0.95 * truth))
    assert check(complete(flipped, boxes=2000))["status"] in REJECTED


def test_json_is_read_strictly(arm, tmp_path):
    chain, theta = arm
    cert = spectrum_certificate(chain, theta[None], "lambda_max", 1.001 * _sup(chain, [theta]))
    text = json.dumps(cert)
    cases = {"duplicate": text[:-1] + ', "claim": ' + json.dumps({**cert["claim"], "bound": "1000"}) + "}",
             "nan": text.replace('"witness"', '"nan": NaN, "witness"', 1) if "witness" in text else text[:-1] + ', "x": NaN}',
             "float": text.replace(json.dumps(cert["claim"]["bound"]), "7.5", 1),
             "trailing": text + " {}"}
    for name, altered in cases.items():
        path = tmp_path / f"{name}.json"
        path.write_text(altered)
        out = verify_file(path)
        assert out["status"] == "bad certificate", (name, out)


def test_the_checker_writes_the_statement_and_reads_none(arm):
    chain, theta = arm
    bound = Fraction(1.001 * _sup(chain, [theta]))
    cert = complete(spectrum_certificate(chain, theta[None], "lambda_max", bound), boxes=2000)
    out = check(cert)
    written = out["claim"].rsplit("<= ", 1)[1]
    assert out["status"] == "re-proved" and Fraction(written) >= bound and Fraction(written) - bound < bound * 1e-9
    lying = {**cert, "claim": {**cert["claim"], "statement": f"lambda_max(M) <= {float(bound) / 10}"}}
    assert check(lying)["status"] == "bad certificate"


def test_a_product_may_not_cite_another_robots_ingredient(run_out):
    certs = _certs(run_out)
    products = [c for c in certs.values() if c["claim"]["kind"] == "product"]
    panda = next(c for c in products if c["ingredients"][1]["chain"]["name"] == "panda")
    planar = next(c for c in products if c["ingredients"][1]["chain"]["name"] != "panda")
    assert check(panda)["status"] == "re-proved"
    mixed = {**panda, "ingredients": [panda["ingredients"][0], planar["ingredients"][1]]}
    out = check(mixed)
    assert out["status"] == "bad certificate" and "chain" in out["why"], out
    short = {**panda, "ingredients": panda["ingredients"][:1]}
    assert check(short)["status"] == "bad certificate"
    other = {**panda, "claim": {**panda["claim"], "formula": "alpha2_z"}}
    assert check(other)["status"] == "bad certificate"  # alpha2_z bounds Z(Phi_l), not f(Phi_l)
    unknown = {**panda, "claim": {**panda["claim"], "formula": "anything"}}
    assert check(unknown)["status"] == "bad certificate"
    declared = {**panda, "claim": {**panda["claim"], "declared": "4"}}  # alpha2 has no r: none may be declared
    assert check(declared)["status"] == "bad certificate"


def test_a_proof_aid_that_falls_short_is_not_refuted_and_the_check_inconclusive(run_out):
    """alpha2's ingredient loosened (a true, weaker claim): the product's arithmetic no longer reaches its bound.
    Not re-proved, and the check INCONCLUSIVE, not VIOLATED."""
    product = next(c for c in _certs(run_out).values() if c["claim"]["kind"] == "product")
    loose = copy.deepcopy(product)
    loose["ingredients"][0]["claim"]["bound"] = str(2 * Fraction(loose["ingredients"][0]["claim"]["bound"]))
    assert check(loose["ingredients"][0])["status"] == "re-proved"
    out = check(loose)
    assert out["status"] == "not re-proved", out
    result = Result("Thm3", Verdict.HOLDS, "held", {"paper": {"value": 1.0, "kind": "upper_bound",
                                                              "certificate": cite(loose)}})
    result = settle(result, out_dir=None, boxes=0, verify=True, memo={})
    assert result.verdict == Verdict.INCONCLUSIVE and "not re-proved" in result.summary


def test_a_key_step_whose_choi_matrix_is_altered_is_not_refuted(run_out):
    step = next(c for c in _certs(run_out).values() if c["claim"]["kind"] == "key-step")
    altered = copy.deepcopy(step)
    altered["choi"][0][0] = str(Fraction(altered["choi"][0][0]) - 100)
    assert check(altered)["status"] == "not re-proved"


def test_a_bad_ridge_is_a_bad_certificate():
    scene = robots.spatial_3r()
    theta = scene.trajectory.theta(np.array([0.0]))[0]
    cert = spectrum_certificate(scene.chain, theta, "lambda_min", 0.01)
    for ridge in ("0", "-1", "1e400", "nan", 0.1):
        out = check({**cert, "metric": {"kind": "shift", "ridge": ridge}})
        assert out["status"] == "bad certificate" and "ridge" in out["why"], (ridge, out)


def test_a_refutation_shows_its_witness_and_both_sides(arm):
    chain, theta = arm
    sup = _sup(chain, [theta])
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(1).random((20000, chain.n))
    witness = q[np.argmax(np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], theta[None, None]))[..., -1])]
    out = check(spectrum_certificate(chain, theta[None], "lambda_max", 0.9 * sup, witness=witness))
    assert out["status"] == "refuted" and out["where"]["witness"]["q"] and set(out["where"]["sides"]) == {
        "pivot", "bound"}, out


@pytest.mark.slow
def test_verify_reads_results_json(run_out, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(run_out, out)
    done = _verify(out)
    assert done.returncode == 0 and " 0 problem(s)" in done.stderr, done.stderr[-2000:]
    results = json.loads((out / "results.json").read_text())
    evidence = results["checks"][0]["evidence"]
    number = next(n for n in _walk(evidence) if "certificate" in n and n.get("kind") in ("upper_bound",
                                                                                          "paper_constant"))
    cited = number["certificate"]["file"]
    number["value"] = number["value"] / 10  # an upper bound made 10x sharper than its certificate
    (out / "results.json").write_text(json.dumps(results))
    done = _verify(out)
    assert done.returncode == 2 and "not implied by the claim" in done.stderr, done.stderr[-2000:]
    number["value"] *= 10
    number["certificate"] = cited  # a citation that is no entry at all
    (out / "results.json").write_text(json.dumps(results))
    done = _verify(out)
    assert done.returncode == 2 and "not among the certificates" in done.stderr, done.stderr[-2000:]
    shutil.copy(run_out / "results.json", out / "results.json")
    (out / cited).unlink()
    done = _verify(out)
    assert done.returncode == 2 and "not among the certificates" in done.stderr, done.stderr[-2000:]


def _walk(node):
    if isinstance(node, dict):
        yield node
        for value in node.values():
            yield from _walk(value)
    elif isinstance(node, list):
        for value in node:
            yield from _walk(value)


def test_bad_options_are_usage_errors(run_out):
    assert _verify("--budget", "-1", run_out).returncode == 2


def test_verify_imports_nothing_of_the_prover(run_out):
    """``inertiaproof verify`` runs in a process with the standard library, flint and inertiaproof.verify alone
    (inertiaproof and inertiaproof.cli, the command's entry point, import nothing themselves)."""
    code = ("import sys; before = set(sys.modules); from inertiaproof.cli import main; rc = main(['verify', "
            "sys.argv[1]]); print('MODULES', sorted(m for m in set(sys.modules) - before "
            "if m.split('.')[0] not in sys.stdlib_module_names))")
    done = subprocess.run([sys.executable, "-c", code, str(run_out / "certificates")], capture_output=True, text=True)
    modules = eval(done.stdout.split("MODULES", 1)[1])  # noqa: S307 - our own print of a list of names
    flint = ("flint", "cython_runtime", "_cython")  # flint and the Cython runtime its extensions load
    assert all(m.startswith(flint) or m in ("inertiaproof", "inertiaproof.cli") or m.startswith("inertiaproof.verify")
               for m in modules), modules
    assert "numpy" not in modules


def test_a_certificate_is_named_by_its_content(arm, tmp_path):
    chain, theta = arm
    cert = spectrum_certificate(chain, theta[None], "lambda_max", 1.001 * _sup(chain, [theta]))
    name, text = certificate_name(cert)
    (tmp_path / name).write_text(text.replace('"lambda_max"', '"lambda_min"'))
    assert verify_file(tmp_path / name)["status"] == "bad certificate"


def test_a_parameter_hull_is_formed_by_the_checker(run_out):
    """Theta(t)'s vertices come with how they were formed (base rows, each load's range and rate): a vertex dropped,
    or a load's range narrowed, is a bad certificate, and the statement names the formation."""
    cert = next(c for c in _certs(run_out).values() if "formation" in c and len(c["parameters"]) > 1)
    out = check(cert)
    assert out["status"] == "re-proved" and "formed from its base and loads (payload on body" in out["claim"], out
    dropped = {**cert, "parameters": cert["parameters"][:-1]}
    assert check(dropped)["status"] == "bad certificate"
    narrowed = copy.deepcopy(cert)
    narrowed["formation"]["loads"][0]["range"][1] = "1/2"
    assert check(narrowed)["status"] == "bad certificate"
    unformed = {k: v for k, v in dropped.items() if k != "formation"}
    assert "as listed" in check(unformed)["claim"]  # what it then claims is only the listed hull, and says so


def test_a_certificate_is_about_its_source_file_as_written(tmp_path):
    """A URDF's chain carries the file's path and SHA-256 and its decimals; the file changed under it is a bad
    certificate, and so is a domain that does not cover a joint's limits as written."""
    from inertiaproof.audit.kinematic_tree import kinematic_tree
    from inertiaproof.audit.urdf import read_urdf

    urdf = tmp_path / "arm.urdf"
    urdf.write_text("""<robot name="arm">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.2 0 0"/><mass value="2"/>
    <inertia ixx="0.01" iyy="0.03" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="fore"><inertial><origin xyz="0.15 0 0"/><mass value="1"/>
    <inertia ixx="0.005" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0.4 0 0" rpy="0.1 0 0"/><axis xyz="0 0 1"/><limit lower="-2.1" upper="2.1" effort="1" velocity="1"/></joint>
</robot>""")
    arm = kinematic_tree(read_urdf(urdf)).chains[0]
    cert = complete(spectrum_certificate(arm.chain, arm.theta[None], "lambda_min", 1e-4), boxes=2000)
    joint = cert["chain"]["joints"][1]
    assert joint["before"] == [{"xyz": ["0.4", "0", "0"], "rpy": ["0.1", "0", "0"]}] and joint["limits"] == ["-2.1", "2.1"]
    assert cert["chain"]["source"]["path"] == str(urdf)
    out = check(cert)
    assert out["status"] == "re-proved" and str(urdf) in out["claim"], out
    narrow = copy.deepcopy(cert)
    narrow["domain"][1][1] = "2"
    assert check(narrow)["status"] == "bad certificate"
    urdf.write_text(urdf.read_text().replace('upper="2.1"', 'upper="3.1"'))
    claims.PROVED.clear()  # a checker's process proves a certificate once; this one saw the file before
    out = check(cert)
    assert out["status"] == "bad certificate" and "SHA-256" in out["why"], out


def test_results_json_reads_a_claims_side_from_its_kind_not_a_stray_relation(tmp_path):
    """A lambda_max claim given a stray ``relation`` ">=" is still an upper claim: a lower bound in results.json
    citing it is a problem; so is a citation whose file is not a name (a list): reported, not a crash."""
    cert = json.loads((Path(__file__).parent / "golden" / "mass-matrix-spectrum-lambda_max.reproved.json").read_text())
    cert["claim"]["relation"] = ">="
    name, text = certificate_name(cert)
    (tmp_path / "certificates").mkdir()
    (tmp_path / "certificates" / name).write_text(text)
    row = verify_file(tmp_path / "certificates" / name)
    assert row["status"] == "re-proved", row
    entry = {"file": f"certificates/{name}", "claim": row["claim"]}
    number = {"kind": "lower_bound", "value": float(Fraction(cert["claim"]["bound"])) / 2, "certificate": entry}
    rows = {f"certificates/{name}": row}
    (tmp_path / "results.json").write_text(json.dumps({"checks": [{"id": "X", "evidence": {"n": number}}]}))
    problems, count = results_problems(tmp_path, rows)
    assert count == 1 and problems == ["X/n: a lower_bound cites a <= claim"], problems
    number["certificate"] = {"file": [entry["file"]], "claim": row["claim"]}
    (tmp_path / "results.json").write_text(json.dumps({"checks": [{"id": "X", "evidence": {"n": number}}]}))
    problems, _ = results_problems(tmp_path, rows)
    assert len(problems) == 1 and "not among the certificates" in problems[0], problems
