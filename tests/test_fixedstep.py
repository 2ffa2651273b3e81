"""Fixed-step schemes of the loading study: their orders, the implicit one on a stiff problem, counted work."""

import numpy as np
import pytest

from inertiaproof.sim import fixedstep

RATE = 1e9  # Prothero-Robinson: y' = -RATE (y - g(t)) + g'(t), solution g for y(0) = g(0); stiff ratio 1e9


def _stiff(t, y, f):
    t = np.asarray(t)[..., None] if np.ndim(y) == 2 else t
    g = np.concatenate([np.cos(t + 0 * y[..., :1]), np.sin(t + 0 * y[..., :1])], -1)
    dg = np.concatenate([-np.sin(t + 0 * y[..., :1]), np.cos(t + 0 * y[..., :1])], -1)
    return -RATE * (y - g) + dg


def _smooth(t, y, f):
    """A harmonic oscillator with a known input f (the scheme's nodes must reach it): q'' = -q + f."""
    q, qd = y[..., :1], y[..., 1:]
    return np.concatenate([qd, -q + np.asarray(f)[..., None]], -1)


def _error(scheme, rhs, steps, exact, inputs=lambda t: 0 * t):
    times = np.linspace(0.0, 1.0, steps + 1)
    nodes = times[:-1, None] + np.diff(times)[:, None] * np.asarray(scheme.nodes)
    work = fixedstep.Work()
    y = fixedstep.integrate(scheme, rhs, np.array([1.0, 0.0]), times, inputs(nodes), work=work)
    return np.abs(y - exact).max(), work


@pytest.mark.parametrize("scheme", [fixedstep.RK4, fixedstep.RADAU_IIA])
def test_each_scheme_has_its_order_with_inputs_at_its_nodes(scheme):
    """q'' = -q + sin(2t): the observed order over 16, 32, 64 steps is the scheme's (an input at the wrong node
    would cut it to 1)."""
    exact = _oscillator_with_input(1.0)
    errors = [_error(scheme, _smooth, k, exact, np.sin)[0] for k in (16, 32, 64)]
    observed = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(np.abs(observed - scheme.order) < 0.25), observed


def _oscillator_with_input(t):
    """q'' = -q + sin(t) with q(0) = 1, qd(0) = 0: q = cos t + (sin t - t cos t) / 2."""
    q = np.cos(t) + (np.sin(t) - t * np.cos(t)) / 2
    qd = -np.sin(t) + (np.cos(t) - np.cos(t) + t * np.sin(t)) / 2
    return np.array([q, qd])


def test_radau_iia_is_stable_and_accurate_where_rk4_blows_up():
    exact = np.array([np.cos(1.0), np.sin(1.0)])
    error, work = _error(fixedstep.RADAU_IIA, _stiff, 32, exact)
    assert error < 1e-9, error  # the stiff mode is damped; what is left is the slow solution's error
    assert work.steps == 32 and work.jacobians >= 1 and work.newton >= 32
    assert work.evaluations == 3 * work.jacobians + 2 * work.newton  # f(y), 2 Jacobian columns, 2 stages
    with np.errstate(all="ignore"):
        rk4, _ = _error(fixedstep.RK4, _stiff, 32, exact)
    assert not rk4 < 1.0  # h x rate = 3e7, far outside RK4's stability interval


def test_newton_failure_is_reported_not_hidden():
    def explosive(t, y, f):
        return np.exp(50 * y)  # no step of h = 0.5 has a solution Newton can find
    times = np.linspace(0.0, 1.0, 3)
    with pytest.raises(fixedstep.NewtonFailure, match="did not converge"):
        fixedstep.integrate(fixedstep.RADAU_IIA, explosive, np.array([1.0, 1.0]), times, np.zeros((2, 3)))
