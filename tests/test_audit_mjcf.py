"""MJCF in the audit: as-written inertias against URDF, kinematics and repairs against MuJoCo, the engine column
against the engines that install here, and the MJCF collections of pybullet_data and dm_control."""

import glob
import os
import warnings

import numpy as np
import pytest

from inertiaproof import cli
from inertiaproof.audit.document import audit_paths, audit_robot
from inertiaproof.audit.engines import engine_column
from inertiaproof.audit.kinematic_tree import kinematic_tree
from inertiaproof.audit.mjcf import read_mjcf
from inertiaproof.audit.urdf import read_urdf
from inertiaproof.dynamics.composite import mass_matrix
from inertiaproof.errors import InputError
from inertiaproof.model.inertia import rotation_rpy
from urdf_samples import inertial, joint, link, robot, write

mujoco = pytest.importorskip("mujoco", reason="MJCF reading needs the mujoco package (inertiaproof[mjcf])")

NONE = dict(samples=64, rounds=0, bounds="none")
BAD = (0.01, 0.01, 0.03, 0.002, -0.001, 0.0005)  # ixx iyy izz ixy iyz ixz: the triangle inequality fails


def mjcf(body_inertial, compiler="", extra=""):
    return (f'<mujoco model="m"><compiler {compiler}/><worldbody><body name="l1" pos="0 0 0.1">'
            f'<joint name="j1" type="hinge" axis="0 0 1" range="-1.5 1.5"/><geom type="box" size=".05 .05 .05"/>'
            f'{body_inertial}{extra}</body></worldbody></mujoco>')


def urdf_twin(ixx, iyy, izz, ixy, iyz, ixz, xyz="0.01 0.02 0.03", rpy="0 0 0"):
    return robot(link("base"), link("l1", inertial(0.7, xyz, rpy, ixx, iyy, izz, ixy, iyz, ixz)),
                 joint("j1", "base", "l1", xyz="0 0 0.1"))


def test_a_bad_fullinertia_gets_the_verdict_and_reason_of_the_same_urdf(tmp_path):
    ixx, iyy, izz, ixy, iyz, ixz = BAD
    xml = write(tmp_path, mjcf(f'<inertial pos="0.01 0.02 0.03" mass="0.7" '
                               f'fullinertia="{ixx} {iyy} {izz} {ixy} {ixz} {iyz}"/>'), "m.xml")
    urdf = write(tmp_path, urdf_twin(*BAD))
    from_mjcf = audit_robot(read_mjcf(xml), **NONE)["links"]["l1"]
    from_urdf = audit_robot(read_urdf(urdf), **NONE)["links"]["l1"]
    assert from_mjcf["verdict"] == from_urdf["verdict"] == "inconsistent"
    assert from_mjcf["reason"] == from_urdf["reason"]
    assert from_mjcf["source"] == "fullinertia" and from_mjcf["location"]["startLine"] == 1
    assert from_mjcf["engines"]["mujoco"]["action"] == "rejects"
    with pytest.raises(ValueError, match="A \\+ B >= C"):  # what MuJoCo itself does with the file
        mujoco.MjModel.from_xml_path(str(xml))


def _r(axis, angle):
    return rotation_rpy(np.eye(3)[axis] * angle)


ORIENTATIONS = [  # compiler, inertial orientation, its rotation (inertial axes -> body axes)
    ('angle="radian"', 'euler="0.3 -0.2 0.5"', _r(0, 0.3) @ _r(1, -0.2) @ _r(2, 0.5)),  # default eulerseq xyz: moving axes
    ('angle="degree" eulerseq="XYZ"', 'euler="20 -10 40"', rotation_rpy(np.radians([20, -10, 40]))),  # fixed axes: URDF rpy
    ('eulerseq="zyx"', 'euler="30 0 -60"', _r(2, np.radians(30)) @ _r(0, np.radians(-60))),
    ("", 'axisangle="0 0 1 90"', _r(2, np.pi / 2)),
    ("", 'quat="0 1 0 0"', _r(0, np.pi)),
]


@pytest.mark.parametrize("compiler, orientation, rotation", ORIENTATIONS)
def test_the_inertial_frame_follows_the_compilers_angle_and_eulerseq(tmp_path, compiler, orientation, rotation):
    xml = write(tmp_path, mjcf(f'<inertial pos="0.01 0.02 0.03" mass="0.7" {orientation} diaginertia="0.01 0.02 0.025"/>',
                               compiler), "m.xml")
    r = read_mjcf(xml)
    assert np.allclose(r.links[1].inertial.rotation, rotation, atol=1e-12)
    if 'eulerseq="XYZ"' in compiler:  # the URDF with the same rpy has the same Phi in the link frame
        u = read_urdf(write(tmp_path, urdf_twin(0.01, 0.02, 0.025, 0, 0, 0, rpy=" ".join(
            repr(float(a)) for a in np.radians([20, -10, 40])))))
        assert np.allclose(r.link_phis()[1], u.link_phis()[1], rtol=1e-12, atol=1e-15)


def _mujoco_mass_matrix(model, q):
    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0 + q
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, full)
    return full


CHAIN = """<mujoco model="c"><compiler angle="radian"/><worldbody>
<body name="a" pos="0.1 0 0.2" euler="0.2 0.1 0"><joint name="s" type="slide" axis="1 0 0" range="-0.5 0.5"/>
  <joint name="h1" type="hinge" axis="0 0 1" pos="0.05 0 0" range="-2 2"/><joint name="h2" type="hinge" axis="0 1 0.3"
   pos="0 0.02 0" range="-1 1" ref="0.3"/><geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.04"/>
  <body name="b" pos="0.3 0 0" quat="0.9 0 0.3 0.1"><joint name="h3" type="hinge" axis="1 0 0" pos="0 0 0.03"
   range="-2 2"/><geom type="box" size="0.1 0.03 0.02" pos="0.1 0 0"/>
   <body name="c" pos="0.2 0 0"><geom type="sphere" size="0.03"/><inertial pos="0.01 0 0" mass="0.3"
    diaginertia="0.001 0.002 0.0025" euler="0.1 0.2 0.3"/><joint name="h4" type="hinge" axis="0 0 1"/></body></body>
</body></worldbody></mujoco>"""


def test_chains_from_mjcf_joints_give_mujocos_mass_matrix(tmp_path):
    """Joint frames at hinge pivots, slides, several joints in one body, ref offsets and rotated bodies: the
    audit's chain M(q) is MuJoCo's mass matrix (mj_fullM) at qpos0 + q."""
    path = write(tmp_path, CHAIN, "c.xml")
    r = read_mjcf(path)
    (sc,) = kinematic_tree(r).chains
    model = mujoco.MjModel.from_xml_path(str(path))
    assert [j.name for j in sc.chain.joints] == ["s", "h1", "h2", "h3", "h4"]
    assert sc.chain.joints[2].limits == pytest.approx((-1.3, 0.7))  # range relative to ref
    for q in np.random.default_rng(0).uniform(-0.8, 0.8, (5, 5)):
        assert np.allclose(mass_matrix(sc.chain, q, sc.theta), _mujoco_mass_matrix(model, q), rtol=1e-9, atol=1e-12)


def test_multi_joint_bodies_are_joint_frames_not_bodies_and_their_chain_is_decided(tmp_path):
    path = write(tmp_path, CHAIN, "c.xml")
    audit = audit_robot(read_mjcf(path), **NONE)
    assert audit["links"]["a/s"]["role"] == "joint_frame" and not audit["bodies"]["a/s"]["judged"]
    assert audit["consistent"] and audit["links"]["a"]["source"] == "geoms"
    assert audit["links"]["c"]["source"] == "diaginertia"
    (chain,) = audit["chains"].values()
    assert chain["singular"]["verdict"] == "never" and "MuJoCo body" in chain["singular"]["argument"]


def test_three_hinges_in_one_body_are_not_decided_by_structure(tmp_path):
    hinges = "".join(f'<joint name="r{a}" type="hinge" axis="{v}"/>' for a, v in zip("xyz", ("1 0 0", "0 1 0", "0 0 1")))
    path = write(tmp_path, f'<mujoco><worldbody><body name="b">{hinges}<geom type="sphere" size=".1"/></body>'
                           '</worldbody></mujoco>', "g.xml")
    (chain,) = audit_robot(read_mjcf(path), **NONE)["chains"].values()
    assert chain["singular"]["verdict"] == "not_excluded" and "gimbal" in chain["singular"]["argument"]


def test_free_and_ball_joints_are_reported_and_left_out(tmp_path):
    path = write(tmp_path, '<mujoco><worldbody><body name="f"><freejoint name="free"/><geom type="sphere" size=".1"/>'
                           '<body name="k" pos="0 0 .3"><joint name="ball" type="ball"/><geom type="sphere" size=".1"/>'
                           '<body name="t" pos="0 0 .3"><joint name="h" type="hinge"/><geom type="sphere" size=".1"/>'
                           '</body></body></body></worldbody></mujoco>', "f.xml")
    audit = audit_robot(read_mjcf(path), **NONE)
    assert {j["joint"]: j["type"] for j in audit["left_out_joints"]} == {"free": "floating", "ball": "ball"}
    assert [c["name"] for c in audit["chains"].values()] == ["k -> t"]


def test_mjcf_that_mujoco_cannot_read_is_one_line_naming_mujoco(tmp_path):
    path = write(tmp_path, '<mujoco><worldbody><body><joint type="fixed"/></body></worldbody></mujoco>', "x.xml")
    with pytest.raises(InputError, match=r"x.xml: MuJoCo .* cannot read it: .*fixed"):
        read_mjcf(path)


@pytest.mark.parametrize("kind", ["fullinertia", "diaginertia"])
def test_write_repaired_mjcf_loads_in_mujoco_and_passes_the_audit(tmp_path, capsys, kind):
    numbers = "0.01 0.01 0.03 0.002 0.0005 -0.001" if kind == "fullinertia" else "0.01 0.01 0.03"
    body = mjcf(f'<inertial pos="0 0 0.01" mass="0.7" euler="0 0 0" {kind}="{numbers}"/>'
                .replace('euler="0 0 0" ', "" if kind == "fullinertia" else 'euler="0 0 0" '))
    # a geom large enough to hold the repaired inertia (no 0.7 kg body in a 0.1 m cube has moments of 0.01 kg m^2:
    # the audit's bounding-ellipsoid finding, :mod:`inertiaproof.audit.mjcf_geometry`)
    path = write(tmp_path, body.replace('size=".05 .05 .05"', 'size=".3 .3 .3"'), "m.xml")
    before = path.read_bytes()
    out = tmp_path / "fixed.xml"
    assert cli.main(["audit", str(path), "--bounds", "none", "--write-repaired", str(out)]) == 1
    diff = capsys.readouterr().out
    assert path.read_bytes() == before and "-" in diff and "+" in diff and kind in diff
    mujoco.MjModel.from_xml_path(str(out))  # MuJoCo now loads it
    assert cli.main(["audit", str(out), "--bounds", "none"]) == 0


CASES = {  # mass, (ixx, iyy, izz, ixy, iyz, ixz)
    "consistent": (1.0, (0.01, 0.02, 0.025, 0, 0, 0)),
    "degenerate": (1.0, (0.01, 0.01, 0.02, 0, 0, 0)),
    "excess 1e-15": (1.0, (0.01, 0.01, 0.02 + 1e-15, 0, 0, 0)),
    "excess 1e-12 small": (1e-3, (1e-6, 1e-6, 2e-6 + 1e-12, 0, 0, 0)),
    "inconsistent": (1.0, (0.01, 0.01, 0.03, 0, 0, 0)),
    "products": (1.0, (0.01, 0.01, 0.01, 0.009, 0.009, 0.009)),
    "point mass": (1.0, (0, 0, 0, 0, 0, 0)),
    "massless with inertia": (0.0, (0.01, 0.02, 0.025, 0, 0, 0)),
    "negative mass": (-1.0, (0.01, 0.02, 0.025, 0, 0, 0)),
    "negative moment": (1.0, (-0.01, 0.02, 0.025, 0, 0, 0)),
    "tiny but consistent": (1e-3, (1e-15, 1.5e-15, 2e-15, 0, 0, 0)),
}


def _engine_case(tmp_path, name):
    mass, six = CASES[name]
    text = robot(link("base", inertial(1.0)),
                 link("l1", inertial(mass, "0 0 0", "0 0 0", *six) + '<collision><geometry><box size="0.1 0.2 0.3"/>'
                      '</geometry></collision>'), joint("j1", "base", "l1", xyz="0 0 0"))
    path = write(tmp_path, text, "case.urdf")
    predicted = audit_robot(read_urdf(path), **NONE)["links"]["l1"]["engines"]
    return path, predicted


@pytest.mark.parametrize("name", CASES)
def test_the_mujoco_column_is_what_mujoco_does(tmp_path, name):
    path, predicted = _engine_case(tmp_path, name)
    try:
        mujoco.MjModel.from_xml_path(str(path))
        outcome, message = "loads", ""
    except ValueError as exc:
        outcome, message = "rejects", str(exc)
    assert predicted["mujoco"]["action"] == outcome
    if outcome == "rejects":
        assert predicted["mujoco"]["text"].removeprefix("rejects: ") in message


@pytest.mark.parametrize("first, tool, want", [
    (inertial(1.0), inertial(0.2, ixx=0.001, iyy=0.001, izz=0.01), "rejects"),  # checked before fusing
    (inertial(0.0, ixx=0, iyy=0, izz=0), inertial(0.2), "loads"),  # a massless moving body with a welded mass
    (inertial(1e-16), inertial(0.2), "loads"),
    (inertial(1e-16), inertial(0.0, ixx=0, iyy=0, izz=0), "rejects"),
])
def test_the_mujoco_column_follows_welded_links(tmp_path, first, tool, want):
    path = write(tmp_path, robot(link("base"), link("l1", first), link("tool", tool), joint("j1", "base", "l1"),
                                 joint("jt", "l1", "tool", kind="fixed")))
    links = audit_robot(read_urdf(path), **NONE)["links"]
    predicted = [links[name]["engines"]["mujoco"]["action"] for name in ("l1", "tool")]
    try:
        mujoco.MjModel.from_xml_path(str(path))
        actual = "loads"
    except ValueError:
        actual = "rejects"
    assert actual == want and ("rejects" in predicted) == (want == "rejects")


@pytest.mark.parametrize("name", CASES)
def test_the_pybullet_column_is_what_pybullet_does(tmp_path, name):
    pybullet = pytest.importorskip("pybullet", reason="pybullet is not installed")
    path, predicted = _engine_case(tmp_path, name)
    client = pybullet.connect(pybullet.DIRECT)
    try:
        body = pybullet.loadURDF(str(path), flags=pybullet.URDF_USE_INERTIA_FROM_FILE, useFixedBase=True,
                                 physicsClientId=client)
        info = pybullet.getDynamicsInfo(body, 0, physicsClientId=client)
    finally:
        pybullet.disconnect(client)
    zeroed = not any(info[2]) and any(CASES[name][1])
    assert (predicted["pybullet"]["action"] == "zeroes") == zeroed


def test_engines_disagree_where_their_tolerances_differ():
    """A 1e-15 excess on a 0.02 moment: MuJoCo, PyBullet and Gazebo refuse it, Drake's 16 eps absolute floor takes it."""
    actions = {k: v["action"] for k, v in engine_column(1.0, np.diag([0.01, 0.01, 0.02 + 1e-15]), fmt="urdf",
                                                         moving=True).items()}
    assert actions == {"mujoco": "rejects", "drake": "loads", "pybullet": "zeroes", "gazebo": "rejects"}
    balanced = engine_column(1.0, np.diag([0.01, 0.01, 0.03]), fmt="mjcf", moving=True, full=False,
                             compiler={"balanceinertia": True})["mujoco"]
    assert balanced["action"] == "balances" and "0.0166667" in balanced["text"]


# -- the collections ---------------------------------------------------------------

def _collection(folder):
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        return audit_paths(sorted(glob.glob(os.path.join(folder, "*.xml"))), samples=64, rounds=0, bounds="arms")


def _check_collection(files):
    for path, f in files.items():
        if f["status"] != "ok":
            assert "MuJoCo" in f["error"] and ("cannot read it" in f["error"] or "cannot compile it" in f["error"])
            continue
        for name, entry in f["links"].items():
            assert entry["verdict"] in ("consistent", "degenerate", "inconsistent")
            if entry["source"] == "geoms" and not entry["massless_frame"]:  # sums of solids: consistent
                assert entry["verdict"] == "consistent", (path, name, entry["reason"])
                assert entry["engines"]["mujoco"]["action"] == "loads"
        assert f["consistent"], (path, f["not_consistent"])
    return sum(f["status"] == "ok" for f in files.values())


def test_pybullet_data_mjcf_files_are_audited():
    pybullet_data = pytest.importorskip("pybullet_data", reason="pybullet (pybullet_data) is not installed")
    files = _collection(os.path.join(pybullet_data.getDataPath(), "mjcf"))
    assert len(files) >= 20
    assert _check_collection(files) >= 10


def test_dm_control_suite_mjcf_files_are_audited():
    dm_control = pytest.importorskip("dm_control", reason="dm-control is not installed")
    files = _collection(os.path.join(os.path.dirname(dm_control.__file__), "suite"))
    assert len(files) >= 15
    assert _check_collection(files) == len(files)
    dog = next(f for p, f in files.items() if p.endswith("dog.xml"))
    assert {link["source"] for link in dog["links"].values()} >= {"geoms", "diaginertia", "joint_frame"}
