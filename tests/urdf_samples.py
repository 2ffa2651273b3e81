"""Small URDF texts for the tests, and where example-robot-data keeps its robots."""

from importlib import metadata
from pathlib import Path

import numpy as np


def inertial(mass=1.0, xyz="0 0 0", rpy="0 0 0", ixx=0.01, iyy=0.02, izz=0.025, ixy=0.0, iyz=0.0, ixz=0.0):
    return (f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="{ixy}" iyz="{iyz}" ixz="{ixz}"/></inertial>')


def link(name, body=None):
    return f'<link name="{name}">{inertial() if body is None else body}</link>'


def joint(name, parent, child, kind="revolute", xyz="0 0 0.1", rpy="0 0 0", axis="0 0 1", lower=-1.5, upper=1.5):
    limit = f'<limit lower="{lower}" upper="{upper}" effort="1" velocity="1"/>' if kind in ("revolute", "prismatic") else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>{limit}</joint>')


def robot(*elements, name="test"):
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join(elements) + "\n</robot>\n"


def two_link_arm(second=None, tool=None):
    """base -> (revolute) l1 -> (revolute) l2 [-> (fixed) tool]."""
    parts = [link("base"), link("l1", inertial(1.0, "0.1 0 0.05", "0.3 0.2 0.1")),
             link("l2", second if second is not None else inertial(0.5, "0.2 0 0", "0 0 0", 0.001, 0.01, 0.01)),
             joint("j1", "base", "l1"), joint("j2", "l1", "l2", xyz="0.3 0 0.05", rpy="0.5 0 0.2", axis="0 1 0")]
    if tool is not None:
        parts += [link("tool", tool), joint("jt", "l2", "tool", kind="fixed", xyz="0.1 0.02 0", rpy="0 0.4 0")]
    return robot(*parts)


def write(tmp_path, text, name="robot.urdf"):
    path = Path(tmp_path) / name
    path.write_text(text)
    return path


def robots_folder():
    """example-robot-data's robots folder, or None when the package is not installed."""
    try:
        folder = Path(metadata.distribution("example-robot-data").locate_file("cmeel.prefix/share/example-robot-data/robots"))
    except metadata.PackageNotFoundError:
        return None
    return folder if folder.is_dir() else None


def random_configurations(chain, count, seed=0):
    low, high = chain.coordinate_box()
    return low + (high - low) * np.random.default_rng(seed).random((count, chain.n))
