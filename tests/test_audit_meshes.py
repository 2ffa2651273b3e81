"""Findings on the bodies inside a link's mesh geometry (:mod:`inertiaproof.audit.mesh_bodies`): each hard finding
fires on a bad inertia of a small box mesh and not on the mesh's own uniform-density inertia (checked against the
box formula of :mod:`inertiaproof.model.solids` and exact arithmetic); ``package://`` (package.xml, folder name,
``--package``), relative and ``file://`` URIs; a scaled mesh; a mesh that is not watertight (hull findings only);
and the corpus test: every watertight mesh link of example-robot-data and pybullet_data, given its own
uniform-density inertia, has no hard finding."""

import json
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from urdf_samples import joint, robot, robots_folder

from inertiaproof import cli
from inertiaproof.audit.geometry import Pose
from inertiaproof.audit.mesh_bodies import _read_parts, _uniform, link_findings, mvee
from inertiaproof.audit.mesh_files import MeshUnread
from inertiaproof.audit.urdf import Inertial, read_urdf
from inertiaproof.errors import InputError

trimesh = pytest.importorskip("trimesh")

SIZE = (0.2, 0.1, 0.05)  # m
VOLUME = Fraction(1, 1000)  # 0.2 * 0.1 * 0.05 exactly (the STL's float32 values are not: see _box)


def _box(path, size=SIZE, drop_face=False):
    """A box mesh centred at the origin, written as STL or OBJ by trimesh."""
    mesh = trimesh.creation.box(extents=size)
    if drop_face:
        mesh = trimesh.Trimesh(mesh.vertices, mesh.faces[1:], process=False)
    path.parent.mkdir(parents=True, exist_ok=True)
    mesh.export(path)
    return path


def _link(name, mass, uri, xyz="0 0 0", inertia=None, scale=None, origin=""):
    if inertia is None:  # the box's own inertia at uniform density
        a, b, c = SIZE
        inertia = (mass * (b * b + c * c) / 12, mass * (a * a + c * c) / 12, mass * (a * a + b * b) / 12, 0, 0, 0)
    ixx, iyy, izz, ixy, iyz, ixz = (repr(float(x)) for x in inertia)
    scaled = f' scale="{scale}"' if scale else ""
    return (f'<link name="{name}"><inertial><origin xyz="{xyz}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="{ixy}" iyz="{iyz}" ixz="{ixz}"/></inertial>'
            f'<collision>{origin}<geometry><mesh filename="{uri}"{scaled}/></geometry></collision></link>')


def _file(folder, *links, name="robot.urdf"):
    base = '<link name="base"><inertial><mass value="1"/><inertia ixx="0.004" iyy="0.004" izz="0.004" ixy="0" ' \
           'iyz="0" ixz="0"/></inertial></link>'
    names = [text.split('"')[1] for text in links]
    path = Path(folder) / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(robot(base, *links, *[joint(f"j_{n}", "base", n) for n in names]))
    return path


def _audit(capsys, path, *argv):
    code = cli.main(["audit", "--bounds", "none", "--json", *argv, str(path)])
    doc = json.loads(capsys.readouterr().out)
    return code, next(iter(doc["files"].values()))


def _rules(f, name, hard=True):
    return sorted(x["rule"] for x in f["links"][name]["bodies_inside"]["findings"] if x["hard"] == hard)


def test_each_hard_finding_fires_on_a_bad_inertia_of_a_box_mesh_and_not_on_its_own(tmp_path, capsys):
    _box(tmp_path / "box.stl")
    _box(tmp_path / "box.obj")
    rho_v = 22600 * float(VOLUME)  # 22.6 kg: the most the box holds
    links = [
        _link("own", 2.7, "box.stl"),  # aluminium, its own inertia
        _link("own_obj", 7.8, "box.obj"),  # steel
        _link("heavy", round(rho_v * 1.001, 6), "box.stl"),
        _link("almost", round(rho_v * 0.999, 6), "box.stl"),
        _link("outside", 2.7, "box.stl", xyz="0.1001 0 0"),  # the box ends at x = 0.1
        _link("edge", 2.7, "box.stl", xyz="0.0999 0 0"),
        _link("ball", 60, "box.stl", inertia=(0.001, 0.001, 0.001, 0, 0, 0)),
        _link("gyration", 0.5, "box.stl", inertia=(0.5, 0.5, 0.5, 0, 0, 0)),  # a radius of gyration of a metre
    ]
    code, f = _audit(capsys, _file(tmp_path, *links))
    assert code == 1
    mesh = f["links"]["own"]["bodies_inside"]["geometry"]["meshes"][0]
    assert mesh["watertight"] and mesh["winding_consistent"] and mesh["fit"]
    assert abs(mesh["signed_volume"] - float(VOLUME)) < 1e-9 and mesh["volume_error"] < 1e-15
    assert _rules(f, "own") == [] and _rules(f, "own_obj") == [] and _rules(f, "almost") == []
    assert _rules(f, "heavy") == ["mass-exceeds-densest"]
    (found,) = [x for x in f["links"]["heavy"]["bodies_inside"]["findings"] if x["hard"]]
    assert found["numbers"]["bound"] == "the meshes' own volume" and "22.6226 kg exceeds" in found["message"]
    assert "com-outside-geometry" in _rules(f, "outside") and "com-outside-geometry" not in _rules(f, "edge")
    assert "second-moment-below-densest-ball" in _rules(f, "ball")
    assert "outside-bounding-ellipsoid" in _rules(f, "gyration")
    # exactly, for the box's corner ellipsoid (semi-axes sqrt(3) s_k / 2): m - sum_k S_kk / a_k^2 < 0
    m, s = Fraction(1, 2), [Fraction(x).limit_denominator(1000) for x in SIZE]
    assert m - sum((Fraction(3, 4) - Fraction(1, 2)) / (3 * (x / 2) ** 2) for x in s) < 0
    # the uniform proposal is the box's (solids' formula), at the CoM of the mesh
    uniform = f["links"]["own"]["bodies_inside"]["uniform"]
    a, b, c = SIZE
    assert np.allclose(sorted(uniform["principal_moments"]), sorted([2.7 * (b * b + c * c) / 12, 2.7 * (a * a + c * c) / 12,
                                                                     2.7 * (a * a + b * b) / 12]), rtol=1e-6)
    assert np.allclose(uniform["com"], 0, atol=1e-9) and uniform["text"].startswith("<inertial><origin xyz=")
    assert "inertia-unlike-geometry" in _rules(f, "gyration", hard=False)


def test_a_scaled_and_placed_mesh_gives_the_same_findings(tmp_path, capsys):
    _box(tmp_path / "mm.stl", size=tuple(1000 * x for x in SIZE))  # a CAD export in millimetres
    origin = '<origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/>'  # turned a quarter about z, moved 0.5 m along x
    links = [_link("own", 2.7, "mm.stl", xyz="0.5 0 0", scale="0.001 0.001 0.001", origin=origin,
                   inertia=(2.7 * (0.2**2 + 0.05**2) / 12, 2.7 * (0.1**2 + 0.05**2) / 12, 2.7 * (0.2**2 + 0.1**2) / 12,
                            0, 0, 0)),  # the box's long side now along y
             _link("outside", 2.7, "mm.stl", xyz="0.56 0 0", scale="0.001 0.001 0.001", origin=origin),
             _link("unscaled", 2.7, "mm.stl")]
    _, f = _audit(capsys, _file(tmp_path, *links))
    assert _rules(f, "own") == []
    assert abs(f["links"]["own"]["bodies_inside"]["geometry"]["volume_bounds"]["the meshes' own volume"]
               - float(VOLUME)) < 1e-9
    assert np.allclose(f["links"]["own"]["bodies_inside"]["uniform"]["com"], [0.5, 0, 0], atol=1e-9)
    assert "com-outside-geometry" in _rules(f, "outside")  # 0.56 > 0.5 + 0.05: outside once turned
    assert _rules(f, "unscaled") == []  # a million times the volume: nothing is too heavy for it
    assert "implausible-density" in _rules(f, "unscaled", hard=False)


def test_a_mesh_that_is_not_watertight_supports_only_hull_findings(tmp_path, capsys):
    _box(tmp_path / "open.stl", drop_face=True)
    links = [_link("open", 2.7, "open.stl"), _link("heavy", 22.7, "open.stl"),
             _link("outside", 2.7, "open.stl", xyz="0 0 0.03")]
    _, f = _audit(capsys, _file(tmp_path, *links))
    inside = f["links"]["open"]["bodies_inside"]
    assert not inside["geometry"]["meshes"][0]["watertight"] and not inside["geometry"]["meshes"][0]["fit"]
    assert "only its convex hull is used" in inside["geometry"]["note"]
    assert inside["uniform"] is None and "the meshes' own volume" not in inside["geometry"]["volume_bounds"]
    assert _rules(f, "open") == [] and not _rules(f, "open", hard=False)
    found = [x for x in f["links"]["heavy"]["bodies_inside"]["findings"] if x["hard"]]
    assert [x["rule"] for x in found] == ["mass-exceeds-densest"] and found[0]["numbers"]["bound"] == "its bounding box"
    assert "com-outside-geometry" in _rules(f, "outside")


def test_package_uris_are_resolved_by_package_xml_folder_name_and_option(tmp_path, capsys):
    workspace = tmp_path / "ws" / "src"
    _box(workspace / "meshes_pkg" / "meshes" / "box.stl")
    (workspace / "meshes_pkg" / "package.xml").write_text("<package><name>my_meshes</name></package>")
    _box(workspace / "named" / "box.obj")
    _box(tmp_path / "elsewhere" / "box.stl")
    absolute = _box(tmp_path / "abs" / "box.stl")
    links = [_link("by_xml", 2.7, "package://my_meshes/meshes/box.stl"),
             _link("by_name", 2.7, "package:///named/box.obj"),
             _link("by_option", 2.7, "package://far_away/box.stl"),
             _link("by_file", 2.7, f"file://{absolute}"),
             _link("relative", 2.7, "../../meshes_pkg/meshes/box.stl")]
    path = _file(workspace / "my_robot" / "urdf", *links)
    code, f = _audit(capsys, path)
    for name in ("by_xml", "by_name", "by_file", "relative"):
        geometry = f["links"][name]["bodies_inside"]["geometry"]
        assert geometry["not_read"] is None and geometry["meshes"][0]["fit"], name
    why = f["links"]["by_option"]["bodies_inside"]["geometry"]["not_read"]
    assert "package 'far_away' not found" in why and "--package far_away=DIR" in why
    code, f = _audit(capsys, path, "--package", f"far_away={tmp_path / 'elsewhere'}")
    assert f["links"]["by_option"]["bodies_inside"]["geometry"]["meshes"][0]["path"] == str(tmp_path / "elsewhere" /
                                                                                           "box.stl")
    assert code == 0
    assert cli.main(["audit", "--package", "nothing", str(path)]) == 2
    assert "--package needs NAME=DIR" in capsys.readouterr().err


def test_a_mesh_that_cannot_be_read_is_named(tmp_path, capsys):
    (tmp_path / "broken.stl").write_bytes(b"solid nothing\nendsolid\n")
    _, f = _audit(capsys, _file(tmp_path, _link("broken", 1, "broken.stl"), _link("missing", 1, "gone.stl")))
    assert f["links"]["missing"]["bodies_inside"]["geometry"]["not_read"].startswith("link 'missing': gone.stl: no such")
    assert "broken.stl" in f["links"]["broken"]["bodies_inside"]["geometry"]["not_read"]


def test_the_minimum_volume_ellipsoid_of_a_box_is_its_corner_ellipsoid():
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 2) for z in (0, 3)], float)
    centre, a = mvee(corners)
    assert np.allclose(centre, [0.5, 1, 1.5], atol=1e-3)
    assert np.allclose(np.sort(np.linalg.eigvalsh(a) ** -0.5), np.sqrt(3) * np.array([0.5, 1, 1.5]), rtol=1e-2)


# -- the corpora ------------------------------------------------------------------

def _corpora():
    out = []
    robots = robots_folder()
    if robots is not None:
        out.append(robots)
    try:
        import pybullet_data

        out.append(Path(pybullet_data.getDataPath()))
    except ImportError:
        pass
    return out


def _uniform_links(folder):
    """(file, link, Inertial, LinkGeometry) for every link of the folder's URDFs whose geometry is all watertight
    meshes (and primitives), given its own uniform-density inertia at 1000 and at 20,000 kg/m^3; each placement of
    the same meshes once."""
    seen = set()
    paths = sorted(folder.rglob("*.urdf"))
    randoms = [p for p in paths if "random_urdfs" in p.parts]  # pybullet_data's 1000 random objects: every 25th
    for path in [p for p in paths if "random_urdfs" not in p.parts] + randoms[::25]:
        try:
            r = read_urdf(path)
        except InputError:  # the files the audit refuses (tests/test_real_robots.py)
            continue
        for name, geometry in r.geometry.items():
            if not geometry.meshes or geometry.unread:
                continue
            try:
                parts = _read_parts(geometry, None)
            except MeshUnread:
                continue
            meshes = [mesh for _, mesh, _ in parts if mesh is not None]
            key = tuple((m.sha256, part.pose, getattr(part, "scale", None)) for (part, m, _) in parts if m) + \
                tuple((p.kind, p.dims, p.pose) for p in geometry.primitives)
            if not all(m.fit for m in meshes) or key in seen:
                continue
            seen.add(key)
            volume = sum(abs(float(np.prod([float(s) for s in part.scale]))) * m.signed_volume
                         for part, m, _ in parts if m is not None)
            for density in (1000.0, 20000.0):
                mass = density * volume
                com, inertia = _uniform(mass, parts)
                six = (inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2])
                written = tuple(repr(float(x)) for x in (mass, *six))
                xyz = tuple(Fraction(repr(float(x))) for x in com)
                inertial = Inertial(mass, np.array(com), np.eye(3), inertia, written)
                yield path, name, inertial, replace(geometry, inertial_pose=Pose(xyz))


@pytest.mark.slow
@pytest.mark.skipif(not _corpora(), reason="neither example-robot-data nor pybullet is installed")
def test_no_hard_finding_on_the_uniform_inertia_of_the_corpora_watertight_meshes():
    flagged, count = [], 0
    for folder in _corpora():
        for path, name, inertial, geometry in _uniform_links(folder):
            out = link_findings(name, inertial, geometry)
            count += 1
            hard = [x["rule"] for x in out["findings"] if x["hard"]]
            if hard:
                flagged.append((str(path), name, hard, out["findings"][0]["message"][:300]))
    assert count > 200 and flagged == []
    print(f"\n{count} links at their own uniform-density inertia, no hard finding")


@pytest.mark.slow
@pytest.mark.skipif(robots_folder() is None, reason="example-robot-data is not installed")
def test_every_centre_outside_a_mesh_hull_is_outside_by_scipy_delaunay():
    """Each com-outside-geometry on a mesh link of example-robot-data, checked against SciPy's Delaunay
    triangulation of the link's mesh vertices (trimesh's own reading, placed in floats) and its primitives' box
    corners: the centre is in no simplex of it."""
    from scipy.spatial import Delaunay

    from inertiaproof.audit.document import audit_paths
    from inertiaproof.audit.mesh_files import resolve
    from inertiaproof.model.inertia import rotation_rpy

    with np.errstate(all="ignore"):
        files = audit_paths([robots_folder()], samples=512, rounds=2, bounds="none")
    checked = 0
    for path, f in files.items():
        if f["status"] != "ok" or not path.endswith(".urdf"):
            continue
        for name, entry in f["links"].items():
            inside = entry.get("bodies_inside") or {}
            if not (inside.get("geometry") or {}).get("meshes") or \
                    "com-outside-geometry" not in {x["rule"] for x in inside["findings"]}:
                continue
            geometry = read_urdf(path).geometry[name]
            points = []
            for p in geometry.primitives:  # a primitive by its bounding box's corners, which hold it
                d = [float(x) for x in p.dims]
                half = {"box": [x / 2 for x in d], "cylinder": [d[0], d[0], d[1] / 2], "sphere": d * 3}[p.kind]
                corners = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]) * half
                points.append(corners @ rotation_rpy([float(x) for x in p.pose.rpy]).T + [float(x) for x in p.pose.xyz])
            for part in geometry.meshes:
                v = trimesh.load(resolve(part.uri, part.base), force="mesh").vertices * [float(s) for s in part.scale]
                points.append(v @ rotation_rpy([float(x) for x in part.pose.rpy]).T + [float(x) for x in part.pose.xyz])
            centre = np.array([float(x) for x in geometry.inertial_pose.xyz])
            assert Delaunay(np.concatenate(points)).find_simplex(centre) < 0, (path, name)
            checked += 1
    assert checked > 50
