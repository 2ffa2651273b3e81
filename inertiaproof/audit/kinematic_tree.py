"""A URDF's tree as the mass matrix sees it: bodies of movable joints and their serial chains.

- A *body* is the child link of a movable joint (revolute, continuous,
  prismatic) together with every link fixed to it; its Phi is the sum of its
  links' Phi expressed in the child link's frame (eq:Phi is linear in the
  density, MassDistributionToInertialParam).
- A *base* is a root (the URDF root, or the child of a floating, planar or
  spherical joint or of an MJCF ball joint, which the audit reports and leaves
  out) with the links fixed to it;
  it does not move in any chain.
- A *chain* is the path of movable joints from a base to a leaf body, as a
  :class:`~inertiaproof.chain.Chain` whose body l is the l-th body on the
  path (frame T_{l-1} . before_l . X_l(q_l), ``after`` = I) with Phi_l in that
  frame. Bodies hanging off the path through other movable joints belong to
  their own chains.

Mimic joints are independent coordinates here, as in Pinocchio's URDF reader
by default; continuous joints are periodic revolute joints without limits.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.dynamics.chain import Chain, Joint, Written
from inertiaproof.model.inertia import skew, spatial_inertia, spatial_inertia_inverse

__all__ = ["Group", "kinematic_tree", "KinematicTree", "LEFT_OUT", "MOVABLE", "phi_in_frame", "SerialChain"]

MOVABLE = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
LEFT_OUT = ("floating", "planar", "spherical", "ball")


def phi_in_frame(phi, pose):
    """Phi of a body given in frame B, expressed in frame A, where ``pose`` (4x4) is B's pose in A.

    The body twist maps as t_B = X t_A with X = [[R^T, -R^T S(p)], [0, R^T]]
    (VelocityRigidMass), so the kinetic energy gives Z_A = X^T Z_B X
    (DefMatrixZ). Exact for every Phi, consistent or not; batched over
    leading axes of ``phi`` and ``pose``.
    """
    pose = np.asarray(pose, dtype=float)
    rt = np.swapaxes(pose[..., :3, :3], -1, -2)
    x = np.zeros(pose.shape[:-2] + (6, 6))
    x[..., :3, :3] = rt
    x[..., :3, 3:] = -rt @ skew(pose[..., :3, 3])
    x[..., 3:, 3:] = rt
    return spatial_inertia_inverse(np.swapaxes(x, -1, -2) @ spatial_inertia(phi) @ x)


@dataclass(frozen=True)
class Group:
    """Links rigidly attached to an anchor link: a body (anchor = a movable joint's child) or a base."""

    anchor: str
    joint: str | None  # the movable joint that moves it; None for a base
    links: tuple  # anchor first
    poses: np.ndarray  # (len(links), 4, 4) each link's frame in the anchor frame
    phi: np.ndarray  # (10,) the summed Phi in the anchor frame

    @property
    def is_body(self):
        return self.joint is not None


@dataclass(frozen=True)
class SerialChain:
    name: str  # "base -> leaf"
    base: str  # anchor of the base group the chain starts from
    chain: Chain
    theta: np.ndarray  # (n, 10), body l's Phi in its frame
    bodies: tuple  # of Group, one per joint


@dataclass(frozen=True)
class KinematicTree:
    groups: dict  # anchor link -> Group
    group_of: dict  # link -> anchor of its group
    left_out: tuple  # (joint name, type) of floating, planar and (MJCF) ball joints
    chains: tuple  # of SerialChain

    def role(self, link):
        """'base', 'body' or 'merged', and the anchor link."""
        anchor = self.group_of[link]
        if not self.groups[anchor].is_body:
            return "base", anchor
        return ("body" if anchor == link else "merged"), anchor


def kinematic_tree(robot):
    """Groups and chains of a :class:`~inertiaproof.urdf.Robot` (a tree, as its reader checked)."""
    children, parent_joint = {}, {}
    for joint in robot.joints:
        children.setdefault(joint.parent, []).append(joint)
        parent_joint[joint.child] = joint
    root = next(link.name for link in robot.links if link.name not in parent_joint)

    members, group_of, pose_in_anchor, written_in_anchor = {}, {}, {}, {}
    stack = [(root, root, np.eye(4), ())]
    while stack:
        link, anchor, pose, written = stack.pop()  # written: the origins from the anchor (None: not all written)
        group_of[link], pose_in_anchor[link], written_in_anchor[link] = anchor, pose, written
        members.setdefault(anchor, []).append(link)
        for joint in reversed(children.get(link, [])):
            if joint.type == "fixed":
                origin = (joint.written or {}).get("origin")
                stack.append((joint.child, anchor, pose @ joint.origin,
                              None if written is None or origin is None else written + (origin,)))
            else:
                stack.append((joint.child, joint.child, np.eye(4), ()))

    names = [link.name for link in robot.links]
    in_anchor = dict(zip(names, phi_in_frame(robot.link_phis(), np.stack([pose_in_anchor[n] for n in names]))))
    groups = {}
    for anchor, links in members.items():
        joint = parent_joint.get(anchor)
        moved_by = joint.name if joint is not None and joint.type in MOVABLE else None
        poses = np.stack([pose_in_anchor[link] for link in links])
        total = np.sum([in_anchor[link] for link in links], axis=0)
        groups[anchor] = Group(anchor, moved_by, tuple(links), poses, total)

    left_out = tuple((j.name, j.type) for j in robot.joints if j.type in LEFT_OUT)
    chains = tuple(_chains(robot, groups, group_of, pose_in_anchor, written_in_anchor, children, parent_joint))
    return KinematicTree(groups, group_of, left_out, chains)


def _chains(robot, groups, group_of, pose_in_anchor, written_in_anchor, children, parent_joint):
    """One serial chain per leaf body, from its base through movable joints only."""
    def body_children(anchor):
        return [j for link in groups[anchor].links for j in children.get(link, []) if j.type in MOVABLE]

    joints = {j.name: j for j in robot.joints}
    for anchor, group in groups.items():
        if not group.is_body or body_children(anchor):
            continue
        path, link = [], anchor
        while groups[group_of[link]].is_body:
            body = group_of[link]
            path.append(joints[groups[body].joint])
            link = parent_joint[body].parent
        path.reverse()
        base = group_of[link]
        chain_joints = []
        for joint in path:
            before = pose_in_anchor[joint.parent] @ joint.origin
            limits = joint.limits if joint.type != "continuous" else None
            origins = written_in_anchor[joint.parent]
            source = joint.written or {}
            written = None if origins is None or "origin" not in source else Written(
                origins + (source["origin"],), (), source["axis"], source["limits"] if limits is not None else None)
            chain_joints.append(Joint(kind=MOVABLE[joint.type], axis=tuple(joint.axis), before=before, limits=limits,
                                      name=joint.name, written=written))
        name = f"{base} -> {anchor}"
        bodies = tuple(groups[j.child] for j in path)
        source = (robot.path, robot.sha256) if robot.sha256 else None
        yield SerialChain(name, base, Chain(tuple(chain_joints), name=name, source=source),
                          np.stack([b.phi for b in bodies]), bodies)
