"""Random smooth parameter trajectories with bounded rates: payload ramps and moving masses on consistent bodies."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import consistent_phi, log_uniform

from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile

__all__ = ["mixed_trajectories", "profiles", "SMOOTH", "trajectories"]

SMOOTH = ("smoothstep", "smootherstep", "cosine")


@st.composite
def profiles(draw):
    return Profile(draw(st.sampled_from(SMOOTH)), draw(st.floats(0.0, 1.0)), draw(log_uniform(1e-2, 10.0)))


@st.composite
def trajectories(draw, bodies, length, moving_mass=False, thinness=6):
    """Consistent bodies of the chain's size (near-degenerate to ordinary) and one payload ramp or moving mass."""
    base = np.stack([draw(consistent_phi(size=(length / 10, length), thinness=thinness)) for _ in range(bodies)])
    body = draw(st.integers(0, bodies - 1))
    profile = draw(profiles())
    if moving_mass:
        start = length * np.array([draw(st.floats(-1, 1)) for _ in range(3)])
        direction = np.array([draw(st.floats(-1, 1)) for _ in range(3)]) + np.array([0.0, 0.0, 1e-3])
        travel = draw(log_uniform(1e-2, 2.0)) * length * direction / np.linalg.norm(direction)  # it does move
        load = MovingMass(body, draw(log_uniform(1e-2, 1e2)), np.zeros((3, 3)), Path("line", profile, tuple(start),
                                                                                   tuple(start + travel)))
    else:
        load = Payload(body, draw(consistent_phi(size=(length / 10, length), thinness=thinness)), profile)
    end = profile.start + profile.duration
    return ParameterTrajectory(base, (load,), (0.0, end + 0.5))


@st.composite
def mixed_trajectories(draw, bodies, length):
    """A moving mass beside a payload ramp on the same consistent bodies (both as :func:`trajectories` draws them)."""
    moving = draw(trajectories(bodies, length, moving_mass=True))
    payload = draw(trajectories(bodies, length))
    return ParameterTrajectory(moving.base, moving.loads + payload.loads, (0.0, max(moving.span[1], payload.span[1])))
