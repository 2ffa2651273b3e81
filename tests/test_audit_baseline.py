"""Across versions and against the datasheet: ``--expect-mass`` (the model's total mass) and ``--baseline`` (an
earlier SARIF or JSON audit: SARIF ``baselineState`` on every result, the exit status counting only new and
updated errors) in text, JSON, SARIF and GitHub annotations."""

import json

import pytest
from test_audit_ci import valid_sarif
from urdf_samples import inertial, joint, link, robot, write

from inertiaproof import cli

# base 1 kg, l1 1 kg, l2 0.5 kg with a triangle inequality that fails (the known defect): 2.5 kg in all
KNOWN = [link("base"), link("l1", inertial(1.0, "0.1 0 0")),
         link("l2", inertial(0.5, "0.2 0 0", ixx=0.001, iyy=0.001, izz=0.01)),
         joint("j1", "base", "l1"), joint("j2", "l1", "l2", axis="0 1 0")]
NEW_BAD = [link("l3", inertial(-0.2)), joint("j3", "l2", "l3")]  # a link with a negative mass


def _audit(capsys, *argv):
    code = cli.main(["audit", "--bounds", "none", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def _results(path):
    return json.loads(path.read_text())["runs"][0]["results"]


# -- --expect-mass ---------------------------------------------------------------------------------------------

def test_expected_mass_matches(tmp_path, capsys):
    path = write(tmp_path, robot(*KNOWN[:2], KNOWN[3], name="arm"), "arm.urdf")  # base and l1: 2 kg, consistent
    for given in (["2"], ["2.0015"], ["arm=2"], ["arm.urdf=2"], ["5", "arm=2"]):  # within 1e-3 relative; by name
        code, out, err = _audit(capsys, path, *[a for g in given for a in ("--expect-mass", g)], "--json")
        doc = json.loads(out)
        mass = doc["files"][str(path)]["total_mass"]
        assert code == 0, (given, err)
        assert mass["matches"] is True and mass["total"]["value"] == 2.0 and mass["message"] is None
        assert doc["summary"]["mass_mismatches"] == 0
    code, out, _ = _audit(capsys, path, "--expect-mass", "2")
    assert code == 0 and "mass    total 2 kg, as expected (2 kg within 0.001 relative)" in out
    # no expectation: the total is still reported, and nothing is judged of it
    code, out, _ = _audit(capsys, path, "--json")
    assert code == 0 and json.loads(out)["files"][str(path)]["total_mass"]["expected"] is None


def test_expected_mass_mismatch_is_a_finding_of_the_file(tmp_path, capsys):
    path = write(tmp_path, robot(*KNOWN[:2], KNOWN[3], name="arm"), "arm.urdf")
    sarif = tmp_path / "audit.sarif"
    code, out, _ = _audit(capsys, path, "--expect-mass", "3.6", "--sarif", sarif, "--json")
    assert code == 1
    doc = json.loads(out)
    mass = doc["files"][str(path)]["total_mass"]
    assert mass["matches"] is False and mass["expected"]["value"] == 3.6 and mass["total"]["value"] == 2.0
    assert [h["link"] for h in mass["heaviest"]] == ["base", "l1"]
    for text in ("arm.urdf", "total mass 2 kg", "expected 3.6 kg", "'base' 1 kg (50%)", "'l1' 1 kg"):
        assert text in mass["message"]
    assert doc["summary"]["mass_mismatches"] == 1 and doc["summary"]["exit_status"] == 1
    (result,) = [r for r in _results(sarif) if r["ruleId"] == "total-mass-mismatch"]
    assert result["level"] == "error" and result["message"]["text"] == mass["message"]
    assert result["properties"]["subject"] == "model"
    valid_sarif(json.loads(sarif.read_text()))
    code, out, _ = _audit(capsys, path, "--expect-mass", "arm=3.6")
    assert code == 1 and f"mass    {mass['message']}" in out and "total mass not the expected" in out
    code, out, _ = _audit(capsys, path, "--expect-mass", "3.6", "--github")
    (line,) = [x for x in out.splitlines() if "total-mass-mismatch" in x]
    assert line.startswith("::error file=") and "expected 3.6 kg" in line
    # a wider tolerance takes it
    assert _audit(capsys, path, "--expect-mass", "2.1", "--mass-tolerance", "0.05")[0] == 0
    assert _audit(capsys, path, "--expect-mass", "2.1", "--mass-tolerance", "0.01")[0] == 1


@pytest.mark.parametrize("argv, says", [
    (["--expect-mass", "-2"], "positive number of kg"),
    (["--expect-mass", "heavy"], "is not a number"),
    (["--expect-mass", "nan"], "positive number of kg"),
    (["--expect-mass", "arm=0"], "positive number of kg"),
    (["--expect-mass", "2", "--expect-mass", "3"], "already given"),
    (["--expect-mass", "=2"], "needs a file or robot name"),
    (["--expect-mass", "nosuch.urdf=2"], "nosuch.urdf is no file audited"),
    (["--expect-mass", "2", "--mass-tolerance", "-1"], "--mass-tolerance"),
])
def test_bad_expected_masses_are_usage_errors(tmp_path, capsys, argv, says):
    path = write(tmp_path, robot(*KNOWN[:2], KNOWN[3], name="arm"), "arm.urdf")
    code, out, err = _audit(capsys, path, *argv)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and says in err, err


# -- --baseline ------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["sarif", "json"])
def test_baseline_of_an_unchanged_model(tmp_path, capsys, kind):
    path = write(tmp_path, robot(*KNOWN, name="arm"), "arm.urdf")
    base = tmp_path / f"base.{kind}"
    code, out, _ = _audit(capsys, path, *(["--sarif", base] if kind == "sarif" else ["--json"]))
    assert code == 1  # l2 is not consistent: the known defect
    if kind == "json":
        base.write_text(out)
    sarif = tmp_path / "now.sarif"
    # the same model, its lines moved by a comment: matched by rule, file and link, not by line
    path.write_text(path.read_text().replace("<robot name=\"arm\">", "<robot name=\"arm\">\n<!-- moved -->\n\n"))
    code, out, _ = _audit(capsys, path, "--baseline", base, "--sarif", sarif, "--json")
    assert code == 0
    results = _results(sarif)
    assert results and all(r["baselineState"] == "unchanged" for r in results)
    assert {r["properties"]["subject"] for r in results} == {"link l2"}
    valid_sarif(json.loads(sarif.read_text()))
    doc = json.loads(out)
    assert doc["findings"] and all(f["baseline_state"] == "unchanged" for f in doc["findings"])
    assert doc["baseline"]["counts"] == {"new": 0, "updated": 0, "unchanged": len(results), "absent": 0}
    assert doc["summary"]["exit_status"] == 0
    # without the baseline, the known defect still fails
    assert _audit(capsys, path)[0] == 1
    # annotations: a known error no longer fails the run
    code, out, _ = _audit(capsys, path, "--baseline", base, "--github")
    assert code == 0 and "::error" not in out and "[unchanged since the baseline]" in out


@pytest.mark.parametrize("kind", ["sarif", "json"])
def test_baseline_catches_a_new_bad_link(tmp_path, capsys, kind):
    path = write(tmp_path, robot(*KNOWN, name="arm"), "arm.urdf")
    base = tmp_path / f"base.{kind}"
    code, out, _ = _audit(capsys, path, *(["--sarif", base] if kind == "sarif" else ["--json"]))
    if kind == "json":
        base.write_text(out)
    old = {(r["ruleId"], r["properties"]["subject"]) for r in _results(base)} if kind == "sarif" else \
        {(f["rule"], f["subject"]) for f in json.loads(out)["findings"]}
    path.write_text(robot(*NEW_BAD[:1], *KNOWN, NEW_BAD[1], name="arm"))  # l3 first: every old line moves
    sarif = tmp_path / "now.sarif"
    code, out, _ = _audit(capsys, path, "--baseline", base, "--sarif", sarif, "--json")
    assert code == 1
    results = _results(sarif)
    valid_sarif(json.loads(sarif.read_text()))
    new = [r for r in results if r["baselineState"] == "new"]
    assert new and all(r["properties"]["subject"] == "link l3" and "'l3'" in r["message"]["text"] for r in new)
    assert any(r["level"] == "error" for r in new)
    assert {(r["ruleId"], r["properties"]["subject"]) for r in results if r["baselineState"] == "unchanged"} == old
    assert {r["baselineState"] for r in results} == {"new", "unchanged"}
    doc = json.loads(out)
    assert {f["subject"] for f in doc["findings"] if f["baseline_state"] == "new"} == {"link l3"}
    assert doc["baseline"]["counted"] >= 1 and doc["summary"]["baseline"]["counts"]["new"] == len(new)
    code, out, _ = _audit(capsys, path, "--baseline", base)
    assert code == 1 and "baseline " in out and "  new      error   " in out and "link l3" in out


def test_baseline_updated_and_absent(tmp_path, capsys):
    path = write(tmp_path, robot(*KNOWN, name="arm"), "arm.urdf")
    base = tmp_path / "base.sarif"
    _audit(capsys, path, "--sarif", base)
    # l2 edited and still inconsistent: the same findings, updated
    path.write_text(robot(*KNOWN[:2], link("l2", inertial(0.5, "0.2 0 0", ixx=0.001, iyy=0.001, izz=0.02)),
                          *KNOWN[3:], name="arm"))
    sarif = tmp_path / "now.sarif"
    assert _audit(capsys, path, "--baseline", base, "--sarif", sarif)[0] == 1
    states = {r["ruleId"]: r["baselineState"] for r in _results(sarif)}
    assert states["inconsistent"] == "updated"
    valid_sarif(json.loads(sarif.read_text()))
    # l2 repaired: its findings are absent, nothing fails
    path.write_text(robot(*KNOWN[:2], link("l2", inertial(0.5, "0.2 0 0")), *KNOWN[3:], name="arm"))
    code, out, _ = _audit(capsys, path, "--baseline", base, "--sarif", sarif, "--json")
    assert code == 0
    results = _results(sarif)
    assert results and all(r["baselineState"] == "absent" and r["level"] == "none" for r in results)
    assert "inconsistent" in {r["ruleId"] for r in results}
    valid_sarif(json.loads(sarif.read_text()))
    doc = json.loads(out)
    assert doc["findings"] == [] and doc["baseline"]["counts"]["absent"] == len(results)
    # a baseline whose SARIF was itself compared with another leaves its own absent results out
    again = tmp_path / "again.sarif"
    assert _audit(capsys, path, "--baseline", sarif, "--sarif", again)[0] == 0
    assert _results(again) == []


def test_baseline_with_expected_mass(tmp_path, capsys):
    """A mass that was already off is known; one that goes off since is new."""
    path = write(tmp_path, robot(*KNOWN[:2], KNOWN[3], name="arm"), "arm.urdf")
    base = tmp_path / "base.sarif"
    assert _audit(capsys, path, "--expect-mass", "3", "--sarif", base)[0] == 1
    assert _audit(capsys, path, "--expect-mass", "3", "--baseline", base)[0] == 0
    clean = tmp_path / "clean.sarif"
    assert _audit(capsys, path, "--sarif", clean)[0] == 0
    code, out, _ = _audit(capsys, path, "--expect-mass", "3", "--baseline", clean)
    assert code == 1 and "new      error   total-mass-mismatch" in out


@pytest.mark.parametrize("content, says", [
    (None, "cannot read"),
    ("{not json", "not JSON"),
    ('{"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "other"}}, "results": []}]}', "not the SARIF"),
    ('{"schema": "inertiaproof.results/1", "files": {}}', "not the SARIF"),
    ("[1, 2]", "not the SARIF"),
])
def test_bad_baselines_are_usage_errors(tmp_path, capsys, content, says):
    path = write(tmp_path, robot(*KNOWN, name="arm"), "arm.urdf")
    base = tmp_path / "base.sarif"
    if content is not None:
        base.write_text(content)
    code, out, err = _audit(capsys, path, "--baseline", base)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1 and says in err, err


def test_baseline_of_the_same_files_elsewhere(tmp_path, capsys, monkeypatch):
    """Relative paths and URIs, and the same repository checked out in another folder: matched by file name."""
    monkeypatch.chdir(tmp_path)
    for folder in ("old", "new"):
        (tmp_path / folder).mkdir()
        write(tmp_path / folder, robot(*KNOWN, name="arm"), "arm.urdf")
        write(tmp_path / folder, robot(*KNOWN[:2], KNOWN[3], name="ok"), "ok.urdf")
    assert _audit(capsys, "old/arm.urdf", "old/ok.urdf", "--sarif", "base.sarif")[0] == 1
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in _results(tmp_path / "base.sarif")}
    assert uris == {"old/arm.urdf"}
    code, out, _ = _audit(capsys, "new/arm.urdf", "new/ok.urdf", "--baseline", "base.sarif", "--json")
    assert code == 0 and {f["baseline_state"] for f in json.loads(out)["findings"]} == {"unchanged"}
    # the known defect copied into the other file is new there
    write(tmp_path / "new", robot(*KNOWN, name="ok"), "ok.urdf")
    code, out, _ = _audit(capsys, "new/arm.urdf", "new/ok.urdf", "--baseline", "base.sarif", "--json")
    states = {(f["file"], f["baseline_state"]) for f in json.loads(out)["findings"]}
    assert code == 1 and states == {("new/arm.urdf", "unchanged"), ("new/ok.urdf", "new")}
