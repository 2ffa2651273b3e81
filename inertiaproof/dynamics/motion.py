"""The terms of the generalized robotics equation (RoboticEquation) along a motion of a scene.

    M(q, Theta) qdd + (C + M(q, Thetadot) + H(q, Psi)) qd + G(q, Theta) = tau + w - J^T Q^T Psidot

:func:`kinematics` gets QJ, dQJ/dq and the body rotations from one complex-step
evaluation of the chain; :func:`equation_terms` returns every term of the
equation separately (for error scales and the power balance of Prop1);
:func:`generalized_forces` is their sum, tau + w. All batched over samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.model import particles

from . import terms
from .chain import COMPLEX_STEP
from .trajectory import MovingMass, ParameterTrajectory

__all__ = [
    "equation_terms", "generalized_forces", "Kinematics", "kinematics", "Parameters", "parameters",
    "parameters_from_density", "TERMS",
]


@dataclass(frozen=True)
class Kinematics:
    qj: np.ndarray  # QJ (..., 6N, n)
    dqj: np.ndarray  # dQJ/dq (..., 6N, n, n)
    rotations: np.ndarray  # R_l (..., N, 3, 3)
    origins: np.ndarray  # z_l (..., N, 3)


def kinematics(chain, q):
    """QJ, dQJ/dq (exact to round-off by a complex step in each coordinate), R_l and z_l at configurations q."""
    q = np.asarray(q, dtype=float)
    steps = q[..., None, :] + 1j * COMPLEX_STEP * np.eye(chain.n)
    rotations, origins, _, _ = chain.joint_frames(q)  # at q itself: bit-equal to a complex step's real part
    stepped = chain.body_jacobian(steps)
    return Kinematics(stepped[..., 0, :, :].real, np.moveaxis(stepped.imag / COMPLEX_STEP, -3, -1),
                      rotations, origins)


@dataclass(frozen=True)
class Parameters:
    """Theta, Thetadot (..., N, 10) and Psi, Psidot (..., 6N) at the sample times."""

    theta: np.ndarray
    theta_dot: np.ndarray
    psi: np.ndarray
    psi_dot: np.ndarray


def parameters(trajectory, times):
    theta, theta_dot = trajectory.theta(times)
    psi, psi_dot = trajectory.psi(times)
    return Parameters(theta, theta_dot, psi, psi_dot)


def parameters_from_density(trajectory, times):
    """As :func:`parameters`, but each moving mass integrated from its density (Defml-DefIl, psi after DefMatrixZ).

    The moving body is the uniform box with its mass and inertia, sampled by Gauss points that translate
    along the path; this is independent of the closed forms in :class:`~inertiaproof.trajectory.MovingMass`.
    """
    times = np.asarray(times, dtype=float)
    fixed = ParameterTrajectory(trajectory.base, tuple(load for load in trajectory.loads
                                                       if not isinstance(load, MovingMass)), trajectory.span)
    theta, theta_dot = fixed.theta(times)
    psi = np.zeros(times.shape + (trajectory.bodies, 6))
    psi_dot = np.zeros_like(psi)
    for load in trajectory.loads:
        if not isinstance(load, MovingMass):
            continue
        offsets, weights = particles.particles_like(load.mass, load.inertia_com)
        c, c_dot, c_ddot = (x[..., None, :] for x in load.path.derivatives(times))
        x = c + offsets
        v, a = np.broadcast_to(c_dot, x.shape), np.broadcast_to(c_ddot, x.shape)
        theta[..., load.body, :] += particles.moments(x, weights)
        theta_dot[..., load.body, :] += particles.moments_rate(x, v, weights)
        psi[..., load.body, :] += particles.lumped_velocity(x, v, weights)
        psi_dot[..., load.body, :] += particles.lumped_velocity_rate(x, a, weights)
    shape = times.shape + (-1,)
    return Parameters(theta, theta_dot, psi.reshape(shape), psi_dot.reshape(shape))


TERMS = ("inertial", "coriolis", "parameter_rate", "lumped_velocity", "gravity", "lumped_acceleration")


def equation_terms(kin, gravity, p: Parameters, qd, qdd):
    """Each term of (RoboticEquation) as it enters tau + w, keyed by :data:`TERMS`:
    M qdd, C qd, M(q, Thetadot) qd, H(q, Psi) qd, G and J^T Q^T Psidot."""
    dm = terms.mass_matrix_partials(kin.qj, kin.dqj, p.theta)
    times = lambda a, x: (a @ x[..., None])[..., 0]  # noqa: E731
    return {
        "inertial": times(terms.mass_matrix(kin.qj, p.theta), qdd),
        "coriolis": times(terms.coriolis(dm, qd), qd),
        "parameter_rate": times(terms.mass_matrix(kin.qj, p.theta_dot), qd),
        "lumped_velocity": times(terms.lumped_velocity_matrix(kin.dqj, p.psi), qd),
        "gravity": terms.gravity(kin.qj, kin.rotations, p.theta, gravity),
        "lumped_acceleration": terms.lumped_acceleration_force(kin.qj, p.psi_dot),
    }


def generalized_forces(kin, gravity, p: Parameters, qd, qdd):
    """tau + w of (RoboticEquation) through :func:`inertiaproof.dynamics.generalized_forces`."""
    return terms.generalized_forces(kin.qj, kin.dqj, kin.rotations, gravity, qdd, qd, p.theta, p.theta_dot,
                                       p.psi, p.psi_dot)
