"""The geometry of each URDF link as written, read into exact numbers.

For every ``<link>``: its ``<collision>`` elements (its ``<visual>`` ones when it has no collision), each a
``<geometry>`` with one ``<box size="x y z">``, ``<cylinder radius length>`` (along z) or ``<sphere radius>``
placed in the link frame by the element's ``<origin xyz rpy>`` (https://wiki.ros.org/urdf/XML/link); and the
``<origin>`` of its ``<inertial>``, the frame its declared inertia is in. Numbers are the rationals the decimals
denote (``0.1`` is 1/10, :func:`inertiaproof.model.exact.written_fraction`). A link whose geometry holds a mesh,
a shape URDF does not define, a dimension that is not a positive number or an ``<origin>`` that is not three
numbers is not decided on: its :attr:`LinkGeometry.unread` says why in one line naming the link and field (the
audit shows it under the file's name). A ``<mesh filename scale>`` is a :class:`MeshPart` in
:attr:`LinkGeometry.meshes` (its file is read and decided on by :mod:`.mesh_bodies`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from inertiaproof.model.exact import written_fraction

__all__ = ["PRIMITIVES", "LinkGeometry", "MeshPart", "Pose", "Primitive", "read_geometry"]

PRIMITIVES = {"box": ("size",), "cylinder": ("radius", "length"), "sphere": ("radius",)}
ZERO = (Fraction(0),) * 3


@dataclass(frozen=True)
class Pose:
    """A frame in the link frame as written: ``xyz`` its origin, ``rpy`` URDF's fixed-axis roll, pitch, yaw."""

    xyz: tuple = ZERO  # of Fraction
    rpy: tuple = ZERO

    @property
    def turned(self):
        return any(self.rpy)


@dataclass(frozen=True)
class Primitive:
    """One URDF primitive: ``dims`` box (x, y, z) side lengths, cylinder (radius, length) along its z axis,
    sphere (radius,); all positive Fractions."""

    kind: str
    dims: tuple
    pose: Pose
    line: int | None = None

    def describe(self):
        """'box 0.6 x 0.6 x 0.6 m', 'cylinder r 0.05 m, length 0.2 m', 'sphere r 0.1 m', then its origin."""
        d = [_decimal(x) for x in self.dims]
        shape = {"box": lambda: f"box {' x '.join(d)} m", "cylinder": lambda: f"cylinder r {d[0]} m, length {d[1]} m",
                 "sphere": lambda: f"sphere r {d[0]} m"}[self.kind]()
        origin = "" if self.pose == Pose() else \
            f" at xyz ({' '.join(map(_decimal, self.pose.xyz))}) rpy ({' '.join(map(_decimal, self.pose.rpy))})"
        return shape + origin + (f" (line {self.line})" if self.line else "")


@dataclass(frozen=True)
class MeshPart:
    """One URDF ``<mesh filename scale>``: ``uri`` as written, ``scale`` three nonzero Fractions (default 1 1 1),
    placed by ``pose``; ``base`` the folder of the file that names it (relative URIs and the package search start
    there)."""

    uri: str
    scale: tuple
    pose: Pose
    base: str
    line: int | None = None
    kind = "mesh"

    def describe(self):
        """'mesh package://x/a.stl scale 0.001 0.001 0.001', then its origin."""
        scale = "" if all(s == 1 for s in self.scale) else f" scale {' '.join(map(_decimal, self.scale))}"
        origin = "" if self.pose == Pose() else \
            f" at xyz ({' '.join(map(_decimal, self.pose.xyz))}) rpy ({' '.join(map(_decimal, self.pose.rpy))})"
        return f"mesh {self.uri}{scale}{origin}" + (f" (line {self.line})" if self.line else "")


@dataclass(frozen=True)
class LinkGeometry:
    """A link's geometry (``source``: ``collision``, ``visual`` or None without either) and the frame of its
    declared inertia (``inertial_pose``; ``inertial_span``: where its ``<inertial>`` stands)."""

    source: str | None
    primitives: tuple = ()  # of Primitive, all of them when ``unread`` is None
    unread: str | None = None  # why the geometry is not decided on
    inertial_pose: Pose = Pose()
    inertial_span: object = None
    meshes: tuple = ()  # of MeshPart (the primitives hold the rest of the geometry)


def _decimal(x):
    """A Fraction as a short decimal (exact when it has one of up to 12 digits)."""
    text = f"{float(x):.12g}"
    return text if Fraction(text) == x else f"{float(x):.6g}..."


class _Unread(ValueError):
    pass


def _fractions(element, attribute, count, default, where):
    """``count`` rationals from an attribute as written (``default`` where it is absent), or _Unread naming it."""
    raw = element.get(attribute)
    if raw is None:
        if default is None:
            raise _Unread(f"{where}: <{element.tag}> misses attribute '{attribute}'")
        return default
    parts = raw.split()
    values = [written_fraction(p) for p in parts]
    if len(parts) != count or None in values:
        raise _Unread(f"{where}: <{element.tag} {attribute}=\"{raw}\"> is not {count} decimal number"
                      f"{'s' * (count > 1)}")
    return tuple(values)


def _pose(element, where):
    origin = None if element is None else element.find("origin")
    if origin is None:
        return Pose()
    return Pose(_fractions(origin, "xyz", 3, ZERO, where), _fractions(origin, "rpy", 3, ZERO, where))


def _primitive(holder, where, base="."):
    """The one primitive (or :class:`MeshPart`) of a ``<collision>`` or ``<visual>``, or _Unread."""
    geometry = holder.find("geometry")
    shapes = [] if geometry is None else [e for e in geometry if isinstance(e.tag, str)]
    if len(shapes) != 1:
        raise _Unread(f"{where}: <{holder.tag}> has {len(shapes)} shapes in its <geometry>, not one")
    shape = shapes[0]
    if shape.tag == "mesh":
        if not shape.get("filename"):
            raise _Unread(f"{where}: <mesh> misses attribute 'filename'")
        scale = _fractions(shape, "scale", 3, (Fraction(1),) * 3, where)
        if not all(scale):
            raise _Unread(f"{where}: <mesh scale=\"{shape.get('scale')}\"> has a zero factor")
        return MeshPart(shape.get("filename").strip(), scale, _pose(holder, where), str(base), shape.sourceline)
    if shape.tag not in PRIMITIVES:
        raise _Unread(f"{where}: <{holder.tag}> is a <{shape.tag}>, not a URDF primitive (box, cylinder, sphere)")
    dims = sum((_fractions(shape, a, 3 if a == "size" else 1, None, where) for a in PRIMITIVES[shape.tag]), ())
    if not all(d > 0 for d in dims):
        raise _Unread(f"{where}: <{shape.tag}> has a dimension that is not positive "
                      f"({', '.join(shape.get(a, '') for a in PRIMITIVES[shape.tag])})")
    return Primitive(shape.tag, dims, _pose(holder, where), shape.sourceline)


def read_geometry(root, path, spans=None):
    """{link name: LinkGeometry} of every ``<link>`` of a checked URDF root (before its geometry is stripped)."""
    spans = spans or {}
    out = {}
    for link in root.findall("link"):
        where = f"link '{link.get('name')}'"  # the file names the entry the message stands in
        inertial = link.find("inertial")
        holders = link.findall("collision") or link.findall("visual")
        source = None if not holders else holders[0].tag
        try:
            inertial_pose = _pose(inertial, where)
        except _Unread:
            inertial_pose = None  # urdf.py reports it as a problem of the inertial
        try:
            parts, unread = tuple(_primitive(h, where, Path(path).parent) for h in holders), None
        except _Unread as exc:
            parts, unread = (), str(exc)
        if not holders:
            unread = f"{where}: no <collision> or <visual>"
        out[link.get("name")] = LinkGeometry(source, tuple(p for p in parts if isinstance(p, Primitive)), unread,
                                             inertial_pose, None if inertial is None else spans.get(inertial),
                                             tuple(p for p in parts if isinstance(p, MeshPart)))
    return out
