"""The payload envelope (inertiaproof.bounds.payload, APP-payload-envelope, ``inertiaproof envelope``) and the checker's
``payload-envelope`` claims: each can fail."""

from __future__ import annotations

import copy
import json
from fractions import Fraction

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings

from inertiaproof.bounds import payload
from inertiaproof.bounds.payload import PayloadSet, envelope
from inertiaproof.checks import payload_envelope as check
from inertiaproof.cli import main as cli_main
from inertiaproof.counterexamples.payloads import payloads
from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import pseudo_inertia, spatial_inertia
from inertiaproof.result import Verdict
from inertiaproof.scene import robots
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.verify.cli import check as verify

ARM = robots.planar_2r()
BALL = PayloadSet.ball(1, 2, (0, 0, 0), Fraction(1, 10))
RATE = Fraction(15, 8)


@pytest.fixture(scope="module")
def found():
    return envelope(ARM.chain, ARM.trajectory.base, BALL, rate=RATE, samples=500, rounds=20)


def _certificates(found):
    return {"alpha1": found["lower"]["certified"]["certificate"], "alpha2": found["upper"]["certified"]["certificate"],
            "chi": found["chi"]["certified"]["certificate"], "chi_paper": found["chi"]["paper"]["certificate"],
            "alpha2_paper": found["upper"]["paper"]["certificate"]}


def test_every_certified_constant_is_re_proved(found):
    for name, cert in _certificates(found).items():
        assert verify(json.loads(json.dumps(cert)))["status"] == "re-proved", name
    high = found["upper"]["observed"]
    assert high["lower"] <= high["upper"] <= 1.25 * high["lower"]


def test_the_checker_does_not_reprove_a_bound_below_the_worst_payload(found):
    """The upper claim is proved on the cover Phi_U of Young's epsilon: a witness below it refutes the cover, not
    the payloads, so the claim is not re-proved (never re-proved)."""
    cert = copy.deepcopy(found["upper"]["certified"]["certificate"])
    assert cert["claim"]["kind"] == "payload-envelope"
    cert["claim"]["bound"] = str(Fraction(found["upper"]["observed"]["lower"] * 0.99))
    out = verify(cert)
    assert out["status"] == "not re-proved" and "cover" in out["why"], out
    heavier = copy.deepcopy(found["upper"]["certified"]["certificate"])
    heavier["payload"]["mass"] = "8"  # the same bound claimed for payloads four times as heavy
    assert verify(heavier)["status"] == "not re-proved"


def test_the_checker_does_not_reprove_a_flange_bound_too_small(found):
    """beta below m ((|c| + R)^2 + 1), or a bound below what beta gives: a proof step that fails (not re-proved)."""
    chi = found["chi"]["paper"]["certificate"]
    assert chi["claim"]["formula"] == "chi_ramp"
    flange = copy.deepcopy(next(i for i in chi["ingredients"] if i["claim"]["kind"] == "payload-envelope"))
    assert verify(flange)["status"] == "re-proved"
    flange["beta"] = str(Fraction(flange["beta"]) * Fraction(99, 100))
    out = verify(flange)
    assert out["status"] == "not re-proved" and "beta" in out["why"], out
    flange = copy.deepcopy(next(i for i in chi["ingredients"] if i["claim"]["kind"] == "payload-envelope"))
    flange["claim"]["bound"] = str(Fraction(flange["claim"]["bound"]) * Fraction(99, 100))
    assert verify(flange)["status"] == "not re-proved"


def test_a_flange_bound_below_a_body_without_the_payload_is_refuted(found):
    """A body that carries no payload with lambda_max(f(Phi_1)) above the bound: refuted at that body (the cover is
    not in its way); the payload's body past the bound is only its cover's failure (not re-proved)."""
    chi = found["chi"]["paper"]["certificate"]
    flange = copy.deepcopy(next(i for i in chi["ingredients"] if i["claim"]["kind"] == "payload-envelope"))
    assert flange["payload"]["body"] == 2
    flange.pop("formation", None)
    for rows in flange["parameters"]:
        rows[0] = ["4", "0", "0", "0", "1", "1", "1", "0", "0", "0"]  # f = diag(1/2, 1/2, 1/2, 4)
    flange["claim"]["bound"] = "3"  # above beta = 2.02, below 4
    out = verify(flange)
    assert out["status"] == "refuted" and out["where"]["witness"]["body"] == 1, out
    flange["claim"]["bound"] = "2"  # below beta = 2.02: body 2 fails with its cover, body 1 (f <= I4) holds
    for rows in flange["parameters"]:
        rows[0] = ["1", "0", "0", "0", "1", "1", "1", "0", "0", "0"]  # f = diag(1/2, 1/2, 1/2, 1)
    out = verify(flange)
    assert out["status"] == "not re-proved" and "cover" in out["why"], out


def test_a_cover_below_the_payloads_is_violated(monkeypatch):
    """Young's term dropped: the certified sup lies below a point mass of the set, which the check sees (VIOLATED)
    and the checker does not re-prove (a witness below the claim refutes the cover it is proved on, not the
    payloads)."""
    real = payload.covering_parameters
    monkeypatch.setattr(payload, "covering_parameters", lambda ball, eps: real(ball, eps) * 0.6)
    result = check.envelope_result("2R", ARM.chain, ARM.trajectory.base, BALL, ramp_s=1.0, profile=PROFILES["ci"],
                                   examples=20, points=0, goal=None)
    assert result.verdict == Verdict.VIOLATED
    cert = result.evidence["constants"]["alpha2"]["certified"]["certificate"].certificate
    assert verify(json.loads(json.dumps(cert)))["status"] == "not re-proved"


def test_the_attack_finds_a_payload_beyond_a_constant_too_small(found):
    bounds = (found["lower"]["certified"]["value"], 0.9 * found["upper"]["observed"]["lower"],
              found["chi"]["certified"]["value"], found["ingredients"]["zeta"][1])
    seen = check.attack(ARM.chain, ARM.trajectory.base, BALL, bounds, RATE, examples=200, seed_value=0,
                        witnesses=np.array([found["upper"]["observed"]["witness"]]))
    assert seen["violation"] is not None and seen["violation"]["margin"] < 0


def test_payloads_of_the_set_stay_within_and_heavier_ones_do_not(found):
    bounds = (found["lower"]["certified"]["value"], found["upper"]["certified"]["value"],
              found["chi"]["certified"]["value"], found["ingredients"]["zeta"][1])
    seen = check.attack(ARM.chain, ARM.trajectory.base, BALL, bounds, RATE, examples=1000, seed_value=1,
                        witnesses=np.array([found["upper"]["observed"]["witness"]]))
    assert seen["violation"] is None and seen["examples"] == 1000
    worst = found["worst_payload"]
    beyond = check._beyond(ARM.chain, ARM.trajectory.base, BALL, bounds[1], worst["com"], np.asarray(worst["q"]))
    assert beyond is not None and beyond["mass"] > float(BALL.mass) and beyond["lambda_max"] > bounds[1]


@settings(max_examples=50, deadline=None)
@given(payloads(2.0, np.array([0.1, 0.0, 0.05]), np.full(3, 0.1)))
def test_drawn_payloads_lie_in_the_lmi_set(phi):
    """Wensing, Kim and Slotine's description: J = f(Phi) >= 0, tr(Q J) >= 0 for the ball's Q, mass <= m."""
    j = pseudo_inertia(phi)
    c, r = np.array([0.1, 0.0, 0.05]), 0.1
    q = np.block([[-np.eye(3), c[:, None]], [c[None], np.array([[r * r - c @ c]])]])
    assert np.linalg.eigvalsh(j)[0] >= -1e-12 * np.abs(j).max()
    assert np.trace(q @ j) >= -1e-12 and phi[0] <= 2.0 + 1e-12


def test_the_lmi_set_reaches_no_further_than_its_point_masses():
    """The sup over the LMI set of v^T M(q, Phi_p) v (an SDP, CVXPY + Clarabel) is the sup over point masses m on
    the sphere, m (|p| + R |omega|)^2 when p is across omega: the S-lemma the envelope rests on."""
    rng = np.random.default_rng(3)
    chain, m, c, r = robots.panda().chain, 3.0, np.array([0.0, 0.05, 0.1]), 0.1
    for _ in range(3):
        qv = rng.uniform(-1, 1, chain.n)
        qj = chain.body_jacobian(qv)[6 * 6:6 * 7]
        t = qj @ rng.normal(size=chain.n)
        j = cp.Variable((4, 4), symmetric=True)
        q_ball = np.block([[-np.eye(3), c[:, None]], [c[None], np.array([[r * r - c @ c]])]])
        sigma = j[:3, :3]
        inertia = cp.trace(sigma) * np.eye(3) - sigma
        h, mass = j[:3, 3], j[3, 3]
        v, w = t[:3], t[3:]
        energy = mass * (v @ v) + 2 * v @ cp.hstack([-(h[1] * w[2] - h[2] * w[1]), -(h[2] * w[0] - h[0] * w[2]),
                                                    -(h[0] * w[1] - h[1] * w[0])]) + w @ inertia @ w
        problem = cp.Problem(cp.Maximize(energy), [j >> 0, cp.trace(q_ball @ j) >= 0, mass <= m])
        problem.solve(solver=cp.CLARABEL)
        p = v + np.cross(w, c)
        across = np.linalg.norm(p - w * (p @ w) / (w @ w))
        along = abs(p @ w) / np.linalg.norm(w)
        point = m * (along**2 + (across + r * np.linalg.norm(w)) ** 2)
        z = spatial_inertia(payload.point_mass(m, c + payload._farthest(p[None], w[None], r)[0]))
        assert t @ z @ t == pytest.approx(point, rel=1e-9)
        assert problem.value == pytest.approx(point, rel=1e-5)


def test_the_worst_point_mass_is_attained(found):
    worst = found["worst_payload"]
    loaded = payload.with_payload(ARM.trajectory.base, BALL, payload.point_mass(worst["mass"], worst["com"]))
    value = np.linalg.eigvalsh(composite.mass_matrix(ARM.chain, np.asarray(worst["q"]), loaded))[-1]
    assert value == pytest.approx(found["upper"]["observed"]["lower"], rel=1e-12)
    assert np.linalg.norm(np.asarray(worst["com"]) - 0) == pytest.approx(0.1, rel=1e-9)


def test_envelope_command_on_a_scene(tmp_path, capsys):
    out = tmp_path / "env"
    assert cli_main(["envelope", "scenes/planar_2r_payload.toml", "--link", "2", "--mass", "1", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "alpha2" in printed and "re-proved" in printed
    assert (out / "envelope.csv").read_text().startswith("mass,alpha1")
    assert (out / "envelope.pdf").is_file() and "<svg" in (out / "envelope.html").read_text()
    assert cli_main(["verify", str(out)]) == 0


@pytest.mark.parametrize("args, words", [
    (["--link", "9", "--mass", "1"], "body is named by its number"),
    (["--link", "2", "--mass", "-1"], "--mass: must be > 0"),
    (["--link", "2", "--mass", "0"], "--mass: must be > 0"),
    (["--link", "2", "--mass", "1", "--ramp", "0"], "--ramp: must be > 0"),
    (["--link", "2", "--mass", "one"], "--mass: 'one' is not a number"),
    (["--link", "2", "--mass", "1e999999999"], "--mass: '1e999999999' is not a number"),  # no 10^(10^9) in memory
])
def test_envelope_bad_input_is_one_line(args, words, capsys):
    assert cli_main(["envelope", "scenes/planar_2r_payload.toml", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err


def test_envelope_bad_link_of_a_urdf(tmp_path, capsys):
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"/><link name="b"><inertial><mass value="1"/><inertia ixx="1" '
                    'iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link><joint name="j" type="revolute">'
                    '<parent link="a"/><child link="b"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" '
                    'velocity="1"/></joint></robot>')
    assert cli_main(["envelope", str(urdf), "--link", "c", "--mass", "1"]) == 2
    assert "--link 'c': no such link" in capsys.readouterr().err
    assert cli_main(["envelope", str(urdf), "--link", "a", "--mass", "1"]) == 2
    assert "fixed base" in capsys.readouterr().err


def test_a_payload_beyond_a_constant_is_saved_and_replays(monkeypatch):
    """A cover too small lets the attack find a payload beyond alpha2: the counterexample replays VIOLATED."""
    from inertiaproof.suite.registry import REPLAYERS

    real = payload.covering_parameters
    monkeypatch.setattr(payload, "covering_parameters", lambda ball, eps: real(ball, eps) * 0.6)
    result = check.envelope_result("2R", ARM.chain, ARM.trajectory.base, BALL, ramp_s=1.0, profile=PROFILES["ci"],
                                   examples=200, points=0, goal=None)
    data = json.loads(json.dumps(result.counterexample["data"]))
    assert REPLAYERS["payload-envelope"](data, None).verdict == Verdict.VIOLATED
    a1, a2, chi, zeta = data["bounds"]
    data["bounds"] = [a1 / 2, 2 * a2, 2 * chi, 2 * zeta]  # with honest constants the same payload stays within
    assert REPLAYERS["payload-envelope"](data, None).verdict == Verdict.HOLDS


def test_the_ellipsoid_cover_bounds_every_point_and_is_the_least_diagonal():
    """U >= S(d)^T S(d) = |d|^2 I - d d^T (Tjaja) on the ellipsoid, and no diagonal entry can be lowered: U_i is
    reached at the end of another semi-axis."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        axes = rng.random(3) ** rng.integers(1, 4)
        u = payload.cover_inertia(axes)
        d = rng.normal(size=(300, 3))
        d = axes * d / np.linalg.norm(d, axis=1)[:, None]
        gram = np.einsum("k,ij->kij", (d * d).sum(1), np.eye(3)) - d[:, :, None] * d[:, None, :]
        assert np.linalg.eigvalsh(np.diag(u) - gram).min() >= -1e-12 * u.max()
        ends = np.diag(axes)  # d = a_j e_j: (|d|^2 - d_i^2) = a_j^2 for i != j
        assert np.allclose(u, [max((ends[j] ** 2).sum() - ends[j][i] ** 2 for j in range(3)) for i in range(3)])


ELLIPSOID = PayloadSet(1, 2, (Fraction(1, 20), 0, 0), (Fraction(3, 20), Fraction(1, 20), Fraction(1, 50)))


def test_an_ellipsoid_envelope_is_certified_re_proved_and_attacked():
    found = envelope(ARM.chain, ARM.trajectory.base, ELLIPSOID, rate=RATE, samples=500, rounds=20)
    for name, cert in _certificates(found).items():
        assert verify(json.loads(json.dumps(cert)))["status"] == "re-proved", name
    assert found["upper"]["certified"]["certificate"]["payload"]["semi_axes"] == ["3/20", "1/20", "1/50"]
    high = found["upper"]["observed"]
    assert high["lower"] <= high["upper"] <= 1.25 * high["lower"]
    d = (np.asarray(found["worst_payload"]["com"]) - [0.05, 0, 0]) / [0.15, 0.05, 0.02]
    assert d @ d == pytest.approx(1, rel=1e-9)  # on the boundary
    bounds = (found["lower"]["certified"]["value"], found["upper"]["certified"]["value"],
              found["chi"]["certified"]["value"], found["ingredients"]["zeta"][1])
    seen = check.attack(ARM.chain, ARM.trajectory.base, ELLIPSOID, bounds, RATE, examples=300, seed_value=2,
                        witnesses=np.array([high["witness"]]))
    assert seen["violation"] is None
    wider = copy.deepcopy(found["upper"]["certified"]["certificate"])
    wider["payload"]["semi_axes"] = ["3/5", "3/5", "3/5"]  # the same bound claimed for a ball four times as far
    assert verify(wider)["status"] == "not re-proved"


@pytest.mark.slow
def test_envelope_command_with_an_ellipsoid(capsys):
    assert cli_main(["envelope", "scenes/planar_2r_payload.toml", "--link", "2", "--mass", "1", "--ellipsoid",
                     "0.15", "0.05", "0.02", "--no-verify"]) == 0
    assert "ellipsoid with semi-axes (0.15, 0.05, 0.02)" in capsys.readouterr().out
    assert cli_main(["envelope", "scenes/planar_2r_payload.toml", "--link", "2", "--mass", "1", "--ellipsoid",
                     "0.1", "-1", "0.1"]) == 2
    assert "--ellipsoid: must be >= 0" in capsys.readouterr().err


def test_a_moving_payload_adds_its_share_to_chi_and_the_sum_is_re_proved():
    still = envelope(ARM.chain, ARM.trajectory.base, BALL, rate=RATE, samples=300, rounds=8)
    moving = envelope(ARM.chain, ARM.trajectory.base, BALL, rate=RATE, speed=Fraction(1, 2), samples=300,
                      rounds=8)
    sharp, paper = moving["chi"]["certified"], moving["chi"]["paper"]
    assert sharp["value"] > still["chi"]["certified"]["value"] and paper["upper"] > still["chi"]["paper"]["upper"]
    for cert in (sharp["certificate"], paper["certificate"]):
        assert cert["claim"]["kind"] == "sum" and verify(json.loads(json.dumps(cert)))["status"] == "re-proved"
    low = copy.deepcopy(sharp["certificate"])
    low["claim"]["bound"] = str(Fraction(low["terms"][0]["claim"]["bound"]))  # the moving share dropped
    assert verify(low)["status"] == "not re-proved"  # the sum's arithmetic fails: no witness
    wrong = copy.deepcopy(sharp["certificate"])
    wrong["terms"][0]["claim"]["bound"] = str(Fraction(wrong["terms"][0]["claim"]["bound"]) / 2)  # its product fails
    wrong["claim"]["bound"] = str(sum(Fraction(t["claim"]["bound"]) for t in wrong["terms"]))
    out = verify(wrong)
    assert out["status"] == "not re-proved" and "term 0" in out["why"], out
    t5 = moving["theorem5"]
    psi = 0.5 * 2 * np.sqrt(1 + 0.1**2)  # m V (1 + (|c| + R)^2)^(1/2)
    assert psi <= t5["psi_star"] <= psi * (1 + 1e-12) and t5["sharp"] <= t5["paper"]


def test_progress_of_a_bracket_not_yet_finite_is_printed(monkeypatch):
    """A deep envelope crashed formatting the progress line of a bracket whose certified side was still infinite."""
    from inertiaproof.bounds import extremes

    clock = iter(range(10**6))  # a second per reading
    monkeypatch.setattr(extremes.time, "perf_counter", lambda: float(next(clock)))
    lines = []
    b = extremes.bracket_extreme(lambda q: q[:, 0] ** 2, lambda c, r: np.full(len(c), np.inf), np.zeros(1),
                                 np.ones(1), sense="max", quantity_name="x^2", samples=16, rounds=200,
                                 rng=np.random.default_rng(0), progress=lines.append, max_boxes=300)
    assert b.observed == pytest.approx(1, abs=0.2) and any("unbounded" in line for line in lines)


def test_the_true_extremes_certified_sides_cite_their_certificates():
    result = check.envelope_result("2R", ARM.chain, ARM.trajectory.base, BALL, ramp_s=1.0, profile=PROFILES["ci"],
                                   examples=10, points=0, goal=None)
    constants, brackets = result.evidence["constants"], result.evidence["brackets"]
    for name, side, bracket in (("alpha1", "lower", "inf lambda_min(M)"), ("alpha2", "upper", "sup lambda_max(M)"),
                                ("chi", "upper", None)):
        extreme = constants[name]["true_extreme"][side]
        cert = extreme["certificate"].certificate
        assert verify(json.loads(json.dumps(cert)))["status"] == "re-proved", name
        assert Fraction(cert["claim"]["bound"]) == Fraction(extreme["value"]) or bracket is None
        if bracket is not None:
            assert extreme["value"] == brackets[bracket][side]["value"]


@pytest.mark.slow
def test_envelope_command_completes_trees_within_the_profiles_count(monkeypatch):
    """As a run does (Profile.tree_boxes): the prover completes a tree the checker does not re-prove with at most
    the profile's count of boxes (UR5's certificates without a partition would hold the command for an hour)."""
    from inertiaproof.suite import certificates

    spent = []
    monkeypatch.setattr(certificates, "settle", lambda result, **kw: spent.append(kw["boxes"]) or result)
    assert cli_main(["envelope", "scenes/planar_2r_payload.toml", "--link", "2", "--mass", "1"]) == 0
    assert spent == [PROFILES["ci"].tree_boxes]


def test_a_payload_set_of_one_point_is_certified():
    """R = 0 (and a flat ellipsoid): the farthest point's step divides by the ellipsoid's reach, 0 here (it crashed)."""
    flat = PayloadSet(1, 2, (0, 0, 0), (Fraction(1, 10), 0, 0))
    for pset in (PayloadSet.ball(1, 2, (Fraction(1, 10), 0, 0), 0), flat):
        found = envelope(ARM.chain, ARM.trajectory.base, pset, rate=RATE, samples=200, rounds=8)
        high = found["upper"]["observed"]
        assert np.isfinite(high["lower"]) and high["lower"] <= high["upper"]
        assert verify(json.loads(json.dumps(found["upper"]["certified"]["certificate"])))["status"] == "re-proved"


def test_alpha2s_ladder_takes_the_profiles_count_of_boxes_and_aims_at_the_attained_value(monkeypatch):
    """The deep profile's envelope_boxes reach alpha2's ladder (its wall-clock guard in proportion) and its targets
    are scaled to the worst payload's attained value, not the cover's higher sup: a rung of 1.05 then closes the
    bracket within 1.05x (Panda, 5 kg within 0.1 m: 1.04997x)."""
    from inertiaproof.bounds import ladders, memo, perron
    from inertiaproof.bounds.pivot_search import ladder_budget

    seen = []
    memo.clear()  # the ladders spied on must run, not come from the memo
    monkeypatch.setattr(perron, "fourier_perron_bound", lambda *a, **k: None)  # a bracket left for the ladder
    monkeypatch.setattr(ladders, "_ladder", lambda chain, family, values, observed, witness, budget, stop, **k:
                        (seen.append((observed, budget)), (np.inf, "", None))[1])
    kw = dict(samples=200, rounds=20, rng=np.random.default_rng(0), progress=None)
    arm = robots.panda()
    ball = PayloadSet.ball(arm.chain.n - 1, 5, (0, 0, 0), Fraction(1, 10))
    b, _ = payload._sup_over_set(arm.chain, arm.trajectory.base, ball, "sup", kw, goal=1.04, boxes=10**6)
    (observed, (boxes, guard_s)), = seen
    worst = payload._worst(arm.chain, arm.trajectory.base, ball, 200, np.random.default_rng(0))[0]
    assert observed == worst <= b.observed and boxes == 10**6
    assert guard_s == pytest.approx(ladder_budget(20)[1] * boxes / ladder_budget(20)[0])
    payload._sup_over_set(arm.chain, arm.trajectory.base, ball, "sup", kw, goal=1.05)
    assert seen[-1][1] == ladder_budget(20) and PROFILES["deep"].envelope_boxes > ladder_budget(800)[0]


def test_the_attack_in_shards_gives_the_same_answer_on_one_and_two_workers(found, monkeypatch):
    from inertiaproof.suite.execution import Executor, ForkExecutor

    monkeypatch.setattr(check, "ATTACK_SHARD", 40)  # 3 shards
    witnesses = np.array([found["upper"]["observed"]["witness"]])
    certified = (found["lower"]["certified"]["value"], found["upper"]["certified"]["value"],
                 found["chi"]["certified"]["value"], found["ingredients"]["zeta"][1])
    too_small = (certified[0], 0.9 * found["upper"]["observed"]["lower"], *certified[2:])
    answers = []
    for bounds in (certified, too_small):
        seen = [check.attack(ARM.chain, ARM.trajectory.base, BALL, bounds, RATE, examples=120, seed_value=3,
                             witnesses=witnesses, executor=executor) for executor in (Executor(), ForkExecutor(2))]
        assert seen[0] == seen[1]
        answers.append(seen[0])
    assert answers[0]["violation"] is None and answers[0]["examples"] == 120
    assert answers[1]["violation"] is not None and answers[1]["examples"] <= 40  # found in the first shard


def test_two_envelopes_are_proved_side_by_side_with_the_answers_of_one_worker(tmp_path, monkeypatch):
    from inertiaproof.suite import runner
    from inertiaproof.suite.execution import Executor, ForkExecutor
    from inertiaproof.suite.timings import without_timings

    monkeypatch.setitem(check.BUILT_IN, "ci", (("planar_2r", 2, Fraction(1, 10)), ("planar_2r", 1, Fraction(1, 20))))
    docs = []
    for i, executor in enumerate((Executor(), ForkExecutor(2))):
        run = runner.run_checks(only=[check.ID], verify=False, executor=executor, out_dir=tmp_path / str(i),
                                counterexample_dir=tmp_path / "found")
        docs.append(without_timings(runner.results_document(run, profile="ci", seed=0, scene=None)))
        provers = [b for b in executor.log if b["label"] == "payload envelope provers"]
        assert provers and provers[-1]["tasks"] == 2
    assert docs[0] == docs[1] and docs[0]["summary"]["HOLDS"] == 1
    assert provers[-1]["where"] == "workers"
