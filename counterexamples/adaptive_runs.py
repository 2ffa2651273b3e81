"""Random adaptive runs of Slotine and Li on a scene: references, initial estimates, gains and payload changes."""

from __future__ import annotations

from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import log_uniform

from inertiaproof.sim.recipe import Recipe, scene_of

__all__ = ["euclidean_runs"]


@st.composite
def _drawn(draw, key, horizon):
    scene = scene_of(key)
    lo, hi = scene.chain.coordinate_box()
    home = tuple(float(a + draw(st.floats(0.0, 1.0)) * (b - a)) for a, b in zip(lo, hi))
    payload = draw(st.none() | st.tuples(st.floats(0.0, 5.0), st.floats(0.1, 0.6 * horizon), log_uniform(1e-2, 1.0)))
    return Recipe(key, "slotine-li", horizon=horizon, lam=draw(log_uniform(1.0, 20.0)), kd=draw(log_uniform(1.0, 50.0)),
                  gamma=draw(log_uniform(1e-2, 1e2)),
                  estimate=tuple(draw(log_uniform(0.3, 3.0)) for _ in range(scene.trajectory.bodies)),
                  amplitude=draw(st.floats(0.05, 1.0)), frequency=draw(st.floats(0.1, 1.5)), home=home,
                  payload=payload)


def euclidean_runs(keys, horizon):
    """Slotine-Li runs on the scenes ``keys``: first each scene as it is (its own reference and gains), then drawn
    ones: home posture in the coordinate box, amplitude 0.05-1 rad, 0.1-1.5 Hz, Lambda 1-20 /s, K_D 1-50 /s times
    diag M, gain 0.01-100, Theta_hat(0) = 0.3-3 times Theta(t0) per body, and the scene's loads or a payload of 0-5 kg
    ramped in 10 ms to 1 s."""
    as_is = st.sampled_from([Recipe(key, "slotine-li", horizon=horizon) for key in keys])
    return as_is | st.sampled_from(list(keys)).flatmap(lambda key: _drawn(key, horizon))
