"""The robot a data set is identified on: a serial chain, its bodies' names and the file's Theta.

ROBOT is a URDF, MJCF or xacro file, or a scene (``*.toml``). A file's bodies are the groups of
:mod:`inertiaproof.audit.kinematic_tree` (a movable joint's child with the links fixed to it, Phi summed in the
child's frame); the data's joints name the chain. Movable joints the data do not name are *locked* at 0: read as
fixed joints, so that what they carry joins the body before them (the Panda's fingers join its hand). The chain is
the tree's first serial chain after locking; the data must name exactly its joints.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from inertiaproof.errors import InputError

__all__ = ["IdentifiedRobot", "robot_model"]


@dataclass(frozen=True)
class IdentifiedRobot:
    """The chain, the names of its joints and bodies, the file's Theta (n, 10) in the body frames, the links of
    each body with their poses in it (4 x 4, for a payload named by a link fixed to a body), the joints locked, and
    the robot file (None for a scene) for a repaired copy."""

    name: str
    chain: object
    joints: tuple
    bodies: tuple
    theta: np.ndarray
    links: dict  # link name -> (body index, pose of the link in the body's frame)
    locked: tuple = ()
    robot: object = None
    groups: tuple = ()  # of kinematic_tree.Group, one per body (files only)

    def body_of(self, link):
        """(body index, pose of ``link`` in that body's frame); InputError naming the link if no body carries it."""
        if link in self.links:
            return self.links[link]
        raise InputError(f"--payload {link!r}: no body of the chain {self.name} carries such a link "
                         f"(bodies: {', '.join(self.bodies)})")


def _scene_model(path, count):
    from inertiaproof.scene.format import load_scene

    scene = load_scene(path)
    n = scene.chain.n
    if count != n:
        raise InputError(f"{path}: the scene's chain has {n} joints, the data {count} (columns q_1 .. q_{n})")
    names = tuple(f"body {k + 1}" for k in range(n))
    links = {name: (k, np.eye(4)) for k, name in enumerate(names)} | {str(k + 1): (k, np.eye(4)) for k in range(n)}
    return IdentifiedRobot(scene.name, scene.chain, tuple(str(k + 1) for k in range(n)), names,
                           np.asarray(scene.trajectory.base, dtype=float), links)


def robot_model(path, joint_names=None, count=None):
    """The :class:`IdentifiedRobot` of a robot file or scene for data that name ``joint_names`` (or, numbered,
    ``count`` joints: the first ``count`` movable joints of the first chain, the rest locked)."""
    path = Path(path)
    if path.suffix.lower() == ".toml":
        if joint_names is not None:
            raise InputError(f"{path}: a scene's joints are numbered: name the data's columns q_1, q_2, ...")
        return _scene_model(path, count)
    from inertiaproof.audit.document import read_robot
    from inertiaproof.audit.kinematic_tree import MOVABLE, kinematic_tree

    robot = read_robot(path)
    movable = [j for j in robot.joints if j.type in MOVABLE]
    if joint_names is None:
        first = kinematic_tree(robot).chains
        if not first:
            raise InputError(f"{path}: no revolute or prismatic joint")
        order = [j.name for j in first[0].chain.joints]
        if count is None or count > len(order):
            raise InputError(f"{path}: the data have {count} joints, the first chain {first[0].name} has "
                             f"{len(order)}: name the columns by joint (q_<joint>)")
        joint_names = order[:count]
    unknown = [name for name in joint_names if name not in {j.name for j in movable}]
    if unknown:
        raise InputError(f"{path}: the data name joint {unknown[0]!r}, which is no revolute or prismatic joint of "
                         "the robot")
    keep = set(joint_names)
    locked = tuple(j.name for j in movable if j.name not in keep)
    if locked:
        joints = tuple(dataclasses.replace(j, type="fixed") if j.name in locked else j for j in robot.joints)
        robot = dataclasses.replace(robot, joints=joints)
    tree = kinematic_tree(robot)
    serial = next((s for s in tree.chains if {j.name for j in s.chain.joints} == keep), None)
    if serial is None:
        raise InputError(f"{path}: the data's joints {', '.join(joint_names)} are not one serial chain of the robot")
    order = [j.name for j in serial.chain.joints]
    links = {}
    for k, group in enumerate(serial.bodies):
        for link, pose in zip(group.links, group.poses):
            links[link] = (k, pose)
    return IdentifiedRobot(serial.name, serial.chain, tuple(order), tuple(g.anchor for g in serial.bodies),
                           np.asarray(serial.theta, dtype=float), links, locked, robot, tuple(serial.bodies))
