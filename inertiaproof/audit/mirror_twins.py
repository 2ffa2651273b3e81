"""Mirror twins: a left link and a right link whose inertias should be reflections of each other.

A pair is two links whose names differ only by a left/right marker (case-insensitive):

- ``left`` / ``right`` anywhere in the name (``left_hip`` / ``right_hip``, ``LeftFoot`` / ``RightFoot``);
- ``l`` / ``r`` as a whole token, tokens being separated by ``_``, ``-``, ``.``, ``/`` or the ends of the name
  (``l_hip`` / ``r_hip``, ``hip_l`` / ``hip_r``, ``arm_L_1`` / ``arm_R_1``); ``FL_hip`` / ``FR_hip`` are not a pair
  (the token is ``FL``, not ``L``);

and whose joints place them mirrored across a plane of the robot. The base frame is the frame of the root link;
every link is placed at q = 0 (each joint's ``<origin>`` alone). With p and p' the origins of the two links' parent
joints in the base frame, the mirror plane is the plane through the base origin normal to the base axis k along
which they differ in sign (p_k p'_k < 0), provided p' = S p within the placement tolerance (the other two
coordinates equal, the k-th opposite; ``PLACEMENT_TOLERANCE`` relative to max(|p|, |p'|), plus 1e-6 m). No such
axis (or two): not a pair, and nothing is checked. A link may be in at most one pair; two links neither of which
has mass (frames) are not listed.

For each pair, with S = I3 - 2 e_k e_k^T the reflection across the plane, m, c, I (mass, centre of mass and
inertia about it) of the left link and m', c', I' of the right one in the base frame at q = 0:

- mass: |m - m'| <= tol max(m, m');
- centre: |c'_i - (S c)_i| <= tol max(|c|, |c'|) + 1e-6 m for each coordinate i, c and c' taken from the link's
  own origin (in base axes), so that an offset of the placement (accepted within its tolerance) is not counted
  again as an offset of the centre;
- inertia: |I'_ij - (S I S)_ij| <= tol lambda_max for each of the six entries, lambda_max the largest principal
  moment of the two;

``tol`` is ``DEFAULT_TOLERANCE`` (1e-3, relative). A mismatch is a finding (rule ``mirror-twin-mismatch``) of level
``warning``: soft, not counted in the exit status, since many real robots are not exact mirrors (a cable on one
side, a motor turned the other way). Its message names both links and each entry that differs, e.g.
``ixy: 0.0012 vs 0.0012 expected -0.0012`` (the left link's entry, the right link's, and the right link's as the
reflection of the left one would have it), all in base axes. A link without mass against one with mass is a
mismatch of the mass (and of every nonzero entry).

Identical parts mounted turned by a half turn rather than mirrored (a copy of one arm on the other side) are
reported too: their inertias are rotations, not reflections, of each other.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["DEFAULT_TOLERANCE", "PLACEMENT_TOLERANCE", "mirror_twins", "RULE", "side_templates"]

RULE = "mirror-twin-mismatch"
DEFAULT_TOLERANCE = 1e-3
PLACEMENT_TOLERANCE = 1e-2
PLACEMENT_ABSOLUTE = 1e-6  # m
AXES = "xyz"
ENTRIES = (("ixx", 0, 0), ("iyy", 1, 1), ("izz", 2, 2), ("ixy", 0, 1), ("iyz", 1, 2), ("ixz", 0, 2))
_WORD = re.compile(r"left|right", re.IGNORECASE)
_TOKEN = re.compile(r"(?<![^_\-./])[lr](?![^_\-./])", re.IGNORECASE)


def side_templates(name):
    """Every (template, side) of a name: the name with one left/right marker replaced by a placeholder, and the
    side ("left" or "right") that marker names."""
    out = []
    for pattern in (_WORD, _TOKEN):
        for m in pattern.finditer(name):
            side = "left" if m.group().lower().startswith("l") else "right"
            out.append((name[:m.start()] + "\0" + name[m.end():], side))
    return out


def _poses(robot):
    """Each link's pose in its root link's frame at q = 0, and its root: {name: (4x4, root)}."""
    children, has_parent = {}, set()
    for joint in robot.joints:
        children.setdefault(joint.parent, []).append(joint)
        has_parent.add(joint.child)
    out = {}
    for link in robot.links:
        if link.name in has_parent:
            continue
        stack = [(link.name, np.eye(4))]
        while stack:
            name, pose = stack.pop()
            if name in out:  # not a tree: the reader has refused it already; do not loop
                continue
            out[name] = (pose, link.name)
            stack += [(j.child, pose @ j.origin) for j in children.get(name, ())]
    return out


def _plane(p, q):
    """The base axis k across whose normal plane p and q are mirrored, or None."""
    tol = PLACEMENT_TOLERANCE * max(np.linalg.norm(p), np.linalg.norm(q)) + PLACEMENT_ABSOLUTE
    found = []
    for k in range(3):
        if p[k] * q[k] < 0:
            s = np.ones(3)
            s[k] = -1
            if np.all(np.abs(q - s * p) <= tol):
                found.append(k)
    return found[0] if len(found) == 1 else None


def _pairs(robot, poses):
    """(left, right, axis) of every mirror-placed left/right pair, in file order of the left link."""
    index = {link.name: k for k, link in enumerate(robot.links)}
    joined = {j.child for j in robot.joints}
    by_template = {}
    for link in robot.links:
        for template, side in side_templates(link.name):
            by_template.setdefault(template, {}).setdefault(side, []).append(link.name)
    used, out = set(), []
    for sides in by_template.values():
        if len(sides.get("left", ())) != 1 or len(sides.get("right", ())) != 1:
            continue
        left, right = sides["left"][0], sides["right"][0]
        if left in used or right in used or left == right or left not in joined or right not in joined:
            continue
        if left not in poses or right not in poses or poses[left][1] != poses[right][1]:
            continue
        axis = _plane(poses[left][0][:3, 3], poses[right][0][:3, 3])
        if axis is None:
            continue
        used |= {left, right}
        out.append((left, right, axis))
    return sorted(out, key=lambda t: index[t[0]])


def _in_base(inertial, pose):
    """(mass, centre relative to the link's origin, inertia about the centre) of an inertial, in base axes; None
    for a link without mass."""
    if inertial is None or not inertial.mass > 0:
        return None
    r = pose[:3, :3] @ inertial.rotation
    return float(inertial.mass), pose[:3, :3] @ inertial.com, r @ inertial.inertia @ r.T


def _check(left, right, axis, a, b, tol):
    """The pair's entry: what was compared, and the differing entries."""
    a = a or (0.0, np.zeros(3), np.zeros((3, 3)))
    b = b or (0.0, np.zeros(3), np.zeros((3, 3)))
    (m, c, i), (m2, c2, i2) = a, b
    s = np.ones(3)
    s[axis] = -1
    expected_c, expected_i = s * c, np.outer(s, s) * i
    differences = []
    if abs(m - m2) > tol * max(m, m2):
        differences.append({"entry": "mass", "left": m, "right": m2, "expected": m})
    c_tol = tol * max(np.linalg.norm(c), np.linalg.norm(c2)) + PLACEMENT_ABSOLUTE
    for k in range(3):
        if abs(c2[k] - expected_c[k]) > c_tol:
            differences.append({"entry": f"com {AXES[k]}", "left": float(c[k]), "right": float(c2[k]),
                                "expected": float(expected_c[k])})
    scale = max(np.linalg.eigvalsh(i)[-1], np.linalg.eigvalsh(i2)[-1], 0.0)
    for entry, p, q in ENTRIES:
        if abs(i2[p, q] - expected_i[p, q]) > tol * scale:
            differences.append({"entry": entry, "left": float(i[p, q]), "right": float(i2[p, q]),
                                "expected": float(expected_i[p, q])})
    plane = f"{AXES[axis]} = 0"
    out = {"left": left, "right": right, "plane": plane, "normal": AXES[axis], "tolerance_rel": tol,
           "matches": not differences, "differences": differences, "message": None}
    if differences:
        said = "; ".join(f"{d['entry']}: {d['left']:.6g} vs {d['right']:.6g} expected {d['expected']:.6g}"
                         for d in differences)
        out["message"] = (f"links '{left}' and '{right}' (mirror twins across the base plane {plane}): the inertial "
                          f"of '{right}' is not the reflection of that of '{left}' (base frame at q = 0; '{left}' vs "
                          f"'{right}' expected): {said} (soft: many real robots are not exact mirrors)")
    return out


def mirror_twins(robot, tol=DEFAULT_TOLERANCE):
    """The mirror twins of a parsed robot (:mod:`.urdf`, :mod:`.mjcf`) as a JSON-ready dict: ``pairs`` (each with
    ``left``, ``right``, ``plane``, ``matches``, ``differences`` and ``message``) and ``mismatches``."""
    if not any(side_templates(link.name) for link in robot.links):  # the common case: nothing to place
        return {"pairs": [], "mismatches": 0}
    poses = _poses(robot)
    inertials = {link.name: link.inertial for link in robot.links}
    pairs = []
    for left, right, axis in _pairs(robot, poses):
        a, b = _in_base(inertials[left], poses[left][0]), _in_base(inertials[right], poses[right][0])
        if a is None and b is None:  # two frames: nothing to compare
            continue
        pairs.append(_check(left, right, axis, a, b, tol))
    return {"pairs": pairs, "mismatches": sum(not p["matches"] for p in pairs)}
