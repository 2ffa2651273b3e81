"""MuJoCo MJCF files read into the audit's links and joints.

MuJoCo itself reads the file (the ``mujoco`` package, the optional extra
``inertiaproof[mjcf]``): its parser resolves includes, defaults, child
classes, frames and the compiler's ``angle`` and ``eulerseq``, and its
compiler places bodies and joints. The numbers the audit judges are

- for a body with an ``<inertial>``: its ``mass``, ``pos`` and ``diaginertia``
  or ``fullinertia`` as written (M(1,1), M(2,2), M(3,3), M(1,2), M(1,3),
  M(2,3)), in the frame of its ``quat``/``euler``/``axisangle``/``xyaxes``/
  ``zaxis`` as MuJoCo resolves it. These bodies get a stand-in inertia
  before compiling, so that a bad inertia, which MuJoCo refuses, is audited
  instead of ending the reading;
- for a body without one (or every body, with ``inertiafromgeom="true"``):
  the mass, CoM, principal axes and moments MuJoCo computed from its geoms
  (after ``boundmass``, ``boundinertia``, ``balanceinertia`` and
  ``settotalmass``), said so in the audit (``source: geoms``).

Joints become the audit's joints: a hinge is ``revolute`` (``continuous``
without limits), a slide ``prismatic``, a free joint ``floating`` and a ball
joint ``ball`` (both reported and left out; their body becomes a base), and
a body without joints is welded to its parent (``fixed``). MuJoCo turns a
hinge about the axis through its ``pos`` and applies a body's joints in
order, so a body with k joints becomes k - 1 massless joint frames
(``body/joint``) and the body, each frame placed at its joint's pivot;
a range is relative to the joint's ``ref`` (qpos0).

Each body's geoms are the audit's geometry of its link, and MuJoCo's own inertia from them (the spec compiled
again with ``inertiafromgeom="true"``) is held against a declared inertial (:mod:`.mjcf_geometry`).

MuJoCo's parser does not expand DTD entities: a model (or a file it
includes) that uses internal ones is given to MuJoCo with them expanded in
place, after the checks of :mod:`.entities` (external entities refused).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from lxml import etree

from inertiaproof.errors import InputError
from inertiaproof.model.inertia import urdf_inertia

from . import entities
from .locate import Source, decode, element_spans
from .mjcf_geometry import body_geometry, mujoco_inertia
from .urdf import Inertial, Link, Robot, UrdfJoint

__all__ = ["is_mjcf", "read_mjcf"]

X_AXIS = np.array([1.0, 0.0, 0.0])


def is_mjcf(path):
    """Whether a file's root element is ``<mujoco>`` (read up to the first start tag)."""
    try:
        for _, element in etree.iterparse(str(path), events=("start",), resolve_entities=False, no_network=True,
                                          load_dtd=False, huge_tree=False):
            return element.tag == "mujoco"
    except OSError:
        return False
    except etree.XMLSyntaxError:  # e.g. an entity in the root's start tag: its name decides (the reader names the rest)
        return _root_name(path) == "mujoco"
    return False


def _root_name(path):
    """The name of the first start tag after the prolog (comments, processing instructions, DOCTYPE), or None."""
    try:
        with open(path, "rb") as f:
            text = decode(f.read(1 << 20))[0]
    except OSError:
        return None
    span = entities.doctype_span(text)
    if span is not None:
        text = text[:span[0]] + text[span[1]:]
    found = re.search(r"<([A-Za-z_][\w.\-]*)", re.sub(r"<!--.*?-->|<\?.*?\?>", "", text, flags=re.S))
    return found.group(1) if found else None


def read_mjcf(path):
    """The robot in an MJCF file; raises InputError with MuJoCo's one-line message when MuJoCo cannot read it."""
    path = Path(path)
    try:
        import mujoco  # the optional extra inertiaproof[mjcf]
    except ImportError:
        raise InputError(f"{path}: reading MJCF needs the mujoco package: pip install 'inertiaproof[mjcf]'") from None
    expanded = _expanded(path)
    try:
        if expanded is None:
            spec = mujoco.MjSpec.from_file(str(path))
        else:  # entities expanded in place: MuJoCo's line numbers stay the file's
            text, include = expanded
            spec = mujoco.MjSpec.from_string(text, include=include or None)
            spec.modelfiledir = str(path.parent)  # meshes, textures and hfields as from the file
    except Exception as exc:  # MuJoCo raises ValueError with its parser's message
        raise InputError(f"{path}: MuJoCo {mujoco.__version__} cannot read it: {_one_line(exc)}") from None
    compiler = {"balanceinertia": bool(spec.compiler.balanceinertia), "boundmass": float(spec.compiler.boundmass),
                "boundinertia": float(spec.compiler.boundinertia)}
    overridden = spec.compiler.inertiafromgeom == mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    written = {}
    for k, body in enumerate(spec.bodies[1:], start=1):
        if body.explicitinertial and not overridden:
            written[k] = _as_written(body)
            body.fullinertia = [np.nan] * 6  # a stand-in MuJoCo accepts; the audit judges the numbers above
            body.inertia, body.mass = [1.0, 1.0, 1.0], 1.0
    try:
        model = spec.compile()
    except Exception as exc:
        raise InputError(f"{path}: MuJoCo {mujoco.__version__} cannot compile it: {_one_line(exc)}") from None
    located = _locate(path, model.nbody - 1)
    links, joints, sources, placed = _tree(model, written, located, str(path), mujoco)
    by_name = {link.name: link for link in links}
    inertials = {b: by_name[model.body(b).name or f"body{b}"].inertial for b in range(1, model.nbody)}
    spans = {b: item[3].get(item[2]) for b, item in located.items() if item[2] is not None}
    geometry = body_geometry(model, placed, [model.body(b).name or f"body{b}" for b in range(model.nbody)], inertials,
                             spans, model if overridden else mujoco_inertia(spec, mujoco))
    return Robot(spec.modelname or path.stem, str(path), tuple(links), tuple(joints), sources=sources,
                 format="mjcf", compiler=compiler, geometry=geometry)


def _expanded(path):
    """(text, {include file: bytes}) for MuJoCo when the model or a file it includes uses internal DTD entities,
    which MuJoCo's parser does not expand: each such file with its entities expanded in place
    (:func:`.entities.expanded_text`, InputError for what is refused); None when none does, or when a file cannot
    be read (MuJoCo then names the problem)."""
    texts, include, any_expanded = {}, {}, False

    def walk(file, key):
        nonlocal any_expanded
        try:
            data = Path(file).read_bytes()
            root = entities.parse(data, file)
        except (OSError, etree.XMLSyntaxError, ValueError) as exc:
            if isinstance(exc, InputError):
                raise
            return False
        text = entities.expanded_text(data, file)
        any_expanded |= text is not None
        if key is None:
            texts[None] = text if text is not None else decode(data)[0]
        elif key not in include:
            include[key] = data if text is None else text.encode("utf-8")
        for element in root.iter("include"):
            name = element.get("file", "")
            if name and name not in include and not walk(Path(path).parent / name, name):
                return False
        return True

    if not walk(path, None) or not any_expanded:
        return None
    return texts[None], include


def _one_line(exc):
    return " ".join(str(exc).split())


def _as_written(body):
    """(attribute, mass, pos, inertia 3x3) of a body's <inertial> as written."""
    full = np.asarray(body.fullinertia, dtype=float)
    if np.isfinite(full[0]):
        xx, yy, zz, xy, xz, yz = full
        return "fullinertia", float(body.mass), np.array(body.ipos, dtype=float), urdf_inertia(xx, yy, zz, xy, yz, xz)
    return "diaginertia", float(body.mass), np.array(body.ipos, dtype=float), np.diag(np.asarray(body.inertia, float))


def _locate(path, count):
    """Per body id (1..count): (file, <body> element, its <inertial> or None, spans of that file), from lxml.

    Includes are followed (their paths relative to the model's folder, as
    MuJoCo resolves them); bodies pair with MuJoCo's ids in document order
    when the counts agree, else nothing is located.
    """
    found = []

    def walk(file):
        try:
            data = Path(file).read_bytes()
            root = entities.parse(data, file)
        except (OSError, etree.XMLSyntaxError, ValueError):  # InputError included: MuJoCo read it, so not here
            return
        spans = element_spans(decode(data)[0], root)
        for element in root.iter("body", "include"):
            if element.tag == "include":
                walk(Path(path).parent / element.get("file", ""))
            else:
                found.append((str(file), element, element.find("inertial"), spans))

    walk(path)
    return {k: item for k, item in enumerate(found, start=1)} if len(found) == count else {}


def _quat_matrix(q):
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _pose(position, rotation=np.eye(3)):
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, position
    return out


def _tree(model, written, located, path, mujoco):
    """Links, joints, sources and ``placed`` of the compiled model.

    ``placed[b]`` is the pose of MuJoCo body b's frame in the link that stands
    for b (the frame of b's last joint, at its pivot).
    """
    name = [model.body(b).name or f"body{b}" for b in range(model.nbody)]
    links, joints, sources, placed = [Link(name[0], None)], [], {}, {0: np.eye(4)}
    for b in range(1, model.nbody):
        parent = int(model.body_parentid[b])
        pending = placed[parent] @ _pose(model.body_pos[b], _quat_matrix(model.body_quat[b]))
        previous = name[parent]
        ids = [j for j in range(model.njnt) if model.jnt_bodyid[j] == b]
        for i, j in enumerate(ids):
            child = name[b] if i == len(ids) - 1 else f"{name[b]}/{model.joint(j).name or f'joint{j}'}"
            joint, pending = _joint(model, j, previous, child, pending, mujoco)
            joints.append(joint)
            if child != name[b]:
                links.append(Link(child, None))
                sources[child] = Source(path, None, "joint_frame")
            previous = child
        if not ids:
            joints.append(UrdfJoint(f"{name[b]} (welded)", "fixed", previous, name[b], pending, X_AXIS, None, None))
            pending = np.eye(4)
        placed[b] = pending
        links.append(Link(name[b], _inertial(model, b, written.get(b), pending)))
        sources[name[b]] = _source(b, written.get(b), located.get(b), path)
    return links, joints, sources, placed


def _joint(model, j, parent, child, pending, mujoco):
    """The audit's joint for MuJoCo joint j, and the pose of the body's frame in the joint's child link."""
    kind = int(model.jnt_type[j])
    jname = model.joint(j).name or f"joint{j}"
    if kind == mujoco.mjtJoint.mjJNT_HINGE:
        pivot = np.asarray(model.jnt_pos[j], dtype=float)
        return (UrdfJoint(jname, "revolute" if model.jnt_limited[j] else "continuous", parent, child,
                          pending @ _pose(pivot), np.array(model.jnt_axis[j], dtype=float), _limits(model, j), None),
                _pose(-pivot))
    if kind == mujoco.mjtJoint.mjJNT_SLIDE:
        return (UrdfJoint(jname, "prismatic", parent, child, pending, np.array(model.jnt_axis[j], dtype=float),
                          _limits(model, j), None), np.eye(4))
    left_out = "floating" if kind == mujoco.mjtJoint.mjJNT_FREE else "ball"
    return UrdfJoint(jname, left_out, parent, child, pending, X_AXIS, None, None), np.eye(4)


def _limits(model, j):
    if not model.jnt_limited[j]:
        return None
    qpos0 = float(model.qpos0[model.jnt_qposadr[j]])
    return tuple(float(x) - qpos0 for x in model.jnt_range[j])


def _inertial(model, b, written, pose):
    """Body b's inertial in its link's frame; ``pose`` is the MuJoCo body frame's pose there."""
    r, p = pose[:3, :3], pose[:3, 3]
    if written is None:
        return Inertial(float(model.body_mass[b]), r @ model.body_ipos[b] + p, r @ _quat_matrix(model.body_iquat[b]),
                        np.diag(model.body_inertia[b]))
    attribute, mass, ipos, inertia = written
    axes = np.eye(3) if attribute == "fullinertia" else _quat_matrix(model.body_iquat[b])
    return Inertial(mass, r @ ipos + p, r @ axes, inertia)


def _source(b, written, located, path):
    if located is None:
        return Source(path, None, written[0] if written else "geoms")
    file, body, inertial, spans = located
    if written is None:
        return Source(file, spans.get(body), "geoms")
    return Source(file, spans.get(inertial), written[0], tuple(inertial.attrib.items()))
