"""Built-in chains with plausible, physically consistent bodies.

Each function returns a :class:`~inertiaproof.scene.Scene` with constant
parameters unless it says otherwise. Bodies are uniform solids placed along
the links, so every Phi is consistent by construction (Theorem 1).
"""

from __future__ import annotations

import numpy as np

from inertiaproof.dynamics.chain import Chain, Coordinate, Joint, Origin
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile, Scaling
from inertiaproof.model import solids
from inertiaproof.model.inertia import inertia_com, rotation_rpy

from .format import Scene

__all__ = [
    "BUILTIN", "HALF_PI", "non_normal_2r", "panda", "PANDA_DH", "PANDA_LIMITS", "passenger_platform", "planar_2r",
    "revolute_prismatic", "spatial_3r", "translating_sphere", "trolley_2r", "ur5",
]

HALF_PI = np.pi / 2


def _rod(mass, start, end, radius):
    """A solid cylinder from ``start`` to ``end`` (body-frame points)."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    axis = end - start
    length = np.linalg.norm(axis)
    z = axis / length
    x = np.cross(z, [1.0, 0, 0] if abs(z[0]) < 0.9 else [0, 1.0, 0])
    x /= np.linalg.norm(x)
    rot = np.column_stack([x, np.cross(z, x), z])
    return solids.solid("cylinder", mass, (radius, length), rot, (start + end) / 2)


def _scene(name, chain, base, loads=(), span=(0.0, 5.0), description=""):
    return Scene(name, chain, ParameterTrajectory(np.asarray(base, float), tuple(loads), span), description)


def planar_2r(payload=None, start=1.0, duration=0.5):
    """Planar 2R arm, links of 1 m and 0.8 m in the x-y plane, gravity along -y; a payload (kg) ramps in over
    [start, start + duration]."""
    chain = Chain.from_dh([(1.0, 0, 0, 0), (0.8, 0, 0, 0)], name="planar 2R", gravity=(0, -9.81, 0))
    base = [_rod(3.0, (-1.0, 0, 0), (0, 0, 0), 0.05), _rod(2.0, (-0.8, 0, 0), (0, 0, 0), 0.04)]
    loads = () if payload is None else (Payload(1, solids.solid("sphere", payload, (0.05,)),
                                                Profile("smootherstep", start, duration)),)
    return _scene("planar-2r", chain, base, loads, description="planar 2R arm" + (" picking up a payload" if loads else ""))


def spatial_3r():
    """Elbow manipulator: vertical base joint, shoulder and elbow (standard DH)."""
    chain = Chain.from_dh([(0.0, HALF_PI, 0.5, 0), (0.6, 0, 0, 0), (0.5, 0, 0, 0)], name="spatial 3R")
    base = [_rod(4.0, (0, -0.5, 0), (0, 0, 0), 0.08), _rod(3.0, (-0.6, 0, 0), (0, 0, 0), 0.05),
            _rod(2.0, (-0.5, 0, 0), (0, 0, 0), 0.04)]
    return _scene("spatial-3r", chain, base, description="spatial elbow manipulator")


PANDA_DH = (  # modified DH (a_{l-1}, alpha_{l-1}, d_l, theta_l), Franka Emika documentation
    (0.0, 0.0, 0.333, 0.0), (0.0, -HALF_PI, 0.0, 0.0), (0.0, HALF_PI, 0.316, 0.0),
    (0.0825, HALF_PI, 0.0, 0.0), (-0.0825, -HALF_PI, 0.384, 0.0), (0.0, HALF_PI, 0.0, 0.0), (0.088, HALF_PI, 0.0, 0.0),
)
PANDA_LIMITS = ((-2.8973, 2.8973), (-1.7628, 1.7628), (-2.8973, 2.8973), (-3.0718, -0.0698),
                (-2.8973, 2.8973), (-0.0175, 3.7525), (-2.8973, 2.8973))


def panda(payload=None):
    """7-DoF Panda-like arm (modified DH, joint limits of the real robot) with link masses near Franka's."""
    chain = Chain.from_dh(PANDA_DH, convention="modified", name="panda", limits=PANDA_LIMITS)
    masses = (4.97, 0.65, 3.23, 3.59, 1.23, 1.67, 1.47)
    segments = (((0, 0, -0.2), (0, 0, 0)), ((0, 0, 0), (0, -0.2, 0)), ((0, 0, -0.2), (0, 0, 0)),
                ((0, 0, 0), (-0.0825, 0.2, 0)), ((0, 0, -0.3), (0, 0, 0)), ((0, 0, 0), (0.088, 0, 0)),
                ((0, 0, 0), (0, 0, 0.2)))
    base = [_rod(m, a, b, 0.06) for m, (a, b) in zip(masses, segments)]
    loads = ()
    if payload is not None:
        loads = (Payload(6, solids.solid("box", payload, (0.1, 0.1, 0.1), position=(0, 0, 0.2)),
                         Profile("smootherstep", 1.0, 1.0)),)
    return _scene("panda", chain, base, loads,
                  description="7-DoF Panda-like arm" + (f" with a {payload:g} kg payload ramp" if loads else ""))


def ur5():
    """6-DoF UR5-like arm (standard DH of Universal Robots)."""
    dh = ((0.0, HALF_PI, 0.089159, 0), (-0.425, 0, 0, 0), (-0.39225, 0, 0, 0),
          (0.0, HALF_PI, 0.10915, 0), (0.0, -HALF_PI, 0.09465, 0), (0.0, 0, 0.0823, 0))
    chain = Chain.from_dh(dh, name="ur5")
    masses = (3.7, 8.393, 2.275, 1.219, 1.219, 0.1879)
    segments = (((0, -0.09, 0), (0, 0, 0)), ((0.425, 0, 0), (0, 0, 0)), ((0.39225, 0, 0), (0, 0, 0)),
                ((0, -0.1, 0), (0, 0, 0)), ((0, 0.09, 0), (0, 0, 0)), ((0, 0, -0.05), (0, 0, 0)))
    base = [_rod(m, a, b, 0.05) for m, (a, b) in zip(masses, segments)]
    return _scene("ur5", chain, base, description="6-DoF UR5-like arm")


def translating_sphere(rate=-0.5, radius=0.1, mass=1.0):
    """CX-sphere: one uniform sphere sliding along x; its density scales by exp(rate t) on [0, inf)."""
    chain = Chain((Joint.of_origins("prismatic", (1.0, 0.0, 0.0), name="slide"),), name="translating sphere",
                  gravity=(0, 0, 0))
    base = [solids.solid("sphere", mass, (radius,))]
    return _scene("translating-sphere", chain, base, (Scaling(0, Profile("exp", rate=rate)),), span=(0.0, np.inf),
                  description=f"uniform sphere whose mass scales by exp({rate:g} t)")


def non_normal_2r():
    """CX-normal: a planar 2R arm whose first coordinate enters cubed, theta_1 = q_1^3, so QJ loses rank at q_1 = 0."""
    j1 = Joint.of_origins("revolute", (0, 0, 1), after=(Origin.of((1.0, 0, 0)),), coordinate=Coordinate("cubic"),
               limits=(-1.5, 1.5), name="cubic shoulder")
    j2 = Joint.of_origins("revolute", (0, 0, 1), after=(Origin.of((0.8, 0, 0)),), name="elbow")
    chain = Chain((j1, j2), name="non-normal 2R", gravity=(0, -9.81, 0))
    base = [_rod(3.0, (-1.0, 0, 0), (0, 0, 0), 0.05), _rod(2.0, (-0.8, 0, 0), (0, 0, 0), 0.04)]
    return _scene("non-normal-2r", chain, base, description="planar 2R with theta_1 = q_1^3")


def revolute_prismatic(limit=None):
    """Asm2/Lem2: a turntable carrying a radial slide; with an unlimited slide QJ is unbounded."""
    j1 = Joint.of_origins("revolute", (0, 0, 1), name="turntable")
    j2 = Joint.of_origins("prismatic", (1, 0, 0), before=(Origin.of((0, 0, 0.2)),),
                          limits=None if limit is None else (-limit, limit), name="radial slide")
    chain = Chain((j1, j2), name="RP" + (" bounded" if limit else " unbounded"))
    base = [solids.solid("cylinder", 5.0, (0.3, 0.2)),
            solids.solid("box", 1.0, (0.2, 0.1, 0.1), rotation_rpy((0, 0, 0)))]
    return _scene("rp-" + ("bounded" if limit else "unbounded"), chain, base,
                  description="turntable with a radial slide" + ("" if limit else " of unlimited travel"))


def trolley_2r(loop=False, mass=4.0):
    """The planar 2R arm with a trolley of ``mass`` kg on its second link: a 0.6 m run along the link
    (GRE-physics) or, with ``loop``, once round a loop of radius 0.15 m (EQ-acc, Thm5: a purely radial run
    exerts little torque through J^T Q^T Psidot)."""
    scene = planar_2r()
    if loop:
        path = Path("circle", Profile("cosine", 0.5, 2.0), center=(-0.4, 0.0, 0.0), radius=0.15)
        name, span, how = "trolley-loop-2r", (0.0, 3.0), "running round a loop on"
    else:
        path = Path("line", Profile("smootherstep", 0.5, 1.5), start=(-0.7, 0, 0.05), end=(-0.1, 0, 0.05))
        name, span, how = "trolley-2r", (0.0, 2.5), "running along"
    trolley = MovingMass(1, mass, inertia_com(solids.solid("box", mass, (0.12, 0.08, 0.06))), path)
    return _scene(name, scene.chain, scene.trajectory.base, (trolley,), span=span,
                  description=f"planar 2R arm with a {mass:g} kg trolley {how} its second link")


def passenger_platform():
    """GRE-physics: a 4-DoF ride (turntable, shoulder, elbow, platform tilt) whose platform carries a 75 kg
    passenger walking a circle of 0.4 m radius on it (translating, not turning)."""
    chain = Chain.from_dh([(0.0, HALF_PI, 1.0, 0), (2.0, 0, 0, 0), (1.5, 0, 0, 0), (0.3, 0, 0, 0)], name="ride")
    base = [_rod(300.0, (0, -1.0, 0), (0, 0, 0), 0.2), _rod(150.0, (-2.0, 0, 0), (0, 0, 0), 0.12),
            _rod(90.0, (-1.5, 0, 0), (0, 0, 0), 0.1),
            solids.solid("box", 200.0, (1.6, 1.2, 0.1), position=(-0.8, 0, 0))]
    passenger = MovingMass(3, 75.0, inertia_com(solids.solid("box", 75.0, (0.4, 0.3, 1.7))),
                           Path("circle", Profile("cosine", 0.0, 4.0), center=(-0.8, 0, 0.9), radius=0.4))
    return _scene("passenger-platform", chain, base, (passenger,), span=(0.0, 4.0),
                  description="4-DoF ride carrying a passenger who walks a circle on its platform")


BUILTIN = {
    "planar-2r": planar_2r,
    "spatial-3r": spatial_3r,
    "panda": panda,
    "panda-payload-3kg": lambda: panda(payload=3.0),
    "ur5": ur5,
    "translating-sphere": translating_sphere,
    "non-normal-2r": non_normal_2r,
    "rp-bounded": lambda: revolute_prismatic(limit=1.0),
    "planar-2r-payload": lambda: planar_2r(payload=2.0),
    "planar-2r-early-payload": lambda: planar_2r(payload=2.0, start=0.3),
    "trolley-2r": trolley_2r,
    "trolley-loop-2r": lambda: trolley_2r(loop=True, mass=2.0),
    "passenger-platform": passenger_platform,
}
