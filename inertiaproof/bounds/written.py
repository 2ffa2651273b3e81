"""The chain, its configuration box and numbers as a certificate writes them (:mod:`inertiaproof.bounds.certificate`):
every number an exact rational ("p/q") equal to the float64 the prover used, each fixed transform as origins
{xyz, rpy} from which the checker builds a rigid transform itself."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from inertiaproof.model.inertia import rotation_rpy

from .domain import search_box

__all__ = ["RIGID", "TURN", "chain_data", "distinct", "domain_data", "exact", "exact_rows", "origin_of", "rpy_of"]

RIGID = 1e-12  # how far a fixed transform's rotation may lie from the one its rpy builds: farther, no certificate


def distinct(stack):
    """The distinct entries of a stack (V, ...) along its first axis, in lexicographic order of their flat rows
    (as ``np.unique(axis=0)``, which once failed at random here comparing its structured view: a TypeError)."""
    stack = np.asarray(stack, float)
    rows = sorted({tuple(row) for row in stack.reshape(len(stack), -1).tolist()})
    return np.array(rows, float).reshape(-1, *stack.shape[1:])


def exact(x):
    """The float64 x (or a Fraction) as the exact rational it is, "p/q" (or "p")."""
    return str(x if isinstance(x, Fraction) else Fraction(float(x)))


def exact_rows(a):
    return [[exact(v) for v in row] for row in np.asarray(a, float)]


def rpy_of(rotation):
    """(roll, pitch, yaw) with rotation_rpy(rpy) = ``rotation`` (URDF: R = Rz(yaw) Ry(pitch) Rx(roll))."""
    r = np.asarray(rotation, float)
    pitch = np.arctan2(-r[2, 0], np.hypot(r[0, 0], r[1, 0]))
    if np.hypot(r[0, 0], r[1, 0]) < 1e-9:  # gimbal lock: the roll is folded into the yaw
        return np.array([0.0, pitch, np.arctan2(-r[0, 1], r[1, 1])])
    return np.array([np.arctan2(r[2, 1], r[2, 2]), pitch, np.arctan2(r[1, 0], r[0, 0])])


def origin_of(transform):
    """The origin {xyz, rpy} (exact rationals) of a rigid 4x4 ``transform``, or None where its rotation is not the
    one its rpy builds (within :data:`RIGID`)."""
    t = np.asarray(transform, float)
    rpy = rpy_of(t[:3, :3])
    if not (np.all(t[3] == (0, 0, 0, 1)) and np.abs(rotation_rpy(rpy) - t[:3, :3]).max() <= RIGID):
        return None
    return {"xyz": [exact(x) for x in t[:3, 3]], "rpy": [exact(x) for x in rpy]}


def _origins(origins):
    return [{"xyz": list(o.xyz), "rpy": list(o.rpy)} for o in origins]


def chain_data(chain):
    """The certificate's chain as its source writes it (:class:`inertiaproof.dynamics.chain.Written`): the file's
    path and SHA-256, each joint's kind, axis, limits and the origins its fixed transforms compose, as decimal
    strings; a joint made from numbers as the exact rationals of its floats. None where a transform is not rigid."""
    joints = []
    for j in chain.joints:
        w = j.written
        if w is None:
            before, after = origin_of(j.before), origin_of(j.after)
            if before is None or after is None:
                return None
            before, after = [before], [after]
        else:
            before, after = _origins(w.before), _origins(w.after)
        axis = list(w.axis) if w is not None and w.axis is not None else [exact(a) for a in j.axis]
        limits = None if j.limits is None else (list(w.limits) if w is not None and w.limits is not None
                                                 else [exact(x) for x in j.limits])
        joints.append({"name": j.name, "kind": j.kind, "axis": axis, "before": before, "after": after,
                       **({} if limits is None else {"limits": limits})})
    source = {} if chain.source is None else {"source": {"path": chain.source[0], "sha256": chain.source[1]}}
    return {"name": chain.name, **source, "joints": joints}


TURN = Fraction(float(np.nextafter(2 * np.pi, np.inf)))  # a rational above 2 pi: a full turn and a little more


def domain_data(chain, written):
    """The certificate's domain: the search box, each edge moved outward to a rational that covers the joint's
    limits as written (``written``: :func:`chain_data`'s joints), and a box of a full turn widened to at least
    2 pi, as the checker demands."""
    lo, hi = search_box(chain)
    out = []
    for a, b, joint in zip(lo, hi, written):
        a, b = Fraction(float(a)), Fraction(float(b))
        if "limits" in joint:
            a, b = min(a, Fraction(joint["limits"][0])), max(b, Fraction(joint["limits"][1]))
        if joint["kind"] == "revolute" and b - a >= Fraction(2 * np.pi) * (1 - Fraction(1, 10**12)):
            b = a + TURN
        out.append([str(a), str(b)])
    return out
