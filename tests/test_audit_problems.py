"""The audit reads what the engines read and reports every problem of a file, each with its line: undeclared
namespace prefixes (as urdfdom's TinyXML reads them), an ``<inertial>`` urdfdom reads past (a missing
``<inertia>`` is a point mass), and several problems of one file in text, JSON, SARIF and GitHub annotations;
Pinocchio (urdfdom) is the oracle of what is read."""

import json
import re

import numpy as np
import pytest
from test_audit_ci import valid_sarif
from urdf_samples import inertial, joint, link, robot, write

from inertiaproof import cli
from inertiaproof.audit.annotations import github_commands, sarif_log
from inertiaproof.audit.text import format_audit
from inertiaproof.audit.urdf import read_urdf
from inertiaproof.errors import InputError

LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
BAD_INERTIA = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="3" ixy="0" iyz="0" ixz="0"/></inertial>'


def _revolute(name, parent, child, extra=""):
    return (f'  <joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>{LIMIT.replace("/>", f" {extra}/>")}</joint>')


# Drake-flavoured: an undeclared prefix on an element and on attributes (one on the root's own line)
PREFIXED = f"""<?xml version="1.0"?>
<robot name="ur" drake:declared_nowhere="1">
  <link name="base">
    <drake:collision_filter_group name="arm"><drake:member link="l1"/></drake:collision_filter_group>
    {inertial()}
  </link>
  <link name="l1">{inertial(mass=2.0, xyz="0.1 0 0")}</link>
  <link name="l2">
    {BAD_INERTIA}
  </link>
{_revolute("j1", "base", "l1", 'drake:acceleration="10"')}
{_revolute("j2", "l1", "l2", 'drake:acceleration="10"')}
</robot>
"""

# a camera with a mass and no <inertia>, and a bad link after it
CAMERA = f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base">{inertial()}</link>
  <link name="camera">
    <inertial>
      <origin xyz="0.02 0 0.01"/>
      <mass value="0.2"/>
    </inertial>
  </link>
  <link name="l2">{BAD_INERTIA}</link>
{_revolute("j1", "base", "camera")}
{_revolute("j2", "camera", "l2")}
</robot>
"""

# three different problems: no <inertia>, a mass that is not a number, an inconsistent inertia
THREE = f"""<?xml version="1.0"?>
<robot name="arm" >
  <link name="base">{inertial()}</link>
  <link name="camera"><inertial><origin xyz="0.02 0 0"/><mass value="0.2"/></inertial></link>
  <link name="plate">
    <inertial><mass value="heavy"/><inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/></inertial>
  </link>
  <link name="l3">{BAD_INERTIA}</link>
{_revolute("j1", "base", "camera", 'drake:acceleration="3"')}
{_revolute("j2", "camera", "plate")}
{_revolute("j3", "plate", "l3")}
</robot>
"""


def _line(text, needle, after=None):
    """The 1-based line of the first ``needle`` in ``text`` (after the first ``after``, if given)."""
    start = 0 if after is None else text.index(after)
    return text.count("\n", 0, text.index(needle, start)) + 1


def _audit(capsys, path, *argv):
    code = cli.main(["audit", "--bounds", "none", *argv, str(path)])
    out, err = capsys.readouterr()
    return code, out, err


def _document(capsys, path):
    code, out, _ = _audit(capsys, path, "--json")
    doc = json.loads(out)
    assert doc["summary"]["exit_status"] == code
    return code, doc, next(iter(doc["files"].values()))


def test_undeclared_prefixes_are_read_as_urdfdom_reads_them(tmp_path, capsys):
    path = write(tmp_path, PREFIXED)
    r = read_urdf(path)
    assert [link.name for link in r.links] == ["base", "l1", "l2"] and r.problems == ()
    assert [j.limits for j in r.joints] == [(-1.0, 1.0), (-1.0, 1.0)]
    assert any("namespace prefix 'drake' is not declared" in w for w in r.warnings)
    code, doc, f = _document(capsys, path)
    assert code == 1 and f["status"] == "ok" and f["not_consistent"] == ["l2", "body l2"]
    where = f["links"]["l2"]["location"]
    assert where["startLine"] == _line(PREFIXED, "<inertia ", after='<link name="l2">')
    lines = PREFIXED.splitlines()
    assert lines[where["startLine"] - 1][where["startColumn"] - 1:].startswith('<inertia ixx="1" iyy="1" izz="3"')


def test_undeclared_prefixes_keep_columns_on_the_root_line(tmp_path, capsys):
    one_line = PREFIXED.replace("\n", " ").replace('<?xml version="1.0"?> ', "")
    code, doc, f = _document(capsys, write(tmp_path, one_line))
    where = f["links"]["l2"]["location"]
    assert code == 1 and where["startLine"] == 1
    assert one_line[where["startColumn"] - 1:].startswith('<inertia ixx="1" iyy="1" izz="3"')


def test_missing_inertia_is_a_point_mass_and_the_rest_is_audited(tmp_path, capsys):
    path = write(tmp_path, CAMERA)
    code, doc, f = _document(capsys, path)
    assert code == 1 and f["status"] == "ok"
    (problem,) = f["problems"]
    line = _line(CAMERA, "<inertial>", after='<link name="camera">')
    assert problem["kind"] == "missing_inertia" and problem["location"]["startLine"] == line
    assert problem["message"].startswith("link 'camera': <inertial> misses <inertia>: urdfdom logs 'Inertial element "
                                         "must have inertia element' and Pinocchio reads the link as a point mass of "
                                         "0.2 kg")
    camera = f["links"]["camera"]
    assert camera["verdict"] == "degenerate" and [s["sign"] for s in camera["signs"]] == ["point_mass"]
    assert camera["inertial"]["mass"] == 0.2 and camera["inertial"]["com"] == [0.02, 0, 0.01]
    assert camera["source"] == "inertial" and camera["location"]["startLine"] == line
    assert camera["repair"]["replacement"] is None  # no <inertia> element to replace
    engines = camera["engines"]
    assert engines["mujoco"]["action"] == engines["pybullet"]["action"] == "rejects"
    assert engines["drake"]["action"] == engines["gazebo"]["action"] == "not_verified"
    later = f["links"]["l2"]  # the bad link after the camera is still audited
    assert later["verdict"] == "inconsistent" and later["location"]["startLine"] == _line(CAMERA, "<inertia ", after='<link name="l2">')
    assert set(f["not_consistent"]) >= {"camera", "l2"}


def _three_lines():
    return {"missing-inertia": _line(THREE, "<inertial>", after='<link name="camera">'),
            "malformed-inertial": _line(THREE, '<mass value="heavy"/>'),
            "inconsistent": _line(THREE, '<inertia ixx="1" iyy="1" izz="3"')}


def test_three_problems_are_all_reported_with_their_lines_in_every_format(tmp_path, capsys):
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    path = write(tmp_path, THREE)
    code, doc, f = _document(capsys, path)
    assert code == 1
    lines = _three_lines()
    assert [(p["kind"], p["location"]["startLine"]) for p in f["problems"]] == [
        ("missing_inertia", lines["missing-inertia"]), ("malformed_inertial", lines["malformed-inertial"])]
    assert f["links"]["plate"]["massless_frame"] and f["links"]["l3"]["verdict"] == "inconsistent"

    text = format_audit(doc)
    assert f"problem camera (line {lines['missing-inertia']}, column 23): link 'camera': <inertial> misses" in text
    assert f"problem plate (line {lines['malformed-inertial']}, column 15): link 'plate': <mass> attribute " \
           'value="heavy" is not a number' in text
    assert "2 problems in inertials" in text and "problems in inertials: 2" in text

    log = valid_sarif(sarif_log(doc))
    results = log["runs"][0]["results"]
    found = {r["ruleId"]: r["locations"][0]["physicalLocation"]["region"]["startLine"] for r in results
             if r["ruleId"] in lines}
    assert found == lines and all(r["level"] == "error" for r in results if r["ruleId"] in lines)
    problem = next(r for r in results if r["ruleId"] == "missing-inertia")
    assert problem["properties"]["engines"]["mujoco"]["action"] == "rejects" and "fixes" not in problem

    commands = github_commands(doc)
    for rule, line in lines.items():
        assert any(re.match(rf"::error file=.*robot\.urdf,line={line},col=\d+,.*title=inertiaproof {rule}::", c)
                   for c in commands), (rule, commands)


def test_a_file_no_engine_loads_is_one_line_naming_the_place(tmp_path, capsys):
    text = THREE.replace('<child link="l3"/>', '<child link="ghost"/>')
    path = write(tmp_path, text)
    with pytest.raises(InputError) as info:
        read_urdf(path)
    line = _line(text, '<child link="ghost"/>')
    assert str(info.value) == f"{path}: joint 'j3': <child link='ghost'> names no link of the file (line {line})"
    code, doc, f = _document(capsys, path)
    assert code == 2 and f["location"] == {"path": str(path), "startLine": line}
    (result,) = sarif_log(doc)["runs"][0]["results"]
    assert result["ruleId"] == "unreadable" and result["locations"][0]["physicalLocation"]["region"] == {
        "startLine": line}
    assert github_commands(doc)[0].startswith(f"::error file={path},line={line},title=inertiaproof unreadable::")


def test_a_value_beyond_the_audits_range_stays_an_error(tmp_path):
    with pytest.raises(InputError, match=r"izz=\"1.7e308\" is out of range .*\(line 3\)"):
        read_urdf(write(tmp_path, robot(link("a", inertial(izz="1.7e308")))))


MALFORMED = {  # the <inertial> of l1: (text, what urdfdom reads: point mass or massless)
    "no inertia": ('<inertial><origin xyz="0.1 0 0"/><mass value="2.5"/></inertial>', "point"),
    "missing iyy": (inertial(mass=2.5, xyz="0.1 0 0").replace(' iyy="0.02"', ""), "point"),
    "nan entry": (inertial(mass=2.5, xyz="0 0.1 0", ixx="nan"), "point"),
    "text entry": (inertial(mass=2.5, ixx="big"), "point"),
    "xacro entry": (inertial(mass=2.5, ixx="${i}"), "point"),
    "no mass": ('<inertial><inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/></inertial>', "massless"),
    "empty": ("<inertial/>", "massless"),
    "mass without value": ('<inertial><mass/><inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/></inertial>',
                           "massless"),
    "text mass": (inertial(mass="heavy"), "massless"),
    "short origin": (inertial(mass=2.5, xyz="0 1"), "massless"),
}


def _arm(body):
    return robot(link("base"), link("l1", body), link("l2"), joint("j1", "base", "l1"), joint("j2", "l1", "l2"))


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_an_inertial_urdfdom_reads_past_is_a_problem_of_its_link(tmp_path, case):
    body, reads = MALFORMED[case]
    r = read_urdf(write(tmp_path, _arm(body)))
    assert {p.link for p in r.problems} == {"l1"} and all(p.span.line == 4 for p in r.problems)
    read = r.link("l1").inertial
    assert not read.inertia.any() and (read.mass == 2.5) == (reads == "point") and r.link("l2").inertial.mass == 1.0


def test_every_error_of_one_inertial_is_reported(tmp_path):
    body = inertial(mass="heavy").replace(' iyy="0.02"', "").replace('ixz="0.0"', 'ixz="x"')
    r = read_urdf(write(tmp_path, _arm(body)))
    assert [p.message.split(":")[1].strip() for p in r.problems] == ["<mass> attribute value=\"heavy\" is not a number",
                                                                    "<inertia> misses attribute 'iyy'",
                                                                    "<inertia> attribute ixz=\"x\" is not a number"]


def test_mujoco_and_pybullet_do_what_the_engine_column_says(tmp_path):
    """The column of a missing <inertia> (both refuse the file) and of a mass that is not a number (MuJoCo refuses
    the file, PyBullet loads it), observed on the engines that install here."""
    missing, malformed = (write(tmp_path, _arm(MALFORMED[case][0]), f"{case}.urdf")
                          for case in ("no inertia", "text mass"))
    mujoco = pytest.importorskip("mujoco")
    for path in (missing, malformed):
        with pytest.raises(ValueError, match="XML Error"):
            mujoco.MjModel.from_xml_path(str(path))
    pybullet = pytest.importorskip("pybullet")
    client = pybullet.connect(pybullet.DIRECT)
    try:
        with pytest.raises(pybullet.error, match="Cannot load URDF file"):
            pybullet.loadURDF(str(missing), useFixedBase=True, physicsClientId=client)
        body = pybullet.loadURDF(str(malformed), useFixedBase=True, flags=pybullet.URDF_USE_INERTIA_FROM_FILE,
                                 physicsClientId=client)
        assert pybullet.getDynamicsInfo(body, 0, physicsClientId=client)[0] == 0.0
    finally:
        pybullet.disconnect(client)


def _pinocchio_inertias(model, robot_read):
    """{link: (mass, CoM in the link frame, rotational inertia about the CoM in the link frame)} of every child of a
    movable joint, from Pinocchio's model."""
    out = {}
    for j in robot_read.joints:
        inertia = model.inertias[model.getJointId(j.name)]
        out[j.child] = (inertia.mass, np.array(inertia.lever), np.array(inertia.inertia))
    return out


def _ours(robot_read, name):
    w = robot_read.link(name).inertial
    return w.mass, w.com, w.rotation @ w.inertia @ w.rotation.T


ORACLE_FILES = {"prefixed": PREFIXED, "camera": CAMERA, "three": THREE,
                **{f"malformed {case}": _arm(body) for case, (body, _) in MALFORMED.items()}}


@pytest.mark.parametrize("case", sorted(ORACLE_FILES))
def test_pinocchio_loads_the_same_files_and_reads_the_same_inertias(tmp_path, case):
    pinocchio = pytest.importorskip("pinocchio")
    path = write(tmp_path, ORACLE_FILES[case])
    model = pinocchio.buildModelFromUrdf(str(path))
    r = read_urdf(path)
    for name, (mass, lever, rotational) in _pinocchio_inertias(model, r).items():
        ours = _ours(r, name)
        assert mass == ours[0], (name, mass, ours)
        if mass:
            assert np.allclose(lever, ours[1], atol=1e-15) and np.allclose(rotational, ours[2], atol=1e-15), name
