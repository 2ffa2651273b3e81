"""One channel for certificates (issue 49): a certificate is a value (content, text and hash made once); evidence cites
it by hash; Result carries the certificates it cites as a list beside its evidence; settle returns a new Result
and leaves the evidence alone; in results.json every cited certificate is among the check's certificates and every
one of those is cited, and every certified number cites one."""

import copy
import hashlib
import json
import pickle
import subprocess
import sys
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds.certificate import spectrum_certificate
from inertiaproof.bounds.completion import complete
from inertiaproof.citation import Certificate, Citation, Settled, cite
from inertiaproof.dynamics import composite
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.scene import robots
from inertiaproof.suite.certificates import _chunks, settle

CERTIFIED = "certified_constant"


def channel_problems(doc):
    """Every way a results.json document breaks the channel: a citation of a hash that is not among its check's
    certificates, a certificate of the check that nothing in its evidence cites, a citation whose file is not its
    certificate's, a certified number that cites nothing."""
    problems = []
    for check in doc["checks"]:
        records = {c["hash"]: c for c in check.get("certificates") or []}
        cited = set()
        stack = [(check["id"], check["evidence"])]
        while stack:
            path, node = stack.pop()
            if isinstance(node, dict):
                entry = node.get("certificate")
                if isinstance(entry, dict) and "hash" in entry:
                    cited.add(entry["hash"])
                    if entry["hash"] not in records:
                        problems.append(f"{path}: cites {entry['hash']}, not among the check's certificates")
                    elif entry.get("file") != records[entry["hash"]].get("file"):
                        problems.append(f"{path}: cites {entry.get('file')}, its certificate is in "
                                        f"{records[entry['hash']].get('file')}")
                elif node.get("kind") == CERTIFIED and "value" in node:
                    problems.append(f"{path}: a certified number that cites no certificate")
                stack.extend((f"{path}/{k}", v) for k, v in node.items() if k != "certificate")
            elif isinstance(node, list):
                stack.extend((f"{path}[{i}]", v) for i, v in enumerate(node))
        problems += [f"{check['id']}: carries {h}, which nothing cites" for h in sorted(set(records) - cited)]
    return problems


def _planar():
    scene = robots.planar_2r()
    chain, theta = scene.chain, scene.trajectory.theta(np.array([0.0]))[0]
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(0).random((4000, chain.n))
    values = np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], theta[None]))[..., 0].min(-1)
    inf = float(values.min())
    cert = complete(spectrum_certificate(chain, theta, "lambda_min", 0.9 * inf, witness=q[np.argmin(values)]),
                    boxes=20000)
    return cert, inf


@pytest.fixture(scope="module")
def planar():
    return _planar()


def test_a_certificate_is_a_value_with_its_hash_made_once():
    content = {"schema": "inertiaproof.certificate/2", "claim": {"kind": "product", "bound": "4"},
               "ingredients": [Certificate({"claim": {"kind": "x", "bound": "2"}})]}
    cert = Certificate(content)
    text = json.dumps({**content, "ingredients": [{"claim": {"kind": "x", "bound": "2"}}]}, sort_keys=True)
    assert cert.text == text and cert.hash == hashlib.sha256(text.encode()).hexdigest()[:16]
    assert cert.name == f"{cert.hash}.json" and Certificate.of(cert) is cert and Certificate.of(None) is None
    assert type(cert["ingredients"][0]) is dict  # a certificate inside another is its content
    with pytest.raises(TypeError):
        cert["claim"] = {}
    with pytest.raises(TypeError):
        cert.hash = "0" * 16
    altered = copy.deepcopy(cert)  # a copy to alter is plain data
    altered["claim"]["bound"] = "5"
    assert type(altered) is dict and cert["claim"]["bound"] == "4"
    assert pickle.loads(pickle.dumps(cert)).hash == cert.hash


def test_a_result_carries_what_its_evidence_cites_and_nothing_of_a_certificates_shape():
    a = Certificate({"schema": "inertiaproof.certificate/2", "claim": {"kind": "x", "bound": "4"}})
    b = {"schema": "inertiaproof.certificate/2", "claim": {"kind": "y", "bound": "1"}}
    evidence = {"side": quantity(2.0, "upper_bound", certificate=a), "again": [quantity(4.0, "upper_bound",
                                                                                       certificate=a)],
                "other": quantity(1.0, "certified_constant", certificate=b),
                "copied": {"value": 1.0, "certificate": cite(cite(b), 1.0)},
                "shaped_like_one": {"value": 3.0, "certificate": dict(a)}}  # not a citation: not a certificate
    result = Result("X", Verdict.HOLDS, "held", evidence)
    assert [c.hash for c in result.certificates] == [a.hash, Certificate(b).hash]
    side = evidence["side"]["certificate"]
    assert isinstance(side, Citation) and side == {"hash": a.hash, "as": "root"}  # 2 = sqrt(4)
    assert evidence["again"][0]["certificate"] == {"hash": a.hash}
    written = result.to_json()
    assert written["certificates"] == [{"hash": a.hash, "status": "not settled"},
                                       {"hash": Certificate(b).hash, "status": "not settled"}]
    assert written["evidence"]["side"]["certificate"] == {"hash": a.hash, "as": "root", "status": "not settled"}


def test_settle_returns_a_new_result_and_leaves_the_evidence_alone(planar, tmp_path):
    cert, inf = planar
    raised = copy.deepcopy(cert)  # a claim above the attained inf: refuted at its witness
    raised["claim"]["bound"] = str(Fraction(1.01 * inf))
    evidence = {"true": quantity(0.9 * inf, "lower_bound", certificate=cert),
                "false": quantity(1.01 * inf, "lower_bound", certificate=raised)}
    result = Result("Def2", Verdict.HOLDS, "held", evidence)
    before = copy.deepcopy(result.evidence)
    settled = settle(result, out_dir=tmp_path, boxes=200, verify=True, memo={})
    assert settled is not result and settled.evidence is result.evidence and result.evidence == before
    assert result.verdict == Verdict.HOLDS and result.summary == "held"  # the input Result is not changed
    assert all(isinstance(s, Settled) for s in settled.certificates)
    assert [s.status for s in settled.certificates] == ["re-proved", "refuted"]
    assert settled.verdict == Verdict.VIOLATED and settled.counterexample["kind"] == "certificate-refuted"
    for s in settled.certificates:
        assert (tmp_path / s.file).read_text() == s.written.text
    doc = {"checks": [settled.to_json()]}
    assert channel_problems(doc) == []
    assert doc["checks"][0]["evidence"]["false"]["certificate"]["status"] == "refuted"
    only_true = settle(Result("Def2", Verdict.HOLDS, "held", {"true": evidence["true"]}), out_dir=None, boxes=200,
                       verify=True, memo={})
    assert only_true.verdict == Verdict.HOLDS


def test_the_channel_check_finds_a_broken_channel(planar):
    """Known bad documents: a citation of a hash the check does not carry, a carried certificate no one cites, a
    certified number without a citation, a citation naming another file."""
    cert, inf = planar
    good = Result("Def2", Verdict.HOLDS, "held", {"n": quantity(0.9 * inf, CERTIFIED, certificate=cert)}).to_json()
    assert channel_problems({"checks": [good]}) == []
    uncited = copy.deepcopy(good)
    uncited["evidence"]["n"].pop("certificate")
    found = channel_problems({"checks": [uncited]})
    assert any("cites no certificate" in p for p in found) and any("nothing cites" in p for p in found)
    stray = copy.deepcopy(good)
    stray["certificates"] = []
    assert any("not among the check's certificates" in p for p in channel_problems({"checks": [stray]}))
    moved = copy.deepcopy(good)
    moved["evidence"]["n"]["certificate"]["file"] = "certificates/0000000000000000.json"
    moved["certificates"][0]["file"] = "certificates/1111111111111111.json"
    assert any("its certificate is in" in p for p in channel_problems({"checks": [moved]}))


@pytest.fixture(scope="module")
def run_out(tmp_path_factory):
    """A run's OUT folder: checks whose evidence cites certificates of several kinds (spectra, products, the key
    step's Choi matrix, sums), re-proved by the checker."""
    out = tmp_path_factory.mktemp("channel")
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "run", "--only", "Def3", "Asm2/Lem2", "Cor2",
                           "--out", str(out), "--workers", "1", "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    return out


def test_every_certificate_in_results_json_is_carried_by_its_result_and_cited(run_out):
    doc = json.loads((run_out / "results.json").read_text())
    carried = [c for check in doc["checks"] for c in check["certificates"]]
    assert carried and all(c["status"] == "re-proved" for c in carried)
    assert channel_problems(doc) == []
    files = {p.name for p in (run_out / "certificates").glob("*.json")}
    assert {c["file"].split("/")[-1] for c in carried} == files  # what is written is what the results carry
    results = [Result.from_json(check) for check in doc["checks"]]
    assert {c["hash"] for r in results for c in r.certificates} == {c["hash"] for c in carried}
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "verify", str(run_out)], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr[-2000:]


def test_a_brackets_certificate_is_made_once_and_again_when_its_side_changes():
    from inertiaproof.bounds.extremes import Bracket

    made = []

    def claim(certified, note, witness, proof):
        made.append(certified)
        return {"schema": "inertiaproof.certificate/2", "claim": {"kind": "x", "bound": str(Fraction(certified))}}

    b = Bracket("inf f", "min", 2.0, 1.0, np.zeros(2), certify=claim)
    first = b.certificate()
    assert b.certificate() is first and made == [1.0]
    assert b.tighten(1.5, "a sharper proof")  # the side moved: a new certificate of the new side
    second = b.certificate()
    assert second is not first and second["claim"]["bound"] == "3/2" and made == [1.0, 1.5]
    b.certify = None
    assert b.certificate() is None


def test_a_certificate_embedded_in_several_goes_to_one_checker_process():
    """The run's chunks of files for the checker's processes: the products sharing an ingredient, and the ingredient's
    own file, in one chunk (a checker process proves it once), the largest other work in the other."""
    def spectrum(tag, size):
        return {"claim": {"kind": "mass-matrix-spectrum", "tag": tag}, "tree": "." * size}

    shared = spectrum("shared", 1000)
    contents = {"a": {"claim": {"kind": "product"}, "ingredients": [shared, spectrum("a", 10)]},
                "b": {"claim": {"kind": "product"}, "ingredients": [shared, spectrum("b", 10)]},
                "c": shared, "d": spectrum("d", 1500)}
    assert _chunks(contents, 2) == [["d"], ["a", "b", "c"]]
    assert _chunks(contents, 1) == [["d", "a", "b", "c"]]
    assert _chunks({}, 2) == []
