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
``<axis>``, ``<inertial>``, ``<origin>``, ``<mass>`` or ``<inertia>`` (the first, as urdfdom); limits with
lower > upper (no limits, as Bullet); ``spherical`` joints (reported and left out, like floating ones);
namespace prefixes the file never declares (``drake:acceleration="..."``, ``<drake:collision_filter_group>``):
TinyXML keeps such names as plain names that urdfdom does not look up, so the audit declares the prefixes on
the root element, on the line of its start tag (lines and the file's own positions stay as they are), and reads their
elements and attributes as unknown ones.

An ``<inertial>`` that urdfdom cannot parse (a missing ``<mass>``, ``value``, ``<inertia>`` or inertia
attribute, a value that is not a finite number) is not an error but a :class:`Problem` on its link
(:attr:`Robot.problems`, with the element's line): urdfdom logs an error and reads the link as far as it got
(its parseInertial reads ``<origin>``, then ``<mass>``, then ``<inertia>``), and so does the audit: a point
mass at the origin's CoM (zero rotational inertia) when only the inertia fails, else a massless link
(checked against Pinocchio in ``tests/test_audit_problems.py``).
Internal DTD entities (``<!DOCTYPE robot [<!ENTITY m "2.5">]>``, ``value="&m;"``)
are expanded after checks, external ones refused (:mod:`.entities`).
Geometry (``<visual>``, ``<collision>``) is read by :mod:`.geometry` into :attr:`Robot.geometry` and is not
passed to yourdfpy (whose engine-specific shapes it rejects). The decimals of
``<mass>`` and ``<inertia>`` are kept as written: the verdict is decided on them.

URDF conventions (https://wiki.ros.org/urdf/XML): ``<inertia>`` is about the
centre of mass in the axes of the ``<inertial><origin>`` frame, whose ``xyz``
is the CoM in the link frame and whose ``rpy`` rotates those axes into the
link's; a joint's ``<origin>`` places the joint frame in the parent link's
frame, and the child link's frame is the joint frame moved by the joint.
"""

from __future__ import annotations

import hashlib
import io
import logging
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from inertiaproof.dynamics.chain import Origin
from inertiaproof.errors import LARGEST, InputError
from inertiaproof.model.inertia import from_urdf, pack, rotation_rpy, urdf_inertia

from . import entities
from .geometry import read_geometry
from .locate import decode, element_spans, urdf_sources

__all__ = [
    "ElementError", "INERTIA_ATTRIBUTES", "Inertial", "JOINT_TYPES", "LARGEST", "Link", "parse_declaring", "Problem",
    "read_urdf", "Robot",
    "UrdfJoint", "XACRO",
]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar", "spherical")
XACRO = "http://ros.org/wiki/xacro"
UNDECLARED = "urn:inertiaproof:undeclared:"  # the namespace an undeclared prefix P is declared with: UNDECLARED + P
INERTIA_ATTRIBUTES = ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")


class ElementError(InputError):
    """A one-line error on one element of a URDF, ending with its line.

    ``detail`` is the message without the file ("link 'a': <mass> misses attribute 'value'"); ``kind`` says what
    is wrong: ``missing`` (an element or attribute), ``format`` (not a number, a wrong count of numbers, an
    unexpanded xacro expression), ``finite`` (nan, inf) or ``range`` (beyond what the audit computes with)."""

    def __init__(self, path, element, detail, kind, line=None):
        self.detail, self.kind, self.element = detail, kind, element
        self.line = element.sourceline if line is None and element is not None else line
        self.expanded = None  # "xacro" when the line is one of the text xacro made of the file
        self.log = ()  # libxml2's messages on undeclared namespace prefixes (bad XML only)
        said = line is not None  # a line given is in ``detail`` already
        super().__init__(f"{path}: {detail}" + (f" (line {self.line})" if self.line and not said else ""))


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
class Problem:
    """Something wrong in a link's ``<inertial>`` that urdfdom logs as an error and reads past (see the module).

    ``kind``: ``missing_inertia`` (an ``<inertial>`` without ``<inertia>``) or ``malformed_inertial``;
    ``reads``: what urdfdom and Pinocchio read instead; ``span``: where the element at fault stands (a
    :class:`.locate.Span`)."""

    link: str
    kind: str
    message: str  # one line naming link and field, and what urdfdom and Pinocchio do with it
    reads: str
    missing: bool  # an element or attribute is missing (else a value is not a number)
    span: object = None
    expanded: str | None = None  # "xacro": the span is in the text xacro made of the file


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
    written: dict | None = None  # as written: origin (an inertiaproof.dynamics.chain.Origin), axis, limits (strings)


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
    problems: tuple = ()  # of Problem: what is wrong in a link's <inertial> and read past, as urdfdom does
    sha256: str = ""  # of the bytes read
    geometry: dict = field(default_factory=dict, compare=False)  # link name -> geometry.LinkGeometry (URDF only)

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
    """The robot in a URDF file; raises InputError with one line naming the bad element (an :class:`ElementError`
    ends with its line).

    ``data``: the text to read instead of the file's (``expanded`` says by what, e.g. "xacro": the positions are
    then in that text, and each Source says so); ``warnings``: what the expansion said."""
    path = Path(path)
    if data is None:
        try:
            data = path.read_bytes()
        except OSError as exc:
            raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    warnings = list(warnings)
    try:
        root = _parse_xml(data, path, warnings)
        written, unlimited, found, unread, origins = _check(root, path, warnings)
    except ElementError as exc:
        exc.expanded = expanded
        raise
    spans = element_spans(decode(data)[0], root)
    sources = urdf_sources(data, root, path, spans)
    if expanded is not None:
        sources = {name: replace(source, expanded=expanded) for name, source in sources.items()}
    problems = tuple(replace(problem, span=spans.get(element), expanded=expanded) for problem, element in found)
    geometry = read_geometry(root, path, spans)  # before _as_engines_read_it strips it
    spherical = {j.get("name") for j in root.iter("joint") if j.get("type") == "spherical"}
    robot = _from_yourdfpy(_as_engines_read_it(root, unread), path, written, unlimited | spherical, spherical)
    joints = tuple(replace(j, written=origins.get(j.name)) for j in robot.joints)
    return replace(robot, links=_as_urdfdom_reads(robot.links, unread), joints=joints, sources=sources,
                   warnings=tuple(warnings), problems=problems, sha256=hashlib.sha256(data).hexdigest(),
                   geometry=geometry)


_DECLARATION = re.compile(rb"^(\s*)(<\?xml\b[^>]*?\?>)", re.S)
_VERSION = re.compile(rb"""version\s*=\s*(["'])([^"']*)\1""")


def _parse_xml(data, path, warnings):
    """The root <robot> of the file's bytes, with what urdfdom reads and lxml does not set right (see the module)."""
    if not data.strip():
        raise InputError(f"{path}: empty file")
    root, _ = parse_declaring(_tolerated(data, warnings), path, warnings)
    if root.tag != "robot":
        raise InputError(f"{path}: the root element is <{root.tag}>, not <robot>")
    return root


def parse_declaring(data, path, warnings):
    """(root element, bytes read) of an XML file's bytes, its undeclared namespace prefixes declared on the root
    start tag (a warning each): the element or attribute kept with its prefixed name, as urdfdom (TinyXML) reads
    it."""
    try:
        return _parse(data, path), data
    except ElementError as exc:
        prefixes = _undeclared_prefixes(exc)
        if not prefixes:
            raise
        for prefix in prefixes:
            warnings.append(f"namespace prefix '{prefix}' is not declared: its elements and attributes are read as "
                            "unknown ones, as urdfdom (TinyXML) reads them")
        data = _declare(data, prefixes)
        return _parse(data, path), data


def _parse(data, path):
    """The root element of the bytes, or one line naming the file: an ElementError with the line of bad XML (its
    ``log``: libxml2's messages)."""
    from lxml import etree

    try:
        return entities.parse(data, path)  # internal DTD entities expanded safely, or refused (see .entities)
    except InputError:
        raise
    except etree.XMLSyntaxError as exc:
        line = f" at line {exc.lineno}" if exc.lineno else ""
        error = ElementError(path, None, f"not well-formed XML{line}: {' '.join(exc.msg.split())}", "format",
                             line=exc.lineno or None)
        error.log = [entry.message for entry in exc.error_log if entry.type_name == "NS_ERR_UNDEFINED_NAMESPACE"]
        raise error from None
    except (ValueError, RecursionError) as exc:
        raise InputError(f"{path}: not usable XML: {exc}") from None


_UNDECLARED = re.compile(r"Namespace prefix (\S+) (?:for \S+ )?on \S+ is not defined")
_ROOT_TAG = re.compile(rb"<!--.*?-->|<\?.*?\?>|<!DOCTYPE(?:[^\[>]|\[.*?\])*>|<([A-Za-z_][\w.:\-]*)", re.S)


def _undeclared_prefixes(error):
    """The namespace prefixes libxml2 found used and never declared, in the order it met them."""
    found = (_UNDECLARED.match(message) for message in error.log)
    return list(dict.fromkeys(m.group(1) for m in found if m and m.group(1) not in ("xml", "xmlns")))


def _declare(data, prefixes):
    """The bytes with ``xmlns:P="urn:inertiaproof:undeclared:P"`` for each prefix inserted right after the root
    element's name, on the same line: every element keeps its line."""
    root = next((m for m in _ROOT_TAG.finditer(data) if m.group(1)), None)
    if root is None:
        return data
    names = b"".join(b' xmlns:%s="%s%s"' % (p.encode(), UNDECLARED.encode(), p.encode()) for p in prefixes)
    return data[:root.end(1)] + names + data[root.end(1):]


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

    def error(problem, kind="format"):
        return ElementError(path, element, f"{_where(element)}: <{element.tag}> {problem}", kind)

    if raw is None:
        if default is None:
            raise error(f"misses attribute '{attribute}'", "missing")
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
        raise error(f"attribute {attribute}=\"{raw}\" is not finite", "finite")
    if not all(abs(v) <= LARGEST for v in values):
        raise error(f"attribute {attribute}=\"{raw}\" is out of range (|x| <= {LARGEST:g})", "range")
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
        raise ElementError(path, found[1], f"{_where(element)} has {len(found)} <{tag}> elements", "format")
    if required and not found:
        raise ElementError(path, element, f"{_where(element)}: <{element.tag}> misses <{tag}>", "missing")
    return found[0] if found else None


def _check_origin(element, path, warnings):
    """The ``xyz`` and ``rpy`` of the element's ``<origin>`` (zeros where absent), checked."""
    origin = _single(element, "origin", path, warnings=warnings)
    if origin is None:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    return (_numbers(origin, "xyz", 3, path, default=(0.0, 0.0, 0.0), warnings=warnings),
            _numbers(origin, "rpy", 3, path, default=(0.0, 0.0, 0.0), warnings=warnings))


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
    mass and inertia as urdfdom reads them ({link: (mass, ixx, iyy, izz, ixy, iyz, ixz)}), the joints whose limits
    are not read (lower > upper), the problems of the inertials ([(Problem, element at fault)]), what urdfdom
    reads of the inertials with problems ({link: Inertial}) and each joint's origin as written ({joint: Origin})."""
    if not root.get("name"):
        raise ElementError(path, root, "<robot> misses attribute 'name'", "missing")
    _expand_leftover_xacro(root, warnings)
    written, unlimited, problems, unread, origins = {}, set(), [], {}, {}
    links = root.findall("link")
    if not links:
        raise ElementError(path, root, f"robot '{root.get('name')}' has no <link> elements", "missing")
    names = set()
    for link in links:
        name = link.get("name")
        if not name:
            raise ElementError(path, link, "a <link> misses attribute 'name'", "missing")
        if name in names:
            raise ElementError(path, link, f"two links are named '{name}'", "format")
        names.add(name)
        inertial = _single(link, "inertial", path, warnings=warnings)
        if inertial is not None:
            written[name], read, link_problems = _read_inertial(name, inertial, path, warnings)
            if read is not None:
                unread[name] = read
                problems += link_problems
    parent_of, joint_names = {}, set()
    for joint in root.findall("joint"):
        name = joint.get("name")
        if not name:
            raise ElementError(path, joint, "a <joint> misses attribute 'name'", "missing")
        if name in joint_names:
            raise ElementError(path, joint, f"two joints are named '{name}'", "format")
        joint_names.add(name)
        kind = joint.get("type")
        if kind not in JOINT_TYPES:
            raise ElementError(path, joint, f"joint '{name}': type {kind!r} is not one of {', '.join(JOINT_TYPES)}",
                               "format")
        ends = {}
        for end in ("parent", "child"):
            link = _single(joint, end, path, required=True).get("link")
            if not link:
                raise ElementError(path, joint.find(end), f"joint '{name}': <{end}> misses attribute 'link'",
                                   "missing")
            if link not in names:
                raise ElementError(path, joint.find(end),
                                   f"joint '{name}': <{end} link='{link}'> names no link of the file", "format")
            ends[end] = link
        if ends["child"] in parent_of:
            raise ElementError(path, joint, f"link '{ends['child']}' is the child of two joints, "
                               f"'{parent_of[ends['child']][0]}' and '{name}'", "format")
        parent_of[ends["child"]] = (name, ends["parent"])
        _check_origin(joint, path, warnings)
        origins[name] = _written(joint)
        axis = _single(joint, "axis", path, warnings=warnings)
        if axis is not None and kind in ("revolute", "continuous", "prismatic"):
            if not any(_numbers(axis, "xyz", 3, path, default=(1.0, 0.0, 0.0), warnings=warnings)):
                raise ElementError(path, axis, f"joint '{name}': <axis xyz=\"{axis.get('xyz')}\"> is the zero vector",
                                   "format")
        limit = _single(joint, "limit", path)
        if kind in ("revolute", "prismatic"):
            if limit is None:
                raise ElementError(path, joint, f"joint '{name}': a {kind} joint needs <limit>", "missing")
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
            raise ElementError(path, mimic, f"joint '{name}': <mimic> misses attribute 'joint'", "missing")
    _check_tree(path, names, parent_of, links)
    return written, unlimited, problems, unread, origins


def _written(joint):
    """A joint's first ``<origin>``, ``<axis>`` and ``<limit>`` (checked) as their attributes write them: the
    origin (zeros where absent), the axis (URDF's default 1 0 0) and the limits (None without a <limit>)."""
    def text(element, attribute, default):
        raw = element.get(attribute) if element is not None else None
        return tuple(raw.split()) if raw else default

    origin, axis, limit = (joint.find(tag) for tag in ("origin", "axis", "limit"))
    return {"origin": Origin(text(origin, "xyz", ("0",) * 3), text(origin, "rpy", ("0",) * 3)),
            "axis": text(axis, "xyz", ("1", "0", "0")),
            "limits": None if limit is None else (text(limit, "lower", ("0",))[0], text(limit, "upper", ("0",))[0])}


URDFDOM_SAYS = {"missing_inertia": "Inertial element must have inertia element"}  # its own log line, observed


def _read_inertial(name, inertial, path, warnings):
    """What urdfdom reads of one link's ``<inertial>``: the decimals (mass, ixx, iyy, izz, ixy, iyz, ixz), and
    for an ``<inertial>`` with errors the Inertial it reads and [(Problem, element at fault)], one per error.

    urdfdom's parseInertial reads ``<origin>``, ``<mass>`` and ``<inertia>`` in that order and stops at the
    first error, keeping what it read: an error in the inertia leaves a point mass at the origin, an earlier one
    no mass. Every error is reported; a value beyond the audit's range stays a one-line error of the file."""
    errors = []

    def attempt(check):
        try:
            return check()
        except ElementError as exc:
            if exc.kind == "range":
                raise
            errors.append(exc)
            return None

    origin = attempt(lambda: _check_origin(inertial, path, warnings))
    mass = attempt(lambda: _single(inertial, "mass", path, required=True, warnings=warnings))
    value = None if mass is None else attempt(lambda: _numbers(mass, "value", 1, path))
    mass_read = not errors
    inertia = attempt(lambda: _single(inertial, "inertia", path, required=True, warnings=warnings))
    for attribute in INERTIA_ATTRIBUTES if inertia is not None else ():
        attempt(lambda a=attribute: _numbers(inertia, a, 1, path))
    if not errors:
        return (mass.get("value").strip(), *(inertia.get(a).strip() for a in INERTIA_ATTRIBUTES)), None, []
    kind = "missing_inertia" if inertia is None else "malformed_inertial"
    if mass_read:
        reads = f"a point mass of {value[0]:g} kg at its <origin> (zero rotational inertia)"
        written = (mass.get("value").strip(), *("0",) * 6)
        read = Inertial(value[0], np.array(origin[0]), rotation_rpy(origin[1]), np.zeros((3, 3)), written)
    else:
        reads = "massless (mass 0, zero inertia)"
        written = ("0",) * 7
        read = Inertial(0.0, np.zeros(3), np.eye(3), np.zeros((3, 3)), written)
    says = URDFDOM_SAYS.get(kind, f"Could not parse inertial element for Link [{name}]")
    problems = [(Problem(name, kind, f"{e.detail}: urdfdom logs '{says}' and Pinocchio reads the link as {reads}",
                         reads, e.kind == "missing"), e.element) for e in errors]
    return written, read, problems


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


def _as_engines_read_it(root, unread=()):
    """The checked document as bytes for yourdfpy: without geometry (which :mod:`.geometry` has read, and whose
    engine-specific shapes yourdfpy rejects), spherical joints as floating ones (both are left out), and without
    the ``<inertial>`` of the links in ``unread`` (:func:`_as_urdfdom_reads` reads those)."""
    from lxml import etree

    for element in [e for e in root.iter("visual", "collision")]:
        element.getparent().remove(element)
    for link in root.findall("link"):
        if link.get("name") in unread:
            for inertial in link.findall("inertial"):
                link.remove(inertial)
    for joint in root.iter("joint"):
        if joint.get("type") == "spherical":
            joint.set("type", "floating")
    return etree.tostring(root)


def _as_urdfdom_reads(links, unread):
    """The links, those in ``unread`` ({name: Inertial}) with the inertial urdfdom reads of them."""
    return tuple(Link(link.name, unread[link.name]) if link.name in unread else link for link in links)


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
