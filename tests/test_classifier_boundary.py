"""The classifier attacked at its boundary: the exact oracle, the families, and VIOLATED for a loosened classifier."""


import numpy as np
import pytest
from hypothesis import given
from inertiaproof.checks.classifier import (
    classifier_result,
    exact_classification,
    replay_classifier_row,
)
from inertiaproof.checks.equivalences import exact_pseudo_inertia
from inertiaproof.counterexamples.classifier import KINDS, boundary_rows, by_delta, degenerate, sweep

from inertiaproof.model import consistency
from inertiaproof.model.consistency import CONSISTENT, DEGENERATE, INCONSISTENT
from inertiaproof.model.exact import definiteness, integer_matrix
from inertiaproof.result import Verdict


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_exactly_degenerate_rows_have_the_rank_of_their_carrier(kind):
    row = degenerate(kind, [3, -5, 7], [[512, 0, 256], [0, 1024, -128]], [[1, 2], [-3, 1], [4, -4], [0, 3]],
                     [1, 2, 3, 4], -400)
    assert exact_classification(row) == (DEGENERATE, KINDS[kind])


@pytest.mark.parametrize("side, verdict", [(-1, INCONSISTENT), (1, CONSISTENT)])
def test_rows_far_enough_from_the_boundary_lie_on_their_side(side, verdict):
    row = by_delta(1e-6, side, 2.0, 0.5, [0.2, 0.7], [1, 2, 3, 4], [0.1, -0.3, 0.2], 300)
    assert exact_classification(row)[0] == verdict


@given(boundary_rows())
def test_the_oracle_agrees_with_sylvester_minors(example):
    """Two exact decisions by different algorithms (pivoted elimination here, Bareiss minors in model.exact)."""
    row, _ = example
    kind, rank = definiteness(integer_matrix(exact_pseudo_inertia(row)))
    expected = {"pd": (CONSISTENT, -1), "psd": (DEGENERATE, (rank or 0) - 1), "indefinite": (INCONSISTENT, -1)}[kind]
    assert exact_classification(row) == (expected if row[0] > 0 else (INCONSISTENT, -1))


def test_the_sweep_covers_every_family_decade_and_magnitude():
    rows, about = sweep(np.random.default_rng(0), repeats=1)
    assert {a["family"] for a in about} == {"by_delta", "degenerate", "off_degenerate", "nonpositive_mass"}
    assert len({a["delta"] for a in about if "delta" in a}) == 13
    scales = np.abs(rows).max(axis=1)
    assert scales.min() < 1e-140 and scales.max() > 1e140
    verdicts = {exact_classification(r)[0] for r in rows}
    assert verdicts == {CONSISTENT, DEGENERATE, INCONSISTENT}


def test_the_classifier_holds(ctx):
    result = classifier_result(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    assert all(result.evidence["negative_controls"].values())


def _loosened_eigenvalues(eigenvalues):
    """Sigma_CoM's eigenvalues shifted up by 1e-6 of their size: rows inconsistent by less pass as consistent."""
    def loose(*entries):
        eig = eigenvalues(*entries)
        return eig + 1e-6 * np.abs(eig).sum(axis=1, keepdims=True)
    return loose


@pytest.mark.parametrize("loosening", ["tolerance 1e-6", "no exact fallback"])
def test_a_loosened_classifier_is_violated_with_a_replayable_row(ctx, monkeypatch, loosening):
    if loosening == "tolerance 1e-6":
        monkeypatch.setattr(consistency, "_sym3_eigenvalues", _loosened_eigenvalues(consistency._sym3_eigenvalues))
    else:
        monkeypatch.setattr(consistency, "RESOLUTION", 0.0)
    result = classifier_result(ctx)
    assert result.verdict == Verdict.VIOLATED, result.summary
    data = result.counterexample["data"]
    assert data["exact"] != data["classifier"]
    assert replay_classifier_row(data, ctx).verdict == Verdict.VIOLATED
    monkeypatch.undo()
    assert replay_classifier_row(data, ctx).verdict == Verdict.HOLDS
