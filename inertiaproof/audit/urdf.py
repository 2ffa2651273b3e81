"""URDF files read into links with inertial parameters and joints.

The file is parsed strictly with lxml first, and every element and attribute
the audit relies on is checked there, so that a malformed file fails with one
line naming the element (bad XML, a missing attribute, a value that is not a
finite number, a joint naming a missing link, two parents, a cycle). The
checked file is then read by yourdfpy, whose numbers the audit uses.

Why check before yourdfpy: it recovers silently from XML errors, and it
fills missing inertia entries with 1.0 and a missing mass with 0.0; an audit
of inertial parameters must not see invented numbers.

What engines read, the audit reads too, with a warning (:attr:`Robot.warnings`):
an XML declaration with another version (``<?xml version="0.0"?>``), after
blank lines or followed by NUL bytes; leftover xacro elements and
``$(optenv NAME default)`` (the default, as xacro without that variable);
more numbers than a vector needs (the first ones, as pybullet); a second
``<axis>`` (the first, as urdfdom); limits with lower > upper (no limits, as
Bullet); ``spherical`` joints (reported and left out, like floating ones).
Internal DTD entities (``<!DOCTYPE robot [<!ENTITY m "2.5">]>``, ``value="&m;"``)
are expanded after checks, external ones refused (:mod:`.entities`).
Geometry (``<visual>``, ``<collision>``) is not read at all. The decimals of
``<mass>`` and ``<inertia>`` are kept as written: the verdict is decided on them.

URDF conventions (https://wiki.ros.org/urdf/XML): ``<inertia>`` is about the
centre of mass in the axes of the ``<inertial><origin>`` frame, whose ``xyz``
is the CoM in the link frame and whose ``rpy`` rotates those axes into the
link's; a joint's ``<origin>`` places the joint frame in the parent link's
frame, and the child link's frame is the joint frame moved by the joint.
"""

from __future__ import annotations

import io
import logging
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from inertiaproof.errors import LARGEST, InputError
from inertiaproof.model.inertia import from_urdf, pack, urdf_inertia

from . import entities
from .locate import urdf_sources

__all__ = [
    "INERTIA_ATTRIBUTES", "Inertial", "JOINT_TYPES", "LARGEST", "Link", "read_urdf", "Robot", "UrdfJoint", "XACRO",
]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "spherical")
XACRO = "http://ros.org/wiki/xacro"
INERTIA_ATTRIBUTES = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")


@dataclass(frozen=True)
class Inertial:
    """One link's ``<inertial>`` as written: mass, CoM and inertia about the CoM in the inertial axes."""

    mass: float
    com: np.ndarray  # (3,) CoM in the link frame: <origin xyz>
    rotation: np.ndarray  # (3, 3) inertial axes -> link axes: <origin rpy>
    inertia: np.ndarray  # (3, 3) about the CoM, inertial axes
    written: tuple | None = None  # the decimals of mass, ixx, iyy, izz, ixy, iyz, ixz as the file writes them

    @property
    def phi_at_com_written(self):
        """:attr:`phi_at_com` as the file writes it (decimal text), or None."""
        if self.written is None:
            return None
        mass, ixx, iyy, izz, ixy, iyz, ixz = self.written
        return (mass, "0", "0", "0", ixx, iyy, izz, ixy, iyz, ixz)

    @property
    def phi_at_com(self):
        """Phi in the inertial frame (origin at the CoM): (m, 0, I_CoM), free of rounding.

        Its verdict is the link's: consistency is invariant under the rigid
        change of frame to the link frame (I_Sigma_IsTranslationInvariant),
        whose floating-point rounding could move a boundary case across.
        """
        return pack(self.mass, np.zeros(3), self.inertia)

    @property
    def phi(self):
        """Phi in the link frame (eq:Phi), by the parallel axis theorem."""
        return from_urdf(self.mass, self.com, self.inertia, self.rotation)


@dataclass(frozen=True)
class Link:
    name: str
    inertial: Inertial | None  # None: no <inertial>, a massless frame

    @property
    def phi(self):
        return np.zeros(10) if self.inertial is None else self.inertial.phi


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray  # (4, 4) joint frame in the parent link frame
    axis: np.ndarray  # (3,) in the joint frame
    limits: tuple | None  # (lower, upper) for revolute and prismatic joints
    mimic: str | None  # the joint this one mimics


@dataclass(frozen=True)
class Robot:
    name: str
    path: str
    links: tuple  # of Link, in file order
    joints: tuple  # of UrdfJoint, in file order
    sources: dict = field(default_factory=dict, compare=False)  # link name -> locate.Source of its inertia
    format: str = "urdf"  # or "mjcf"
    compiler: dict = field(default_factory=dict, compare=False)  # MJCF <compiler> settings that touch inertias
    warnings: tuple = ()  # what was odd but read as engines read it

    def link(self, name):
        return next(link for link in self.links if link.name == name)

    def link_phis(self):
        """Phi of every link in its link frame (N, 10), zero for a link without <inertial>; batched."""
        phis = np.zeros((len(self.links), 10))
        rows = [k for k, link in enumerate(self.links) if link.inertial is not None]
        if rows:
            written = [self.links[k].inertial for k in rows]
            phis[rows] = from_urdf(np.array([w.mass for w in written]), np.array([w.com for w in written]),
                                   np.array([w.inertia for w in written]), np.array([w.rotation for w in written]))
        return phis


def read_urdf(path, *, data=None, expanded=None, warnings=()):
    """The robot in a URDF file; raises InputError with one line naming the bad element.

    ``data``: the text to read instead of the file's (``expanded`` says by what, e.g. "xacro": the positions are
    then in that text, and each Source says so); ``warnings``: what the expansion said."""
    path = Path(path)
    if data is None:
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    warnings = list(warnings)
    root = _parse_xml(data, path, warnings)
    written, unlimited = _check(root, path, warnings)
    sources = urdf_sources(data, root, path)
    if expanded is not None:
        sources = {name: replace(source, expanded=expanded) for name, source in sources.items()}
    spherical = {j.get("name") for j in root.iter("joint") if j.get("type") == "spherical"}
    robot = _from_yourdfpy(_as_engines_read_it(root), path, written, unlimited | spherical, spherical)
    return replace(robot, sources=sources, warnings=tuple(warnings))


_DECLARATION = re.compile(rb"^(\s*)(<\?xml\b[^>]*?\?>)", re.S)
_VERSION = re.compile(rb"""version\s*=\s*(["'])([^"']*)\1""")


def _parse_xml(data, path, warnings):
    from lxml import etree

    if not data.strip():
        raise InputError(f"{path}: empty file")
    data = _tolerated(data, warnings)
    try:
        root = entities.parse(data, path)  # internal DTD entities expanded safely, or refused (see .entities)
    except InputError:
        raise
    except etree.XMLSyntaxError as exc:
        line = f" at line {exc.lineno}" if exc.lineno else ""
        raise InputError(f"{path}: not well-formed XML{line}: {' '.join(exc.msg.split())}") from None
    except (ValueError, RecursionError) as exc:
        raise InputError(f"{path}: not usable XML: {exc}") from None
    if root.tag != "robot":
        raise InputError(f"{path}: the root element is <{root.tag}>, not <robot>")
    return root


def _tolerated(data, warnings):
    """The bytes with what TinyXML (pybullet) and urdfdom accept but lxml does not set right, each with a warning:
    NUL bytes at the end, blank lines before the XML declaration, a declaration of another XML version."""
    if data.rstrip(b"\x00\t\r\n ") != data.rstrip(b"\t\r\n "):
        data = data.rstrip(b"\x00\t\r\n ") + b"\n"
        warnings.append("NUL bytes after the end of the document are ignored")
    declaration = _DECLARATION.match(data)
    if declaration is None:
        return data
    blank, text = declaration.groups()
    if blank:
        warnings.append("blank lines before the XML declaration are ignored")
    version = _VERSION.search(text)
    if version and version.group(2) != b"1.0":
        warnings.append(f"the XML declaration says version \"{version.group(2).decode(errors='replace')}\"; "
                        "read as XML 1.0, as pybullet reads it")
        text = text[:version.start(2)] + b"1.0" + text[version.end(2):]
    return text + data[declaration.end():]


def _where(element):
    """'link 'x'' or 'joint 'y'' for the named element that holds ``element``."""
    while element is not None and element.tag not in ("link", "joint"):
        element = element.getparent()
    if element is None:
        return "<robot>"
    return f"{element.tag} '{element.get('name', '?')}'"


def _numbers(element, attribute, count, path, default=None, warnings=None):
    """``count`` finite floats from a whitespace-separated attribute. With ``warnings``, more numbers than
    ``count`` are read as their first ``count`` (as pybullet does), with a warning; the attribute is trimmed."""
    raw = element.get(attribute)

    def error(problem):
        return InputError(f"{path}: {_where(element)}: <{element.tag}> {problem}")

    if raw is None:
        if default is None:
            raise error(f"misses attribute '{attribute}'")
        return default
    if "$(" in raw or "${" in raw:
        raise error(f"attribute {attribute}=\"{raw}\" is an unexpanded xacro expression: run xacro on the file "
                    "first")
    parts = raw.split()
    if warnings is not None and len(parts) > count:
        warnings.append(f"{_where(element)}: <{element.tag} {attribute}=\"{raw}\"> has {len(parts)} numbers; "
                        f"the first {count} are read, as pybullet reads them")
        parts = parts[:count]
        element.set(attribute, " ".join(parts))
    if len(parts) != count:
        raise error(f"attribute {attribute}=\"{raw}\" needs {count} number{'s' * (count > 1)}")
    try:
        values = tuple(float(p) for p in parts)
    except ValueError:
        raise error(f"attribute {attribute}=\"{raw}\" is not a number") from None
    if not all(math.isfinite(v) for v in values):
        raise error(f"attribute {attribute}=\"{raw}\" is not finite")
    if not all(abs(v) <= LARGEST for v in values):
        raise error(f"attribute {attribute}=\"{raw}\" is out of range (|x| <= {LARGEST:g})")
    return values


def _single(element, tag, path, required=False, warnings=None):
    """The one child ``tag``; with ``warnings``, a second one is dropped (urdfdom reads the first) with a warning."""
    found = element.findall(tag)
    if len(found) > 1 and warnings is not None:
        warnings.append(f"{_where(element)} has {len(found)} <{tag}> elements; the first is read, as urdfdom reads it")
        for extra in found[1:]:
            element.remove(extra)
        found = found[:1]
    if len(found) > 1:
        raise InputError(f"{path}: {_where(element)} has {len(found)} <{tag}> elements")
    if required and not found:
        raise InputError(f"{path}: {_where(element)}: <{element.tag}> misses <{tag}>")
    return found[0] if found else None


def _check_origin(element, path, warnings):
    origin = _single(element, "origin", path)
    if origin is not None:
        _numbers(origin, "xyz", 3, path, default=(0.0, 0.0, 0.0), warnings=warnings)
        _numbers(origin, "rpy", 3, path, default=(0.0, 0.0, 0.0), warnings=warnings)


_OPTENV = re.compile(r"\$\(optenv\s+\S+\s*([^)]*)\)")


def _expand_leftover_xacro(root, warnings):
    """Drop xacro elements (macros, properties left in a generated file) and read $(optenv NAME default) as its
    default, each with a warning; other xacro expressions stay and are named where the audit reads them."""
    leftovers = [e for e in root.iter() if isinstance(e.tag, str) and e.tag.startswith(f"{{{XACRO}}}")]
    for element in leftovers:
        if element.getparent() is not None:
            warnings.append(f"a leftover <xacro:{element.tag.split('}')[1]}> element is ignored")
            element.getparent().remove(element)
    for element in root.iter():
        for attribute, value in element.attrib.items():
            if "$(optenv" in value:
                expanded = _OPTENV.sub(lambda m: m.group(1).strip(), value)
                warnings.append(f"{_where(element)}: <{element.tag} {attribute}=\"{value}\"> read as \"{expanded}\" "
                                "(the default of $(optenv), as xacro without that variable)")
                element.set(attribute, expanded)


def _check(root, path, warnings):
    """Every element and attribute the audit reads, with one-line errors; returns the decimals of each link's
    mass and inertia as written ({link: (mass, ixx, iyy, izz, ixy, iyz, ixz)}) and the joints whose limits are
    not read (lower > upper)."""
    if not root.get("name"):
        raise InputError(f"{path}: <robot> misses attribute 'name'")
    _expand_leftover_xacro(root, warnings)
    written, unlimited = {}, set()
    links = root.findall("link")
    if not links:
        raise InputError(f"{path}: robot '{root.get('name')}' has no <link> elements")
    names = set()
    for link in links:
        name = link.get("name")
        if not name:
            raise InputError(f"{path}: a <link> misses attribute 'name' (line {link.sourceline})")
        if name in names:
            raise InputError(f"{path}: two links are named '{name}'")
        names.add(name)
        inertial = _single(link, "inertial", path)
        if inertial is None:
            continue
        _check_origin(inertial, path, warnings)
        mass = _single(inertial, "mass", path, required=True)
        _numbers(mass, "value", 1, path)
        inertia = _single(inertial, "inertia", path, required=True)
        for attribute in INERTIA_ATTRIBUTES:
            _numbers(inertia, attribute, 1, path)
        written[name] = (mass.get("value").strip(), *(inertia.get(a).strip() for a in INERTIA_ATTRIBUTES))
    parent_of, joint_names = {}, set()
    for joint in root.findall("joint"):
        name = joint.get("name")
        if not name:
            raise InputError(f"{path}: a <joint> misses attribute 'name' (line {joint.sourceline})")
        if name in joint_names:
            raise InputError(f"{path}: two joints are named '{name}'")
        joint_names.add(name)
        kind = joint.get("type")
        if kind not in JOINT_TYPES:
            raise InputError(f"{path}: joint '{name}': type {kind!r} is not one of {', '.join(JOINT_TYPES)}")
        ends = {}
        for end in ("parent", "child"):
            link = _single(joint, end, path, required=True).get("link")
            if not link:
                raise InputError(f"{path}: joint '{name}': <{end}> misses attribute 'link'")
            if link not in names:
                raise InputError(f"{path}: joint '{name}': <{end} link='{link}'> names no link of the file")
            ends[end] = link
        if ends["child"] in parent_of:
            raise InputError(f"{path}: link '{ends['child']}' is the child of two joints, "
                             f"'{parent_of[ends['child']][0]}' and '{name}'")
        parent_of[ends["child"]] = (name, ends["parent"])
        _check_origin(joint, path, warnings)
        axis = _single(joint, "axis", path, warnings=warnings)
        if axis is not None and kind in ("revolute", "continuous", "prismatic"):
            if not any(_numbers(axis, "xyz", 3, path, default=(1.0, 0.0, 0.0), warnings=warnings)):
                raise InputError(f"{path}: joint '{name}': <axis xyz=\"{axis.get('xyz')}\"> is the zero vector")
        limit = _single(joint, "limit", path)
        if kind in ("revolute", "prismatic"):
            if limit is None:
                raise InputError(f"{path}: joint '{name}': a {kind} joint needs <limit>")
            lower = _numbers(limit, "lower", 1, path, default=(0.0,))[0]
            upper = _numbers(limit, "upper", 1, path, default=(0.0,))[0]
            if lower > upper:
                warnings.append(f"joint '{name}': <limit> has lower {lower:g} > upper {upper:g}, which Bullet reads "
                                "as no limit; audited without limits")
                unlimited.add(name)
        if kind == "spherical":
            warnings.append(f"joint '{name}' is spherical (a pybullet extension): reported and left out")
        mimic = _single(joint, "mimic", path)
        if mimic is not None and mimic.get("joint") is None:
            raise InputError(f"{path}: joint '{name}': <mimic> misses attribute 'joint'")
    _check_tree(path, names, parent_of, links)
    return written, unlimited


def _check_tree(path, names, parent_of, links):
    """One root, no cycle: following parents from every link ends at the root."""
    roots = [link.get("name") for link in links if link.get("name") not in parent_of]
    for start in names:
        seen, link = [], start
        while link in parent_of:
            joint, parent = parent_of[link]
            if joint in seen:
                cycle = seen[seen.index(joint):] + [joint]
                raise InputError(f"{path}: joints {' -> '.join(repr(j) for j in cycle)} form a cycle")
            seen.append(joint)
            link = parent
    if len(roots) > 1:
        raise InputError(f"{path}: {len(roots)} root links ({', '.join(repr(r) for r in roots[:3])}"
                         f"{', ...' if len(roots) > 3 else ''}): a URDF is one tree")


def _as_engines_read_it(root):
    """The checked document as bytes for yourdfpy: without geometry (which the audit does not read, and whose
    engine-specific shapes yourdfpy rejects), spherical joints as floating ones (both are left out)."""
    from lxml import etree

    for element in [e for e in root.iter("visual", "collision")]:
        element.getparent().remove(element)
    for joint in root.iter("joint"):
        if joint.get("type") == "spherical":
            joint.set("type", "floating")
    return etree.tostring(root)


def _from_yourdfpy(data, path, written, unlimited, spherical):
    import yourdfpy

    logger = logging.getLogger("yourdfpy")
    was, logger.disabled = logger.disabled, True  # its complaints would reach stderr; ours name the file
    try:
        model = yourdfpy.URDF.load(io.BytesIO(data), build_scene_graph=False, build_collision_scene_graph=False,
                                   load_meshes=False, load_collision_meshes=False).robot
    except Exception as exc:  # yourdfpy raises many kinds on elements the audit does not read
        raise InputError(f"{path}: yourdfpy cannot read it: {type(exc).__name__}: {exc}") from None
    finally:
        logger.disabled = was
    links = tuple(Link(link.name, _inertial(link.inertial, written.get(link.name))) for link in model.links)
    joints = tuple(
        UrdfJoint(
            name=j.name,
            type="spherical" if j.name in spherical else j.type,
            parent=j.parent,
            child=j.child,
            origin=np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float),
            axis=np.asarray(j.axis, dtype=float),
            limits=(float(j.limit.lower or 0.0), float(j.limit.upper or 0.0))
            if j.type in ("revolute", "prismatic") and j.name not in unlimited else None,
            mimic=j.mimic.joint if j.mimic is not None else None,
        )
        for j in model.joints
    )
    return Robot(model.name, str(path), links, joints)


def _inertial(inertial, written):
    if inertial is None:
        return None
    origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=float)
    raw = np.asarray(inertial.inertia, dtype=float)
    inertia = urdf_inertia(raw[0, 0], raw[1, 1], raw[2, 2], raw[0, 1], raw[1, 2], raw[0, 2])
    return Inertial(float(inertial.mass), origin[:3, 3].copy(), origin[:3, :3].copy(), inertia, written)
