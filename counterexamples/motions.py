"""Random analytic motions on random chains: q(t), Theta(t) and Psi(t) as sines (a complex step in t passes).

Theta and Psi are arbitrary (Prop1 and Prop2 hold for all Theta, Thetadot,
Psi); their centres are consistent bodies of the chain's size, their
amplitudes up to the centres' size, so the terms stay comparable.
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from inertiaproof.counterexamples.chains import chains
from inertiaproof.counterexamples.inertias import consistent_phi, log_uniform

from inertiaproof.dynamics.trajectory import SineMotion

__all__ = ["joint_motion", "motions", "sines"]


def sines(rng, center, amplitude):
    """A SineMotion about ``center`` with entrywise amplitudes up to ``amplitude``, rates 0.2 to 5, any phase."""
    shape = np.shape(center)
    return SineMotion(np.asarray(center, float), amplitude * rng.uniform(-1, 1, shape), rng.uniform(0.2, 5.0, shape),
                      rng.uniform(0, 2 * np.pi, shape))


def joint_motion(chain, length, rng):
    """q(t) over the chain's box: revolute joints turn by up to 1.5 rad, prismatic ones slide by up to the length."""
    lo, hi = chain.coordinate_box()
    revolute = np.array([j.revolute for j in chain.joints])
    center = lo + (hi - lo) * rng.random(chain.n)
    return sines(rng, center, np.where(revolute, 1.5, length))


@st.composite
def motions(draw):
    """(chain, {"q": ..., "theta": ..., "psi": ...}, times): a random chain with analytic motions and sample times."""
    chain, length = draw(chains())
    bodies = np.stack([draw(consistent_phi(size=(length / 10, length))) for _ in range(chain.bodies)])
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    scale = draw(log_uniform(1e-3, 1.0))
    motion = {"q": joint_motion(chain, length, rng),
              "theta": sines(rng, bodies, scale * np.abs(bodies).max(-1, keepdims=True)),
              "psi": sines(rng, np.zeros(6 * chain.bodies), bodies[:, 0].max() * length)}
    return chain, motion, rng.uniform(0.0, 10.0, 8)
