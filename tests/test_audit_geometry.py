"""Hard and soft findings on the bodies inside a link's URDF primitives (:mod:`inertiaproof.audit.bodies_inside`):
each hard finding decided exactly on the decimals as written (a float-equal decimal across the boundary
decides the other way), checked here against independent rational arithmetic; none fires on a link whose
inertia is its own geometry's at uniform density; every output format carries them."""

import json
from fractions import Fraction

import numpy as np
import pytest
from test_audit_ci import valid_sarif
from urdf_samples import joint, robot, write

from inertiaproof import cli
from inertiaproof.audit.bodies_inside import HARD, ellipsoid
from inertiaproof.audit.geometry import Pose, Primitive
from inertiaproof.model.inertia import rotation_rpy
from inertiaproof.model.solids import solid, volume

PI_LOW, PI_HIGH = Fraction(333, 106), Fraction(355, 113)  # 333/106 < pi < 355/113
DENSEST = 22600


def _link(name, mass, xyz="0 0 0", rpy="0 0 0", inertia=(0.01, 0.01, 0.01, 0, 0, 0), geometry="", tag="collision"):
    ixx, iyy, izz, ixy, iyz, ixz = inertia
    shapes = "".join(f'<{tag}><origin xyz="{g_xyz}" rpy="{g_rpy}"/><geometry>{shape}</geometry></{tag}>'
                     for shape, g_xyz, g_rpy in geometry)
    return (f'<link name="{name}"><inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="{ixy}" iyz="{iyz}" ixz="{ixz}"/></inertial>'
            f'{shapes}</link>')


def _file(tmp_path, *links):
    """The links, the first a base, each other one moved by a revolute joint from the base."""
    parts = [_link("base", 1, geometry=[('<sphere radius="0.1"/>', "0 0 0", "0 0 0")], inertia=(0.004,) * 3 + (0,) * 3)]
    parts += list(links)
    names = [text.split('"')[1] for text in links]
    parts += [joint(f"j_{n}", "base", n) for n in names]
    return write(tmp_path, robot(*parts))


def _audit(capsys, path, *argv):
    code = cli.main(["audit", "--bounds", "none", "--json", *argv, str(path)])
    doc = json.loads(capsys.readouterr().out)
    return code, next(iter(doc["files"].values()))


def _rules(f, name, hard=True):
    return sorted(x["rule"] for x in (f["links"][name]["bodies_inside"] or {"findings": []})["findings"]
                  if x["hard"] == hard)


def test_the_60_kg_base_with_0001_on_the_diagonal(tmp_path, capsys):
    base = _link("base", 60, inertia=(0.001, 0.001, 0.001, 0, 0, 0),
                 geometry=[('<box size="0.6 0.6 0.6"/>', "0 0 0", "0 0 0")])
    path = write(tmp_path, robot(base, _link("l1", 1), joint("j1", "base", "l1")))
    code, f = _audit(capsys, path, "--floating-base")
    assert code == 1 and f["consistent"] and f["geometry_errors"] == ["base: second-moment-below-densest-ball"]
    (found,) = [x for x in f["links"]["base"]["bodies_inside"]["findings"] if x["hard"]]
    assert "tr(I_CoM) = 0.003 kg m^2 is below 6/5 m R^2 = 0.531" in found["message"]
    # exactly: tr^3 2000 pi^2 rho^2 < 1944 m^5 holds already with pi's upper bound
    assert Fraction(3, 1000) ** 3 * 2000 * PI_HIGH**2 * DENSEST**2 < 1944 * 60**5
    uniform = f["links"]["base"]["bodies_inside"]["uniform"]
    assert 'ixx="3.6" iyy="3.6" izz="3.6"' in uniform["text"] and uniform["span"]["startLine"] == 3
    assert _audit(capsys, path)[0] == 0  # a fixed base is not counted (its finding is a warning)


def test_a_centre_of_mass_outside_its_cylinder_decided_on_the_decimals(tmp_path, capsys):
    cylinder = [('<cylinder radius="0.05" length="0.2"/>', "0 0 0", "0 0 0")]
    inside = _link("l1", 1, xyz="0 0 0.1", inertia=(0.001, 0.001, 0.001, 0, 0, 0), geometry=cylinder)
    outside = _link("l2", 1, xyz="0 0 0.10000000000000001", inertia=(0.001, 0.001, 0.001, 0, 0, 0),
                    geometry=cylinder)
    assert float("0.10000000000000001") == 0.1  # the same double: only the decimal tells them apart
    code, f = _audit(capsys, _file(tmp_path, inside, outside))
    assert "com-outside-geometry" not in _rules(f, "l1") and "com-outside-geometry" in _rules(f, "l2")
    assert code == 1 and "l2: com-outside-geometry" in f["geometry_errors"]
    message = next(x["message"] for x in f["links"]["l2"]["bodies_inside"]["findings"])
    assert "centre of mass (0 0 0.1...)" in message  # not a decimal of 12 digits: shown as its float, marked
    assert "cylinder r 0.05 m, length 0.2 m" in message


def test_a_hand_sized_link_with_a_radius_of_gyration_of_a_metre(tmp_path, capsys):
    hand = _link("hand", "0.5", inertia=(0.5, 0.5, 0.5, 0, 0, 0),
                 geometry=[('<box size="0.1 0.08 0.03"/>', "0 0 0", "0 0 0")])
    code, f = _audit(capsys, _file(tmp_path, hand))
    assert code == 1 and "outside-bounding-ellipsoid" in _rules(f, "hand")
    # exactly: m - sum_k S_kk / a_k^2 < 0, S_kk = tr/2 - I_kk, a_k^2 = 3 (s_k / 2)^2
    m, s = Fraction(1, 2), [Fraction(1, 10), Fraction(8, 100), Fraction(3, 100)]
    assert m - sum((Fraction(3, 4) - Fraction(1, 2)) / (3 * (x / 2) ** 2) for x in s) < 0
    assert "second-moment-below-densest-ball" not in _rules(f, "hand")  # a metre is far above the ball's bound


def test_the_mass_the_densest_material_fits_is_decided_at_the_boundary(tmp_path, capsys):
    box = [('<box size="0.1 0.1 0.1"/>', "0 0 0", "0 0 0")]
    inertia = (0.1, 0.1, 0.1, 0, 0, 0)
    exact = _link("l1", "22.6", inertia=inertia, geometry=box)  # 22600 kg/m^3 * 0.001 m^3: fits, exactly
    over = _link("l2", "22.600000000000001", inertia=inertia, geometry=box)
    assert float("22.600000000000001") == 22.6
    code, f = _audit(capsys, _file(tmp_path, exact, over))
    assert "mass-exceeds-densest" not in _rules(f, "l1") and "mass-exceeds-densest" in _rules(f, "l2")
    code, f = _audit(capsys, _file(tmp_path, exact, over), "--max-density", "30000")
    assert "mass-exceeds-densest" not in _rules(f, "l2")
    # a cylinder: pi enters, decided by a ball; 1 kg in r 0.01, length 0.1 (at most 0.71 kg)
    cylinder = _link("l3", 1, inertia=inertia, geometry=[('<cylinder radius="0.01" length="0.1"/>', "0 0 0", "0 0 0")])
    assert Fraction(1) > DENSEST * PI_HIGH * Fraction(1, 100) ** 2 * Fraction(1, 10)
    code, f = _audit(capsys, _file(tmp_path, cylinder))
    assert "mass-exceeds-densest" in _rules(f, "l3")


UNIFORM = [  # (shape, dims for solids.solid, URDF element, origin xyz, origin rpy)
    ("box", (0.3, 0.2, 0.1), '<box size="0.3 0.2 0.1"/>', "0 0 0", "0 0 0"),
    ("box", (0.6, 0.04, 0.04), '<box size="0.6 0.04 0.04"/>', "0.1 -0.2 0.3", "0.4 -1.1 2.5"),
    ("cylinder", (0.05, 0.4), '<cylinder radius="0.05" length="0.4"/>', "0 0 0.2", "0 1.5707963267948966 0"),
    ("cylinder", (0.2, 0.02), '<cylinder radius="0.2" length="0.02"/>', "0.01 0.02 0.03", "0.3 0.2 0.1"),
    ("sphere", (0.07,), '<sphere radius="0.07"/>', "0 0.5 0", "0 0 0"),
]


@pytest.mark.parametrize("in_link_axes", [False, True])
def test_no_hard_finding_on_the_uniform_inertia_of_its_own_geometry(tmp_path, capsys, in_link_axes):
    links = []
    for k, (shape, dims, element, xyz, rpy) in enumerate(UNIFORM):
        for density in (150.0, 2700.0, 22000.0):  # up to near the densest material
            mass = float(f"{density * volume(shape, dims):.6g}")
            rotation = rotation_rpy([float(x) for x in rpy.split()])
            phi = solid(shape, mass, dims)  # about its centre, in its own axes: diagonal
            inertia = np.diag(phi[4:7])
            if in_link_axes:  # the inertia turned into the link's axes, the inertial origin unturned
                inertia, inertial_rpy = rotation @ inertia @ rotation.T, "0 0 0"
            else:
                inertial_rpy = rpy
            six = tuple(repr(float(inertia[a, b])) for a, b in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2)))
            links.append(_link(f"l{k}_{density:g}".replace(".", "_"), mass, xyz, inertial_rpy, six,
                               [(element, xyz, rpy)]))
    code, f = _audit(capsys, _file(tmp_path, *links))
    flagged = {name: _rules(f, name) for name in f["links"] if _rules(f, name)}
    assert flagged == {} and code == 0
    assert all(not link["bodies_inside"]["not_decided"] for link in f["links"].values())


def test_each_primitive_lies_in_its_ellipsoid():
    """Every corner of a box, rim point of a cylinder and pole of a sphere is in the ellipsoid, exactly (the
    cylinder's rim points (3/5 r, 4/5 r, +-eta) and (r, 0, +-eta) are rational)."""
    def inside(primitive, points):
        centre, _, squared = ellipsoid([primitive])
        return [sum(Fraction(str(p[k])) ** 2 / Fraction(str(squared[k])) for k in range(3)) for p in points]

    box = Primitive("box", (Fraction(3, 10), Fraction(1, 5), Fraction(1, 10)), Pose())
    corners = [(sx * Fraction(3, 20), sy * Fraction(1, 10), sz * Fraction(1, 20))
               for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    assert inside(box, corners) == [1] * 8  # on the ellipsoid: it is the one through the corners
    r, eta = Fraction(1, 20), Fraction(1, 5)
    cylinder = Primitive("cylinder", (r, 2 * eta), Pose())
    rim = [(x, y, z) for x, y in ((r, 0), (3 * r / 5, 4 * r / 5), (0, -r)) for z in (eta, -eta)]
    assert inside(cylinder, rim) == [1] * 6  # 2/3 + 1/3
    sphere = Primitive("sphere", (Fraction(7, 100),), Pose())
    assert inside(sphere, [(Fraction(7, 100), 0, 0), (0, 0, Fraction(-7, 100))]) == [1, 1]


def test_several_primitives_and_turned_ones(tmp_path, capsys):
    spheres = [('<sphere radius="0.05"/>', "0 0 0.1", "0 0 0"), ('<sphere radius="0.05"/>', "0 0 -0.1", "0 0 0")]
    between = _link("between", 1, geometry=spheres, inertia=(0.01, 0.01, 0.001, 0, 0, 0))  # in the hull, no sphere
    beyond = _link("beyond", 1, xyz="0.06 0 0", geometry=spheres, inertia=(0.01, 0.01, 0.001, 0, 0, 0))
    # a box 0.4 long turned 90 degrees about z (as written: 1.5707963267948966) holds (0, 0.15, 0), not (0.15, 0, 0)
    turned = [('<box size="0.4 0.02 0.02"/>', "0 0 0", "0 0 1.5707963267948966")]
    along = _link("along", 0.1, xyz="0 0.15 0", geometry=turned, inertia=(0.004, 0.0001, 0.004, 0, 0, 0))
    across = _link("across", 0.1, xyz="0.15 0 0", geometry=turned, inertia=(0.004, 0.0001, 0.004, 0, 0, 0))
    # pr2_gripper.urdf's right_tip (pybullet_data): two turned boxes whose bounding box is centred on z = 0 (a
    # ball holding zero, which flint's arb ** 2 would make nan), a radius of gyration of 3 m
    tips = [('<box size="0.03 0.01 0.02"/>', "0.105 0.015 0", "-3.1415 0 0"),
            ('<box size="0.01 0.02 0.02"/>', "0.095 0.005 0", "-3.1415 0 -0.5")]
    tip = _link("tip", 0.1, inertia=(1, 1, 1, 0, 0, 0), geometry=tips)
    code, f = _audit(capsys, _file(tmp_path, between, beyond, along, across, tip))
    assert "outside-bounding-ellipsoid" in _rules(f, "tip") and not f["links"]["tip"]["bodies_inside"]["not_decided"]
    assert "com-outside-geometry" not in _rules(f, "between")
    assert any(n.startswith("com-outside-geometry") for n in f["links"]["between"]["bodies_inside"]["not_decided"])
    assert "com-outside-geometry" in _rules(f, "beyond")  # outside the bounding box of both
    assert "com-outside-geometry" not in _rules(f, "along") and "com-outside-geometry" in _rules(f, "across")


def test_geometry_not_read_is_named_and_visual_is_used_without_collision(tmp_path, capsys):
    mesh = _link("mesh", 60, inertia=(0.001, 0.001, 0.001, 0, 0, 0),
                 geometry=[('<mesh filename="package://x/a.stl"/>', "0 0 0", "0 0 0")])
    visual = _link("visual", 1, xyz="0 0 1", geometry=[('<sphere radius="0.1"/>', "0 0 0", "0 0 0")], tag="visual")
    bad = _link("bad", 1, geometry=[('<box size="0.1 0.1"/>', "0 0 0", "0 0 0")])
    code, f = _audit(capsys, _file(tmp_path, mesh, visual, bad))
    assert f["links"]["mesh"]["bodies_inside"]["geometry"]["not_read"].startswith(
        "link 'mesh': package://x/a.stl: package 'x' not found")  # meshes: tests/test_audit_meshes.py
    assert _rules(f, "mesh") == ["second-moment-below-densest-ball"]  # needs no geometry
    assert f["links"]["bad"]["bodies_inside"]["geometry"]["not_read"].endswith(
        "link 'bad': <box size=\"0.1 0.1\"> is not 3 decimal numbers")
    assert f["links"]["visual"]["bodies_inside"]["geometry"]["source"] == "visual"
    assert "com-outside-geometry" in _rules(f, "visual")


def test_every_output_format_carries_the_findings(tmp_path, capsys):
    pytest.importorskip("jsonschema", reason="jsonschema is not installed")
    hand = _link("hand", "0.5", inertia=(0.5, 0.5, 0.5, 0, 0, 0),
                 geometry=[('<box size="0.1 0.08 0.03"/>', "0 0 0", "0 0 0")])
    path = _file(tmp_path, hand)
    sarif = tmp_path / "audit.sarif"
    assert cli.main(["audit", "--bounds", "none", "--sarif", str(sarif), str(path)]) == 1
    text = capsys.readouterr().out
    assert "finding outside-bounding-ellipsoid: link 'hand'" in text and "uniform hand: <inertial>" in text
    log = valid_sarif(json.loads(sarif.read_text()))
    results = [r for r in log["runs"][0]["results"] if r["ruleId"] in HARD]
    (result,) = results
    assert result["level"] == "error" and result["ruleId"] == "outside-bounding-ellipsoid"
    (change,) = result["fixes"][0]["artifactChanges"]
    inserted = change["replacements"][0]["insertedContent"]["text"]
    assert inserted.startswith("<inertial>") and 'ixx="0.000304166667"' in inserted
    assert cli.main(["audit", "--bounds", "none", "--github", str(path)]) == 1
    commands = capsys.readouterr().out.splitlines()
    assert any(c.startswith("::error ") and "title=inertiaproof outside-bounding-ellipsoid" in c for c in commands)
    assert any(c.startswith("::notice ") and "inertia-unlike-geometry" in c for c in commands)
