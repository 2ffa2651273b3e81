"""Cor1:ingredients: the bounds' brackets, time extremes and constants are what they claim; wrong ones are seen."""

import numpy as np
import pytest
from inertiaproof.checks import bound_ingredients
from inertiaproof.checks.bound_ingredients import ingredients_result, replay_ingredient

from inertiaproof.bounds import apriori, block_form, branch, families, ladders, spectral, strategies, time
from inertiaproof.result import Verdict
from inertiaproof.scene import robots


def _swapped_singular_values(kind_function):
    def wrong(a, kind):
        if kind in ("smax", "smin"):
            s = np.linalg.svd(a, compute_uv=False)
            return s[..., -1] if kind == "smax" else s[..., 0]
        return kind_function(a, kind)
    return wrong


def _theorem3_without_factor_2(upper_constants):
    def wrong(zeta, z_max, sigma, observed, zeta_observed=None):
        found = upper_constants(zeta, z_max, sigma, observed, zeta_observed=zeta_observed)
        found["paper"]["upper"] /= 2
        return found
    return wrong


@pytest.fixture
def small(ctx):
    """The audit on the planar 2R with a payload and the trolley loop (a few seconds)."""
    return lambda: ingredients_result(ctx, [robots.planar_2r(payload=1.0)],
                                      {"trolley": robots.trolley_2r(loop=True, mass=2.0).trajectory})


def test_the_ingredients_hold(small):
    result = small()
    assert result.verdict == Verdict.HOLDS, result.summary


@pytest.mark.parametrize("mistake", ["sigma_max and sigma_min swapped", "Theorem 3 without its factor 2",
                                     "a ramp's range taken as its start", "vertex bound rounded inwards"])
def test_a_wrong_ingredient_is_violated(ctx, small, monkeypatch, mistake):
    if mistake == "sigma_max and sigma_min swapped":
        wrong = _swapped_singular_values(spectral.spectral)
        for module in (families, branch, apriori, ladders, strategies, block_form, time):
            monkeypatch.setattr(module, "spectral", wrong)
    elif mistake == "Theorem 3 without its factor 2":
        monkeypatch.setattr(bound_ingredients, "upper_constants",
                            _theorem3_without_factor_2(bound_ingredients.upper_constants))
    elif mistake == "a ramp's range taken as its start":
        range_ = time.profile_range
        monkeypatch.setattr(time, "profile_range", lambda profile, span: (range_(profile, span)[0],) * 2)
    else:
        for module in (families, apriori, ladders, strategies, block_form):
            monkeypatch.setattr(module, "ROUNDING", -module.ROUNDING)
    result = small()
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert result.counterexample["kind"] == "bound-ingredient"


def test_the_replayer_reruns_the_audit(ctx, monkeypatch):
    for module in (families, apriori, ladders, strategies, block_form):
        monkeypatch.setattr(module, "ROUNDING", -module.ROUNDING)
    data = {"where": "vertex bound", "what": "vertex bound lmax strictly outside an exact value", "excess": 1.0}
    monkeypatch.setattr(bound_ingredients, "ingredients_result",
                        lambda c: ingredients_result(c, [], {}))
    assert replay_ingredient(data, ctx).verdict == Verdict.VIOLATED
