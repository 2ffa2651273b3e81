"""Energies of the chain and the power balance that Prop1 implies for (RoboticEquation).

With T_q = 1/2 qd^T M(q, Theta) qd and U(q, Theta) of (PotentialEnergy),
the skew-symmetry of Mdot - 2C - M(q, Thetadot) and of H(q, Psi) (Prop1)
turns (RoboticEquation) into

    d/dt (T_q + U) = qd^T (tau + w - J^T Q^T Psidot) - 1/2 qd^T M(q, Thetadot) qd + U(q, Thetadot),

since U is linear in Theta. The right-hand side is the *supplied power*;
a simulation that integrates it alongside the state can be judged without a
reference solution: E(t) - E(t0) must equal the supplied work.
"""

from __future__ import annotations

import numpy as np

from . import terms

__all__ = ["kinetic_energy", "potential_energy", "supplied_power"]


def kinetic_energy(qj, theta, qd):
    """T_q = 1/2 qd^T M(q, Theta) qd (KineticEnergy without nu and the Psi term)."""
    return 0.5 * np.einsum("...i,...ij,...j->...", qd, terms.mass_matrix(qj, theta), qd)


def potential_energy(rotations, origins, theta, g):
    """U = -sum_l g^T (m_l z_l + R_l h_l) (PotentialEnergy) for gravitational acceleration g."""
    g = np.asarray(g, dtype=float)
    m, h = theta[..., 0], theta[..., 1:4]
    world_moment = m[..., None] * origins + (rotations @ h[..., None])[..., 0]
    return -np.einsum("...li,i->...", world_moment, g)


def supplied_power(kin, gravity, p, qd, tau):
    """qd^T (tau - J^T Q^T Psidot) - 1/2 qd^T M(q, Thetadot) qd + U(q, Thetadot): the rate of T_q + U."""
    lumped = terms.lumped_acceleration_force(kin.qj, p.psi_dot)
    return (np.einsum("...i,...i->...", qd, tau - lumped) - kinetic_energy(kin.qj, p.theta_dot, qd)
            + potential_energy(kin.rotations, kin.origins, p.theta_dot, gravity))
