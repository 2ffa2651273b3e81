"""The audit where robot descriptions live: SARIF, GitHub annotations, repaired copies, pre-commit, the pytest
plugin and the Python API."""

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from urdf_samples import inertial, joint, link, robot, robots_folder, write

from inertiaproof import audit_urdf, cli
from inertiaproof.audit.repair import nearest_consistent_inertia, written_inertia
from inertiaproof.model.consistency import CONSISTENT, physical_consistency
from inertiaproof.model.inertia import pack

SCHEMA = Path(__file__).parent / "sarif" / "sarif-schema-2.1.0.json"
REPO = Path(__file__).resolve().parent.parent
# l2's <inertia> spans three lines and shares its first line with other elements; l3 is behind a comment
BAD = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.02" izz="0.025" ixy="0" iyz="0" ixz="0"/></inertial></link>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" iyy="0.02" izz="0.025" ixy="0" iyz="0" ixz="0"/></inertial></link>
  <link name="l2"><inertial><origin xyz="0.2 0 0"/><mass value="0.5"/><inertia
      ixx="0.001" iyy="0.001"
      izz="0.01" ixy="0" iyz="0" ixz="0"/></inertial></link>
  <!-- <link name="l3"><inertial><inertia ixx="1"/></inertial></link> -->
  <link name="l3"><inertial><mass value="0.2"/><inertia ixx="0.002" iyy="0.002" izz="0.002" ixy="0.0019" iyz="0.0019" ixz="0.0019"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _audit(capsys, *argv):
    code = cli.main(["audit", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def _region_text(text, region):
    lines = text.splitlines(keepends=True)
    start = sum(map(len, lines[:region["startLine"] - 1])) + region["startColumn"] - 1
    end = sum(map(len, lines[:region["endLine"] - 1])) + region["endColumn"] - 1
    return start, end, text[start:end]



def valid_sarif(log):
    """``log`` (a SARIF document) after validating it against SARIF 2.1.0's schema (draft 4)."""
    jsonschema = pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    jsonschema.validate(log, json.loads(SCHEMA.read_text()), cls=jsonschema.Draft4Validator)
    return log


def test_sarif_validates_and_points_at_each_inertia_element(tmp_path, capsys):
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    path = write(tmp_path, BAD)
    sarif = tmp_path / "audit.sarif"
    code, _, _ = _audit(capsys, path, "--bounds", "none", "--sarif", sarif)
    log = valid_sarif(json.loads(sarif.read_text()))
    assert code == 1
    results = log["runs"][0]["results"]
    rules = [r["id"] for r in log["runs"][0]["tool"]["driver"]["rules"]]
    errors = {r["message"]["text"].split("'")[1]: r for r in results if r["ruleId"] == "inconsistent"}
    assert set(errors) == {"l2", "l3"} and all(r["level"] == "error" for r in errors.values())
    text = path.read_text()
    lines = text.splitlines()
    for name, result in errors.items():
        assert rules[result["ruleIndex"]] == result["ruleId"]
        region = result["locations"][0]["physicalLocation"]["region"]
        first = lines[region["startLine"] - 1]
        assert f'<link name="{name}">' in first and first[region["startColumn"] - 1:].startswith("<inertia")
        _, _, element = _region_text(text, region)
        assert element.startswith("<inertia") and element.endswith("/>")
        assert result["properties"]["engines"]["mujoco"]["action"] == "rejects"
    assert errors["l2"]["locations"][0]["physicalLocation"]["region"]["endLine"] == 7
    # the fixes, applied, give a file whose every link is consistent
    changes = []
    for result in errors.values():
        (replacement,) = result["fixes"][0]["artifactChanges"][0]["replacements"]
        start, end, _ = _region_text(text, replacement["deletedRegion"])
        changes.append((start, end, replacement["insertedContent"]["text"]))
    for start, end, new in sorted(changes, reverse=True):
        text = text[:start] + new + text[end:]
    fixed = write(tmp_path, text, "fixed.urdf")
    assert _audit(capsys, fixed, "--bounds", "none")[0] == 0


def test_sarif_of_an_unreadable_file_and_of_signs(tmp_path, capsys):
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    broken = write(tmp_path, "<robot name='x'><link name='a'>", "broken.urdf")
    path = write(tmp_path, BAD)
    sarif = tmp_path / "audit.sarif"
    assert _audit(capsys, broken, path, "--bounds", "none", "--sarif", sarif)[0] == 2
    results = json.loads(sarif.read_text())["runs"][0]["results"]
    kinds = {r["ruleId"] for r in results}
    assert {"unreadable", "inconsistent", "power_of_ten"} <= kinds
    unreadable = next(r for r in results if r["ruleId"] == "unreadable")
    assert unreadable["locations"][0]["physicalLocation"]["artifactLocation"]["uri"].endswith("broken.urdf")


def test_github_annotations(tmp_path, capsys):
    path = write(tmp_path, BAD)
    code, out, err = _audit(capsys, path, "--bounds", "none", "--github")
    assert code == 1 and "NOT CONSISTENT" in err
    errors = [line for line in out.splitlines() if line.startswith("::error ")]
    assert len(errors) == 2
    assert re.match(r"::error file=.*robot\.urdf,line=5,col=\d+,endLine=7,endColumn=\d+,title=inertiaproof "
                    r"inconsistent::link 'l2': triangle inequality", errors[0])
    assert all("%0A" not in line or "::" in line for line in out.splitlines())


def test_write_repaired_leaves_the_original_and_passes(tmp_path, capsys):
    path = write(tmp_path, BAD)
    before = path.read_bytes()
    out = tmp_path / "repaired.urdf"
    code, diff, err = _audit(capsys, path, "--bounds", "none", "--write-repaired", out)
    assert code == 1 and path.read_bytes() == before
    assert diff.startswith(f"--- {path}\n+++ {out}\n")
    assert sum(line.startswith("-") and not line.startswith("---") for line in diff.splitlines()) == 4
    assert _audit(capsys, out, "--bounds", "none")[0] == 0
    def elsewhere(text):
        return re.sub(r"<inertia\s[^>]*/>", "<inertia/>", text)

    assert elsewhere(out.read_text()) == elsewhere(before.decode())  # nothing but the repaired elements changed


def test_write_repaired_refuses_to_overwrite_and_says_what_it_cannot_repair(tmp_path, capsys):
    path = write(tmp_path, robot(link("base"), link("l1", inertial(-1.0)), joint("j1", "base", "l1")))
    assert _audit(capsys, path, "--bounds", "none", "--write-repaired", path)[0] == 2
    code, _, err = _audit(capsys, path, "--bounds", "none", "--write-repaired", tmp_path / "copy.urdf")
    assert code == 1 and "link l1 left as written: no repair of the inertia: the mass must be positive" in err


def test_written_repairs_are_consistent_as_written_even_with_a_tiny_slack():
    """The repair's printed digits, read back, are consistent; six digits alone (the old printing) are not."""
    rng = np.random.default_rng(3)
    needed_more, checked = 0, 0
    for _ in range(60):
        a = rng.normal(size=(3, 3))
        w = a @ a.T * 10.0 ** rng.uniform(-6, 0)
        w[2, 2] += np.trace(w)  # break the triangle inequality
        repaired = nearest_consistent_inertia(1.0, w, slack=1e-12)
        if repaired.inertia is None:
            continue
        text, slack = written_inertia(1.0, repaired.inertia, slack=1e-12)
        back = np.zeros((3, 3))
        for name, (i, j) in {"ixx": (0, 0), "iyy": (1, 1), "izz": (2, 2), "ixy": (0, 1), "iyz": (1, 2),
                             "ixz": (0, 2)}.items():
            back[i, j] = back[j, i] = float(text[name])
        assert physical_consistency(pack(1.0, np.zeros(3), back)).verdict == CONSISTENT and slack > 0
        six = np.vectorize(lambda x: float(f"{x:.6g}"))(repaired.inertia)
        needed_more += physical_consistency(pack(1.0, np.zeros(3), six)).verdict != CONSISTENT
        checked += 1
    assert checked >= 50 and needed_more > 0


def _hooks():
    import yaml

    return {hook["id"]: hook for hook in yaml.safe_load((REPO / ".pre-commit-hooks.yaml").read_text())}


def _git_repo(tmp_path, text):
    repo = tmp_path / "robots"
    repo.mkdir()
    write(repo, text, "arm.urdf")
    subprocess.run(["git", "init", "-q", str(repo)], check=True)
    subprocess.run(["git", "-C", str(repo), "add", "arm.urdf"], check=True)
    return repo


@pytest.mark.slow
def test_pre_commit_hook_fails_a_bad_urdf_and_passes_its_repair(tmp_path):
    pytest.importorskip("pre_commit", reason="pre-commit is not installed")
    from pre_commit.clientlib import load_manifest

    assert {h["id"] for h in load_manifest(str(REPO / ".pre-commit-hooks.yaml"))} == {"inertiaproof-audit",
                                                                                        "inertiaproof-audit-mjcf"}
    hook = _hooks()["inertiaproof-audit"]
    repo = _git_repo(tmp_path, BAD)
    # the published hook with this environment's inertiaproof as its command (language: python would install it)
    entry = hook["entry"].replace("inertiaproof", f"{sys.executable} -m inertiaproof", 1)
    local = {"repos": [{"repo": "local", "hooks": [dict(hook, entry=entry, language="system")]}]}
    (repo / ".pre-commit-config.yaml").write_text(json.dumps(local))
    env = dict(os.environ, PRE_COMMIT_HOME=str(tmp_path / "cache"), HOME=str(tmp_path))

    def run():
        return subprocess.run([sys.executable, "-m", "pre_commit", "run", "--all-files"], cwd=repo, env=env,
                              capture_output=True, text=True)

    failed = run()
    assert failed.returncode == 1 and "NOT CONSISTENT" in failed.stdout, failed.stdout + failed.stderr
    subprocess.run([sys.executable, "-m", "inertiaproof", "audit", "arm.urdf", "--bounds", "none", "--write-repaired",
                    "fixed.urdf"], cwd=repo, capture_output=True, check=False)
    shutil.move(repo / "fixed.urdf", repo / "arm.urdf")
    passed = run()
    assert passed.returncode == 0, passed.stdout + passed.stderr


def test_pytest_plugin_turns_links_into_items(tmp_path):
    """One pytest run over the bad file and its repaired copy: the bad links fail, the repaired ones pass."""
    write(tmp_path, BAD, "arm.urdf")
    (tmp_path / "fixed").mkdir()
    assert cli.main(["audit", str(tmp_path / "arm.urdf"), "--bounds", "none", "--write-repaired",
                     str(tmp_path / "fixed" / "arm.urdf")]) == 1
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-rA", "--inertiaproof-audit",
                          "arm.urdf", "--inertiaproof-audit", "fixed"], cwd=tmp_path, capture_output=True, text=True)
    out = run.stdout
    assert run.returncode == 1 and "2 failed, 4 passed, 2 skipped" in out, out + run.stderr
    assert "FAILED arm.urdf::l2 - inconsistent" in out and "FAILED arm.urdf::l3 - inconsistent" in out
    assert "suggested: ixx=" in out and "PASSED fixed::arm.urdf::l2" in out and "PASSED fixed::arm.urdf::l3" in out
    assert "base: base link that does not move" in out


def test_python_api_records_and_html(tmp_path):
    path = write(tmp_path, BAD.replace('name="l3"', 'name="l3&lt;"').replace('link="l3"', 'link="l3&lt;"'))
    audit = audit_urdf(path, bounds="none")
    assert not audit.consistent and audit.exit_status == 1
    records = audit.to_records()
    assert [r["link"] for r in records] == ["base", "l1", "l2", "l3<"]
    assert all(list(r) == list(records[0]) for r in records)
    json.dumps(records)  # plain values: straight into pandas.DataFrame(records)
    l2 = records[2]
    assert (l2["verdict"], l2["mujoco"], l2["drake"], l2["line"]) == ("inconsistent", "rejects", "replaces", 5)
    assert l2["repair"].startswith('ixx="')
    page = audit._repr_html_()
    assert "<table>" in page and "l3&lt;" in page and "l3<" not in page


@pytest.mark.slow
def test_example_robot_data_repairs_are_consistent_as_written(tmp_path, capsys):
    """Every printed repair of the example-robot-data robots, read back with the smallest slack, is consistent."""
    folder = robots_folder()
    if folder is None:
        pytest.skip("example-robot-data is not installed")
    code, out, _ = _audit(capsys, folder, "--bounds", "none", "--json", "--repair-slack", "1e-12")
    written = [(link["inertial"]["mass"], link["repair"]["written"]) for f in json.loads(out)["files"].values()
               if f["status"] == "ok" for link in f["links"].values() if link["repair"] and link["repair"]["written"]]
    assert len(written) >= 30
    for mass, text in written:
        m = np.zeros((3, 3))
        for name, (i, j) in {"ixx": (0, 0), "iyy": (1, 1), "izz": (2, 2), "ixy": (0, 1), "iyz": (1, 2),
                             "ixz": (0, 2)}.items():
            m[i, j] = m[j, i] = float(text[name])
        assert physical_consistency(pack(mass, np.zeros(3), m)).verdict == CONSISTENT
