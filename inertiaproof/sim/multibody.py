"""The chain plus its moving masses as an ordinary multibody system in Pinocchio (the independent engine).

A moving mass of Section 3 (a trolley, a passenger) becomes a rigid body of
its own, a *rider*, carried by body l on one prismatic joint along its path
(a trolley on a straight rail) or on three (x, y, z of body l's frame, a
passenger walking anywhere). The rider translates and does not turn relative
to body l, as :class:`~inertiaproof.trajectory.MovingMass` assumes. Its joints
follow the prescribed path; Pinocchio's inverse dynamics (RNEA) of this
augmented model then gives the torques on the original joints that the
generalized robotics equation (RoboticEquation) must reproduce.

Pinocchio (PyPI package ``pin``) is imported only when a model is built.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.dynamics.chain import COMPLEX_STEP
from inertiaproof.dynamics.forward import solve_mass
from inertiaproof.dynamics.trajectory import MovingMass
from inertiaproof.model.inertia import inertia_com, unpack

__all__ = ["augmented_model", "inverse_dynamics", "joint_motion", "Rider", "riders", "RigidChain"]


@dataclass(frozen=True)
class Rider:
    """A body translating inside body ``body`` along prismatic joints with unit ``axes`` (k, 3) from ``origin``."""

    body: int
    mass: float
    inertia_com: np.ndarray
    axes: np.ndarray
    origin: np.ndarray

    @classmethod
    def from_moving_mass(cls, load: MovingMass):
        path = load.path
        if path.shape == "line":
            start, end = np.asarray(path.start, float), np.asarray(path.end, float)
            axes = ((end - start) / np.linalg.norm(end - start))[None, :]
            return cls(load.body, load.mass, np.asarray(load.inertia_com, float), axes, start)
        return cls(load.body, load.mass, np.asarray(load.inertia_com, float), np.eye(3), np.zeros(3))

    def coordinates(self, c, c_dot, c_ddot):
        """Joint positions, velocities, accelerations (..., k) for the rider's centre path c(t)."""
        return (c - self.origin) @ self.axes.T, c_dot @ self.axes.T, c_ddot @ self.axes.T


def riders(trajectory):
    """The rider of every moving mass of a parameter trajectory."""
    return tuple(Rider.from_moving_mass(load) for load in trajectory.loads if isinstance(load, MovingMass))


def _se3(pin, transform):
    return pin.SE3(np.asarray(transform[:3, :3], float), np.asarray(transform[:3, 3], float))


def augmented_model(chain, theta, rider_list=()):
    """A ``pin.Model``: joint k moves body k with constant parameters ``theta[k]``; then each rider's joints.

    The configuration vector is (chain joint variables, rider 1 coordinates, rider 2 coordinates, ...).
    """
    import pinocchio as pin

    model = pin.Model()
    model.gravity.linear = np.asarray(chain.gravity, dtype=float)
    parent, previous_after, joint_ids = 0, np.eye(4), []
    for k, joint in enumerate(chain.joints):
        axis = np.asarray(joint.axis, dtype=float)
        jm = pin.JointModelRevoluteUnaligned(axis) if joint.revolute else pin.JointModelPrismaticUnaligned(axis)
        jid = model.addJoint(parent, jm, _se3(pin, previous_after @ joint.before), f"joint{k + 1}")
        model.appendBodyToJoint(jid, _se3(pin, joint.after).act(_inertia(pin, theta[k])), pin.SE3.Identity())
        joint_ids.append(jid)
        parent, previous_after = jid, joint.after
    for r, rider in enumerate(rider_list):
        carrier = chain.joints[rider.body].after.copy()
        carrier[:3, 3] += carrier[:3, :3] @ rider.origin
        parent, placement = joint_ids[rider.body], carrier
        for a, axis in enumerate(rider.axes):
            parent = model.addJoint(parent, pin.JointModelPrismaticUnaligned(np.asarray(axis, float)),
                                    _se3(pin, placement), f"rider{r + 1}_{a + 1}")
            placement = np.eye(4)
        model.appendBodyToJoint(parent, pin.Inertia(float(rider.mass), np.zeros(3),
                                                    np.asarray(rider.inertia_com, float)), pin.SE3.Identity())
    return model


def _inertia(pin, phi):
    m, h, _ = unpack(phi)
    return pin.Inertia(float(m), h / m, inertia_com(phi))


def joint_motion(chain, q, qd, qdd):
    """Joint variables x = g(q) and their rates x' = g'(q) qd, x'' = g'(q) qdd + g''(q) qd^2, and g'(q)."""
    if all(j.coordinate.name == "identity" for j in chain.joints):
        return q, qd, qdd, np.ones_like(q)
    values, slopes, curvatures = [], [], []
    for k, joint in enumerate(chain.joints):
        c = joint.coordinate
        values.append(c.value(q[..., k]))
        slopes.append(c.derivative(q[..., k]))
        curvatures.append(c.derivative(q[..., k] + 1j * COMPLEX_STEP).imag / COMPLEX_STEP)
    x, dx, ddx = (np.stack(v, -1) for v in (values, slopes, curvatures))
    return x, dx * qd, dx * qdd + ddx * qd * qd, dx


def inverse_dynamics(chain, trajectory, times, q, qd, qdd):
    """Torques on the chain's coordinates (samples, n) from Pinocchio's RNEA of the augmented model.

    The chain's bodies keep the trajectory's parameters *without* the moving masses (the riders carry
    those); any other load (a payload, a scaling) must be absent, as a rider model has no such thing.
    """
    import pinocchio as pin

    if any(not isinstance(load, MovingMass) for load in trajectory.loads):
        raise ValueError("the augmented model covers moving masses only; this trajectory also adds mass")
    rider_list = riders(trajectory)
    model = augmented_model(chain, trajectory.base, rider_list)
    data = model.createData()
    x, xd, xdd, slope = joint_motion(chain, q, qd, qdd)
    extra = [[], [], []]
    for rider, load in zip(rider_list, (m for m in trajectory.loads if isinstance(m, MovingMass))):
        for store, value in zip(extra, rider.coordinates(*load.path.derivatives(times))):
            store.append(value)
    columns = [np.concatenate([a] + b, -1) for a, b in zip((x, xd, xdd), extra)]
    torques = np.array([pin.rnea(model, data, p, v, a) for p, v, a in zip(*columns)])
    return slope * torques[:, :chain.n]


class RigidChain:
    """Pinocchio's forward dynamics of the augmented model in the chain's coordinates q, riders prescribed.

    The bodies are rigid with constant parameters between calls of :meth:`set_theta`: the classical
    robotics equation (ClassicalRoboticEquation) of the chain with its riders, nothing of Section 3.
    """

    def __init__(self, chain, trajectory):
        import pinocchio as pin

        self.pin, self.chain = pin, chain
        self.moving = tuple(load for load in trajectory.loads if isinstance(load, MovingMass))
        self.rider_list = riders(trajectory)
        self.model = augmented_model(chain, trajectory.base, self.rider_list)
        self.data = self.model.createData()
        self.rider_dofs = self.model.nv - chain.n

    def set_theta(self, theta):
        """Parameters (N, 10) of the chain's bodies, the riders not included."""
        for k, joint in enumerate(self.chain.joints):
            self.model.inertias[k + 1] = _se3(self.pin, joint.after).act(_inertia(self.pin, theta[k]))

    def rider_motion(self, t):
        """Positions, velocities, accelerations of the rider joints at time t."""
        parts = [rider.coordinates(*load.path.derivatives(np.asarray(t, float)))
                 for rider, load in zip(self.rider_list, self.moving)]
        if not parts:
            return np.zeros(0), np.zeros(0), np.zeros(0)
        return tuple(np.concatenate([p[i] for p in parts]) for i in range(3))

    def mass_matrix(self, q):
        """M in the coordinates q: D M_x D with D = diag(g'(q))."""
        x, _, _, slope = joint_motion(self.chain, q, np.zeros_like(q), np.zeros_like(q))
        full = self.pin.crba(self.model, self.data, np.concatenate([x, np.zeros(self.rider_dofs)]))
        n = self.chain.n
        return slope[:, None] * full[:n, :n] * slope[None, :]

    def accelerations(self, q, qd, tau, rider):
        """qdd with the riders on their prescribed ``rider`` = (position, velocity, acceleration)."""
        n = self.chain.n
        x, xd, xdd0, slope = joint_motion(self.chain, q, qd, np.zeros_like(q))
        position = np.concatenate([x, rider[0]])
        full = self.pin.crba(self.model, self.data, position)
        bias = self.pin.rnea(self.model, self.data, position, np.concatenate([xd, rider[1]]),
                             np.concatenate([xdd0, rider[2]]))[:n]
        mass = slope[:, None] * full[:n, :n] * slope[None, :]
        return solve_mass(mass, tau - slope * bias)
