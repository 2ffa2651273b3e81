"""GRE's particle route: it holds, it is independent of the symbolic Z and twists, and the loading assumption shows."""

import dataclasses

import numpy as np
import pytest
from inertiaproof.checks.generalized_equation import generalized_robotics_equation, replay_particle_claim
from inertiaproof.symbolic import derivations, gate, kinematics, lagrangian, particles, robotics_equation
from inertiaproof.symbolic.claims import PARTICLE_GRE, entries, gre_residual
from inertiaproof.symbolic.evidence import claim_result, run_claim
from inertiaproof.symbolic.fingerprints import fingerprints
from inertiaproof.symbolic.identity import fixed_point, point_json
from inertiaproof.symbolic.particles import ParticleKey, derivation_of_particles
from inertiaproof.symbolic.systems import profile_systems

from inertiaproof.result import Verdict


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """Derivations made now, in this process, with an empty disk cache (a monkeypatch is then seen)."""
    monkeypatch.setenv("INERTIAPROOF_CACHE", str(tmp_path / "cache"))
    derivations.forget()
    particles.forget()
    yield
    derivations.forget()
    particles.forget()


def test_particles_on_2r_and_3r_hold_with_every_control_detected(fresh):
    outcomes = [run_claim(PARTICLE_GRE, derivation_of_particles(k), rng=np.random.default_rng(0))
                for k in (ParticleKey("2R", 2), ParticleKey("3R", 1))]
    result = claim_result(PARTICLE_GRE, outcomes)
    assert result.verdict == Verdict.HOLDS, result.summary
    assert all(c["detected"] for c in result.evidence["negative_controls"].values())


def test_the_loading_difference_is_m_of_thetadot_times_qd_and_not_zero(fresh):
    p = derivation_of_particles(ParticleKey("2R", 1))
    jets = p.calc
    assert p.difference_terms > 0
    assert all(jets.is_zero(a - b) for a, b in zip(p.loading_difference, p.loading_term))
    assert not all(jets.is_zero(x) for x in p.loading_term)
    # with the at-rest assumption dropped, Lagrange's equations no longer describe the particles
    wrong = PARTICLE_GRE.residual(p, euler_lagrange=p.newton_with_the_body)
    assert not all(jets.is_zero(x) for x in wrong)


def _flip_first_moment(spatial_inertia):
    def wrong(phi):
        z = [list(row) for row in spatial_inertia(phi)]
        for i in range(3):
            for j in range(3, 6):
                z[i][j], z[j][i] = -z[i][j], -z[j][i]
        return z
    return wrong


def _flip_angular_velocity(body_twist):
    def wrong(self, frame, derivative):
        twist = body_twist(self, frame, derivative)
        return twist[:3] + [-x for x in twist[3:]]
    return wrong


@pytest.mark.parametrize("mutant", [pytest.param("sign of S(h) in Z", marks=pytest.mark.slow),
                                    "sign of the body angular velocity"])
def test_a_wrong_z_or_twist_turns_gre_violated_even_after_the_lockfile_is_updated(fresh, ctx, tmp_path, monkeypatch,
                                                                                  mutant):
    if mutant == "sign of S(h) in Z":
        wrong = _flip_first_moment(lagrangian.spatial_inertia)
        monkeypatch.setattr(lagrangian, "spatial_inertia", wrong)
        monkeypatch.setattr(robotics_equation, "spatial_inertia", wrong)
    else:
        monkeypatch.setattr(kinematics.ChainTwin, "_body_twist", _flip_angular_velocity(kinematics.ChainTwin._body_twist))
    ds = [derivations.derivation(k) for k in profile_systems(ctx.profile)]
    # the two routes through Z and the twists agree with each other: the mutant is invisible to them ...
    assert all(d.calc.is_zero(x) for d in ds for x in gre_residual(d))
    # ... and to the gate once its lockfile is rewritten from the mutated derivations
    found = {k: v for d in ds for k, v in fingerprints(d).items()}
    labels = [d.key.label for d in ds]
    lock = tmp_path / "lock.json"
    gate.update(lock, found, labels)
    assert not gate.compare(gate.read_lock(lock)["objects"], found, labels)["failures"]
    # the particle route shares neither, and GRE says VIOLATED with a replayable row
    result = generalized_robotics_equation(ctx)
    assert result.verdict == Verdict.VIOLATED, result.summary
    assert result.counterexample["kind"] == "particle-claim"
    assert replay_particle_claim(result.counterexample["data"], ctx).verdict == Verdict.VIOLATED


def test_the_replayer_holds_on_the_correct_code(fresh, ctx):
    p = derivation_of_particles(ParticleKey("2R", 1))
    residual = entries(PARTICLE_GRE.residual(p))[0]
    data = {"id": "GRE", "system": dataclasses.asdict(p.key), "entry": 0, "point": point_json(fixed_point(p.calc, 0)),
            "value": "1"}
    assert p.calc.evaluate(residual[0], fixed_point(p.calc, 0)) == 0
    assert replay_particle_claim(data, ctx).verdict == Verdict.HOLDS


def test_a_wrong_symbolic_rate_factor_turns_gre_violated(ctx, monkeypatch):
    """The cubic map is derived symbolically only on a scene's chain; its twin's g' is checked against g in every run."""
    from inertiaproof.checks.generalized_equation import replay_coordinate_polynomial
    from inertiaproof.symbolic import jets

    monkeypatch.setitem(jets.COORDINATE_POLYNOMIALS, "cubic", ((0, 0, 0, 1), (0, 0, 2)))
    result = generalized_robotics_equation(ctx)
    assert result.verdict == Verdict.VIOLATED and "cubic" in result.summary
    assert replay_coordinate_polynomial(result.counterexample["data"], ctx).verdict == Verdict.VIOLATED
