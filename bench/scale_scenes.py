"""Scale inputs of issue 49: a 30-joint serial scene and a 500-link tree URDF.

    python bench/scale_scenes.py [OUT_DIR]      # writes OUT_DIR/serial_30.toml and OUT_DIR/tree_500.urdf (default out/scale)

The scene is the snake of ``scenes/many_links_24.toml`` grown to ``n`` joints (standard DH, twists alternating
+-90 degrees, 10 cm links of 0.5 kg as solid cylinders, limits +-1 rad) with a 0.5 kg payload ramp at the tip.
The tree has a trunk of ``trunk`` revolute joints and ``branches`` branches of ``depth`` links each hung from the
trunk's links in turn (5 + 99 x 5 = 500 links with a body), every link a consistent solid cylinder, axes
alternating z, y, x. ``inertiaproof run --scene OUT/serial_30.toml --workers 1`` and
``inertiaproof audit OUT/tree_500.urdf --bounds all`` are the measured commands (bench/results/scale.md).
"""

from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["serial_scene", "tree_urdf"]

AXES = ("0 0 1", "0 1 0", "1 0 0")
QUARTER = 1.5707963267948966


def serial_scene(n=30, *, length=0.1, mass=0.5, radius=0.02, payload=0.5):
    """TOML text of an n-joint spatial snake scene with a tip payload ramp (the format of scenes/README.md)."""
    rows = [f"# A {n}-joint spatial snake arm (standard DH, twists alternating +-90 degrees, {length:g} m links of "
            f"{mass:g} kg)", f"# with a {payload:g} kg payload ramp at its tip: written by bench/scale_scenes.py.",
            f'name = "serial-{n}"', f'description = "{n}-DoF spatial snake arm with a tip payload"', "",
            "[chain]", 'convention = "standard"', "gravity = [0.0, 0.0, -9.81]", ""]
    for k in range(n):
        rows += ["[[chain.joint]]", 'type = "revolute"', f"a = {length!r}",
                 f"alpha = {QUARTER if k % 2 == 0 else -QUARTER!r}", "limits = [-1.0, 1.0]", ""]
    solid = (f'solid = {{ shape = "cylinder", dims = [{radius!r}, {length!r}], rpy = [0.0, {QUARTER!r}, 0.0], '
             f"position = [{-length / 2!r}, 0.0, 0.0] }}")
    for _ in range(n):
        rows += ["[[body]]", f"mass = {mass!r}", solid, ""]
    rows += ["[[load]]", 'kind = "payload"', f"body = {n}", f"mass = {payload!r}",
             'solid = { shape = "sphere", dims = [0.03] }',
             'profile = { shape = "smootherstep", start = 0.2, duration = 0.3 }', "",
             "[time]", "start = 0.0", "end = 1.0", "",
             "[control]", 'kind = "computed_torque"', "bandwidth = 10.0", "amplitude = 0.2", "frequency = 1.0",
             "horizon = 0.6", ""]
    return "\n".join(rows)


def _link(name, length, mass, radius):
    ixx = mass * (3 * radius**2 + length**2) / 12
    izz = mass * radius**2 / 2
    return (f'  <link name="{name}">\n'
            f'    <inertial><origin xyz="{length / 2} 0 0" rpy="0 {QUARTER} 0"/><mass value="{mass}"/>\n'
            f'      <inertia ixx="{ixx:.9g}" iyy="{ixx:.9g}" izz="{izz:.9g}" ixy="0" ixz="0" iyz="0"/></inertial>\n'
            f'  </link>')


def _joint(name, parent, child, offset, axis):
    return (f'  <joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>\n'
            f'    <origin xyz="{offset}" rpy="0 0 0"/><axis xyz="{axis}"/>\n'
            f'    <limit lower="-2.8" upper="2.8" effort="10" velocity="1"/></joint>')


def tree_urdf(trunk=5, branches=99, depth=5, *, length=0.1, mass=0.5, radius=0.02):
    """URDF text of a tree: a serial trunk of ``trunk`` links and ``branches`` serial branches of ``depth`` links,
    branch b hanging from trunk link b mod trunk (each link a solid cylinder, revolute joints limited to +-2.8 rad)."""
    links, joints = ['  <link name="base"/>'], []
    for k in range(trunk):
        links.append(_link(f"trunk{k}", length, mass, radius))
        joints.append(_joint(f"t{k}", "base" if k == 0 else f"trunk{k - 1}", f"trunk{k}",
                             "0 0 0" if k == 0 else f"{length} 0 0", AXES[k % 3]))
    for b in range(branches):
        for k in range(depth):
            child = f"b{b}_{k}"
            links.append(_link(child, length, mass, radius))
            parent = f"trunk{b % trunk}" if k == 0 else f"b{b}_{k - 1}"
            offset = f"{length / 2} {0.01 * (b % 7)} 0" if k == 0 else f"{length} 0 0"
            joints.append(_joint(f"j{b}_{k}", parent, child, offset, AXES[(b + k + 1) % 3]))
    name = f"tree{trunk + branches * depth}"
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join(links + joints) + "\n</robot>\n"


def write(out):
    """Write serial_30.toml and tree_500.urdf into ``out``; return their paths."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    scene, tree = out / "serial_30.toml", out / "tree_500.urdf"
    scene.write_text(serial_scene(30))
    tree.write_text(tree_urdf())
    return scene, tree


if __name__ == "__main__":
    for path in write(sys.argv[1] if len(sys.argv) > 1 else "out/scale"):
        print(path)
