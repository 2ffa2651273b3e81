"""The URDF reader (one-line errors naming the element) and the extracted chains against Pinocchio."""

import numpy as np
import pytest
from urdf_samples import inertial, joint, link, random_configurations, robot, robots_folder, two_link_arm, write

from inertiaproof.audit.kinematic_tree import kinematic_tree, phi_in_frame
from inertiaproof.audit.urdf import read_urdf
from inertiaproof.dynamics.terms import mass_matrix
from inertiaproof.errors import InputError
from inertiaproof.model.consistency import DEGENERATE, INCONSISTENT, physical_consistency
from inertiaproof.model.inertia import from_urdf, rotation_rpy, unit_body

BAD_FILES = {  # an <inertial> urdfdom reads past is a problem of its link, not an error: tests/test_audit_problems.py
    "bad xml": ("<robot name='r'><link name='a'></robot>", r"not well-formed XML at line 1"),
    "empty": ("  \n", r"empty file"),
    "not a robot": ("<model name='r'/>", r"root element is <model>"),
    "robot without name": ("<robot><link name='a'/></robot>", r"<robot> misses attribute 'name'"),
    "no links": ("<robot name='r'/>", r"robot 'r' has no <link> elements"),
    "link without name": ("<robot name='r'><link/></robot>", r"a <link> misses attribute 'name'"),
    "duplicate link": (robot(link("a"), link("a")), r"two links are named 'a'"),
    "huge value": (robot(link("a", inertial(izz="1.7e308"))), r"link 'a': <inertia> attribute izz=\"1.7e308\" is out of range"),
    "inf joint origin": (robot(link("a"), link("b"), joint("j", "a", "b", xyz="0 inf 0")),
                         r"joint 'j': <origin> attribute xyz=\"0 inf 0\" is not finite"),
    "missing link": (robot(link("a"), joint("j", "a", "ghost")), r"joint 'j': <child link='ghost'> names no link"),
    "joint type": (robot(link("a"), link("b"), joint("j", "a", "b", kind="hinge")), r"joint 'j': type 'hinge' is not one of"),
    "no limit": (robot(link("a"), link("b"), joint("j", "a", "b").replace('<limit lower="-1.5" upper="1.5" effort="1" velocity="1"/>', "")),
                 r"joint 'j': a revolute joint needs <limit>"),
    "unexpanded xacro": (robot(link("a"), link("b"), joint("j", "a", "b", xyz="$(arg x) 0 0")),
                         r"joint 'j': <origin> attribute xyz=\"\$\(arg x\) 0 0\" is an unexpanded xacro expression"),
    "commas": (robot(link("a"), link("b"), joint("j", "a", "b", xyz="0.07, 0, -0.69")),
               r"joint 'j': <origin> attribute xyz=\"0.07, 0, -0.69\" is not a number"),
    "zero axis": (robot(link("a"), link("b"), joint("j", "a", "b", axis="0 0 0")), r"joint 'j': <axis xyz=\"0 0 0\"> is the zero vector"),
    "two parents": (robot(link("a"), link("b"), link("c"), joint("j1", "a", "c"), joint("j2", "b", "c")),
                    r"link 'c' is the child of two joints, 'j1' and 'j2'"),
    "cycle": (robot(link("a"), link("b"), link("c"), joint("j1", "a", "b"), joint("j2", "b", "c"), joint("j3", "c", "b")),
              r"link 'b' is the child of two joints"),
    "pure cycle": (robot(link("r"), link("a"), link("b"), joint("ja", "b", "a"), joint("jb", "a", "b")),
                   r"joints .* form a cycle"),
    "two roots": (robot(link("a"), link("b")), r"2 root links \('a', 'b'\): a URDF is one tree"),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_malformed_urdf_is_one_line_naming_the_element(tmp_path, case):
    text, message = BAD_FILES[case]
    path = write(tmp_path, text)
    with pytest.raises(InputError, match=message) as info:
        read_urdf(path)
    assert "\n" not in str(info.value) and str(path) in str(info.value)


ARM = two_link_arm()
TOLERATED = {  # what pybullet (and urdfdom) read: (text, warning, check of the robot read)
    "xml version 0.0": (ARM.replace('<?xml version="1.0"?>', '<?xml version="0.0" ?>'),
                        'the XML declaration says version "0.0"', None),
    "blank lines first": ("\n\n" + ARM, "blank lines before the XML declaration", None),
    "NUL at the end": (ARM + "\x00", "NUL bytes after the end", None),
    "xacro leftover": (ARM.replace('<robot name="test">', '<robot name="test" xmlns:xacro="http://ros.org/wiki/xacro">'
                                   '<xacro:property name="w" value="1"/>'), "leftover <xacro:property>", None),
    "optenv": (ARM.replace('rpy="0.5 0 0.2"', 'rpy="$(optenv ARM_RPY 0.5 0 0.2)"'), "(the default of $(optenv)",
               lambda r: np.allclose(r.joints[1].origin[:3, :3], rotation_rpy([0.5, 0, 0.2]))),
    "four numbers": (ARM.replace('rpy="0.5 0 0.2"', 'rpy="0.5 0 0.2 0"'), "has 4 numbers; the first 3 are read",
                     lambda r: np.allclose(r.joints[1].origin[:3, :3], rotation_rpy([0.5, 0, 0.2]))),
    "two axes": (ARM.replace('<axis xyz="0 1 0"/>', '<axis xyz="0 1 0"/><axis xyz="1 0 0"/>'),
                 "has 2 <axis> elements; the first is read", lambda r: np.allclose(r.joints[1].axis, [0, 1, 0])),
    "reversed limits": (ARM.replace('lower="-1.5" upper="1.5"', 'lower="1" upper="-1"', 1),
                        "lower 1 > upper -1, which Bullet reads as no limit", lambda r: r.joints[0].limits is None),
    "spherical joint": (ARM.replace('type="revolute"', 'type="spherical"', 1).replace(
        '<limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>', "</joint>", 1), "is spherical",
        lambda r: r.joints[0].type == "spherical"),
}


@pytest.mark.parametrize("case", sorted(TOLERATED))
def test_what_engines_read_is_read_with_a_warning(tmp_path, case):
    text, warning, check = TOLERATED[case]
    path = tmp_path / "r.urdf"
    path.write_bytes(text.encode())
    r = read_urdf(path)
    assert any(warning in w for w in r.warnings), r.warnings
    assert [link.name for link in r.links] == ["base", "l1", "l2"] and (check is None or check(r))


def test_engine_specific_geometry_is_not_read(tmp_path):
    text = two_link_arm().replace('<link name="base">', '<link name="base"><collision><geometry><plane normal="0 0 1"/>'
                                  '</geometry></collision><visual><geometry><cdf filename="x.cdf"/></geometry></visual>')
    assert read_urdf(write(tmp_path, text)).warnings == ()


def only_file(path):
    from inertiaproof.audit.api import audit_urdf

    (doc,) = audit_urdf(path, bounds="none").document["files"].values()
    return doc


def test_spherical_joints_are_left_out_of_the_audit(tmp_path):
    text = TOLERATED["spherical joint"][0]
    doc = only_file(write(tmp_path, text))
    assert doc["left_out_joints"][0]["type"] == "spherical" and any("spherical" in w for w in doc["warnings"])


def test_inertia_is_judged_on_its_decimals_as_written(tmp_path):
    plate = robot(link("a", inertial(mass="1", ixx="0.1", iyy="0.7", izz="0.8")))
    entry = only_file(write(tmp_path, plate))["links"]["a"]
    assert entry["verdict"] == "degenerate" and entry["float64_verdict"] == "inconsistent"
    assert "as float64: inconsistent" in entry["reason"]


def test_unreadable_path_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        read_urdf(tmp_path / "missing.urdf")


def test_reader_keeps_numbers_as_written(tmp_path):
    path = write(tmp_path, two_link_arm())
    r = read_urdf(path)
    l1 = r.link("l1").inertial
    assert l1.mass == 1.0 and np.array_equal(l1.com, [0.1, 0, 0.05])
    assert np.allclose(l1.rotation, rotation_rpy([0.3, 0.2, 0.1]), atol=1e-15)
    assert np.array_equal(np.diag(l1.inertia), [0.01, 0.02, 0.025])
    assert np.allclose(l1.phi, from_urdf(1.0, [0.1, 0, 0.05], np.diag([0.01, 0.02, 0.025]), rotation_rpy([0.3, 0.2, 0.1])))
    assert [(j.name, j.type, j.limits) for j in r.joints] == [("j1", "revolute", (-1.5, 1.5)), ("j2", "revolute", (-1.5, 1.5))]


def test_verdict_on_the_inertia_as_written_decides_a_thin_rod_exactly(tmp_path):
    """A line mass (principal moments a, a, 0) off the link origin stays degenerate: the rigid shift's rounding is not decided."""
    rod = inertial(0.0307, "0 -0.009 -0.089", "0.1 0.2 0.3", 0.00012, 0.00012, 0.0)
    r = read_urdf(write(tmp_path, robot(link("rod", rod))))
    exact = physical_consistency(r.link("rod").inertial.phi_at_com)
    assert exact.verdict == DEGENERATE and exact.degenerate_rank == 1
    shifted = physical_consistency(r.link("rod").phi)
    assert shifted.verdict in (DEGENERATE, INCONSISTENT)  # rounding of the shift may go either way


def test_phi_in_frame_matches_the_parallel_axis_theorem():
    rng = np.random.default_rng(1)
    for _ in range(5):
        rot, p = rotation_rpy(rng.normal(size=3)), rng.normal(size=3)
        com, ic = rng.normal(size=3), np.diag(rng.uniform(1, 2, 3))
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = rot, p
        expected = from_urdf(2.0, p + rot @ com, rot @ ic @ rot.T)
        assert np.allclose(phi_in_frame(from_urdf(2.0, com, ic), pose), expected, rtol=1e-13, atol=1e-13)
    assert np.allclose(phi_in_frame(unit_body(), np.eye(4)), unit_body())


def test_phi_in_frame_is_linear_also_for_inconsistent_bodies():
    rng = np.random.default_rng(2)
    a, b = rng.normal(size=10), rng.normal(size=10)
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation_rpy([0.1, -0.4, 2.0]), [1.0, 2.0, -0.5]
    assert np.allclose(phi_in_frame(a + 3 * b, pose), phi_in_frame(a, pose) + 3 * phi_in_frame(b, pose))


def test_tree_merges_fixed_links_into_their_body(tmp_path):
    tool = inertial(0.2, "0.01 0 0", "0 0 0", 1e-4, 1e-4, 1e-4)
    r = read_urdf(write(tmp_path, two_link_arm(tool=tool)))
    tree = kinematic_tree(r)
    assert tree.role("base") == ("base", "base") and tree.role("l2") == ("body", "l2")
    assert tree.role("tool") == ("merged", "l2")
    (sc,) = tree.chains
    assert [j.name for j in sc.chain.joints] == ["j1", "j2"] and sc.base == "base"
    tool_pose = np.eye(4)
    tool_pose[:3, :3], tool_pose[:3, 3] = rotation_rpy([0, 0.4, 0]), [0.1, 0.02, 0]
    expected = r.link("l2").phi + phi_in_frame(r.link("tool").phi, tool_pose)
    assert np.allclose(sc.theta[1], expected, rtol=1e-14, atol=1e-16)


def test_floating_joint_is_left_out_and_its_child_is_a_base(tmp_path):
    text = robot(link("world", ""), link("trunk"), link("leg"), joint("free", "world", "trunk", kind="floating"),
                 joint("hip", "trunk", "leg"))
    tree = kinematic_tree(read_urdf(write(tmp_path, text)))
    assert tree.left_out == (("free", "floating"),)
    assert tree.role("trunk") == ("base", "trunk")
    (sc,) = tree.chains
    assert sc.base == "trunk" and [j.name for j in sc.chain.joints] == ["hip"]


pinocchio = pytest.importorskip("pinocchio")
from pinocchio_urdf import chain_only_xml, crba  # noqa: E402


def _compare(path, sc, model, count=4):
    names = [j.name for j in sc.chain.joints]
    qs = random_configurations(sc.chain, count)
    ours = mass_matrix(sc.chain.body_jacobian(qs), sc.theta)
    for q, m in zip(qs, ours):
        theirs = crba(model, names, q)
        assert np.allclose(m, theirs, rtol=1e-11, atol=1e-13 * np.abs(theirs).max()), (path, sc.name, q)


def test_small_arm_against_pinocchio(tmp_path):
    path = write(tmp_path, two_link_arm(tool=inertial(0.2, "0.01 0 0", "0 0.3 0", 1e-4, 2e-4, 2.5e-4)))
    (sc,) = kinematic_tree(read_urdf(path)).chains
    model = pinocchio.buildModelFromUrdf(str(path))
    _compare(path, sc, model)
    without_tool = type(sc)(sc.name, sc.base, sc.chain, np.stack([sc.theta[0], read_urdf(path).link("l2").phi]), sc.bodies)
    with pytest.raises(AssertionError):
        _compare(path, without_tool, model)


ROBOTS = robots_folder()
needs_robots = pytest.mark.skipif(ROBOTS is None, reason="example-robot-data is not installed (test extra)")


@needs_robots
def test_every_chain_of_every_shipped_robot_against_pinocchio():
    """Single-chain arms against Pinocchio's model of the whole file; every chain against Pinocchio's model of its links."""
    from inertiaproof.audit.document import is_serial_arm

    whole_file_checks = 0
    for path in sorted(ROBOTS.rglob("*.urdf")):
        if path.name == "ur3.urdf":  # shipped empty
            continue
        tree = kinematic_tree(read_urdf(path))
        if len(tree.chains) == 1 and is_serial_arm(tree.chains) and not tree.left_out:
            _compare(path, tree.chains[0], pinocchio.buildModelFromUrdf(str(path)))
            whole_file_checks += 1
        for sc in tree.chains:
            _compare(path, sc, pinocchio.buildModelFromXML(chain_only_xml(path, tree, sc)), count=2)
    assert whole_file_checks >= 15
