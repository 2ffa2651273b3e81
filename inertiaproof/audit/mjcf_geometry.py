"""The geoms of each MJCF body as the audit's geometry, and MuJoCo's own inertia from them.

Read from the model MuJoCo compiled (:mod:`.mjcf`): the compiler has applied ``angle``, ``eulerseq``, ``fromto``,
defaults and frames, so each geom's ``geom_type``, ``geom_size``, ``geom_pos`` and ``geom_quat`` (in its body's
frame) are MuJoCo's float64 numbers. Each geom becomes a :class:`.geometry.Primitive` in the audit's link frame
(the body frame placed where :mod:`.mjcf` puts it):

- ``box`` (half-sizes a, b, c): the box 2a x 2b x 2c; ``sphere`` (r): itself; ``cylinder`` (r, half-length h):
  radius r, length 2h;
- ``capsule`` (r, h): enclosed by the cylinder of radius r and length 2h + 2r (its hemispherical caps fit in the
  cylinder's ends), ``ellipsoid`` (a, b, c): by the box 2a x 2b x 2c. A superset G' of the geom G keeps every hard
  finding of :mod:`.bodies_inside` a theorem about G: a body inside G is inside G', so a mass, centre or inertia no
  body inside G' has, no body inside G has (the bounds are weaker, never wrong);
- ``mesh``, ``plane``, ``hfield`` and ``sdf`` geoms: not decided on (:attr:`.geometry.LinkGeometry.unread`).

Every geom of the body counts, visual ones too (contype 0): their union holds the body, whatever the body's
collision geoms are. The geoms' poses enter exactly as the doubles MuJoCo compiled (a rotation through its
roll-pitch-yaw angles, computed in float64: a few ulps, so only a boundary case within that rounding can go
either way); the declared inertial as :mod:`.mjcf` reads it.

MuJoCo's own inertia (:func:`mujoco_inertia`): the spec compiled once more with ``inertiafromgeom="true"``, so
that every body gets the mass, centre and principal moments MuJoCo computes from its geoms at their densities.
:func:`compare_with_mujoco` holds a declared ``<inertial>`` against it at the declared mass (the geoms' inertia
scaled to it, i.e. their shapes filled uniformly): the soft finding ``unlike-mujoco-inertia`` when a principal
moment is more than :data:`.bodies_inside.MOMENT_RATIO` times off, or the centre is farther from MuJoCo's than
MuJoCo's radius of gyration sqrt(tr(I)/(2 m)); with the proposal (MuJoCo's inertia at the declared mass, as an
``<inertial>`` element in the body frame).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .bodies_inside import MOMENT_RATIO
from .geometry import LinkGeometry, Pose, Primitive

__all__ = ["RULE", "SOFT_REPLACED", "MjcfGeometry", "body_geometry", "compare_with_mujoco", "mujoco_inertia",
           "with_mujoco"]

RULE = "unlike-mujoco-inertia"
SOFT_REPLACED = ("implausible-density", "inertia-unlike-geometry")  # replaced for MJCF by the comparison with MuJoCo
BOX, SPHERE, CAPSULE, ELLIPSOID, CYLINDER = 6, 2, 3, 4, 5  # mjtGeom
NOT_READ = {0: "plane", 1: "hfield", 7: "mesh", 8: "sdf"}


@dataclass(frozen=True)
class MjcfGeometry(LinkGeometry):
    """A body's geoms (:class:`.geometry.LinkGeometry`) and MuJoCo's inertia from them (``mujoco``: mass, centre
    and axes in the link frame, principal moments, and the body-frame numbers for the proposal; None when MuJoCo
    could not compute it, ``mujoco_unread`` saying why)."""

    mujoco: dict | None = None
    mujoco_unread: str | None = None
    enclosed: int = 0  # capsules and ellipsoids, entered as the cylinders and boxes that enclose them


def _quat(q):
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _rpy(r):
    """Roll, pitch, yaw of R = Rz(yaw) Ry(pitch) Rx(roll), float64."""
    c = math.hypot(r[0, 0], r[1, 0])
    if c < 1e-12:
        return math.atan2(-r[1, 2], r[1, 1]), math.atan2(-r[2, 0], c), 0.0
    return math.atan2(r[2, 1], r[2, 2]), math.atan2(-r[2, 0], c), math.atan2(r[1, 0], r[0, 0])


def _pose(rotation, position):
    """The exact Pose of float64 numbers (the identity rotation stays exactly zero angles)."""
    angles = (0.0, 0.0, 0.0) if np.array_equal(rotation, np.eye(3)) else _rpy(rotation)
    return Pose(tuple(Fraction(float(x)) for x in position), tuple(Fraction(float(a)) for a in angles))


def _primitive(kind, size, pose, name):
    """The Primitive of one geom (a superset for capsules and ellipsoids), or the reason it is not read."""
    s = [Fraction(float(x)) for x in size]
    if kind == BOX:
        return Primitive("box", tuple(2 * x for x in s), pose)
    if kind == SPHERE:
        return Primitive("sphere", (s[0],), pose)
    if kind == CYLINDER:
        return Primitive("cylinder", (s[0], 2 * s[1]), pose)
    if kind == CAPSULE:
        return Primitive("cylinder", (s[0], 2 * s[1] + 2 * s[0]), pose)
    if kind == ELLIPSOID:
        return Primitive("box", tuple(2 * x for x in s), pose)
    return f"body '{name}': a {NOT_READ.get(kind, f'type {kind}')} geom is not decided on"


def body_geometry(model, placed, names, inertials, spans, compiled_from_geoms):
    """{link name: MjcfGeometry} of every body with a positive mass: its geoms placed in its link frame
    (``placed[b]``: body b's frame in its link), the declared inertial's pose (``inertials[b]``, link frame) and
    MuJoCo's inertia from the geoms (``compiled_from_geoms``: the model compiled with inertiafromgeom="true", or
    the reason it could not be)."""
    out = {}
    for b in range(1, model.nbody):
        inertial = inertials.get(b)
        if inertial is None:
            continue
        place = placed[b]
        geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == b]
        parts, unread = [], None
        for g in geoms:
            rotation = place[:3, :3] @ _quat(model.geom_quat[g])
            position = place[:3, :3] @ model.geom_pos[g] + place[:3, 3]
            found = _primitive(int(model.geom_type[g]), model.geom_size[g], _pose(rotation, position), names[b])
            if isinstance(found, str):
                unread = unread or found
            else:
                parts.append(found)
        if not geoms:
            unread = f"body '{names[b]}': no geoms"
        inertial_pose = _pose(inertial.rotation, inertial.com)
        mujoco, why = _mujoco_of(compiled_from_geoms, b, place)
        enclosed = sum(int(model.geom_type[g]) in (CAPSULE, ELLIPSOID) for g in geoms)
        out[names[b]] = MjcfGeometry("geoms", () if unread else tuple(parts), unread, inertial_pose, spans.get(b),
                                     mujoco=mujoco, mujoco_unread=why, enclosed=enclosed)
    return out


def mujoco_inertia(spec, mujoco):
    """The model of ``spec`` compiled with inertiafromgeom="true" (MuJoCo's inertia from the geoms of every body),
    or a one-line reason it cannot be; the spec's compiler setting is restored."""
    before = spec.compiler.inertiafromgeom
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_TRUE
    try:
        with warnings.catch_warnings():  # the first compile has said what MuJoCo warns about the file
            warnings.simplefilter("ignore")
            return spec.compile()
    except Exception as exc:  # MuJoCo raises ValueError with its compiler's message
        return f"MuJoCo cannot compute the inertia from the geoms: {' '.join(str(exc).split())}"
    finally:
        spec.compiler.inertiafromgeom = before


def _mujoco_of(model, b, place):
    if isinstance(model, str):
        return None, model
    mass = float(model.body_mass[b])
    if not mass > 0:
        return None, "MuJoCo's inertia from the geoms has no mass (geoms of zero density or mass)"
    axes = _quat(model.body_iquat[b])
    return {"mass": mass, "com": place[:3, :3] @ model.body_ipos[b] + place[:3, 3], "axes": place[:3, :3] @ axes,
            "moments": np.array(model.body_inertia[b], dtype=float), "body_pos": np.array(model.body_ipos[b]),
            "body_quat": np.array(model.body_iquat[b])}, None


def _g(x):
    return f"{float(x):.9g}"


def compare_with_mujoco(name, inertial, geometry):
    """(finding or None, proposal or None, not decided or None) of a declared inertial against MuJoCo's inertia
    from the body's geoms, at the declared mass (see the module)."""
    found = getattr(geometry, "mujoco", None)
    if found is None:
        return None, None, getattr(geometry, "mujoco_unread", None)
    m = float(inertial.mass)
    if not m > 0:
        return None, None, None
    scale = m / found["mass"]
    theirs = found["moments"] * scale
    declared = np.linalg.eigvalsh(inertial.inertia)  # principal moments: the same in every frame
    mine_sorted, theirs_sorted = np.sort(declared), np.sort(theirs)
    ratio = max(max(x / y, y / x) for x, y in zip(mine_sorted, theirs_sorted)) \
        if min(mine_sorted) > 0 and min(theirs_sorted) > 0 else math.inf
    offset = float(np.linalg.norm(np.asarray(inertial.com) - found["com"]))
    gyration = math.sqrt(float(theirs.sum()) / (2 * m))
    proposal = {"principal_moments": theirs_sorted.tolist(),
                "text": f'<inertial pos="{" ".join(map(_g, found["body_pos"]))}" '
                        f'quat="{" ".join(map(_g, found["body_quat"]))}" mass="{_g(m)}" '
                        f'diaginertia="{" ".join(map(_g, theirs))}"/>',
                "span": None if geometry.inertial_span is None else geometry.inertial_span.region(),
                "from": "MuJoCo's inertia from the geoms, scaled to the declared mass"}
    if ratio <= MOMENT_RATIO and offset <= gyration:
        return None, proposal, None
    said = []
    if ratio > MOMENT_RATIO:
        said.append(f"principal moments ({', '.join(f'{x:.4g}' for x in mine_sorted)}) kg m^2 are up to "
                    f"{ratio:.3g}x off MuJoCo's from the geoms at {m:g} kg ({', '.join(f'{x:.4g}' for x in theirs_sorted)})")
    if offset > gyration:
        said.append(f"the centre of mass is {offset:.4g} m from MuJoCo's ({' '.join(f'{x:.4g}' for x in found['com'])}),"
                    f" more than its radius of gyration {gyration:.4g} m")
    finding = {"rule": RULE, "hard": False, "message": f"link '{name}': declared <inertial> against MuJoCo's own "
               f"inertia from its geoms (inertiafromgeom): {'; '.join(said)}",
               "numbers": {"ratio": float(ratio) if math.isfinite(ratio) else None, "com_offset": offset,
                           "gyration": gyration, "mujoco_mass": found["mass"]}}
    return finding, proposal, None


def with_mujoco(name, inertial, geometry, found):
    """The findings of :func:`.bodies_inside.link_findings` on an MJCF body (``found``), its soft findings on the
    geoms' own shapes replaced by the comparison with MuJoCo's inertia (:func:`compare_with_mujoco`), which also
    gives the proposal; the enclosures of capsules and ellipsoids said in the geometry's entry."""
    if found is None or inertial is None:
        return found
    found["findings"] = [f for f in found["findings"] if f["rule"] not in SOFT_REPLACED]
    finding, proposal, why = compare_with_mujoco(name, inertial, geometry)
    if finding is not None:
        found["findings"].append(finding)
    if why is not None:
        found["not_decided"].append(f"{RULE}: {why}")
    found["uniform"] = proposal
    enclosed = getattr(geometry, "enclosed", 0)
    if found.get("geometry") and enclosed:
        found["geometry"]["note"] = (f"{enclosed} capsule or ellipsoid geom(s) enter as the cylinder or box that "
                                     "encloses them: the hard findings hold for the geoms themselves")
    return found
