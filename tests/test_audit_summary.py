"""The audit's summary keeps judged links and bodies apart from joint frames, massless frames and bases and the
links of a fixed base (issue 27): dm_control's suite has no inconsistent judged link or body."""

import json
import os
import re

import pytest
from urdf_samples import inertial, joint, link, robot, write

from inertiaproof import cli
from inertiaproof.audit.api import audit_urdf
from inertiaproof.audit.text import format_audit


def _audit(capsys, *argv):
    code = cli.main(["audit", "--bounds", "none", *map(str, argv)])
    return code, capsys.readouterr().out


@pytest.fixture(scope="module")
def suite():
    dm_control = pytest.importorskip("dm_control", reason="dm-control is not installed")
    pytest.importorskip("mujoco", reason="MJCF reading needs the mujoco package")
    return os.path.join(os.path.dirname(dm_control.__file__), "suite")


@pytest.mark.parametrize("floating", [False, True])
def test_dm_control_suite_has_no_inconsistent_judged_body(suite, capsys, floating):
    code, out = _audit(capsys, suite, "--json", *(["--floating-base"] if floating else []))
    doc = json.loads(out)
    s = doc["summary"]
    assert s["unreadable"] == 0 and s["files_not_consistent"] == 0
    # the one hard geometric finding: point_mass.xml's 0.3 kg in a sphere of radius 1 cm, denser than osmium
    # (:mod:`inertiaproof.audit.mjcf_geometry`), so the exit status is 1
    errors = {os.path.basename(path): f["geometry_errors"] for path, f in doc["files"].items() if f["geometry_errors"]}
    assert code == 1 and errors == {"point_mass.xml": ["pointmass: second-moment-below-densest-ball",
                                                       "pointmass: mass-exceeds-densest"]}
    assert s["links"]["inconsistent"] == s["links"]["invalid"] == s["links"]["degenerate"] == 0
    assert s["bodies"]["inconsistent"] == s["bodies"]["invalid"] == s["bodies"]["degenerate"] == 0
    assert s["bodies"]["consistent"] > 100 and s["links"]["consistent"] > 100
    apart = s["links_not_judged"]
    assert apart["joint_frames"] > 50 and apart["massless_frames"] >= 19  # every model's massless world
    assert sum(apart.values()) == s["links"]["not_judged"]
    links = [entry for f in doc["files"].values() for entry in f["links"].values()]
    assert s["links"]["not_judged"] + sum(s["links"][k] for k in ("consistent", "degenerate", "inconsistent",
                                                                   "invalid")) == len(links)
    text = format_audit(doc)
    totals = text.rsplit("\n", 1)[-1]
    assert "judged links: " in totals and "0 inconsistent" in totals and "joint frames" in totals
    assert re.search(r"judged bodies: \d+ consistent, 0 degenerate, 0 inconsistent, 0 invalid", totals)
    # the massless frames and bases (as written: mass 0, 'inconsistent') are listed as not judged, never as
    # inconsistent links or bodies
    assert re.findall(r"(?<!\b0 )\binconsistent\b", text) == []
    from inertiaproof.report.audit import _bodies
    assert all(_bodies(f["bodies"]) == [] for f in doc["files"].values())


def test_counts_by_why_a_link_is_not_judged(tmp_path, capsys):
    massless = '<inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" iyz="0" ixz="0"/></inertial>'
    text = robot(link("world", ""), link("base"), link("plate", inertial(0.2)), link("l1"), link("tool", massless),
                 joint("fix", "world", "base", kind="fixed"), joint("bolt", "base", "plate", kind="fixed"),
                 joint("j1", "base", "l1"), joint("jt", "l1", "tool", kind="fixed"))
    path = write(tmp_path, text)
    code, out = _audit(capsys, path, "--json")
    doc = json.loads(out)
    f = doc["files"][str(path)]
    assert code == 0
    assert f["counts"] == {"consistent": 1, "degenerate": 0, "inconsistent": 0, "invalid": 0, "not_judged": 4}
    assert f["not_judged"] == {"joint_frames": 0, "massless_frames": 2, "fixed_base": 2}
    assert f["body_counts"] == {"consistent": 1, "degenerate": 0, "inconsistent": 0, "invalid": 0, "not_judged": 0}
    totals = format_audit(doc).rsplit("\n", 1)[-1]
    assert ("judged links: 1 consistent, 0 degenerate, 0 inconsistent, 0 invalid; 4 not judged (2 massless frames "
            "or bases, 2 links of a fixed base); judged bodies: 1 consistent, 0 degenerate, 0 inconsistent, "
            "0 invalid") in totals
    table = format_audit(doc)
    assert re.search(r"world +base \(fixed\) +not judged", table)
    assert re.search(r"tool +merged into l1 +not judged", table)
    records = audit_urdf(path, bounds="none").to_records()
    assert [r["link"] for r in records if r["judged"]] == ["l1"]


def test_a_massless_floating_base_is_a_frame_not_an_inconsistent_body(tmp_path, capsys):
    text = robot(link("world", ""), link("pelvis"), link("l1"), joint("free", "world", "pelvis", kind="floating"),
                 joint("j1", "pelvis", "l1"))
    path = write(tmp_path, text)
    code, out = _audit(capsys, path, "--json", "--floating-base")
    f = json.loads(out)["files"][str(path)]
    assert code == 0 and f["consistent"]
    assert not f["bodies"]["world"]["judged"] and "a frame, not a body" in f["bodies"]["world"]["reason"]
    assert f["bodies"]["pelvis"]["judged"] and f["body_counts"]["consistent"] == 2
