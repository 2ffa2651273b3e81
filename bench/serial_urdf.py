"""A serial URDF of n revolute joints (a spatial snake: 10 cm links of 0.5 kg, axes alternating z, y, x) for the
scaling benchmarks and tests of the Section 4 brackets.

Run: python bench/serial_urdf.py 30 out/serial_30.urdf
"""

from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["serial_urdf"]

AXES = ("0 0 1", "0 1 0", "1 0 0")


def serial_urdf(n, *, length=0.1, mass=0.5, radius=0.02):
    """URDF text of an n-joint serial chain with consistent solid-cylinder links and limits +-2.8 rad."""
    ixx = mass * (3 * radius**2 + length**2) / 12
    izz = mass * radius**2 / 2
    links = ['  <link name="base"/>']
    joints = []
    for k in range(n):
        links.append(
            f'  <link name="link{k}">\n'
            f'    <inertial><origin xyz="{length / 2} 0 0" rpy="0 1.5707963267948966 0"/><mass value="{mass}"/>\n'
            f'      <inertia ixx="{ixx:.9g}" iyy="{ixx:.9g}" izz="{izz:.9g}" ixy="0" ixz="0" iyz="0"/></inertial>\n'
            f'  </link>')
        parent = "base" if k == 0 else f"link{k - 1}"
        offset = "0 0 0" if k == 0 else f"{length} 0 0"
        joints.append(
            f'  <joint name="j{k}" type="revolute"><parent link="{parent}"/><child link="link{k}"/>\n'
            f'    <origin xyz="{offset}" rpy="0 0 0"/><axis xyz="{AXES[k % 3]}"/>\n'
            f'    <limit lower="-2.8" upper="2.8" effort="10" velocity="1"/></joint>')
    return f'<?xml version="1.0"?>\n<robot name="serial{n}">\n' + "\n".join(links + joints) + "\n</robot>\n"


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    out = Path(sys.argv[2]) if len(sys.argv) > 2 else Path(f"serial_{n}.urdf")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(serial_urdf(n))
    print(out)
