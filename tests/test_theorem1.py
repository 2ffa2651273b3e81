"""Def1/Thm1-suff, Rem2, Thm1-nec, Thm1-boundary: they hold; wrong input is VIOLATED and replays."""

import json

import numpy as np
import pytest
from hypothesis import Phase
from hypothesis import strategies as st
from inertiaproof.checks import theorem1 as t1
from inertiaproof.counterexamples.densities import signed_densities
from inertiaproof.counterexamples.inertias import log_uniform

from inertiaproof.cli import main
from inertiaproof.model import density, quadrature
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.model.realise import quaternion, realising_solid
from inertiaproof.result import Verdict

FIND = (Phase.generate, Phase.target)  # no shrinking: a negative test needs a counterexample, not the smallest


def test_sufficiency_and_remark2_hold_on_one_shared_hunt(ctx):
    suff = t1.theorem1_sufficiency(ctx)
    rem2 = t1.remark2(ctx)
    assert suff.verdict == Verdict.HOLDS and rem2.verdict == Verdict.HOLDS, (suff.summary, rem2.summary)
    assert suff.evidence["hunt"]["examples"]["value"] == rem2.evidence["hunt"]["examples"]["value"]
    assert ctx.shared("sufficiency_hunt", None) is t1.sufficiency_hunt(ctx)
    families = suff.evidence["families"]
    assert {"box", "ellipsoid", "sphere", "cylinder", "cone", "tetrahedron", "bernstein_box"} <= set(families)
    assert any(k.startswith("mixture") for k in families)
    assert suff.evidence["exact_decisions"]["value"] > 0
    assert 0 < suff.evidence["hunt"]["smallest_margin"]["value"] < 1e-12


def test_negative_density_is_violated_and_replays(ctx, capsys):
    result = t1.sufficiency_result(ctx, strategies={"signed": signed_densities()}, phases=FIND)
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["data"]["certified_nonnegative"] is False
    path = ctx.save_counterexample(result)
    assert main(["replay", str(path)]) == 1
    out = capsys.readouterr().out
    assert "VIOLATED" in out and "negative somewhere" in out


def test_remark2_sees_the_negative_density(ctx):
    result = t1.remark2_result(ctx, strategies={"signed": signed_densities()}, phases=FIND)
    assert result.verdict == Verdict.VIOLATED and result.counterexample["data"]["id"] == "Rem2"


def test_exact_decision_of_a_density_below_float_resolution():
    """A box 1e-9 thick: lambda_min(f)/||f|| ~ 1e-19 is far below eps, yet f > 0 exactly, and its margin is accurate."""
    spec = density.parse({"components": [{"type": "solid", "shape": "box", "mass": 1.0, "dims": [1.0, 0.5, 1e-9],
                                          "quaternion": [0.3, 0.2, -0.9, 0.1], "position": [0.7, -0.2, 0.4]}]})
    lam, slack, f_pd, strict, exactly = t1.density_margins(spec)
    assert exactly and f_pd and strict
    assert 0 < lam < 1e-17 and 0 < slack < 1e-17
    flat = density.parse({"components": [{**spec["components"][0], "dims": [1.0, 0.5, 1e-9]}]})
    assert t1.exact_decisions(flat) == (True, True)


def test_necessity_holds(ctx):
    result = t1.theorem1_necessity(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    assert result.evidence["largest_residual"]["value"] <= result.evidence["bound"]["value"]


@st.composite
def indefinite_pseudo_inertia(draw):
    q, _ = np.linalg.qr(np.array([[draw(st.floats(-1, 1)) for _ in range(4)] for _ in range(4)]) + 1e-3 * np.eye(4))
    lam = np.array([-draw(log_uniform(1e-6, 1.0))] + [draw(log_uniform(1e-2, 1.0)) for _ in range(3)])
    return q @ np.diag(lam) @ q.T


def test_non_positive_definite_f_is_not_realised_and_replays(ctx, capsys):
    result = t1.necessity_result(ctx, strategy=indefinite_pseudo_inertia(), phases=FIND)
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["data"]["positive_definite"] is False
    path = ctx.save_counterexample(result)
    assert main(["replay", str(path)]) == 2  # Thm1-nec assumes f > 0: an indefinite f is bad input, not a violation
    assert "Thm1-nec assumes f > 0" in capsys.readouterr().err


def test_realisation_reproduces_a_nearly_singular_f():
    rng = np.random.default_rng(5)
    q, _ = np.linalg.qr(rng.normal(size=(4, 4)))
    f = q @ np.diag([1e-13, 0.3, 0.7, 1.0]) @ q.T
    margin, record = t1.realisation(f)
    assert margin > 0 and max(record["residuals"].values()) < 1e-13


def test_a_realisation_that_fakes_the_moments_is_caught(monkeypatch):
    """If the construction took |sigma| instead of failing, the quadrature check of its moments catches it."""
    from inertiaproof.model import realise

    real = realise.realising_solid

    def fake(phi, shape="ellipsoid"):
        m, h = phi[0], phi[1:4]
        c = h / m
        sig, axes = np.linalg.eigh(t1.pseudo_inertia(phi)[:3, :3] - m * np.outer(c, c))
        if np.linalg.det(axes) < 0:
            axes[:, 0] *= -1
        dims = np.sqrt(realise.FACTOR[shape] * np.abs(sig) / m)
        return {"components": [{"type": "solid", "shape": shape, "mass": float(m), "dims": dims.tolist(),
                                "quaternion": quaternion(axes).tolist(), "position": c.tolist()}]}, None

    monkeypatch.setattr(t1, "realising_solid", fake)
    q, _ = np.linalg.qr(np.random.default_rng(1).normal(size=(4, 4)))
    f = q @ np.diag([-0.05, 0.3, 0.7, 1.0]) @ q.T
    margin, record = t1.realisation(f)
    assert margin == -1.0 and "moments differ" in record["failure"]
    assert real is realise.realising_solid


def test_quaternion_round_trip():
    rng = np.random.default_rng(2)
    for _ in range(50):
        q = rng.normal(size=4)
        r = density.rotation(q)
        np.testing.assert_allclose(density.rotation(quaternion(r)), r, atol=1e-14)


def test_realising_solid_refuses_without_mass():
    phi = pseudo_inertia_inverse(np.diag([1.0, 1.0, 1.0, -1.0]))
    spec, why = realising_solid(phi)
    assert spec is None and "mass" in why


def test_boundary_holds_with_exact_zero_eigenvalues(ctx):
    result = t1.theorem1_boundary(ctx)
    assert result.verdict == Verdict.HOLDS, result.summary
    rows = result.evidence["examples"]
    assert {r["triangle_equalities"]["value"] for r in rows.values()} == {1, 2, 3}
    assert all(r["classifier"] == "degenerate" and r["classifier_rank"]["value"] == r["carrier_dimension"]["value"]
               for r in rows.values())
    slopes = [q["value"] for q in result.evidence["fitted_slopes"].values()]
    assert all(1.8 < s < 2.2 for s in slopes)
    assert result.evidence["members_decided_exactly"]["value"] > 0


def test_a_solid_passed_off_as_planar_is_violated_and_replays(ctx, capsys):
    box = density.moments(density.parse({"components": [{"type": "solid", "shape": "box", "mass": 3.0,
                                                         "dims": [0.5, 0.25, 0.125]}]}), exact=True)
    result = t1.boundary_result(ctx, examples=t1.boundary_examples() + [("thin box", 2, box)])
    assert result.verdict == Verdict.VIOLATED
    assert result.counterexample["data"]["row"]["f"] == "pd"
    path = ctx.save_counterexample(result)
    assert main(["replay", str(path)]) == 1
    assert "thin box" in capsys.readouterr().out


@pytest.mark.parametrize("kind,data,where", [
    ("pseudo_inertia", {"f": [[1, 0], [0, 1]]}, "field 'f'"),
    ("boundary", {"moments": {"m": "1", "h": ["0"], "sigma": []}}, "field 'moments'"),
    ("equivalence", {"id": "EQ-schur", "phi": [1, 2, "x"]}, "field 'phi'"),
    ("equivalence", {"id": "EQ-triangle", "lambda": ["1", "2", "3"], "rotation": [["1", "1", "0"], ["0", "1", "0"],
                                                                                     ["0", "0", "1"]]}, "orthogonal"),
    ("identity", {"id": "nope"}, "names no check"),
])
def test_malformed_counterexamples_fail_in_one_line(tmp_path, capsys, kind, data, where):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"schema": "inertiaproof.counterexample/1", "kind": kind, "data": data}))
    assert main(["replay", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and where in err[0]


def test_flattening_series_is_monotone_and_positive():
    lines, distances, decided, all_pd = t1.flattening_series(np.logspace(0, -8, 9))
    assert all_pd
    for points in lines.values():
        margins = [p[1] for p in points]
        assert all(a > b for a, b in zip(margins[:5], margins[1:6]))


def test_hunt_evidence_is_json(ctx):
    result = t1.theorem1_sufficiency(ctx)
    json.dumps(result.to_json())


def test_quadrature_of_a_realised_ellipsoid_is_independent_of_its_formula():
    phi = pseudo_inertia_inverse(np.diag([0.2, 0.1, 0.05, 2.0]))
    spec, _ = realising_solid(phi)
    value, _, _ = quadrature.moments(density.parse(spec))
    np.testing.assert_allclose(density.moment_matrix(*value), pseudo_inertia(phi), atol=1e-15)
