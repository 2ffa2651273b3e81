"""Each body's bounding ellipsoid from its links' geometry as the audit reads it, for the consistent fit's condition
tr(Q_l f(Phi_l)) >= 0 (Wensing, Kim and Slotine 2017; :mod:`.consistent`).

A body of the identification is a group of links (:mod:`inertiaproof.audit.kinematic_tree`): the anchor link and
the links fixed to it, Phi_l about the anchor link's origin in its axes, the frame a URDF link's ``<inertial>`` and
``<collision>`` are written in, so the audit's link frame is the body frame for the anchor, and each other link's
geometry is moved into it by its pose in the group (a link without mass and without geometry, a frame such as
tool0, adds nothing). The geometry (:mod:`inertiaproof.audit.geometry`, collision
else visual; meshes resolved with package:// as :mod:`inertiaproof.audit.mesh_files` does) becomes the audit's cloud
of points with per-coordinate error bounds (:mod:`inertiaproof.audit.mesh_bodies`: every mesh vertex, each
primitive's bounding-box corners); a link's pose in the body adds 2^-50 (|R| |p| + |t|) + |R| E to the bound. The
ellipsoid {x : |L (x - e)|^2 <= rho} is the audit's minimum-volume one of that cloud (Khachiyan), rho an upper bound
over every true point (:func:`inertiaproof.audit.mesh_bodies._ellipsoids`), so it holds the whole geometry; then
M = L^T L / rho (rho raised by ``Q_MARGIN`` for the float division) and Q = [[-M, M e], [e^T M, 1 - e^T M e]], so that
tr(Q f(Phi)) = int rho(x) (1 - (x - e)^T M (x - e)) dx.

A body whose file Phi_l fails the condition (tr(Q f(Phi_file)) < 0: the file's inertia is not that of a mass inside
its geometry, the audit's ``outside-bounding-ellipsoid``) must not get a condition that excludes the file's values:
``mode`` "grown" (the default) grows the ellipsoid about its centre by s = ((m - v) / m (1 + GROW_MARGIN))^(1/2),
v = tr(Q f(Phi_file)) (tr(Q f(Phi)) = m - tr(M Sigma_e), Sigma_e the second moment about e, so M / s^2 puts the
file's values just inside), an ellipsoid that holds the geometry and the file's values; "strict" gives that body
none. A body gets none, with the reason in one line, when a link of it with mass has no geometry the audit reads.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import pseudo_inertia

__all__ = ["GROW_MARGIN", "MODES", "Q_MARGIN", "BodyEllipsoid", "body_ellipsoids", "ellipsoid_matrix"]

MODES = ("grown", "strict")
GROW_MARGIN = 1e-6  # relative: the grown ellipsoid's s^2 raised so the file's values stay inside after rounding
Q_MARGIN = 1e-9  # relative: rho (1 + Q_MARGIN) covers the rounding of M = L^T L / rho and of Q's entries
ROUND = 2.0**-50


class BodyEllipsoid(dict):
    """{body name: Q (4 x 4)} of the bodies that got one, with ``notes``: {body name: what was done, in words}."""

    def __init__(self, q, notes):
        super().__init__(q)
        self.notes = notes


def ellipsoid_matrix(l_matrix, centre, rho):
    """Q (4 x 4) of the ellipsoid {x : |L (x - e)|^2 <= rho} (module docstring)."""
    m = l_matrix.T @ l_matrix / (rho * (1 + Q_MARGIN))
    m = (m + m.T) / 2
    me = m @ centre
    return np.block([[-m, me[:, None]], [me[None, :], np.array([[1.0 - centre @ me]])]])


def _moved(piece, pose):
    """A cloud piece (points, bounds, hints) in the link frame moved into the body frame by ``pose`` (4 x 4)."""
    p, e, h = piece
    r, t = pose[:3, :3], pose[:3, 3]
    if np.array_equal(pose, np.eye(4)):
        return piece
    moved = p @ r.T + t
    bound = e @ np.abs(r).T + ROUND * (np.abs(p) @ np.abs(r).T + np.abs(t)) + 1e-300
    return moved, bound, h @ r.T + t


def _link_pieces(name, geometry, packages):
    """The link's cloud pieces in its own frame, or the reason there are none."""
    from inertiaproof.audit.mesh_bodies import _cloud, _read_parts
    from inertiaproof.audit.mesh_files import MeshUnread

    if geometry is None:
        return None, f"link {name}: no geometry read"
    if geometry.unread and not geometry.meshes:
        return None, geometry.unread
    if geometry.source is None or not (geometry.meshes or geometry.primitives):
        return None, f"link {name}: no <collision> or <visual>"
    try:
        parts = _read_parts(geometry, packages)
    except (MeshUnread, OSError, ValueError) as exc:
        return None, f"link {name}: {exc}"
    cloud = _cloud(parts)
    return [(cloud.points, cloud.error, cloud.hints)], None


def body_ellipsoids(robot, packages=None, mode="grown"):
    """The :class:`BodyEllipsoid` of an :class:`.robot.IdentifiedRobot` read from a URDF (other files and scenes:
    none, with the reason); ``mode`` (:data:`MODES`) says what a body whose file values fail its ellipsoid gets."""
    from inertiaproof.audit.mesh_bodies import _Cloud, _ellipsoids

    notes, found = {}, {}
    source = getattr(robot.robot, "geometry", None)
    if robot.robot is None or getattr(robot.robot, "format", None) != "urdf" or not source:
        return BodyEllipsoid({}, {b: "no URDF geometry (bounding ellipsoids are read from URDF links)"
                                  for b in robot.bodies})
    masses = {link.name: link.phi for link in robot.robot.links}
    for l, (name, group) in enumerate(zip(robot.bodies, robot.groups)):
        pieces, why, massless = [], None, []
        for link, pose in zip(group.links, group.poses):
            if not np.any(masses.get(link, np.zeros(10))) and not getattr(source.get(link), "source", None):
                massless.append(link)  # a frame without mass or geometry (tool0): holds nothing
                continue
            got, why = _link_pieces(link, source.get(link), packages)
            if got is None:
                break
            pieces += [_moved(piece, np.asarray(pose, float)) for piece in got]
        if why is not None:
            notes[name] = f"no ellipsoid: {why}"
            continue
        candidates = _ellipsoids(_Cloud(pieces))
        chosen = next((c for c in candidates if c[0] == "minimum-volume"), candidates[0] if candidates else None)
        if chosen is None:
            notes[name] = "no ellipsoid: none holds the cloud"
            continue
        label, l_matrix, centre, rho = chosen
        q = ellipsoid_matrix(np.asarray(l_matrix, float), np.asarray(centre, float), float(rho))
        value = float(np.trace(q @ pseudo_inertia(robot.theta[l])))
        axes = np.sort(np.sqrt(float(rho) / np.maximum(np.linalg.eigvalsh(l_matrix.T @ l_matrix), 1e-300)))
        held = [k for k in group.links if k not in massless]
        kinds = sorted({source[k].source for k in held})
        described = (f"the {label} ellipsoid of {', '.join(held)} ({'/'.join(kinds)}), centre "
                     f"({', '.join(f'{x:.4g}' for x in centre)}) m, semi-axes ({', '.join(f'{x:.4g}' for x in axes)}) m")
        if value < 0 and mode == "strict":
            notes[name] = (f"no ellipsoid: the file's own inertia fails {described} (tr(Q f(Phi_file)) = {value:.3g} "
                           "< 0), so the condition would exclude it")
            continue
        if value < 0:
            mass = float(robot.theta[l][0])
            if not mass > 0:
                notes[name] = f"no ellipsoid: the file's values fail {described} and its mass is not positive"
                continue
            grow = np.sqrt((mass - value) / mass * (1 + GROW_MARGIN))  # tr(M Sigma_e) = m - value
            q = ellipsoid_matrix(np.asarray(l_matrix, float), np.asarray(centre, float), float(rho) * grow**2)
            notes[name] = (f"{described}, grown {grow:.4g}-fold about its centre: the file's own inertia fails the "
                           f"geometry's ellipsoid (tr(Q f(Phi_file)) = {value:.3g} < 0), so the condition holds the "
                           "geometry and the file's values (on its boundary)")
            found[name] = q
            continue
        found[name] = q
        notes[name] = f"{described}; the file's values inside (tr(Q f(Phi_file)) = {value:.3g})"
    return BodyEllipsoid(found, notes)
