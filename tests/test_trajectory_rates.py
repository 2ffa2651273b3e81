"""GRE-physics:rates: the trajectories' rates are derivatives, the profiles' bounds are attained; wrong ones are seen."""

import numpy as np
import pytest
from inertiaproof.checks.trajectory_rates import rates_result, replay_rates, time_derivative

from inertiaproof.bounds import time as bounds_time
from inertiaproof.dynamics.trajectory import Profile
from inertiaproof.result import Verdict


def test_time_derivative_of_a_sine_is_exact_to_its_estimate():
    t = np.linspace(0.1, 2.0, 7)
    value, error = time_derivative(np.sin, t, 1e-3)
    assert np.all(np.abs(value - np.cos(t)) <= error) and np.all(error < 1e-9)


def test_the_rates_hold(ctx):
    result = rates_result(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary


def _wrong_second_derivative(derivatives):
    def wrong(self, t):
        s, ds, dds = derivatives(self, t)
        return s, ds, (dds * 0.5 if self.shape == "smoothstep" else dds)
    return wrong


@pytest.mark.parametrize("mistake", ["s'' of a smoothstep", "rate bound of a smootherstep",
                                     "acceleration bound of a smoothstep"])
def test_a_wrong_rate_or_bound_is_violated(ctx, monkeypatch, mistake):
    if mistake == "s'' of a smoothstep":
        monkeypatch.setattr(Profile, "derivatives", _wrong_second_derivative(Profile.derivatives))
    elif mistake == "rate bound of a smootherstep":
        rate_bound = Profile.rate_bound
        monkeypatch.setattr(Profile, "rate_bound",
                            lambda self: rate_bound(self) * (0.8 if self.shape == "smootherstep" else 1.0))
    else:
        monkeypatch.setitem(bounds_time.ACCELERATION_PEAK, "smoothstep", 3.0)
    result = rates_result(ctx)
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert replay_rates(result.counterexample["data"], ctx).verdict == Verdict.VIOLATED
