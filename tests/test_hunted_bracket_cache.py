"""The deep Thm3 false alarm of issue 25: two hunted scenes named by the same sample seed shared a bracket.

The reported-constant hunt (checks.constant_hunt) names a hunted scene ``hunted-{seed}`` with the description
``random {chain name}, {n} joints``, and Hypothesis draws the seed 0 again and again. Brackets were cached per
run under (name, description, quantity) only, so a later example with the same seed and chain name (a 1-joint
"random general-axis R" chain) took the sup lambda_max(M) bracket of an earlier one with heavier parameters:
"observed 4.0" against its own constant 3.658, saved with its own parameter sets (I33 = 2.0 and 2.91), on which the
replay finds 2.91. The cache key now holds a digest of the chain and the trajectory, and a case replays its
bound-bracket counterexample before it reports it.
"""

import numpy as np

from inertiaproof.bounds.configuration import mass_sup
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.checks.bound_verdicts import case_result, parameter_stack, replay_bracket, scene_digest
from inertiaproof.checks.constant_hunt import example_key, hunted_scene, light_context
from inertiaproof.checks.mass_matrix_bounds import upper_bound_case
from inertiaproof.dynamics.chain import Chain
from inertiaproof.dynamics.trajectory import ParameterTrajectory, Payload, Profile
from inertiaproof.result import Verdict
from inertiaproof.suite.context import Context
from inertiaproof.suite.profiles import PROFILES

# the 1-joint chain of the deep run's counterexample (seed 0, Thm3), as saved
CHAIN = Chain.from_data({"name": "random general-axis R", "gravity": [0.0, 0.0, -9.81], "joints": [{
    "kind": "revolute", "axis": [0.0, 0.0, 1.0], "coordinate": "identity", "limits": None, "name": "joint1",
    "before": [[-0.9999999995065197, 3.128880255528015e-05, -2.823344548703255e-06, 0.0],
               [-3.1415926530726385e-05, -0.9959535176922982, 0.08986984816598086, 0.0],
               [0.0, 0.08986984821032985, 0.9959535181837816, -0.44814125697839324], [0.0, 0.0, 0.0, 1.0]],
    "after": np.eye(4).tolist()}]})
BASE = np.array([1.0, 0.0, 0.0, 0.35569, 2.12652, 2.12652, 2.0, 0.0, 0.0, 0.0])  # I33 = 2.0
LOAD = np.array([0.43408, 0.0, 0.13535, -0.32255, 1.15002, 1.10771, 0.91025, 0.0, 0.10057, 3.934e-05])  # -> 2.91


def _trajectory(scale):
    return ParameterTrajectory(scale * BASE[None], (Payload(0, LOAD, Profile("smootherstep", 1.0, 0.5)),), (0.0, 5.0))


def _value_at_witness(scene, witness):
    data = {"chain": scene.chain.to_data(), "witness": np.asarray(witness).tolist(),
            "thetas": parameter_stack(scene.trajectory, False), "spectral": "lmax", "sense": "upper",
            "constant_upper": np.inf, "constant_lower": np.inf}
    return replay_bracket(data)[0]


def test_same_seed_scenes_do_not_share_brackets():
    heavy = hunted_scene((CHAIN, _trajectory(2.0), 0))  # drawn first: I33 = 4.0
    light_one = hunted_scene((CHAIN, _trajectory(1.0), 0))  # the saved example: I33 = 2.0 and 2.91
    assert (heavy.name, heavy.description) == (light_one.name, light_one.description)
    assert scene_digest(heavy) != scene_digest(light_one)
    assert example_key((CHAIN, _trajectory(2.0), 0)) != example_key((CHAIN, _trajectory(1.0), 0))
    assert example_key((CHAIN, _trajectory(1.0), 0)) == example_key((CHAIN, _trajectory(1.0), 0))

    ctx = light_context(Context(PROFILES["deep"], seed=0))  # one context for the whole hunt, as in reported_hunt
    first = upper_bound_case(ctx, heavy, 1.0)
    verdict, why, evidence, cx = upper_bound_case(ctx, light_one, 1.0)
    fresh = upper_bound_case(light_context(Context(PROFILES["deep"], seed=0)), light_one, 1.0)
    assert verdict == fresh[0] == Verdict.HOLDS, why
    assert cx is None
    drop = lambda b: {k: v for k, v in b.items() if k != "convergence"}  # noqa: E731 (timings in the record)
    assert drop(evidence["bracket"]) == drop(fresh[2]["bracket"])
    assert drop(evidence["bracket"]) != drop(first[2]["bracket"])
    # the attained value is the left-hand side at the witness on the very parameter sets the case saves
    observed = evidence["bracket"]["lower"]["value"]
    witness = np.asarray(evidence["bracket"]["witness"])
    value = _value_at_witness(light_one, witness)
    assert abs(value - observed) <= 1e-9 * abs(observed)
    assert observed < 3.0 < first[2]["bracket"]["lower"]["value"]


def test_a_bracket_of_other_parameters_is_no_counterexample():
    """What the shared bracket did: the heavy scene's bracket judged against the light scene's constant. Its attained
    value is not found again on the saved parameter sets, so the case does not report a VIOLATED it cannot show."""
    ctx = light_context(Context(PROFILES["deep"], seed=0))
    heavy, light_one = (hunted_scene((CHAIN, _trajectory(s), 0)) for s in (2.0, 1.0))
    wrong = mass_sup(CHAIN, parameter_vertices(heavy.trajectory)[0], samples=200, rounds=0.8,
                     rng=ctx.rng("wrong"))
    constant = upper_bound_case(ctx, light_one, 1.0)[2]["constant_range"]
    lo, hi = constant["lower"]["value"], constant["upper"]["value"]
    assert wrong.observed > hi  # judged alone, the borrowed bracket refutes the light scene's constant
    quiet = {"violated": False, "counterexample": None, "evidence": {}}
    verdict, why, _, cx = case_result("Thm3", light_one, "upper", wrong, (lo, hi), 1.0, 1.0, quiet, {}, {},
                                      replay={"thetas": parameter_stack(light_one.trajectory, False),
                                              "spectral": "lmax"})
    assert verdict == Verdict.INCONCLUSIVE and cx is None
    assert "not computed on the scene's parameters" in why
