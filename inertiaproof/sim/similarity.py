"""The same scene in other units of length: a way to measure round-off.

Multiplying every length by lambda (link geometry, centres of mass, paths
of moving masses, gravity in m/s^2) and keeping masses and times gives a
physically identical scene: a revolute torque scales by lambda^2, a prismatic
force by lambda, a prismatic coordinate by lambda. In exact arithmetic the
rescaled torques divided back agree; in floating point they differ by the
round-off of the computation, so their spread over a few lambda estimates
the numerical resolution of any engine, ours or Pinocchio, without knowing
how it computes (it captures cancellation of large intermediate terms, e.g.
m |v|^2 of a small body far from the base).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Payload

__all__ = ["coordinate_factors", "FACTORS", "force_factors", "rescaled_chain", "rescaled_phi", "rescaled_trajectory"]

FACTORS = (1.0, 3.0, 0.7, 1.3)


def rescaled_phi(phi, factor):
    """Phi of the same body with lengths times ``factor``: h by factor, I by factor^2."""
    phi = np.array(phi, dtype=float)
    phi[..., 1:4] *= factor
    phi[..., 4:] *= factor**2
    return phi


def _rescaled_transform(transform, factor):
    t = np.array(transform, dtype=float)
    t[:3, 3] *= factor
    return t


def rescaled_chain(chain, factor):
    if any(not j.revolute and j.coordinate.name != "identity" for j in chain.joints):
        raise ValueError("a prismatic joint with a coordinate map has no rescaled coordinate")
    joints = tuple(dataclasses.replace(j, before=_rescaled_transform(j.before, factor), written=None,
                                       after=_rescaled_transform(j.after, factor),
                                       limits=None if j.limits is None or j.revolute
                                       else tuple(factor * np.asarray(j.limits)))
                   for j in chain.joints)
    return Chain(joints, name=chain.name, gravity=tuple(factor * np.asarray(chain.gravity, dtype=float)))


def rescaled_trajectory(trajectory, factor):
    loads = []
    for load in trajectory.loads:
        if isinstance(load, Payload):
            load = dataclasses.replace(load, phi=rescaled_phi(load.phi, factor))
        elif isinstance(load, MovingMass):
            p = load.path
            path = dataclasses.replace(p, start=tuple(factor * np.asarray(p.start)),
                                       end=tuple(factor * np.asarray(p.end)),
                                       center=tuple(factor * np.asarray(p.center)), radius=factor * p.radius)
            load = dataclasses.replace(load, inertia_com=factor**2 * np.asarray(load.inertia_com), path=path)
        loads.append(load)
    return ParameterTrajectory(rescaled_phi(trajectory.base, factor), tuple(loads), trajectory.span)


def coordinate_factors(chain, factor):
    """How each generalized coordinate scales: ``factor`` for a prismatic joint, 1 for a revolute one."""
    return np.array([1.0 if j.revolute else factor for j in chain.joints])


def force_factors(chain, factor):
    """How each generalized force scales: energy (factor^2) over the coordinate's scale."""
    return factor**2 / coordinate_factors(chain, factor)
