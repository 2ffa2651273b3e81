"""SDFormat in the audit (:mod:`inertiaproof.audit.sdf`): pybullet_data's KUKA iiwa as SDF and as URDF give the same
verdicts and kinematics for the same numbers; every SDF file of the corpora (pybullet_data, example-robot-data's
Cassie) is read; SDFormat's defaults, ``relative_to`` frames and several problems of one file, each with its line,
in every output format."""

import json
from pathlib import Path

import numpy as np
import pytest
from test_audit_ci import valid_sarif
from urdf_samples import inertial, joint, link, robot, robots_folder, write

from inertiaproof import cli
from inertiaproof.audit.sdf import read_sdf
from inertiaproof.audit.urdf import read_urdf
from inertiaproof.errors import InputError


def _pybullet_data():
    pybullet_data = pytest.importorskip("pybullet_data", reason="pybullet (pybullet_data) is not installed")
    return Path(pybullet_data.getDataPath())


def _audit(capsys, *paths):
    code = cli.main(["audit", "--bounds", "none", "--workers", "1", "--json", *map(str, paths)])
    return code, json.loads(capsys.readouterr().out)


def _inertial(mass="1", xyz="0 0 0 0 0 0", ixx="0.01", iyy="0.01", izz="0.01", ixy="0", iyz="0", ixz="0",
              relative_to=None):
    rel = f' relative_to="{relative_to}"' if relative_to else ""
    return (f"<inertial><pose{rel}>{xyz}</pose><mass>{mass}</mass><inertia><ixx>{ixx}</ixx><ixy>{ixy}</ixy>"
            f"<ixz>{ixz}</ixz><iyy>{iyy}</iyy><iyz>{iyz}</iyz><izz>{izz}</izz></inertia></inertial>")


def _box(size, pose="0 0 0 0 0 0", tag="collision", relative_to=None):
    rel = f' relative_to="{relative_to}"' if relative_to else ""
    return (f'<{tag} name="c"><pose{rel}>{pose}</pose><geometry><box><size>{size}</size></box></geometry>'
            f"</{tag}>")


def _model(*parts, version="1.7"):
    return f'<?xml version="1.0"?>\n<sdf version="{version}">\n<model name="m">\n' + "\n".join(parts) + \
        "\n</model>\n</sdf>\n"


def _revolute(name, parent, child, pose=""):
    return (f'<joint name="{name}" type="revolute">{pose}<parent>{parent}</parent><child>{child}</child>'
            "<axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>")


def test_kuka_iiwa_as_sdf_and_as_urdf_give_the_same_verdicts_and_kinematics(capsys):
    folder = _pybullet_data() / "kuka_iiwa"
    _, doc = _audit(capsys, folder / "model.sdf", folder / "model_for_sdf.urdf")
    sdf, urdf = (doc["files"][str(folder / name)] for name in ("model.sdf", "model_for_sdf.urdf"))
    assert sdf["status"] == urdf["status"] == "ok" and sdf["format"] == "sdf"
    assert set(sdf["links"]) == set(urdf["links"])
    for name, entry in sdf["links"].items():
        twin = urdf["links"][name]
        if name == "lbr_iiwa_link_0":  # the files differ here: mass 0 in the SDF, 0.01 in the URDF
            assert entry["inertial"]["mass"] == 0 and twin["inertial"]["mass"] == 0.01
            assert entry["verdict"] == "inconsistent" and twin["verdict"] == "consistent"
            continue
        assert (entry["verdict"], entry["reason"]) == (twin["verdict"], twin["reason"]), name
        assert entry["inertial"]["inertia"] == twin["inertial"]["inertia"]
        assert entry["location"]["path"].endswith("model.sdf") and entry["location"]["startLine"] > 1
    assert sdf["counts"] == urdf["counts"]  # link_0 is the fixed base: not judged in either
    # the same tree: joint origins (the SDF writes pi/2 as 1.5708) and axes; CoMs in the same frames
    s, u = read_sdf(folder / "model.sdf"), read_urdf(folder / "model_for_sdf.urdf")
    by_child = {j.child: j for j in u.joints}
    for j in s.joints:
        assert np.allclose(j.origin, by_child[j.child].origin, atol=1e-4) and np.allclose(j.axis, by_child[j.child].axis)
        assert j.limits == pytest.approx(by_child[j.child].limits, abs=1e-5)
    for a in s.links:
        assert np.allclose(a.inertial.com, u.link(a.name).inertial.com, atol=1e-12)


def _corpus_sdf_files():
    files = sorted(_pybullet_data().rglob("*.sdf"))
    robots = robots_folder()
    if robots is not None:
        files += sorted(robots.rglob("*.sdf"))
    return files


def test_every_sdf_file_of_the_corpora_is_read_each_problem_with_a_line(capsys):
    files = _corpus_sdf_files()
    assert len(files) >= 15
    _, doc = _audit(capsys, *files)
    assert all(f["status"] == "ok" for f in doc["files"].values()), \
        [f.get("error") for f in doc["files"].values() if f["status"] != "ok"]
    links = sum(len(f["links"]) for f in doc["files"].values())
    assert links >= 200
    for f in doc["files"].values():
        for problem in f["problems"]:
            assert problem["location"]["startLine"] >= 1 and "startColumn" in problem["location"]
    if robots_folder() is not None:  # Cassie, shipped by example-robot-data only as SDF
        cassie = [f for path, f in doc["files"].items() if path.endswith("cassie.sdf")]
        assert cassie and len(cassie[0]["links"]) > 30


def test_cassie_hard_findings_are_real_in_the_numbers_of_the_file(capsys):
    """Every mass-exceeds-densest flag on Cassie is m > 22,600 kg/m^3 times the volume of the link's box or
    sphere, recomputed here from the file's own elements."""
    robots = robots_folder()
    if robots is None:
        pytest.skip("example-robot-data is not installed")
    path = next(robots.rglob("cassie.sdf"))
    _, doc = _audit(capsys, path)
    f = doc["files"][str(path)]
    flagged = [name for name, link in f["links"].items()
               for found in (link["bodies_inside"] or {}).get("findings", ()) if found["rule"] == "mass-exceeds-densest"]
    assert flagged
    from lxml import etree

    root = etree.parse(str(path)).getroot()
    for name in flagged:
        element = root.find(f".//link[@name='{name}']")
        mass = float(element.find("inertial/mass").text)
        holders = element.findall("collision") or element.findall("visual")
        volume = 0.0
        for holder in holders:
            shape = holder.find("geometry")[0]
            if shape.tag == "box":
                volume += np.prod([float(x) for x in shape.find("size").text.split()])
            elif shape.tag == "sphere":
                volume += 4 / 3 * np.pi * float(shape.find("radius").text) ** 3
            elif shape.tag == "cylinder":
                volume += np.pi * float(shape.find("radius").text) ** 2 * float(shape.find("length").text)
        assert mass > 22600 * volume, name


def test_a_bad_inertia_is_the_urdf_verdict_and_geometry_findings_fire(tmp_path, capsys):
    bad = ("0.01", "0.01", "0.03")  # A + B < C
    sdf = write(tmp_path, _model(
        f'<link name="base">{_inertial()}{_box("0.1 0.1 0.1")}</link>',
        f'<link name="l1"><pose>0 0 0.1 0 0 0</pose>{_inertial("0.7", "0.01 0.02 0.03 0 0 0", *bad)}'
        f'{_box("0.2 0.2 0.2")}</link>',
        # the 60 kg base in a 0.6 m box with 0.001 on the diagonal
        f'<link name="l2"><pose>0 0 0.3 0 0 0</pose>{_inertial("60", ixx="0.001", iyy="0.001", izz="0.001")}'
        f'{_box("0.6 0.6 0.6")}</link>',
        _revolute("j1", "base", "l1"), _revolute("j2", "l1", "l2")), "m.sdf")
    urdf = write(tmp_path, robot(link("base"), link("l1", inertial(0.7, "0.01 0.02 0.03", "0 0 0", *map(float, bad))),
                                 link("l2"), joint("j1", "base", "l1"), joint("j2", "l1", "l2")))
    code, doc = _audit(capsys, sdf, urdf)
    f, u = doc["files"][str(sdf)], doc["files"][str(urdf)]
    assert code == 1 and f["links"]["l1"]["verdict"] == "inconsistent" == u["links"]["l1"]["verdict"]
    assert f["links"]["l1"]["reason"] == u["links"]["l1"]["reason"]
    assert f["links"]["l1"]["location"]["startLine"] == 5
    assert f["links"]["l1"]["engines"]["gazebo"]["action"] == "rejects"
    assert f["links"]["l1"]["engines"]["mujoco"]["text"] == "does not read SDFormat"
    assert "l2: second-moment-below-densest-ball" in f["geometry_errors"]
    uniform = f["links"]["l2"]["bodies_inside"]["uniform"]["text"]
    assert uniform.startswith("<inertial><pose>0 0 0 0 0 0</pose><mass>60</mass>") and "<ixx>3.6</ixx>" in uniform


def test_relative_to_frames_place_the_geometry_and_the_joints(tmp_path, capsys):
    """A <frame> 0.5 m up: a box placed relative to it holds a CoM at z = 0.5 of the link, not one at 0; a link
    posed relative to a frame; a joint posed relative to its parent link."""
    text = _model(
        '<frame name="up" attached_to="l1"><pose relative_to="l1">0 0 0.5 0 0 0</pose></frame>',
        '<frame name="shelf"><pose>1 0 0 0 0 0</pose></frame>',
        f'<link name="base">{_inertial()}{_box("0.1 0.1 0.1")}</link>',
        f'<link name="l1"><pose relative_to="shelf">0 0 0.2 0 0 0</pose>'
        f'{_inertial("1", "0 0 0.5 0 0 0", ixx="0.002", iyy="0.002", izz="0.002")}'
        f'{_box("0.1 0.1 0.1", relative_to="up")}</link>',
        f'<link name="l2"><pose relative_to="l1">0 0 0.4 0 0 0</pose>'
        f'{_inertial("1", "0 0 0 0 0 0", ixx="0.002", iyy="0.002", izz="0.002")}'
        f'{_box("0.1 0.1 0.1", relative_to="up")}</link>',
        _revolute("j1", "base", "l1", '<pose relative_to="base">1 0 0.2 0 0 0</pose>'),
        _revolute("j2", "l1", "l2"), version="1.8")
    path = write(tmp_path, text, "frames.sdf")
    r = read_sdf(path)
    assert [p.pose.xyz for p in r.geometry["l1"].primitives] == [(0, 0, 0.5)]  # exact: 0.5 through 'up'
    assert np.allclose([float(x) for x in r.geometry["l2"].primitives[0].pose.xyz], [0, 0, 0.1])
    j1, j2 = r.joints
    assert np.allclose(j1.origin[:3, 3], [1, 0, 0.2]) and np.allclose(j2.origin[:3, 3], [0, 0, 0.4])
    _, doc = _audit(capsys, path)
    f = doc["files"][str(path)]
    assert "com-outside-geometry" not in [x["rule"] for x in f["links"]["l1"]["bodies_inside"]["findings"]]
    assert "l2: com-outside-geometry" in f["geometry_errors"]  # its CoM at its origin, the box 0.1 m above it
    bad = write(tmp_path, text.replace('relative_to="shelf"', 'relative_to="nowhere"'), "bad.sdf")
    with pytest.raises(InputError, match="relative_to 'nowhere' names no frame"):
        read_sdf(bad)


THREE = _model(
    '<link name="base"><pose>0 0 0 0 0 0</pose>' + _inertial() + "</link>",
    '<link name="camera"><pose>0 0 0.1 0 0 0</pose></link>',  # no <inertial>: SDFormat's 1 kg, unit diagonal
    '<link name="plate"><pose>0 0 0.2 0 0 0</pose><inertial><mass>0.5</mass></inertial></link>',  # no <inertia>
    '<link name="arm"><pose>0 0 0.3 0 0 0</pose><inertial><mass>heavy</mass><inertia><ixx>0.01</ixx>'
    "<iyy>0.01</iyy><izz>0.01</izz></inertia></inertial></link>",  # not a number
    _revolute("j1", "base", "camera"), _revolute("j2", "camera", "plate"), _revolute("j3", "plate", "arm"))


def test_three_problems_are_reported_with_their_lines_in_every_format(tmp_path, capsys):
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    path = write(tmp_path, THREE, "three.sdf")
    code, doc = _audit(capsys, path)
    f = doc["files"][str(path)]
    assert code == 1 and f["status"] == "ok"
    found = [(p["link"], p["kind"], p["location"]["startLine"]) for p in f["problems"]]
    assert found == [("camera", "sdformat_default", 5), ("plate", "sdformat_default", 6),
                     ("arm", "malformed_inertial", 7)]
    assert f["links"]["camera"]["inertial"]["mass"] == 1.0 and f["links"]["camera"]["inertial"]["inertia"]["ixx"] == 1
    assert f["links"]["plate"]["inertial"]["mass"] == 0.5 and f["links"]["plate"]["inertial"]["inertia"]["izz"] == 1
    assert f["links"]["arm"]["inertial"]["mass"] == 1.0  # the default in place of 'heavy'
    assert f["links"]["camera"]["engines"]["gazebo"]["action"] == "defaults"
    sarif = tmp_path / "a.sarif"
    assert cli.main(["audit", "--bounds", "none", "--sarif", str(sarif), str(path)]) == 1
    text = capsys.readouterr().out
    assert "problem camera (line 5" in text and "problem arm (line 7" in text
    log = valid_sarif(json.loads(sarif.read_text()))
    lines = sorted((r["ruleId"], r["locations"][0]["physicalLocation"]["region"]["startLine"])
                   for r in log["runs"][0]["results"] if r["ruleId"] in ("sdformat-default", "malformed-inertial"))
    assert lines == [("malformed-inertial", 7), ("sdformat-default", 5), ("sdformat-default", 6)]
    assert cli.main(["audit", "--bounds", "none", "--github", str(path)]) == 1
    commands = [c for c in capsys.readouterr().out.splitlines() if "sdformat-default" in c or "malformed" in c]
    assert len(commands) == 3 and all(c.startswith("::error ") and ",line=" in c for c in commands)


def test_a_folder_picks_up_sdf_files_and_bad_input_is_one_line(tmp_path, capsys):
    write(tmp_path, THREE, "model.sdf")
    write(tmp_path, '<?xml version="1.0"?>\n<sdf version="1.7"><model name="m"><link name="a">\n<inertial>'
          "<mass>1</mass></inertial></link><joint name='j' type='revolute'><parent>a</parent><child>zz</child>"
          "</joint></model></sdf>", "broken.sdf")
    code, doc = _audit(capsys, tmp_path)
    assert code == 2 and {Path(p).name for p in doc["files"]} == {"model.sdf", "broken.sdf"}
    error = doc["files"][str(tmp_path / "broken.sdf")]
    assert error["status"] == "error" and "joint 'j': 'zz' names no link" in error["error"]
    assert error["location"]["startLine"] == 3


def test_write_repaired_sdf_is_consistent_and_keeps_the_rest(tmp_path, capsys):
    bad = ("0.01", "0.01", "0.03")
    path = write(tmp_path, _model(
        f'<link name="base">{_inertial()}</link>',
        f'<link name="l1"><pose>0 0 0.1 0 0 0</pose>{_inertial("0.7", "0.01 0.02 0.03 0 0 0", *bad)}</link>',
        _revolute("j1", "base", "l1")), "m.sdf")
    before = path.read_text()
    fixed = tmp_path / "fixed.sdf"
    assert cli.main(["audit", "--bounds", "none", "--write-repaired", str(fixed), str(path)]) == 1
    capsys.readouterr()
    assert path.read_text() == before
    repaired = read_sdf(fixed)
    assert repaired.link("base").inertial.written == read_sdf(path).link("base").inertial.written
    code, doc = _audit(capsys, fixed)
    assert code == 0 and doc["files"][str(fixed)]["links"]["l1"]["verdict"] == "consistent"
    assert fixed.read_text().count("<inertia>") == 2 and "<pose>0.01 0.02 0.03 0 0 0</pose>" in fixed.read_text()


def test_nested_models_and_an_include_are_read(tmp_path, capsys):
    (tmp_path / "arm").mkdir()
    write(tmp_path / "arm", '<?xml version="1.0"?>\n<model><name>arm</name><sdf version="1.7">model.sdf</sdf></model>',
          "model.config")
    write(tmp_path / "arm", _model(f'<link name="upper">{_inertial("2", ixx="1", iyy="1", izz="3")}</link>',
                                   '<link name="bare"/>'), "model.sdf")
    world = ('<?xml version="1.0"?>\n<sdf version="1.7"><world name="w"><model name="robot">'
             f'<link name="base">{_inertial()}</link>'
             '<include><uri>model://arm</uri><name>left</name><pose>0 0.2 0 0 0 0</pose></include>'
             f'<model name="tool"><pose>0 0 1 0 0 0</pose><link name="tip">{_inertial()}</link></model>'
             '<joint name="j" type="revolute"><parent>base</parent><child>left::upper</child><axis><xyz>0 0 1</xyz>'
             "<limit><lower>-1</lower><upper>1</upper></limit></axis></joint>"
             '<joint name="k" type="fixed"><parent>base</parent><child>tool::tip</child></joint>'
             "</model></world></sdf>")
    path = write(tmp_path, world, "world.sdf")
    r = read_sdf(path)
    # two roots (base, and the included model's free link 'bare'): both free in the world
    assert [link.name for link in r.links] == ["world", "base", "left::upper", "left::bare", "tool::tip"]
    assert [(j.parent, j.child, j.type) for j in r.joints[2:]] == [("world", "base", "floating"),
                                                                   ("world", "left::bare", "floating")]
    (problem,) = r.problems  # in the included file: its message names that file and line, no location in this one
    assert problem.link == "left::bare" and f"(in {tmp_path / 'arm' / 'model.sdf'}, line 5)" in problem.message
    assert problem.span is None
    assert np.allclose(r.joints[1].origin[:3, 3], [0, 0, 1])
    code, doc = _audit(capsys, path)
    upper = doc["files"][str(path)]["links"]["left::upper"]
    assert code == 1 and upper["verdict"] == "inconsistent"  # 1 + 1 < 3, in the included file
    assert upper["location"]["path"].endswith("model.sdf") and upper["location"]["startLine"] == 4


ORACLE_FILES = ("kuka_iiwa/model.sdf", "kuka_iiwa/kuka_with_gripper.sdf", "gripper/wsg50_one_motor_gripper_new.sdf",
                "gripper/wsg50_with_r2d2_gripper.sdf", "gripper/wsg50_one_motor_gripper_no_finger.sdf")


def _pose(p, position, orientation):
    out = np.eye(4)
    out[:3, :3] = np.array(p.getMatrixFromQuaternion(orientation)).reshape(3, 3)
    out[:3, 3] = position
    return out


def test_the_centres_of_mass_are_where_pybullet_places_them():
    """pybullet's own SDF reader is the oracle: every link's CoM in its base link's frame at q = 0, from the audit's
    joint origins and CoMs, is pybullet's (getLinkState) to 1e-12."""
    p = pytest.importorskip("pybullet", reason="pybullet is not installed")
    folder = _pybullet_data()
    client = p.connect(p.DIRECT)
    try:
        compared = 0
        for name in ORACLE_FILES:
            p.resetSimulation(physicsClientId=client)
            (body,) = p.loadSDF(str(folder / name), physicsClientId=client)[:1]
            r = read_sdf(folder / name)
            parent = {j.child: j for j in r.joints}

            def frame(link, parent=parent):
                j = parent.get(link)
                return np.eye(4) if j is None else frame(j.parent) @ j.origin

            base = p.getBodyInfo(body, physicsClientId=client)[0].decode()
            position, orientation = p.getBasePositionAndOrientation(body, physicsClientId=client)
            info = p.getDynamicsInfo(body, -1, physicsClientId=client)
            root = _pose(p, position, orientation) @ np.linalg.inv(_pose(p, info[3], info[4]))
            for k in range(p.getNumJoints(body, physicsClientId=client)):
                link = r.link(p.getJointInfo(body, k, physicsClientId=client)[12].decode())
                theirs = np.linalg.inv(root) @ np.append(p.getLinkState(body, k, physicsClientId=client)[0], 1)
                mine = np.linalg.inv(frame(base)) @ frame(link.name) @ np.append(link.inertial.com, 1)
                assert np.allclose(mine, theirs, atol=1e-12), (name, link.name)
                compared += 1
    finally:
        p.disconnect(client)
    assert compared == 40
