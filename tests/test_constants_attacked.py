"""Every constant the suite computes and reports as a bound, made false in general, is caught (issue 12).

Each test replaces one formula of inertiaproof.bounds.formulas (a factor dropped, the constant divided or
multiplied by 10), runs the check that reports it (its scenes, its hunt of the pointwise inequality on random
chains, its hunt of the reported constants on random scenes), and asserts: VIOLATED, with a counterexample that
``inertiaproof replay`` turns VIOLATED on the falsified code and HOLDS on the real code. With the real formulas
the same checks HOLD.
"""

import numpy as np
import pytest
from inertiaproof.checks.constant_hunt import reported_hunt
from inertiaproof.checks.mass_matrix_bounds import thm2_result, thm3_result
from inertiaproof.checks.other_components import acc_result, thm4_result, thm5_result
from inertiaproof.checks.pointwise import CONSTANTS, constant_margins, run_hunt

from inertiaproof.bounds import formulas
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import Profile
from inertiaproof.suite.replay import replay

ATTACK = Profile("test", examples=30, samples=300, rounds=4, symbolic_max_n=2, derandomize=True)
PAYLOAD = [robots.planar_2r(payload=1.0)]
TROLLEY = [robots.trolley_2r(loop=True, mass=2.0)]

RESULTS = {"Thm2": (thm2_result, PAYLOAD), "Thm3": (thm3_result, PAYLOAD), "Thm4": (thm4_result, PAYLOAD),
           "EQ-acc": (acc_result, TROLLEY), "Asm3/Thm5": (thm5_result, TROLLEY)}

FALSIFIED = [  # (check, formula, constant it computes, the formula made false in general)
    ("Thm2", "alpha1", "alpha1", lambda xi, gamma: 10 * xi * gamma),
    ("Thm2", "alpha1_z", "alpha1 (certified, Z)", lambda z_min, gamma: 10 * z_min * gamma),
    ("Thm3", "alpha2", "alpha2", lambda zeta, s: zeta * s**2),  # the key step's factor 2 dropped
    ("Thm3", "alpha2_z", "alpha2 (certified, Z)", lambda z_max, s: z_max * s**2 / 10),
    ("Thm4", "chi", "chi", lambda mu, s, bodies: np.sqrt(69.0 * bodies) * mu * s**2 / 10),
    ("Thm4", "chi_sharp", "chi (certified, factor 2)", lambda mu, s: mu * s**2),  # the sharp factor 2 dropped
    ("Thm4", "chi_z", "chi (certified, Z)", lambda zdot, s: zdot * s**2 / 10),
    ("EQ-acc", "acceleration", "dPsi* S", lambda dpsi, s: dpsi * s / 10),
    ("Asm3/Thm5", "lumped_velocity", "sqrt(6N) Psi* Y", lambda psi, y, rows: np.sqrt(rows) * psi * y / 10),
    ("Asm3/Thm5", "lumped_velocity_sharp", "Psi* Y_rss (certified)", lambda psi, y_rss: psi * y_rss / 10),
]


def ctx(tmp_path=None):
    outputs = Outputs(counterexample_dir=tmp_path) if tmp_path is not None else Outputs()
    return Context(ATTACK, seed=0, outputs=outputs)


def test_every_constant_of_a_check_is_tested():
    """The pointwise checks and hunts test each formula of inertiaproof.bounds.formulas through CONSTANTS."""
    tested = {name for _, name, _, _ in FALSIFIED}
    assert tested == {n for n in formulas.__all__ if n != "KEY_STEP_UPPER"}
    assert {constant for _, _, constant, _ in FALSIFIED} == {c for cs in CONSTANTS.values() for c in cs}


@pytest.mark.parametrize("check_id", sorted(RESULTS))
def test_real_constants_hold(check_id):
    fn, scenes = RESULTS[check_id]
    assert fn(ctx(), scenes).verdict == Verdict.HOLDS


@pytest.mark.parametrize("check_id, name, constant, wrong", FALSIFIED, ids=[f[1] for f in FALSIFIED])
def test_falsified_constant_is_caught_and_replays(check_id, name, constant, wrong, monkeypatch, tmp_path):
    fn, scenes = RESULTS[check_id]
    with monkeypatch.context() as patch:
        patch.setattr(formulas, name, wrong)
        run = ctx(tmp_path)
        result = fn(run, scenes)
        assert result.verdict == Verdict.VIOLATED, result.summary
        assert result.counterexample is not None
        path = run.outputs.save_counterexample(result, profile="ci", seed=0)  # replay reads a named profile
        assert replay(path).verdict == Verdict.VIOLATED
    assert replay(path).verdict == Verdict.HOLDS  # the real formula: the same point holds


@pytest.mark.parametrize("check_id, name, constant, wrong", FALSIFIED, ids=[f[1] for f in FALSIFIED])
def test_hunt_on_random_chains_alone_catches_the_falsified_constant(check_id, name, constant, wrong, monkeypatch):
    """Not only the built-in scenes: the hunt over random chains finds a chain breaking the falsified constant."""
    moving = True if check_id in ("EQ-acc", "Asm3/Thm5") else None
    monkeypatch.setattr(formulas, name, wrong)
    _, cx = run_hunt(check_id, ctx(), 1.0, moving, constants=[constant])
    assert cx is not None and cx["data"]["constant"] == constant
    from inertiaproof.suite.registry import REPLAYERS
    assert REPLAYERS["bound-point"](cx["data"], ctx()).verdict == Verdict.VIOLATED
    monkeypatch.undo()
    assert REPLAYERS["bound-point"](cx["data"], ctx()).verdict == Verdict.HOLDS


def test_constants_are_evaluated_by_the_formulas_module(monkeypatch):
    """A replaced formula changes what the pointwise check compares (the check reads the function at call time)."""
    chain = robots.planar_2r(payload=1.0).chain
    traj = robots.planar_2r(payload=1.0).trajectory
    t = np.linspace(0, 1, 4)
    theta, theta_dot = traj.theta(t)
    psi, psi_dot = traj.psi(t)
    state = {"theta": theta, "theta_dot": theta_dot, "psi": psi, "psi_dot": psi_dot}
    q = np.random.default_rng(0).uniform(-1, 1, (4, 2))
    before = constant_margins("Thm3", chain, q, state)["alpha2"][3]
    monkeypatch.setattr(formulas, "alpha2", lambda zeta, s: 3 * zeta * s**2)
    after = constant_margins("Thm3", chain, q, state)["alpha2"][3]
    assert np.allclose(after, 1.5 * before)


def test_reported_constants_hunt_catches_a_wrong_certified_number(monkeypatch, tmp_path):
    """The certified alpha2 as the check computes it for a random scene (branch and bound, Z, the paper's) made
    a tenth: the hunt of reported constants finds a scene and the bound-constant file replays."""
    from inertiaproof.bounds import constants

    real = constants.upper_constants

    def optimistic(*args, **kwargs):
        out = real(*args, **kwargs)
        out["certified"]["value"] = out["certified"]["value"] / 10
        return out

    with monkeypatch.context() as patch:
        patch.setattr("inertiaproof.checks.mass_matrix_bounds.upper_constants", optimistic)
        _, cx = reported_hunt("Thm3", ctx(), False, examples=5)
        assert cx is not None and cx["kind"] == "bound-constant" and cx["data"]["constant"] == "certified"
        from inertiaproof.suite.registry import REPLAYERS
        assert REPLAYERS["bound-constant"](cx["data"], ctx()).verdict == Verdict.VIOLATED
    assert REPLAYERS["bound-constant"](cx["data"], ctx()).verdict == Verdict.HOLDS


def test_inertiaproof_replay_of_a_falsified_constants_file_holds_on_the_real_code(monkeypatch, tmp_path):
    """The command line: a counterexample found with chi's factor 2 dropped, replayed by `inertiaproof replay` in a
    fresh process (the real code) exits 0 and says HOLDS."""
    import subprocess
    import sys

    monkeypatch.setattr(formulas, "chi_sharp", lambda mu, s: mu * s**2)
    run = ctx(tmp_path)
    result = thm4_result(run, PAYLOAD)
    assert result.verdict == Verdict.VIOLATED
    path = run.outputs.save_counterexample(result, profile="ci", seed=0)
    assert replay(path).verdict == Verdict.VIOLATED
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "replay", str(path)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0 and "HOLDS" in done.stdout, done.stdout + done.stderr


# -- the audit's constants (inertiaproof audit reports alpha1, alpha2 and certified sides per chain) --------------

from hypothesis import HealthCheck, find, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from inertiaproof.counterexamples.chains import chains  # noqa: E402
from inertiaproof.counterexamples.inertias import consistent_phi  # noqa: E402

from inertiaproof.audit.document import chain_bounds  # noqa: E402
from inertiaproof.dynamics import composite  # noqa: E402

AUDIT_SETTINGS = dict(database=None, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))


@st.composite
def audited_chains(draw):
    """A random chain (1 to 6 joints, revolute and prismatic) with constant consistent bodies."""
    chain, length = draw(chains(max_joints=6))
    theta = np.stack([draw(consistent_phi(size=(length / 10, length))) for _ in range(chain.bodies)])
    return chain, theta


def audit_margin(example):
    """Smallest relative margin of sampled lambda_min(M(q)) / lambda_max(M(q)) against every constant and certified
    side ``chain_bounds`` (what ``inertiaproof audit`` reports) gives for the chain; below -1e-9: a reported bound
    is wrong."""
    chain, theta = example
    found = chain_bounds(chain, theta, samples=200, rounds=0.8)
    lo, hi = chain.coordinate_box()
    q = lo + (hi - lo) * np.random.default_rng(1).random((400, chain.n))
    w = np.linalg.eigvalsh(composite.mass_matrix(chain, q, theta))
    low, high = w[:, 0].min(), w[:, -1].max()
    scale = abs(high) + abs(low)
    lows = [found[k]["value"] for k in ("alpha1_certified", "alpha1_paper_lower", "inf_lambda_min_certified")]
    highs = [found[k]["value"] for k in ("alpha2_certified", "alpha2_paper_upper", "sup_lambda_max_certified")]
    margins = [(low - float(v)) / scale for v in lows] + [(float(v) - high) / scale for v in highs]
    return min(m for m in margins if np.isfinite(m))


@settings(max_examples=8, **AUDIT_SETTINGS)
@given(audited_chains())
def test_audit_constants_hold_on_random_chains(example):
    assert audit_margin(example) >= -1e-9


def test_audit_catches_a_falsified_certified_alpha2(monkeypatch):
    """alpha2 at the level of Z made a tenth: some random chain's reported alpha2 lies below a sampled lambda_max."""
    monkeypatch.setattr(formulas, "alpha2_z", lambda z_max, s: z_max * s**2 / 10)
    found = find(audited_chains(), lambda ex: audit_margin(ex) < -1e-9, settings=settings(max_examples=30,
                                                                                          **AUDIT_SETTINGS))
    monkeypatch.undo()
    assert audit_margin(found) >= -1e-9  # the same chain with the real formula
