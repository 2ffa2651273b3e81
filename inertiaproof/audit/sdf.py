"""SDFormat files (Gazebo's ``.sdf``, a model folder's ``model.sdf``) read into the audit's links and joints.

Read by the specification (http://sdformat.org/spec, versions 1.4 to 1.11) with the XML reader the URDF audit
uses (:mod:`.entities`, :mod:`.locate`), so that every problem has its line and column: no well-kept SDFormat
parser installs from PyPI (libsdformat's Python bindings come with Gazebo's own packages, not from PyPI).

What is read, per ``<model>`` (``<sdf><model>``, every ``<world><model>``, nested models, and ``<include>`` of a
``model://NAME`` or a path, found beside the file, in its parent folders or on ``GZ_SIM_RESOURCE_PATH``,
``GAZEBO_MODEL_PATH`` or ``SDF_PATH``):

- ``<link><inertial>``: ``<mass>`` (default 1), ``<inertia>`` with ``<ixx>`` .. ``<izz>`` (defaults: 1 on the
  diagonal, 0 off it), ``<pose>`` (the CoM and the inertia's axes in the link frame). The decimals are kept as
  written: the verdict is decided on them. What the specification defaults is what sdformat, Gazebo and Drake
  read: a link without ``<inertial>``, an ``<inertial>`` without ``<mass>`` or ``<inertia>`` and a missing
  diagonal moment are each a :class:`.urdf.Problem` (kind ``sdformat_default``) naming the default read, and a
  value that is not a finite number one of kind ``malformed_inertial`` (the default read in its place); the rest
  of the file is audited. ``<inertial><pose relative_to>`` is read in the link frame, as sdformat reads it
  (it reports an error for a non-empty one: gazebosim/sdformat#380, #480), with a warning. Missing products
  of inertia are SDFormat's 0, with one warning per file: pybullet's ``loadSDF`` refuses such a file.
- ``<pose>``: six numbers ``x y z roll pitch yaw`` (fixed axes, R = Rz(yaw) Ry(pitch) Rx(roll), as URDF's
  rpy), ``degrees="true"`` and ``rotation_format="quat_xyzw"`` (seven numbers) as SDFormat 1.9 defines them;
  ``relative_to`` names a link, joint, ``<frame>`` or nested model of the same scope (``inner::name`` into a
  nested one); the defaults: a link's and a nested model's pose relative to the model frame, a joint's relative
  to its child link, a frame's relative to the frame it is ``attached_to``.
- ``<collision>`` (``<visual>`` where a link has none) ``<geometry>``: ``<box><size>``, ``<cylinder><radius>
  <length>`` (along z), ``<sphere><radius>`` as :class:`.geometry.Primitive`; a ``<capsule>`` enclosed by the
  cylinder of its radius and full length and an ``<ellipsoid>`` by the box of its radii (supersets: every
  theorem of :mod:`.bodies_inside` on them holds for the shape inside). A pose is exact (the decimals as
  written) when it is relative to the link or every frame between it and the link is only translated (the
  translations add exactly); else it is composed in float64 (each product of 4x4 poses rounds by a few ulps) and
  the doubles are read exactly. A ``<mesh>`` (``<uri>``, ``<scale>``) is a :class:`.geometry.MeshPart`, decided on
  by :mod:`.mesh_bodies` as a URDF mesh; a ``<plane>``, ``<heightmap>`` or ``<polyline>`` is not decided on:
  :attr:`.geometry.LinkGeometry.unread` says so.
- ``<joint type>`` with ``<parent>``, ``<child>`` (``world`` as a parent) and ``<axis><xyz>`` (in the joint
  frame, or ``expressed_in`` a frame (1.7+), or the model frame with ``use_parent_model_frame`` (up to 1.6)),
  ``<limit><lower><upper>`` (beyond +-1e16: no limit, SDFormat's default). revolute, continuous, prismatic,
  fixed and ball joints are the audit's; universal, revolute2, screw and gearbox joints are reported and left out
  (their child becomes a base). A joint to a link that already has a parent closes a kinematic loop (Cassie's
  rods): reported and left out.

The audit's frame of a link is the frame of the joint that moves it (the child link's frame moved by the joint's
pose), as URDF defines a link frame, so the joints' origins and the links' CoMs are re-expressed in those frames
(float64); the geometry and the ``<inertial>`` pose stay in the SDFormat link frame, exact. Root links of a model
without a joint to the world are free (a ``floating`` joint from ``world``), fixed to it in a ``<static>``
model. Links and joints of a nested model are named ``inner::name``; in a world of several models each is
prefixed by its model's name.
"""

from __future__ import annotations

import hashlib
import math
import os
import re
from dataclasses import dataclass, field, replace
from fractions import Fraction
from pathlib import Path

import numpy as np
from lxml import etree

from inertiaproof.errors import LARGEST, InputError
from inertiaproof.model.exact import written_fraction
from inertiaproof.model.inertia import rotation_rpy, urdf_inertia

from . import geometry as _geometry_module
from .geometry import LinkGeometry, Pose, Primitive
from .locate import Source, decode, element_spans
from .urdf import (
    ElementError,
    Inertial,
    Link,
    Problem,
    Robot,
    UrdfJoint,
    parse_declaring,
)

__all__ = ["DEFAULT_INERTIAL", "SDF_JOINTS", "is_sdf", "read_sdf", "sdf_inertial_text"]

SDF_JOINTS = {"revolute": "revolute", "continuous": "continuous", "prismatic": "prismatic", "fixed": "fixed",
              "ball": "ball"}  # the rest (universal, revolute2, screw, gearbox) is reported and left out
DIAGONAL, PRODUCTS = ("ixx", "iyy", "izz"), ("ixy", "iyz", "ixz")
DEFAULT_INERTIAL = "mass 1 kg, ixx = iyy = izz = 1 kg m^2 (SDFormat's defaults)"
UNLIMITED = 1e16  # SDFormat's default joint limits are -+1e16: beyond it a joint has no limit
WORLD = "world"
PATH_VARIABLES = ("GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH", "GAZEBO_MODEL_PATH", "SDF_PATH")


def is_sdf(path):
    """Whether a file's root element is ``<sdf>`` (read up to the first start tag)."""
    try:
        for _, element in etree.iterparse(str(path), events=("start",), resolve_entities=False, no_network=True,
                                          load_dtd=False, huge_tree=False):
            return etree.QName(element).localname == "sdf"
    except (OSError, etree.XMLSyntaxError):
        return Path(path).suffix.lower() == ".sdf"
    return False


# -- poses ----------------------------------------------------------------------

def _matrix(rotation, position):
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, position
    return out


def _rpy_of(r):
    """Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll) (float64)."""
    pitch = math.atan2(-r[2, 0], math.hypot(r[0, 0], r[1, 0]))
    if math.hypot(r[0, 0], r[1, 0]) < 1e-12:  # gimbal lock: yaw 0
        return math.atan2(-r[1, 2], r[1, 1]), pitch, 0.0
    return math.atan2(r[2, 1], r[2, 2]), pitch, math.atan2(r[1, 0], r[0, 0])


def _quat_xyzw(q):
    x, y, z, w = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@dataclass(frozen=True)
class _Pose:
    """A ``<pose>`` as read: its 4x4 matrix, ``relative_to`` ('' for the default) and, when its numbers are
    decimals in roll-pitch-yaw radians, the exact :class:`.geometry.Pose`."""

    matrix: np.ndarray
    relative_to: str = ""
    exact: Pose | None = field(default_factory=Pose)


IDENTITY = _Pose(np.eye(4))


class _Reader:
    """One file's elements, with its path, spans and the warnings and problems found while reading it."""

    def __init__(self, path, root, data, warnings):
        self.path, self.root, self.warnings = path, root, warnings
        self.spans = element_spans(decode(data)[0], root)

    def fail(self, element, detail, kind="format"):
        return ElementError(self.path, element, detail, kind)

    def text(self, element):
        return " ".join((element.text or "").split())

    def numbers(self, element, count, where, allowed=None):
        """The floats of an element's text: ``count`` of them (or one of ``allowed`` counts)."""
        raw = self.text(element)
        parts = raw.split()
        if len(parts) not in (allowed or (count,)):
            raise self.fail(element, f"{where}: <{element.tag}>{raw}</{element.tag}> needs {count} numbers")
        try:
            values = [float(p) for p in parts]
        except ValueError:
            raise self.fail(element, f"{where}: <{element.tag}>{raw}</{element.tag}> is not a number") from None
        if not all(math.isfinite(v) and abs(v) <= LARGEST for v in values):
            raise self.fail(element, f"{where}: <{element.tag}>{raw}</{element.tag}> is not finite or out of range "
                            f"(|x| <= {LARGEST:g})", "range")
        return values

    def pose(self, holder, where):
        """The ``<pose>`` child of an element, or the identity relative to the default frame."""
        element = holder.find("pose")
        if element is None:
            return IDENTITY
        relative = (element.get("relative_to") or element.get("frame") or "").strip()
        quat = (element.get("rotation_format") or "euler_rpy").strip() == "quat_xyzw"
        degrees = (element.get("degrees") or "false").strip().lower() in ("true", "1")
        if not self.text(element):
            return _Pose(np.eye(4), relative)
        values = self.numbers(element, 7 if quat else 6, where)
        if quat:
            return _Pose(_matrix(_quat_xyzw(values[3:]), values[:3]), relative, None)
        rpy = np.radians(values[3:]) if degrees else np.array(values[3:])
        parts = self.text(element).split()
        exact = None if degrees else _exact_pose(parts[:3], parts[3:])
        return _Pose(_matrix(rotation_rpy(rpy), values[:3]), relative, exact)


def _exact_pose(xyz, rpy):
    values = [written_fraction(p) for p in (*xyz, *rpy)]
    return None if None in values else Pose(tuple(values[:3]), tuple(values[3:]))


def _float_pose(matrix):
    """The exact Pose of a float64 4x4 pose (its rotation as roll-pitch-yaw in float64)."""
    return Pose(tuple(Fraction(float(x)) for x in matrix[:3, 3]), tuple(Fraction(float(a)) for a in _rpy_of(matrix)))


# -- one model's scope ---------------------------------------------------------

@dataclass
class _Scope:
    """The frames of one model (names relative to it) and where its frame stands in the audit's top frame."""

    prefix: str  # "" for the top model, "inner::" for a nested one (relative to the top)
    static: bool
    exact_base: Pose | None = None  # the model frame in the top frame, exact (None: not known exactly)
    frames: dict = field(default_factory=dict)  # name -> (relative_to, _Pose, kind)
    resolved: dict = field(default_factory=dict)  # name -> 4x4 in the top frame


@dataclass
class _LinkRecord:
    name: str
    element: object
    reader: _Reader
    scope: _Scope
    static: bool


@dataclass
class _JointRecord:
    name: str
    element: object
    reader: _Reader
    scope: _Scope
    kind: str
    parent: str
    child: str


class _Model:
    """Every link, joint and frame of the file, resolved into the top frame."""

    def __init__(self, path, warnings):
        self.path, self.warnings = path, warnings
        self.links, self.joints, self.scopes, self.included = [], [], [], set()

    # frames ----------------------------------------------------------------
    def resolve(self, scope, name, chain=()):
        """The pose of frame ``name`` of ``scope`` in the top frame."""
        if name in scope.resolved:
            return scope.resolved[name]
        if name in chain:
            raise InputError(f"{self.path}: the poses of {' -> '.join(repr(n) for n in (*chain, name))} refer to "
                             "each other in a cycle")
        if name not in scope.frames:
            raise InputError(f"{self.path}: relative_to '{name}' names no frame of model scope "
                             f"'{scope.prefix.rstrip(':') or 'top'}'")
        relative, pose, _ = scope.frames[name]
        base = self.resolve(scope, relative, (*chain, name)) if relative is not None else np.eye(4)
        scope.resolved[name] = base @ pose.matrix
        return scope.resolved[name]

    def exact(self, scope, name):
        """The pose of frame ``name`` in the top frame as an exact Pose when every frame it is given relative to
        is only translated (the translations then add exactly), else None."""
        if name == "__model__":
            return scope.exact_base
        relative, pose, _ = scope.frames[name]
        parent = self.exact(scope, relative) if relative is not None else None
        if parent is None or pose.exact is None or parent.turned:
            return None
        return Pose(tuple(a + b for a, b in zip(parent.xyz, pose.exact.xyz)), pose.exact.rpy)

    def walk(self, model, reader, prefix, base, parent_static=False, name_override=None, exact_base=None):
        """Read one ``<model>`` element; ``base``: its frame's pose in the top frame (``exact_base``: exact)."""
        static_element = model.find("static")
        static = parent_static or (static_element is not None and reader.text(static_element) in ("true", "1"))
        scope = _Scope(prefix, static, exact_base)
        self.scopes.append(scope)
        scope.frames["__model__"] = (None, _Pose(base), "model")
        scope.resolved["__model__"] = base
        where = f"model '{name_override or model.get('name', '?')}'"
        for link in model.findall("link"):
            name = link.get("name")
            if not name:
                raise reader.fail(link, f"{where}: a <link> misses attribute 'name'", "missing")
            pose = reader.pose(link, f"link '{prefix}{name}'")
            scope.frames[name] = (pose.relative_to or "__model__", pose, "link")
            self.links.append(_LinkRecord(prefix + name, link, reader, scope, static))
        for frame in model.findall("frame"):
            name = frame.get("name")
            pose = reader.pose(frame, f"frame '{prefix}{name}'")
            attached = (frame.get("attached_to") or "").strip() or "__model__"
            scope.frames[name] = (pose.relative_to or attached, pose, "frame")
        for joint in model.findall("joint"):
            name = joint.get("name")
            if not name:
                raise reader.fail(joint, f"{where}: a <joint> misses attribute 'name'", "missing")
            ends = {}
            for end in ("parent", "child"):
                element = joint.find(end)
                if element is None or not reader.text(element):
                    raise reader.fail(joint, f"joint '{prefix}{name}' misses <{end}>", "missing")
                ends[end] = reader.text(element)
            pose = reader.pose(joint, f"joint '{prefix}{name}'")
            scope.frames[name] = (pose.relative_to or ends["child"], pose, "joint")
            self.joints.append(_JointRecord(prefix + name, joint, reader, scope, joint.get("type", ""),
                                            ends["parent"], ends["child"]))
        for child in model:  # nested models and includes in document order
            if child.tag == "model":
                self._nested(scope, child, reader, prefix, static)
            elif child.tag == "include":
                self._include(scope, child, reader, prefix, static)
        return scope

    def _nested(self, scope, nested, reader, prefix, static):
        name = nested.get("name", "")
        pose = reader.pose(nested, f"model '{prefix}{name}'")
        scope.frames[name] = (pose.relative_to or "__model__", pose, "model")
        self._enter(scope, nested, reader, prefix, static, name)

    def _enter(self, scope, model, reader, prefix, static, name):
        """Walk a nested model of ``scope`` named ``name`` (its frame entered already); its frames are then
        reachable from ``scope`` as ``name::frame``."""
        inner = self.walk(model, reader, f"{prefix}{name}::", self.resolve(scope, name), static, name,
                          self.exact(scope, name))
        for key in list(inner.frames):
            if key != "__model__":
                top = self.resolve(inner, key)
                scope.frames[f"{name}::{key}"] = (None, _Pose(top, "", self.exact(inner, key)), inner.frames[key][2])
                scope.resolved[f"{name}::{key}"] = top

    def _include(self, scope, include, reader, prefix, static):
        uri_element = include.find("uri")
        uri = reader.text(uri_element) if uri_element is not None else ""
        target = _find_model(uri, reader.path)
        if target is None:
            self.warnings.append(f"<include> of '{uri}' (line {include.sourceline}): not found beside the file, in "
                                 f"its parent folders or on {', '.join(PATH_VARIABLES)}; its links are not audited")
            return
        if target in self.included:
            self.warnings.append(f"<include> of '{uri}' (line {include.sourceline}) includes {target} again: read once")
            return
        self.included.add(target)
        inner_reader = _open(target, self.warnings)
        model = _top_models(inner_reader)
        if not model:
            self.warnings.append(f"<include> of '{uri}': {target} has no <model>; nothing audited")
            return
        name_element = include.find("name")
        name = reader.text(name_element) if name_element is not None else model[0].get("name", "")
        static_element = include.find("static")
        inner_static = static or (static_element is not None and reader.text(static_element) in ("true", "1"))
        pose = reader.pose(include, f"include '{name}'")
        if include.find("pose") is None:  # the included model's own pose
            pose = inner_reader.pose(model[0], f"model '{name}'")
        scope.frames[name] = (pose.relative_to or "__model__", pose, "model")
        self._enter(scope, model[0], inner_reader, prefix, inner_static, name)


def _find_model(uri, path):
    """The file an ``<include><uri>`` names (a model folder's model.config <sdf>, else model.sdf), or None."""
    if not uri or re.match(r"https?://", uri):
        return None
    rest = uri.split("://", 1)[1] if "://" in uri else uri
    candidates = []
    if uri.startswith("model://"):
        roots = [p for folder in Path(path).resolve().parents for p in (folder,)]
        for variable in PATH_VARIABLES:
            roots += [Path(p) for p in os.environ.get(variable, "").split(os.pathsep) if p]
        candidates = [root / rest for root in roots]
    else:
        candidates = [Path(rest) if Path(rest).is_absolute() else Path(path).parent / rest]
    for candidate in candidates:
        if candidate.is_file():
            return candidate.resolve()
        if candidate.is_dir():
            config = candidate / "model.config"
            if config.is_file():
                try:
                    found = etree.parse(str(config)).getroot().findall("sdf")
                except (etree.XMLSyntaxError, OSError):
                    found = []
                for sdf in found:
                    if (candidate / (sdf.text or "").strip()).is_file():
                        return (candidate / sdf.text.strip()).resolve()
            if (candidate / "model.sdf").is_file():
                return (candidate / "model.sdf").resolve()
    return None


def _open(path, warnings, data=None):
    """A :class:`_Reader` of one SDFormat file (undeclared namespace prefixes read as unknown names, as
    :mod:`.urdf` reads them)."""
    if data is None:
        try:
            data = Path(path).read_bytes()
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    if not data.strip():
        raise InputError(f"{path}: empty file")
    root, data = parse_declaring(data, path, warnings)
    if etree.QName(root).localname != "sdf":
        raise InputError(f"{path}: the root element is <{root.tag}>, not <sdf>")
    return _Reader(path, root, data, warnings)


def _top_models(reader):
    return reader.root.findall("model") + reader.root.findall("world/model")


# -- inertials and geometry ----------------------------------------------------

def _inertial(record, problems, product_gaps, model_path):
    """(Inertial in the SDFormat link frame, decimals, its Source) of a link as sdformat reads it; problems appended
    as (Problem, element at fault)."""
    reader, link, name = record.reader, record.element, record.name
    inertial = link.find("inertial")
    values = {"mass": "1", **{k: "1" for k in DIAGONAL}, **{k: "0" for k in PRODUCTS}}
    pose = IDENTITY

    elsewhere = "" if reader.path == model_path else f" (in {reader.path}, line {{line}})"

    def problem(kind, element, what, reads):
        where = elsewhere.format(line=element.sourceline)  # an included file: the location names the model's file
        message = (f"link '{name}'{where}: {what}: sdformat and Gazebo read {reads}"
                   + ("; pybullet's loadSDF cannot load the file" if kind == "sdformat_default" and
                      element is not link else ""))
        problems.append((Problem(name, kind, message, reads, kind == "sdformat_default"), None if where else element))

    if inertial is None:
        if not record.static:
            problem("sdformat_default", link, "no <inertial>", DEFAULT_INERTIAL)
        return values, pose, Source(str(reader.path), reader.spans.get(link), "sdf_inertial"), inertial
    pose = reader.pose(inertial, f"link '{name}' <inertial>")
    if pose.relative_to and pose.relative_to != name.rpartition("::")[2]:
        reader.warnings.append(f"link '{name}': <inertial><pose relative_to=\"{pose.relative_to}\"> (line "
                               f"{inertial.find('pose').sourceline}) is read in the link frame, as sdformat reads "
                               "it (it reports an error for a non-empty relative_to there)")
    mass = inertial.find("mass")
    if mass is None:
        problem("sdformat_default", inertial, "<inertial> has no <mass>", "mass 1 kg (SDFormat's default)")
    else:
        values["mass"] = _value(reader, mass, name, "1", problem)
    inertia = inertial.find("inertia")
    if inertia is None:
        problem("sdformat_default", inertial, "<inertial> has no <inertia>",
                "ixx = iyy = izz = 1 kg m^2 (SDFormat's defaults)")
    else:
        missing_products = []
        for key in (*DIAGONAL, *PRODUCTS):
            element = inertia.find(key)
            if element is None and key in DIAGONAL:
                problem("sdformat_default", inertia, f"<inertia> has no <{key}>", f"{key} = 1 kg m^2 (SDFormat's "
                        "default)")
            elif element is None:
                missing_products.append(key)
            else:
                values[key] = _value(reader, element, name, values[key], problem)
        if missing_products:
            product_gaps.append(name)
    if inertia is None:  # no element a repair could replace
        return values, pose, Source(str(reader.path), reader.spans.get(inertial), "sdf_inertial"), inertial
    return values, pose, Source(str(reader.path), reader.spans.get(inertia), "sdf"), inertial


def _value(reader, element, name, default, problem):
    """The decimal text of a one-number element, or ``default`` with a problem when it is not a finite number."""
    text = reader.text(element)
    try:
        value = float(text)
    except ValueError:
        value = None
    if value is None or not math.isfinite(value) or len(text.split()) != 1:
        problem("malformed_inertial", element, f"<{element.tag}>{text}</{element.tag}> is not a finite number",
                f"{element.tag} = {default} (SDFormat's default; sdformat reports an error)")
        return default
    if abs(value) > LARGEST:
        raise reader.fail(element, f"link '{name}': <{element.tag}>{text}</{element.tag}> is out of range "
                          f"(|x| <= {LARGEST:g})", "range")
    return text


SHAPES = {"box": ("size",), "cylinder": ("radius", "length"), "sphere": ("radius",), "capsule": ("radius", "length"),
          "ellipsoid": ("radii",)}


class _Unread(ValueError):
    pass


def _geometry(model, record, inertial_element, inertial_pose):
    """The link's LinkGeometry in its SDFormat link frame."""
    reader, link, name = record.reader, record.element, record.name
    holders = link.findall("collision") or link.findall("visual")
    source = holders[0].tag if holders else None
    span = None if inertial_element is None else reader.spans.get(inertial_element)
    where = f"link '{name}'"
    if not holders:
        return LinkGeometry(None, (), f"{where}: no <collision> or <visual>", inertial_pose, span)
    try:
        parts = tuple(_primitive(model, record, h, where) for h in holders)
    except _Unread as exc:
        return LinkGeometry(source, (), str(exc), inertial_pose, span)
    meshes = tuple(p for p in parts if not isinstance(p, Primitive))
    return LinkGeometry(source, tuple(p for p in parts if isinstance(p, Primitive)), None, inertial_pose, span,
                        *((meshes,) if meshes else ()))


def _primitive(model, record, holder, where):
    reader = record.reader
    geometry = holder.find("geometry")
    shapes = [] if geometry is None else [e for e in geometry if isinstance(e.tag, str)]
    if len(shapes) != 1:
        raise _Unread(f"{where}: <{holder.tag}> has {len(shapes)} shapes in its <geometry>, not one")
    shape = shapes[0]
    mesh_part = getattr(_geometry_module, "MeshPart", None)  # the mesh geometry of :mod:`.mesh_bodies`
    if shape.tag == "mesh" and mesh_part is not None:
        uri, scale = shape.find("uri"), shape.find("scale")
        if uri is None or not reader.text(uri):
            raise _Unread(f"{where}: <mesh> has no <uri>")
        factors = [written_fraction(p) for p in (reader.text(scale).split() if scale is not None else ["1"] * 3)]
        if len(factors) != 3 or None in factors or not all(factors):
            raise _Unread(f"{where}: <mesh><scale> is not three nonzero decimal numbers")
        return mesh_part(reader.text(uri), tuple(factors), _in_link(model, record, reader.pose(holder, where), where),
                         str(Path(reader.path).parent), shape.sourceline)
    if shape.tag not in SHAPES:
        raise _Unread(f"{where}: <{holder.tag}> is a <{shape.tag}>, not decided on (box, cylinder, sphere, capsule, "
                      "ellipsoid are)")
    dims = []
    for key in SHAPES[shape.tag]:
        element = shape.find(key)
        count = 3 if key in ("size", "radii") else 1
        parts = [] if element is None else reader.text(element).split()
        values = [written_fraction(p) for p in parts]
        if len(parts) != count or None in values:
            raise _Unread(f"{where}: <{shape.tag}> has no <{key}> of {count} decimal number{'s' * (count > 1)}")
        dims += values
    if not all(d > 0 for d in dims):
        raise _Unread(f"{where}: <{shape.tag}> has a dimension that is not positive")
    kind = shape.tag
    if kind == "capsule":  # enclosed by the cylinder of its radius and full length
        kind, dims = "cylinder", [dims[0], dims[1] + 2 * dims[0]]
    elif kind == "ellipsoid":  # enclosed by the box of its radii
        kind, dims = "box", [2 * d for d in dims]
    return Primitive(kind, tuple(dims), _in_link(model, record, reader.pose(holder, where), where), shape.sourceline)


def _in_link(model, record, pose, where):
    """A pose given relative to ``pose.relative_to`` as a :class:`.geometry.Pose` in the link frame."""
    own = record.name.rpartition("::")[2]
    if not pose.relative_to or pose.relative_to == own:
        if pose.exact is not None:
            return pose.exact
        return _float_pose(pose.matrix)
    scope = record.scope
    link, other = model.exact(scope, own), model.exact(scope, pose.relative_to)
    if link is not None and other is not None and not link.turned and not other.turned and pose.exact is not None:
        return Pose(tuple(o + g - k for o, g, k in zip(other.xyz, pose.exact.xyz, link.xyz)), pose.exact.rpy)
    return _float_pose(np.linalg.inv(model.resolve(scope, own)) @ model.resolve(scope, pose.relative_to) @ pose.matrix)


# -- the robot -----------------------------------------------------------------

def read_sdf(path, *, data=None):
    """The robot in an SDFormat file (see the module); raises InputError with one line naming the bad element."""
    path = Path(path)
    warnings = []
    reader = _open(path, warnings, data)
    raw = reader.path.read_bytes() if data is None else data
    models = _top_models(reader)
    if not models:
        raise InputError(f"{path}: no <model> in <sdf> or <world>")
    model = _Model(path, warnings)
    several, seen = len(models) > 1, {}
    for element in models:
        name = element.get("name", "")
        seen[name] = seen.get(name, 0) + 1
        if seen[name] > 1:
            warnings.append(f"model '{name}' (line {element.sourceline}) repeats a model name of the world (sdformat "
                            f"refuses it, pybullet loads both): read as '{name}#{seen[name]}'")
            name = f"{name}#{seen[name]}"
        prefix = f"{name}::" if several else ""
        pose = reader.pose(element, f"model '{name}'")
        model.walk(element, reader, prefix, pose.matrix, exact_base=pose.exact)
    for include in reader.root.findall("world/include"):
        top = _Scope("", False, Pose())
        top.frames["__model__"] = (None, IDENTITY, "model")
        top.resolved["__model__"] = np.eye(4)
        model._include(top, include, reader, "", False)
    if not model.links:
        raise InputError(f"{path}: no <link> in its models")
    return _robot(path, model, models, raw, warnings)


def _robot(path, model, models, raw, warnings):
    problems, product_gaps, frame_of, geometry, sources = [], [], {}, {}, {}
    names = [r.name for r in model.links]
    if len(set(names)) != len(names):
        twice = next(n for n in names if names.count(n) > 1)
        raise InputError(f"{path}: two links are named '{twice}'")
    records = {r.name: r for r in model.links}
    for r in model.links:
        frame_of[r.name] = model.resolve(r.scope, r.name.rpartition("::")[2])
    # joints: the tree
    world = WORLD if WORLD not in records else "__world__"  # a link named world is the parent "world" names
    parent_of, kept = {}, []
    for j in model.joints:
        parent = _link_name(j, j.parent, records) or (world if j.parent == WORLD else None)
        child = _link_name(j, j.child, records)
        if child is None or parent is None:
            missing = j.child if child is None else j.parent
            raise ElementError(path, j.element, f"joint '{j.name}': '{missing}' names no link of the file", "format")
        if child in parent_of:
            warnings.append(f"joint '{j.name}' (line {j.element.sourceline}): link '{child}' is already the child of "
                            f"joint '{parent_of[child].name}': a kinematic loop, reported and left out")
            continue
        if j.kind not in SDF_JOINTS:
            warnings.append(f"joint '{j.name}' is a {j.kind or 'untyped'} joint: reported and left out (its child "
                            "becomes a base)")
        parent_of[child] = j
        kept.append((j, parent, child))
    kept = _acyclic(kept, warnings)
    parent_of = {child: j for j, _, child in kept}
    kinematic = {}  # link -> the audit's frame of it (its parent joint's frame) in the top frame
    for r in model.links:
        j = parent_of.get(r.name)
        kinematic[r.name] = model.resolve(j.scope, j.name.rpartition("::")[2]) if j is not None else frame_of[r.name]
    links, joints = [], []
    roots = [n for n in names if n not in parent_of]
    to_world = [j for j, parent, _ in kept if parent == world]
    synthetic = len(roots) > 1 or bool(to_world)
    if synthetic:
        links.append(Link(world, None))
    for r in model.links:
        values, pose, source, element = _inertial(r, problems, product_gaps, Path(path))
        sources[r.name] = source
        inertia = urdf_inertia(*(float(values[k]) for k in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")))
        placed = np.linalg.inv(kinematic[r.name]) @ frame_of[r.name]  # the SDFormat link frame in the audit's
        local = pose.matrix
        com = placed[:3, :3] @ local[:3, 3] + placed[:3, 3]
        written = tuple(values[k] for k in ("mass", "ixx", "iyy", "izz", "ixy", "iyz", "ixz"))
        links.append(Link(r.name, Inertial(float(values["mass"]), com, placed[:3, :3] @ local[:3, :3], inertia,
                                           written)))
        exact = pose.exact if pose.exact is not None else _float_pose(local)
        geometry[r.name] = _geometry(model, r, element, exact)
    for j, parent, child in kept:
        joints.append(_joint(model, j, parent, child, kinematic, world))
    if synthetic:
        for root in roots:
            kind = "fixed" if records[root].static else "floating"
            joints.append(UrdfJoint(f"{root} ({'static' if kind == 'fixed' else 'free'})", kind, world, root,
                                    kinematic[root], np.array([1.0, 0.0, 0.0]), None, None))
    if product_gaps:
        shown = ", ".join(f"'{n}'" for n in product_gaps[:3]) + (", ..." if len(product_gaps) > 3 else "")
        warnings.append(f"{len(product_gaps)} link(s) ({shown}) omit products of inertia in <inertia>: read as "
                        "SDFormat's 0; pybullet's loadSDF refuses such a file ('inertia element must have ixx,ixy,"
                        "ixz,iyy,iyz,izz child elements')")
    spans = {}
    for reader in {id(r.reader): r.reader for r in model.links}.values():
        spans.update(reader.spans)
    found = tuple(replace(p, span=spans.get(e)) for p, e in problems)
    name = models[0].get("name") if len(models) == 1 else (model.links[0].reader.root.find("world").get("name")
                                                           if model.links[0].reader.root.find("world") is not None
                                                           else path.stem)
    return Robot(name or path.stem, str(path), tuple(links), tuple(joints), sources=sources, format="sdf",
                 warnings=tuple(warnings), problems=found, sha256=hashlib.sha256(raw).hexdigest(), geometry=geometry)


def _link_name(joint, ref, records):
    """The full name of the link a joint's <parent> or <child> names in its scope (or from the top), or None."""
    for candidate in (joint.scope.prefix + ref, ref):
        if candidate in records:
            return candidate
    return None


def _acyclic(kept, warnings):
    """The joints without those that close a cycle of parents (each reported)."""
    parent = {child: (j, p) for j, p, child in kept}
    dropped = set()
    for start in list(parent):
        seen, link = [], start
        while link in parent and parent[link][0].name not in dropped:
            j, p = parent[link]
            if j.name in seen:
                dropped.add(j.name)
                warnings.append(f"joint '{j.name}' closes a cycle of parents: reported and left out")
                break
            seen.append(j.name)
            link = p
    return [(j, p, c) for j, p, c in kept if j.name not in dropped]


def _joint(model, j, parent, child, kinematic, world):
    reader, element = j.reader, j.element
    frame = kinematic[child]
    origin = np.linalg.inv(kinematic[parent]) @ frame if parent != world else frame
    kind = SDF_JOINTS.get(j.kind, j.kind or "fixed")
    axis_element = element.find("axis")
    axis, limits = np.array([0.0, 0.0, 1.0]), None
    if axis_element is not None and axis_element.find("xyz") is not None:
        xyz = axis_element.find("xyz")
        axis = np.array(reader.numbers(xyz, 3, f"joint '{j.name}' <axis>"))
        if not axis.any():
            raise reader.fail(xyz, f"joint '{j.name}': <axis><xyz> is the zero vector")
        expressed = (xyz.get("expressed_in") or "").strip()
        parent_frame = axis_element.find("use_parent_model_frame")
        if parent_frame is not None and reader.text(parent_frame) in ("true", "1"):
            expressed = "__model__"
        if expressed and expressed != j.name.rpartition("::")[2]:
            axis = frame[:3, :3].T @ model.resolve(j.scope, expressed)[:3, :3] @ axis
        axis = axis / np.linalg.norm(axis)
    if kind in ("revolute", "prismatic") and axis_element is not None:
        limit = axis_element.find("limit")
        bounds = [-UNLIMITED, UNLIMITED]
        for k, key in enumerate(("lower", "upper")):
            found = None if limit is None else limit.find(key)
            if found is not None:
                bounds[k] = reader.numbers(found, 1, f"joint '{j.name}' <limit>")[0]
        if max(abs(b) for b in bounds) < UNLIMITED and bounds[0] <= bounds[1]:
            limits = tuple(bounds)
        elif kind == "revolute":
            kind = "continuous"
    if kind == "prismatic" and limits is None:
        limits = None
    return UrdfJoint(j.name, kind, parent, child, origin, axis, limits, None)


def sdf_inertial_text(urdf_text):
    """An ``<inertial>`` written as URDF (:mod:`.bodies_inside`'s uniform proposal) as SDFormat writes it."""
    if not urdf_text:
        return urdf_text
    try:
        element = etree.fromstring(urdf_text)
    except etree.XMLSyntaxError:
        return None
    origin, mass, inertia = (element.find(tag) for tag in ("origin", "mass", "inertia"))
    if mass is None or inertia is None:
        return None
    xyz = (origin.get("xyz") if origin is not None else None) or "0 0 0"
    rpy = (origin.get("rpy") if origin is not None else None) or "0 0 0"
    entries = "".join(f"<{k}>{inertia.get(k)}</{k}>" for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    return f"<inertial><pose>{xyz} {rpy}</pose><mass>{mass.get('value')}</mass><inertia>{entries}</inertia></inertial>"
