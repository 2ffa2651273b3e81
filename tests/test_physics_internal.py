"""GRE-physics, internal motion: the equation against Pinocchio's augmented model, and the density integrals."""

from pathlib import Path

import numpy as np
import pytest
from inertiaproof.checks import physics

from inertiaproof.dynamics import motion
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Profile
from inertiaproof.dynamics.trajectory import Path as LoadPath
from inertiaproof.model import particles, solids
from inertiaproof.model.inertia import inertia_com, rotation_rpy
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene
from inertiaproof.sim import crosscheck
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.registry import REPLAYERS

SCENES = Path(__file__).resolve().parent.parent / "scenes"


def ctx(**kw):
    return Context(PROFILES["ci"], **kw)


def builtin(*keys):
    return [({"builtin": k}, robots.BUILTIN[k]()) for k in keys]


def test_box_particles_have_the_moments_of_the_solid():
    rot = rotation_rpy((0.3, -0.2, 1.1))
    points, weights = particles.box_particles((0.3, 0.2, 0.1), rot)
    phi = particles.moments(points + np.array([0.1, -0.4, 0.2]), 2.5 * weights)
    exact = solids.solid("box", 2.5, (0.3, 0.2, 0.1), rot, (0.1, -0.4, 0.2))
    np.testing.assert_allclose(phi, exact, rtol=1e-14, atol=1e-15)


def test_particles_like_reproduce_mass_and_inertia():
    phi = solids.solid("cylinder", 3.0, (0.1, 0.5), rotation_rpy((0.4, 0.1, 0.0)))
    points, weights = particles.particles_like(3.0, inertia_com(phi))
    np.testing.assert_allclose(particles.moments(points, weights), phi, atol=1e-14)
    with pytest.raises(ValueError, match="Sigma_c"):
        particles.particles_like(1.0, np.diag([1.0, 1.0, 3.0]))


@pytest.mark.parametrize("path", [
    LoadPath("line", Profile("smootherstep", 0.2, 1.0), start=(-0.7, 0.1, 0.05), end=(0.3, -0.2, 0.4)),
    LoadPath("circle", Profile("cosine", 0.0, 1.5), center=(0.2, 0.1, -0.3), radius=0.4, normal=(0.3, -1.0, 0.5)),
])
def test_moving_mass_closed_forms_equal_the_density_integrals(path):
    base = robots.spatial_3r().trajectory.base
    load = MovingMass(2, 1.7, inertia_com(solids.solid("box", 1.7, (0.2, 0.1, 0.3))), path)
    trajectory = ParameterTrajectory(base, (load,), (0.0, 1.5))
    t = np.linspace(0, 1.5, 41)
    closed, integrated = motion.parameters(trajectory, t), motion.parameters_from_density(trajectory, t)
    for name in ("theta", "theta_dot", "psi", "psi_dot"):
        a, b = getattr(closed, name), getattr(integrated, name)
        assert np.abs(a - b).max() <= 1e-14 * max(1.0, np.abs(b).max()), name


def test_internal_motion_holds_on_trolley_and_passenger():
    result = physics.internal_motion_result(builtin("trolley-2r", "passenger-platform"), ctx())
    assert result.verdict == Verdict.HOLDS, result.summary
    assert result.evidence["max_relative_torque_error"]["value"] < 1e-13
    for entry in result.evidence["scenes"].values():
        assert entry["worst_ratio"]["value"] <= 1.0


def _perturbed(name, factor):
    """The equation's inverse dynamics with one term scaled by ``factor``."""
    def forces(kin, gravity, p, qd, qdd):
        terms = motion.equation_terms(kin, gravity, p, qd, qdd)
        terms[name] = factor * terms[name]
        return sum(terms.values())
    return forces


@pytest.mark.parametrize("term", ["lumped_velocity", "lumped_acceleration", "parameter_rate"])
def test_one_perturbed_term_is_violated(term):
    result = physics.internal_motion_result(builtin("trolley-2r"), ctx(), forces=_perturbed(term, 1 + 1e-6),
                                            samples=60)
    assert result.verdict == Verdict.VIOLATED, result.summary
    data = result.counterexample["data"]
    assert result.counterexample["kind"] == "gre-physics-internal"
    assert data["scene"] == {"builtin": "trolley-2r"} and data["ratio"] > crosscheck.VIOLATION_RATIO
    replayed = REPLAYERS["gre-physics-internal"](data, ctx())
    assert replayed.verdict == Verdict.HOLDS  # the current (correct) equation at the saved sample


def test_terms_sum_to_the_generalized_forces():
    scene = robots.passenger_platform()
    t = np.linspace(0, 4, 7)
    q, qd, qdd = crosscheck.smooth_motion(scene.chain, t, np.random.default_rng(3))
    kin, p = motion.kinematics(scene.chain, q), motion.parameters(scene.trajectory, t)
    total = sum(motion.equation_terms(kin, scene.chain.gravity, p, qd, qdd).values())
    np.testing.assert_allclose(total, motion.generalized_forces(kin, scene.chain.gravity, p, qd, qdd), rtol=1e-12,
                               atol=1e-10)


def test_extreme_lengths_are_not_a_spurious_violation():
    scene = load_scene(SCENES / "extreme_lengths.toml")
    result = physics.internal_motion_result([({"source": scene.source}, scene)], ctx(), samples=80)
    assert result.verdict == Verdict.HOLDS, result.summary
    entry = result.evidence["scenes"]["extreme-lengths"]
    assert entry["resolution"]["value"] > 1e-13  # the measured round-off is far above eps here


def test_without_pinocchio_it_is_inconclusive(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "pinocchio", None)
    result = physics.internal_motion_result(builtin("trolley-2r"), ctx())
    assert result.verdict == Verdict.INCONCLUSIVE and "Pinocchio" in result.summary
