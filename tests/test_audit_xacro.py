"""``inertiaproof audit robot.urdf.xacro``: expanded by the xacro package, audited like the URDF it expands to
(issue 27)."""

import json
import re
import sys

import pytest

from inertiaproof import cli
from inertiaproof.audit.document import audit_paths
from inertiaproof.audit.xacro_files import expand

pytest.importorskip("xacro", reason="xacro files need the xacro package (pip install xacro)")

XACRO = """<?xml version="1.0"?>
<robot name="arm" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="tip_izz" default="0.015"/>
  <xacro:property name="reach" value="0.3"/>
  <xacro:macro name="segment" params="name mass izz">
    <link name="${name}">
      <inertial>
        <origin xyz="${reach/2} 0 0" rpy="0 0 0"/>
        <mass value="${mass}"/>
        <inertia ixx="0.01" iyy="0.01" izz="${izz}" ixy="0" iyz="0" ixz="0"/>
      </inertial>
    </link>
  </xacro:macro>
  <link name="base"/>
  <xacro:segment name="upper" mass="1.5" izz="0.012"/>
  <xacro:segment name="fore" mass="0.5" izz="$(arg tip_izz)"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <joint name="elbow" type="revolute">
    <parent link="upper"/><child link="fore"/><origin xyz="${reach} 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def urdf(tip_izz):
    """The URDF the xacro file expands to, written by hand."""
    def segment(name, mass, izz):
        return (f'<link name="{name}"><inertial><origin xyz="0.15 0 0" rpy="0 0 0"/><mass value="{mass}"/>'
                f'<inertia ixx="0.01" iyy="0.01" izz="{izz}" ixy="0" iyz="0" ixz="0"/></inertial></link>')
    return f"""<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  {segment("upper", 1.5, "0.012")}
  {segment("fore", 0.5, tip_izz)}
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
</robot>
"""


def _files(tmp_path, tip_izz=None):
    (tmp_path / "arm.urdf.xacro").write_text(XACRO)
    (tmp_path / "arm.urdf").write_text(urdf(tip_izz or "0.015"))
    return tmp_path / "arm.urdf.xacro", tmp_path / "arm.urdf"


def _cli(capsys, *argv):
    code = cli.main(["audit", "--bounds", "none", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("tip_izz", [None, "0.03"])
def test_a_xacro_file_audits_like_the_urdf_it_expands_to(tmp_path, capsys, tip_izz):
    xacro_file, twin = _files(tmp_path, tip_izz)
    extra = ["--xacro-arg", f"tip_izz:={tip_izz}"] if tip_izz else []
    code, out, err = _cli(capsys, "--json", *extra, xacro_file, twin)
    doc = json.loads(out)
    expanded, plain = doc["files"][str(xacro_file)], doc["files"][str(twin)]
    assert code == (1 if tip_izz else 0) and expanded["status"] == plain["status"] == "ok", err
    assert set(expanded["links"]) == {"base", "upper", "fore"}  # the macro made two links
    assert expanded["not_consistent"] == plain["not_consistent"] == (["fore", "body fore"] if tip_izz else [])
    assert _without_positions(expanded) == _without_positions(plain)


def _without_positions(entry):
    """The entry without what depends on the text it was read from: locations, the replacement text's span."""
    entry = json.loads(json.dumps(entry))
    for link in entry["links"].values():
        link["location"] = None
        if link["repair"]:
            link["repair"]["replacement"] = None
    return entry


def test_positions_are_lines_of_the_expanded_text(tmp_path):
    xacro_file, _ = _files(tmp_path)
    text, _ = expand(xacro_file, {"tip_izz": "0.03"})
    lines = text.split("\n")
    entry = audit_paths([xacro_file], samples=64, rounds=0, bounds="none",
                        xacro_args={"tip_izz": "0.03"})[str(xacro_file)]
    for name in ("upper", "fore"):
        where = entry["links"][name]["location"]
        assert where["expanded"] == "xacro" and where["path"] == str(xacro_file)
        assert lines[where["startLine"] - 1][where["startColumn"] - 1:].startswith("<inertia ")
    assert 'izz="0.03"' in lines[entry["links"]["fore"]["location"]["startLine"] - 1]
    repair = entry["links"]["fore"]["repair"]
    assert repair["written"] and repair["replacement"] is None  # no span in the .xacro file to replace


def test_annotations_and_repaired_copies_do_not_point_into_the_xacro_file(tmp_path, capsys):
    xacro_file, _ = _files(tmp_path)
    code, out, _ = _cli(capsys, "--github", "--xacro-arg", "tip_izz:=0.03", xacro_file)
    errors = [line for line in out.splitlines() if line.startswith("::error")]
    assert code == 1 and errors and all(",line=" not in line for line in errors)
    assert "of the text xacro expands the file to" in errors[0]
    before = xacro_file.read_text()
    code, out, err = _cli(capsys, "--write-repaired", tmp_path / "copy.urdf.xacro", "--xacro-arg", "tip_izz:=0.03",
                          xacro_file)
    assert xacro_file.read_text() == before and (tmp_path / "copy.urdf.xacro").read_text() == before
    assert "link fore left as written" in err


def test_what_xacro_cannot_expand_is_one_line_naming_the_file(tmp_path, capsys, monkeypatch):
    needs = tmp_path / "needs.urdf.xacro"
    needs.write_text(XACRO.replace('<xacro:arg name="tip_izz" default="0.015"/>', '<xacro:arg name="tip_izz"/>'))
    ros = tmp_path / "ros.urdf.xacro"
    ros.write_text(XACRO.replace('izz="$(arg tip_izz)"', 'izz="0.015"').replace(
        "<link name=\"base\"/>", '<xacro:include filename="$(find robot_description)/urdf/parts.xacro"/>'
                                 '<link name="base"/>'))
    broken = tmp_path / "broken.urdf.xacro"
    broken.write_text(XACRO.replace("</robot>", ""))
    code, _, err = _cli(capsys, needs, ros, broken)
    errors = [line for line in err.splitlines() if line.startswith("inertiaproof: error:")]
    assert code == 2 and len(errors) == 3 and "Traceback" not in err
    for path, line in zip((needs, ros, broken), errors):
        assert line.startswith(f"inertiaproof: error: {path}: xacro cannot expand it: "), line
    code, _, err = _cli(capsys, "--xacro-arg", "tip_izz=0.03", needs)
    assert code == 2 and err.strip().count("\n") == 0 and "name:=value" in err
    monkeypatch.setitem(sys.modules, "xacro", None)  # the package is not installed
    code, _, err = _cli(capsys, needs)
    assert code == 2 and err.strip().count("\n") == 0 and "pip install xacro" in err and str(needs) in err


def test_the_pre_commit_hook_takes_xacro_files():
    yaml = pytest.importorskip("yaml")
    from pathlib import Path

    hooks = {h["id"]: h for h in yaml.safe_load((Path(__file__).resolve().parent.parent / ".pre-commit-hooks.yaml")
                                                .read_text())}
    files = re.compile(hooks["inertiaproof-audit"]["files"])
    assert files.search("robot.urdf.xacro") and files.search("arm.xacro") and files.search("robot.urdf")
    assert not files.search("model.xml")
