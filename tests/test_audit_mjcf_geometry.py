"""MJCF geoms as the audit's geometry (:mod:`inertiaproof.audit.mjcf_geometry`): the hard findings of
:mod:`inertiaproof.audit.bodies_inside` on a body's geoms (placed by MuJoCo's compiler: angle units, euler, fromto),
decided here against independent rational arithmetic; the soft finding against MuJoCo's own inertia from the geoms;
and, on the dm_control and pybullet_data collections, no hard finding on a body whose inertia MuJoCo computed from
geoms no denser than the densest material."""

import glob
import json
import os
from fractions import Fraction

import numpy as np
import pytest
from test_audit_ci import valid_sarif
from urdf_samples import write

from inertiaproof import cli

mujoco = pytest.importorskip("mujoco", reason="MJCF reading needs the mujoco package (inertiaproof[mjcf])")

DENSEST = 22600


def _model(*bodies, compiler=""):
    return (f'<mujoco model="m"><compiler {compiler}/><worldbody>' + "".join(bodies) + "</worldbody></mujoco>")


def _body(name, geom, inertial="", z=0.0):
    return (f'<body name="{name}" pos="0 0 {z}"><joint name="j_{name}" type="hinge" axis="0 0 1"/>{geom}{inertial}'
            "</body>")


def _audit(capsys, path):
    code = cli.main(["audit", "--bounds", "none", "--workers", "1", "--json", str(path)])
    return code, next(iter(json.loads(capsys.readouterr().out)["files"].values()))


def _rules(f, name, hard=True):
    return sorted(x["rule"] for x in (f["links"][name]["bodies_inside"] or {"findings": []})["findings"]
                  if x["hard"] == hard)


BOX = '<geom type="box" size=".05 .04 .015"/>'  # a hand-sized box: 0.1 x 0.08 x 0.03 m


def test_a_declared_inertial_outside_its_box_geoms_bound_fires_the_hard_finding(tmp_path, capsys):
    hand = _body("hand", BOX, '<inertial pos="0 0 0" mass="0.5" diaginertia="0.5 0.5 0.5"/>')  # gyration ~1 m
    # the box's own inertia at 0.5 kg: m (b^2 + c^2) / 3 with half-sizes
    own = [0.5 * (0.04**2 + 0.015**2) / 3, 0.5 * (0.05**2 + 0.015**2) / 3, 0.5 * (0.05**2 + 0.04**2) / 3]
    fits = _body("fits", BOX, f'<inertial pos="0 0 0" mass="0.5" diaginertia="{own[0]!r} {own[1]!r} {own[2]!r}"/>',
                 z=0.5)
    code, f = _audit(capsys, write(tmp_path, _model(hand, fits), "m.xml"))
    assert code == 1 and "hand: outside-bounding-ellipsoid" in f["geometry_errors"]
    assert _rules(f, "fits") == [] and not f["links"]["fits"]["bodies_inside"]["not_decided"]
    # exactly (the box's half-sizes as MuJoCo's doubles): m - sum_k S_kk / a_k^2 < 0, a_k^2 = 3 b_k^2
    m, s = Fraction(1, 2), [Fraction(0.05), Fraction(0.04), Fraction(0.015)]
    assert m - sum((Fraction(3, 4) - Fraction(1, 2)) / (3 * b**2) for b in s) < 0
    (found,) = [x for x in f["links"]["hand"]["bodies_inside"]["findings"] if x["hard"]]
    assert "holding its geoms box" in found["message"] and f["links"]["hand"]["location"]["startLine"] == 1


def test_the_compilers_angle_units_euler_and_fromto_place_the_geoms(tmp_path, capsys):
    """A box 0.4 m long turned 90 degrees about z (euler in degrees) holds a CoM at (0, 0.15, 0), not one at
    (0.15, 0, 0); a capsule from (0, 0, 0) to (0.3, 0, 0) of radius 0.02 holds a CoM at x = 0.31 (its cap) and,
    enclosed by the cylinder from x = -0.02 to 0.32, not one at x = 0.33."""
    turned = '<geom type="box" size=".2 .01 .01" euler="0 0 90"/>'
    inertia = 'diaginertia="0.004 0.0001 0.004"'
    along = _body("along", turned, f'<inertial pos="0 0.15 0" mass="0.1" {inertia}/>')
    across = _body("across", turned, f'<inertial pos="0.15 0 0" mass="0.1" {inertia}/>', z=0.5)
    capsule = '<geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>'
    cap_inertia = 'diaginertia="0.00002 0.001 0.001"'
    in_cap = _body("in_cap", capsule, f'<inertial pos="0.31 0 0" mass="0.3" {cap_inertia}/>', z=1.0)
    beyond = _body("beyond", capsule, f'<inertial pos="0.33 0 0" mass="0.3" {cap_inertia}/>', z=1.5)
    code, f = _audit(capsys, write(tmp_path, _model(along, across, in_cap, beyond, compiler='angle="degree"'),
                                   "m.xml"))
    assert "com-outside-geometry" not in _rules(f, "along") and "com-outside-geometry" in _rules(f, "across")
    assert "com-outside-geometry" not in _rules(f, "in_cap") and "com-outside-geometry" in _rules(f, "beyond")
    assert "capsule or ellipsoid" in f["links"]["beyond"]["bodies_inside"]["geometry"]["note"]
    assert code == 1


def test_the_soft_finding_against_mujocos_own_inertia_from_the_geoms(tmp_path, capsys):
    cube = '<geom type="box" size=".1 .1 .1"/>'  # MuJoCo's moments at 1 kg: 0.02 / 3 = 0.00667 kg m^2
    small = _body("small", cube, '<inertial pos="0 0 0" mass="1" diaginertia="0.0006 0.0006 0.0006"/>')  # 11x
    near = _body("near", cube, '<inertial pos="0 0 0" mass="1" diaginertia="0.006 0.007 0.0065"/>', z=0.5)
    rod = '<geom type="box" size=".3 .02 .02"/>'  # radius of gyration sqrt(tr / 2m) = 0.174 m
    shifted = _body("shifted", rod, '<inertial pos="0.25 0 0" mass="1" diaginertia="0.000267 0.0301 0.0301"/>', z=1.0)
    code, f = _audit(capsys, write(tmp_path, _model(small, near, shifted), "m.xml"))
    assert code == 0 and f["geometry_errors"] == []  # soft findings: notes, not counted
    assert _rules(f, "small", hard=False) == ["unlike-mujoco-inertia"] and _rules(f, "small") == []
    message = f["links"]["small"]["bodies_inside"]["findings"][0]["message"]
    assert "MuJoCo's own inertia from its geoms" in message and "up to 11.1x off" in message
    assert _rules(f, "near", hard=False) == []
    assert _rules(f, "shifted", hard=False) == ["unlike-mujoco-inertia"]
    assert "radius of gyration 0.17" in f["links"]["shifted"]["bodies_inside"]["findings"][0]["message"]
    proposal = f["links"]["small"]["bodies_inside"]["uniform"]["text"]
    assert proposal.startswith('<inertial pos="0 0 0" quat="1 0 0 0" mass="1" diaginertia="0.00666666667')
    # the MuJoCo comparison names what MuJoCo itself computes with inertiafromgeom="true"
    spec = mujoco.MjSpec.from_string(_model(small, compiler='inertiafromgeom="true"'))
    model = spec.compile()
    assert np.allclose(model.body_inertia[1] / model.body_mass[1], 0.02 / 3)
    # in SARIF (valid against the schema) and GitHub annotations: notes
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    path, sarif = tmp_path / "m.xml", tmp_path / "m.sarif"
    assert cli.main(["audit", "--bounds", "none", "--sarif", str(sarif), str(path)]) == 0
    capsys.readouterr()
    log = valid_sarif(json.loads(sarif.read_text()))
    assert sorted(r["level"] for r in log["runs"][0]["results"] if r["ruleId"] == "unlike-mujoco-inertia") == \
        ["note", "note"]
    assert cli.main(["audit", "--bounds", "none", "--github", str(path)]) == 0
    assert sum(c.startswith("::notice ") and "unlike-mujoco-inertia" in c
               for c in capsys.readouterr().out.splitlines()) == 2


def _collections():
    files = []
    try:
        import dm_control

        files += sorted(glob.glob(os.path.join(os.path.dirname(dm_control.__file__), "suite", "*.xml")))
    except ImportError:
        pass
    try:
        import pybullet_data

        files += sorted(glob.glob(os.path.join(pybullet_data.getDataPath(), "mjcf", "*.xml")))
    except ImportError:
        pass
    return files


def test_no_hard_finding_on_mujocos_own_inertia_from_geoms_of_possible_density(capsys):
    """A body whose inertia MuJoCo computed from its geoms is a sum of solids inside them: no hard finding fires
    unless a geom is denser than the densest material (dm_control's point mass: 0.3 kg in a sphere of 1 cm;
    pybullet_data's striker coaster: 40 kg in a disk of 2 mm), and then the mass finding says so, with the density
    recomputed here from MuJoCo's own model."""
    files = _collections()
    if len(files) < 10:
        pytest.skip("dm_control and pybullet_data are not installed")
    code = cli.main(["audit", "--bounds", "none", "--workers", "1", "--json", *files])
    doc = json.loads(capsys.readouterr().out)
    checked, dense = 0, []
    for path, f in doc["files"].items():
        if f["status"] != "ok":
            continue
        for name, link in f["links"].items():
            found = link["bodies_inside"]
            if link["source"] != "geoms" or found is None or not (found.get("geometry") or {}).get("primitives"):
                continue
            checked += 1
            hard = [x for x in found["findings"] if x["hard"]]
            if hard:
                mass = next(x for x in hard if x["rule"] == "mass-exceeds-densest")["numbers"]
                assert mass["density"] > DENSEST
                dense.append((os.path.basename(path), name, mass["density"]))
    assert checked >= 100
    for file, name, density in dense:  # recomputed from MuJoCo: the body's mass over its geoms' volumes
        model = mujoco.MjModel.from_xml_path(next(p for p in files if p.endswith(os.sep + file)))
        b = model.body(name).id
        volume = 0.0
        for g in np.flatnonzero(model.geom_bodyid == b):
            size, kind = model.geom_size[g], model.geom_type[g]
            volume += {2: 4 / 3 * np.pi * size[0] ** 3, 5: np.pi * size[0] ** 2 * 2 * size[1],
                       6: 8 * np.prod(size)}[int(kind)]
        assert model.body_mass[b] / volume == pytest.approx(density, rel=1e-9) and density > DENSEST
    assert {name for _, name, _ in dense} <= {"pointmass", "coaster"} and code in (0, 1, 2)  # 2: files MuJoCo refuses
