"""The APP checks (checks/applications.py): each holds on the built-in scenes and is VIOLATED on a wrong input;
``inertiaproof adapt`` on the shipped scenes with both laws and all three plants; the [adaptive] table."""

import dataclasses
import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from inertiaproof import cli
from inertiaproof.budget import Budget
from inertiaproof.checks import applications as app
from inertiaproof.checks import euclidean_escape as escape
from inertiaproof.dynamics import motion
from inertiaproof.model.exact import definiteness, integer_matrix, to_fractions
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse
from inertiaproof.report import adapt as adapt_report
from inertiaproof.result import Verdict
from inertiaproof.sim import tracking
from inertiaproof.sim.recipe import Recipe
from inertiaproof.scene.format import INTEGRATORS, SceneError, parse_scene
from inertiaproof.suite.catalog import APPLICATIONS, BY_ID
from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.replay import replay

SCENES = Path(__file__).resolve().parents[1] / "scenes"
KEY = "planar-2r-payload"


@pytest.fixture(scope="module")
def app_ctx(tmp_path_factory):
    """One ci context for the module: the robustness study of the 2R payload scene is simulated once."""
    out = tmp_path_factory.mktemp("app")
    return Context(PROFILES["ci"], seed=0, outputs=Outputs(out, out / "found"))


def _saved(result, ctx):
    path = ctx.save_counterexample(result)
    assert path is not None
    return replay(path)


def test_the_rows_are_in_the_catalog():
    assert [e.id for e in APPLICATIONS] == ["APP-estimate-bounds", "APP-euclidean-escape", "APP-robustness",
                                           "APP-payload-envelope"]
    assert all(BY_ID[e.id] is e for e in APPLICATIONS)


def test_estimate_bounds_hold_and_fail_without_the_qj_brackets(app_ctx):
    result = app.estimate_bounds_result(app_ctx, [KEY])
    assert result.verdict == Verdict.HOLDS, result.summary
    natural = [row for name, row in result.evidence["runs"].items() if "natural" in name]
    assert len(natural) == len(app.SETTINGS["ci"].ramps) and all(row["margin"] > 0 for row in natural)
    wrong = app.estimate_bounds_result(app_ctx, [KEY], gamma_override=1.0, sigma_override=1.0)
    assert wrong.verdict == Verdict.VIOLATED
    assert wrong.counterexample["data"]["bound"] == "upper"
    assert _saved(wrong, app_ctx).verdict == Verdict.VIOLATED


def test_an_inconsistent_estimate_passed_as_consistent_violates_the_lower_bound(app_ctx):
    def xi_of_the_truth(recipe, run, batch):
        theta = recipe.spec().trajectory.theta(run.t)[0]
        return float(np.linalg.eigvalsh(pseudo_inertia(theta))[..., 0].min())

    wrong = app.estimate_bounds_result(app_ctx, [KEY], xi_override=xi_of_the_truth)
    assert wrong.verdict == Verdict.VIOLATED
    assert wrong.counterexample["data"]["bound"] == "lower"
    assert wrong.counterexample["data"]["recipe"]["law"] == "slotine-li"


def test_a_consistency_below_float_resolution_is_proved_in_rationals():
    """f(Phi) = diag(1, 1, 2^-46, 1): lambda_min 1.4e-14 is below eigvalsh's resolution (64 eps (n + 4) zeta); the
    check proves 15/16 of it exactly (the thin rod's natural-law runs, xi_hat 1.7e-13, are decided so), and the
    proof fails at and beyond the exact lambda_min, and for a body that is not consistent."""
    tiny = 2.0 ** -46
    phi = pseudo_inertia_inverse(np.diag([1.0, 1.0, tiny, 1.0]))
    assert app._exceeds(phi, tiny / 2) and not app._exceeds(phi, tiny) and not app._exceeds(phi, 2 * tiny)
    theta_hat = np.stack([phi, pseudo_inertia_inverse(np.diag([2.0, 1.0, 1.0, 3.0]))])[None]  # (1 sample, 2 bodies)
    lambda_min = np.linalg.eigvalsh(pseudo_inertia(theta_hat))[..., 0]
    assert lambda_min.min() < app.eigh_resolution(2 + 4) * 3.0
    x, how = app._proved_xi(theta_hat, lambda_min, tiny, app.eigh_resolution(2 + 4) * 3.0)
    assert x == tiny * 15 / 16 and how.startswith("1 of 2")
    assert app._proved_xi(theta_hat, lambda_min, 4 * tiny, app.eigh_resolution(2 + 4) * 3.0) is None


def test_the_lower_margin_is_resolved_in_the_jacobi_scaling():
    """A graded mass matrix D A D (D = diag(1e4, 1, 1e-4), cond 1e16, as extreme_lengths' units make it): its
    lambda_min is below eigvalsh's rounding of lambda_max, but the sign of M - alpha1 1 is decided in the scaling
    (_lower_margin) and agrees with exact arithmetic on both sides of the exact threshold, 0.1 % away."""
    a = np.array([[2.0, 0.5, 0.2], [0.5, 1.5, 0.3], [0.2, 0.3, 1.0]])
    d = np.array([1e4, 1.0, 1e-4])
    mass = d[:, None] * a * d[None, :]

    def positive_definite(alpha):
        return definiteness(integer_matrix(to_fractions(mass) - np.diag([Fraction(alpha)] * 3)))[0] == "pd"

    low, high = 0.0, 1e-6  # bisection of the exact threshold alpha* = lambda_min(M)
    for _ in range(50):
        middle = (low + high) / 2
        low, high = (middle, high) if positive_definite(middle) else (low, middle)
    assert 0 < low < app.eigh_resolution(3) * np.linalg.eigvalsh(mass)[-1]  # unresolved without the scaling
    assert app._lower_margin(mass, 0.999 * low) > app.eigh_resolution(3)
    assert app._lower_margin(mass, 1.001 * low) < -app.eigh_resolution(3)


def test_euclidean_escape_is_found_saved_and_replays(app_ctx):
    result = escape.euclidean_escape_result(app_ctx, {KEY: 3})
    assert result.verdict == Verdict.HOLDS, result.summary
    euclidean, natural = (result.evidence["escapes"][KEY]["run"]["laws"][k] for k in ("euclidean", "natural"))
    assert euclidean["inf_lambda_min_M_hat"] < 0 < natural["inf_lambda_min_M_hat"]
    assert euclidean["min_lambda_min_f_hat"] < 0 < natural["min_lambda_min_f_hat"]
    replayed = replay(result.evidence["escapes"][KEY]["witness_file"])
    assert replayed.verdict == Verdict.HOLDS, replayed.summary


@pytest.mark.slow
def test_a_scene_without_an_escape_borrows_the_built_in_witness(app_ctx):
    """That Slotine-Li may escape is existential: a scene whose own runs keep M_hat definite is hunted first, then the
    built-in scene's witness proves the claim; the natural law is read off the runs of both."""
    scene = str(SCENES / "sphere_counterexample.toml")
    alone = escape.euclidean_escape_result(app_ctx, {scene: 3})
    assert alone.verdict == Verdict.INCONCLUSIVE, alone.summary
    result = escape.euclidean_escape_result(app_ctx, {scene: 3}, elsewhere={KEY: 3})
    assert result.verdict == Verdict.HOLDS, result.summary
    assert result.summary.startswith(f"no escape on {scene} in ") and list(result.evidence["escapes"]) == [KEY]
    assert list(result.evidence["searched"]["scenes"]) == [scene, KEY]
    found = escape.euclidean_escape_result(app_ctx, {KEY: 3}, elsewhere={scene: 3})
    assert list(found.evidence["searched"]["scenes"]) == [KEY]  # a witness at home: nothing hunted elsewhere
    wrong = escape.euclidean_escape_result(app_ctx, {scene: 3}, elsewhere={KEY: 3},
                                           twin=lambda r: dataclasses.replace(r, law="slotine-li"))
    assert wrong.verdict == Verdict.VIOLATED


def test_the_escape_hunt_is_budgeted_in_runs_and_a_clock_stop_claims_nothing(app_ctx, monkeypatch):
    monkeypatch.setitem(app.SETTINGS, "ci", dataclasses.replace(app.SETTINGS["ci"], hunt_runs=0))
    capped = escape.euclidean_escape_result(app_ctx, {KEY: 3})
    assert capped.verdict == Verdict.INCONCLUSIVE and " in 0 runs" in capped.summary
    assert capped.evidence["searched"]["runs_budget"] == 0
    monkeypatch.setitem(app.SETTINGS, "ci", dataclasses.replace(app.SETTINGS["ci"], hunt_runs=6))
    expired = dataclasses.replace(app_ctx, budget=Budget.of(0.0))
    clocked = escape.euclidean_escape_result(expired, {KEY: 3})
    assert clocked.verdict == Verdict.INCONCLUSIVE and "safety net" in clocked.summary


def test_a_scene_file_seeds_its_hunts_by_its_text_not_its_path(tmp_path):
    text = (Path(__file__).parents[1] / "scenes" / "planar_2r_payload.toml").read_text()
    (tmp_path / "a").mkdir()
    for name, body in (("a/s.toml", text), ("b.toml", text), ("c.toml", text + "\n# edited\n")):
        (tmp_path / name).write_text(body)
    assert app.stream_name(str(tmp_path / "a/s.toml")) == app.stream_name(str(tmp_path / "b.toml"))
    assert app.stream_name(str(tmp_path / "b.toml")) != app.stream_name(str(tmp_path / "c.toml"))
    assert app.stream_name(KEY) == KEY


def test_a_euclidean_law_passed_as_natural_is_violated(app_ctx):
    wrong = escape.euclidean_escape_result(app_ctx, {KEY: 3}, twin=lambda r: dataclasses.replace(r, law="slotine-li"))
    assert wrong.verdict == Verdict.VIOLATED and "gain" in wrong.summary and " at t = " in wrong.summary
    assert _saved(wrong, app_ctx).verdict == Verdict.VIOLATED


def test_robustness_holds_and_a_plant_without_its_rate_term_is_violated(app_ctx):
    result = app.robustness_result(app_ctx, [KEY])
    assert result.verdict == Verdict.HOLDS, result.summary
    table = result.evidence["table"]
    assert {row["plant"] for row in table} == {"gre", "classical"}  # Eq. (2) is the generalized one when Psi = 0
    assert len(table) == len(app.SETTINGS["ci"].ramps) * 2 * len(app.SETTINGS["ci"].laws)
    fastest = [row for row in table if row["load_s"] == min(app.SETTINGS["ci"].ramps)]
    assert all(row["rate"] > 50 for row in fastest)  # a 10 ms ramp of 2 kg

    def no_rate(kin, g, p, qd, qdd):
        return motion.generalized_forces(kin, g, dataclasses.replace(p, theta_dot=0 * p.theta_dot), qd, qdd)

    wrong = app.robustness_result(app_ctx, [KEY], forces=no_rate)
    assert wrong.verdict == Verdict.VIOLATED
    assert wrong.counterexample["kind"] == "adaptive-balance"


# -- inertiaproof adapt and the [adaptive] table ------------------------------------------------

@pytest.mark.parametrize("scene", ["planar_2r_payload", "trolley_2r", "panda_payload_3kg"])
@pytest.mark.parametrize("law", ["slotine-li", "natural"])
@pytest.mark.parametrize("plant", ["gre", "pagilla", "classical"])
def test_adapt_runs_the_shipped_scenes(scene, law, plant, tmp_path, capsys):
    horizon = "0.1" if scene.startswith("panda") else "0.4"
    code = cli.main(["adapt", "--scene", str(SCENES / f"{scene}.toml"), "--law", law, "--plant", plant,
                     "--out", str(tmp_path), "--horizon", horizon, "--samples", "9", "--rtol", "1e-4",
                     "--configurations", "4"])
    assert code == 0, capsys.readouterr()
    doc = json.loads((tmp_path / "adapt.json").read_text())
    assert doc["law"] == law and doc["plant"] == plant and doc["status"] == "ok"
    assert len(doc["series"]["t"]) == 9 and len(doc["series"]["lambda_min_f_hat"][0]) == len(doc["gains"]["kd"])
    header = (tmp_path / "series.csv").read_text().splitlines()[0].split(",")
    assert {"tracking_error", "parameter_error", "lambda_min_f_hat_1", "lambda_max_M_hat"} <= set(header)


def test_adapt_report_plots_the_series(tmp_path, capsys):
    code = cli.main(["adapt", "--scene", str(SCENES / "planar_2r_payload.toml"), "--law", "natural", "--out",
                     str(tmp_path), "--horizon", "0.3", "--samples", "7", "--rtol", "1e-4"])
    assert code == 0 and cli.main(["report", str(tmp_path), "--no-pdf"]) == 0
    assert (tmp_path / "adapt.html").is_file() and not (tmp_path / "report.html").exists()
    document = adapt_report.build(adapt_report.load(tmp_path / "adapt.json"))
    assert len(document.figures()) == 5


@pytest.mark.parametrize("gains, message", [
    ("lambda = -1.0\n", "lambda: must be > 0"),
    ("speed = 1.0\n", "speed: unknown key"),
    ("[gamma]\nnatural = \"fast\"\n", "gamma.natural: must be a number"),
])
def test_adapt_rejects_a_bad_gains_file_in_one_line(gains, message, tmp_path, capsys):
    path = tmp_path / "gains.toml"
    path.write_text(gains)
    code = cli.main(["adapt", "--scene", str(SCENES / "planar_2r_payload.toml"), "--law", "natural", "--gains",
                     str(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "\n" not in err and message in err and str(path) in err


def test_adapt_rejects_a_negative_horizon_in_one_line(tmp_path, capsys):
    code = cli.main(["adapt", "--scene", str(SCENES / "planar_2r_payload.toml"), "--law", "natural", "--horizon",
                     "-1", "--out", str(tmp_path)])
    assert code == 2 and "--horizon: must be > 0" in capsys.readouterr().err


def test_the_adaptive_table_of_a_scene():
    text = (SCENES / "panda_payload_3kg.toml").read_text()
    scene = parse_scene(text, "panda.toml")
    assert scene.adaptive.gain("natural") == 200.0 and scene.adaptive.lam == 5.0
    with pytest.raises(SceneError, match=r"panda.toml:\d+: adaptive.estimate: must be a list of 7 numbers"):
        parse_scene(text.replace("estimate = 1.0", "estimate = [1.0, 2.0]"), "panda.toml")
    assert scene.adaptive.integrator == "auto" and INTEGRATORS == ("auto",) + tuple(tracking.SOLVERS)
    with pytest.raises(SceneError, match=r"panda.toml:\d+: adaptive.integrator: must be one of auto, RK45, DOP853"):
        parse_scene(text.replace("estimate = 1.0", "estimate = 1.0\nintegrator = \"Euler\""), "panda.toml")
    assert scene.adaptive.work == 0.0
    with pytest.raises(SceneError, match=r"panda.toml:\d+: adaptive.work: must be >= 0"):
        parse_scene(text.replace("estimate = 1.0", "estimate = 1.0\nwork = -5"), "panda.toml")


def test_a_scene_may_give_its_runs_more_counted_work(monkeypatch, tmp_path, capsys):
    """trolley_2r.toml asks for 150,000 units ([adaptive] work): the study's batch gets BATCH of that, not of the
    profile's 36,000; a profile that gives more keeps its own. A gains file has no such key."""
    budgets = []

    def stand_in(chain, runs, horizon, *, max_evaluations, **kw):
        budgets.append(max_evaluations * tracking.evaluation_cost(chain.n, len(runs)))
        return [tracking.Run(spec, i, "ok", "", 0.1, 100, work=100) for i, spec in enumerate(runs)], None

    monkeypatch.setattr(tracking, "simulate", stand_in)
    recipes = [Recipe(str(SCENES / "trolley_2r.toml"), law, horizon=0.5) for law in ("slotine-li", "natural")]
    for work, expected in ((36_000, 150_000), (1_500_000, 1_500_000)):
        app.simulate_recipes(recipes, dataclasses.replace(app.SETTINGS["ci"], work=work))
        assert abs(budgets.pop() - app.BATCH * expected) < 2
    gains = tmp_path / "gains.toml"
    gains.write_text("work = 1000\n")
    code = cli.main(["adapt", "--scene", str(SCENES / "trolley_2r.toml"), "--law", "natural", "--gains", str(gains),
                     "--out", str(tmp_path)])
    assert code == 2 and "work: unknown key" in capsys.readouterr().err


def test_the_scene_chooses_the_integrator_of_its_runs():
    """stiff_mass_ratio_1e6.toml asks for DOP853 ([adaptive] integrator): the study's runs use it."""
    recipe = Recipe(str(SCENES / "stiff_mass_ratio_1e6.toml"), "slotine-li", horizon=0.05)
    (run,), _ = app.simulate_recipes([recipe], dataclasses.replace(app.SETTINGS["ci"], work=3_000))
    assert run.method == "DOP853" and run.finished


def test_a_run_stopped_by_the_clock_is_inconclusive_and_a_finished_unbalanced_run_violated(app_ctx, monkeypatch):
    """A plant without its rate term (a known bad input) breaks the Lyapunov balance: VIOLATED when its runs finish.
    The same runs stopped by the wall-clock safety net (max_seconds 0) are no evidence: INCONCLUSIVE, saying so."""
    small = dataclasses.replace(app.SETTINGS["ci"], scenes=((KEY, (0.1,)),), laws=("slotine-li",), settle=0.2)

    def no_rate(kin, g, p, qd, qdd):
        return motion.generalized_forces(kin, g, dataclasses.replace(p, theta_dot=0 * p.theta_dot), qd, qdd)

    monkeypatch.setitem(app.SETTINGS, "ci", small)
    wrong = app.robustness_result(app_ctx, [KEY], forces=no_rate)
    assert wrong.verdict == Verdict.VIOLATED and "do not close their Lyapunov balance" in wrong.summary
    monkeypatch.setitem(app.SETTINGS, "ci", dataclasses.replace(small, max_seconds=0.0))
    clocked = app.robustness_result(app_ctx, [KEY], forces=no_rate)
    assert clocked.verdict == Verdict.INCONCLUSIVE and "clock: 2" in clocked.summary, clocked.summary
    assert all(note.endswith("no evidence)") for note in clocked.evidence["notes"][:2])


def _run(status, balance, looser=np.nan, second_opinion=""):
    return tracking.Run(None, 0, status, "", 1.0, 100, balance_error=balance, looser_balance_error=looser,
                        second_opinion=second_opinion)


def test_the_balance_verdict_follows_the_tolerance():
    """Measured on stiff_thin_rod (natural law, rtol 3e-5 -> 3e-6): 1.31 -> 0.099, the residual follows the
    tolerance (integration error of an ill-scaled state), not a wrong plant; a level residual is VIOLATED; a run
    that did not finish decides nothing."""
    rtol = 3e-5
    assert app.balance_verdict(_run("ok", 0.02), rtol)[0] == Verdict.HOLDS
    assert app.balance_verdict(_run("ok", 0.099, 1.31), rtol)[0] == Verdict.HOLDS
    assert app.balance_verdict(_run("ok", 0.5, 0.6, "BDF's 5.1e-01"), rtol)[0] == Verdict.VIOLATED
    assert app.balance_verdict(_run("ok", 0.5, 0.6), rtol)[0] == Verdict.INCONCLUSIVE  # one method alone: unconfirmed
    for status in ("clock", "budget", "nan", tracking.BARRIER):
        assert app.balance_verdict(_run(status, 0.5, 0.6), rtol)[0] == Verdict.INCONCLUSIVE
    assert app.balance_verdict(_run("budget", 0.5, 0.6), rtol)[1].startswith("simulated again at rtol 3e-06")
    assert app.balance_verdict(_run("budget", 0.5), rtol)[1].startswith("budget")
    # a run past its law's barrier ends its batch (alone it would again): no split of the batch for it
    assert app.batch_finished([_run("ok", 0.0), _run(tracking.BARRIER, 0.0)])
    assert not app.batch_finished([_run("ok", 0.0), _run("clock", 0.0)])


@pytest.mark.parametrize("radau, verdict", [(0.02, Verdict.HOLDS), (0.25, Verdict.VIOLATED)])
def test_a_level_residual_is_claimed_only_when_a_second_method_finds_it_too(monkeypatch, radau, verdict):
    """Measured on trolley_2r's natural run (gre, 0.25 s traverse): BDF's residual goes 0.27 -> 0.24 from rtol 3e-5
    to 3e-6, level, where Radau's falls to 0.020: BDF did not converge, the plant is right. The study asks Radau
    (SECOND_OPINION) before it claims a level residual; here a stand-in integrator returns those residuals."""
    calls = []

    def stand_in(chain, specs, horizon, *, rtol, method, **kw):
        method = "BDF" if method == "auto" else method
        calls.append(method)
        error = {"BDF": 0.27 if rtol > 1e-5 else 0.24, "Radau": radau}[method]
        return [tracking.Run(specs[0], 0, "ok", "", 0.1, 10, balance_error=error, method=method, work=10)], None

    monkeypatch.setattr(tracking, "simulate", stand_in)
    s = app.SETTINGS["ci"]
    (run,), _ = app.simulate_recipes([Recipe("trolley-2r", "natural", "gre", horizon=1.7, timing=(0.2, 0.25))], s)
    assert calls == ["BDF", "BDF", "Radau"] and run.method == "Radau" and run.second_opinion == "BDF's 2.40e-01"
    assert run.looser_balance_error == 0.27
    assert app.balance_verdict(run, s.rtol)[0] == verdict


def test_runs_that_crossed_their_barrier_are_simulated_finer_alone(monkeypatch):
    """passenger_platform: its batch finished, one natural run past its barrier; simulated finer, that run nears the
    barrier again and collapses, so a batch of it and the other finer run would stop both: the finer runs go alone
    (the other one then finishes). A stand-in integrator records how the runs are grouped."""
    sizes, barrier = [], []

    def stand_in(chain, specs, horizon, *, rtol, method, **kw):
        sizes.append((len(specs), rtol < 1e-5))
        barrier.append(barrier[0] if barrier else specs[-1])  # the first batch's second run
        return [tracking.Run(spec, i, tracking.BARRIER if spec is barrier[0] else "ok", "", 0.1, 10,
                             balance_error=0.05 if rtol > 1e-5 else 1e-4, method="BDF", work=10)
                for i, spec in enumerate(specs)], None

    monkeypatch.setattr(tracking, "simulate", stand_in)
    recipes = [Recipe("trolley-2r", "natural", "gre", horizon=1.7, timing=(0.2, d)) for d in (1.0, 0.25)]
    app.simulate_recipes(recipes, app.SETTINGS["ci"])
    assert sizes == [(2, False), (1, True), (1, True)]


def test_an_unfinished_natural_run_is_no_evidence_against_the_law():
    data = {"resolution": 1e-12, "laws": {"natural": {"status": "ok", "min_lambda_min_f_hat": -1.0,
                                                      "max_lambda_max_f_hat": 1.0, "margin": -1.0}}}
    assert escape.natural_fails(data)
    for status in ("clock", "budget", "step collapse", "barrier"):
        data["laws"]["natural"]["status"] = status
        assert not escape.natural_fails(data)


def test_runs_alone_share_the_counted_work_and_the_left_over_goes_to_those_the_count_stopped():
    """A batch that stopped early splits into its runs alone: each with an equal share of the work left (what a run
    does not use passes to those after it), then the runs the count stopped once more with what is left. Measured
    on scenes/trolley_2r.toml (ci): runs alone need 410-2,606 evaluations, one more than 5,000; with 12,000 units at
    1 a evaluation, the 2,606 one finishes on the second pass, and nothing is spent beyond the work."""
    need = [422, 1058, 446, 2606, 428, 620, 542, 6000, 446, 728, 410, 578]
    calls = []

    def simulate(i, work, again):
        spec = need[i]
        calls.append((spec, work))
        assert again == (len(calls) > len(need))  # the second pass is implicit
        done = spec <= int(work)
        used = spec if done else int(work)
        return [tracking.Run(spec, 0, "ok" if done else "budget", "", 0.0, used, work=used)], None

    runs = [None] * len(need)
    app._alone(runs, [None] * len(runs), 12_000, simulate, 1.0)
    assert [r.status for r in runs] == ["ok"] * 7 + ["budget"] + ["ok"] * 4
    assert sum(min(w, s) for s, w in calls) <= 12_000 and len(calls) == len(need) + 2  # 2606 and 6000 again
    first = dict(calls[:len(need)])
    assert first[422] == 1000 and first[1058] > 1000  # the first run's unused share went to the rest


def test_a_long_chain_simulates_its_runs_alone_and_judges_rk45_on_the_2r_count(monkeypatch):
    """A chain of more than BATCH_JOINTS joints skips the batch: the 24-link snake's runs go alone at once, with the
    work of a WORK_JOINTS-joint chain (2.9x the 2R work, where its own evaluation cost would give 7x), and RK45 or not
    is judged on the 2R count (explicit_budget); the 2R arm's runs go as a batch first, on its own count."""
    calls = []

    def simulate(chain, specs, horizon, **kw):
        calls.append((len(specs), kw["max_evaluations"], kw["explicit_budget"], kw["method"]))
        return [tracking.Run(spec, i, "budget", "", 0.0, kw["max_evaluations"], work=kw["max_evaluations"])
                for i, spec in enumerate(specs)], None

    monkeypatch.setattr(tracking, "simulate", simulate)
    s = app.SETTINGS["ci"]
    for key, batched in ((str(Path(__file__).parents[1] / "scenes" / "many_links_24.toml"), False), (KEY, True)):
        calls.clear()
        recipes = [Recipe(key, law, "gre", horizon=1.0, timing=(0.2, 0.1)) for law in ("slotine-li", "natural")]
        app.simulate_recipes(recipes, s)
        n = recipes[0].chain().n
        assert [c[0] for c in calls] == ([2] if batched else []) + [1, 1]  # the second pass: nothing left
        ratio = tracking.evaluation_cost(n, 1) / tracking.evaluation_cost(2, 1)
        assert (ratio > 6.9) == (not batched)
        ratio = tracking.evaluation_cost(min(n, app.WORK_JOINTS), 1) / tracking.evaluation_cost(2, 1)
        assert (2.8 < ratio < 3.0) == (not batched)
        for size, evaluations, explicit, method in calls:
            assert explicit == max(int(evaluations / max(ratio, 1.0)), 1) and method == "auto"


def test_a_studys_runs_end_the_same_on_a_machine_three_times_slower(monkeypatch):
    """simulate_recipes budgets in counted work: with the wall clock running three times as fast (a machine three
    times slower, as under CPU hogs) the same runs finish, or stop at the count after the same evaluations (a work
    of 600 units: the batch stops early and its runs go on alone), and none stops at the clock."""
    import time as real_time
    import types

    from inertiaproof.sim.recipe import Recipe

    recipes = [Recipe(KEY, law, "gre", horizon=0.9, timing=(0.2, d)) for d in (0.5, 0.01) for law in ("slotine-li",
                                                                                                      "natural")]

    def outcomes():
        return {work: [(r.status, r.evaluations, r.jacobians) for r in app.simulate_recipes(
            recipes, dataclasses.replace(app.SETTINGS["ci"], work=work))[0]] for work in (600, 900)}

    idle = outcomes()
    slow = types.SimpleNamespace(perf_counter=lambda: 3 * real_time.perf_counter())
    monkeypatch.setattr(app, "time", slow)
    monkeypatch.setattr(tracking, "time", slow)
    assert outcomes() == idle
    assert {r[0] for r in idle[600]} == {"budget"} and {r[0] for r in idle[900]} == {"ok"}, idle


def test_the_runs_alone_get_what_the_batch_left_and_a_finer_run_keeps_its_implicit_method(monkeypatch):
    """trolley_2r (ci): its batch of 12 stops early (a run stiffened: tracking._stiffened); the runs alone share the
    rest of the study's work, not only the 1 - BATCH kept back for them. The natural run that needed BDF alone is
    simulated finer with BDF again, not with RK45 chosen afresh from the stiffness at its start. A stand-in
    integrator records the budgets and methods."""
    s = app.SETTINGS["ci"]
    recipes = [Recipe("trolley-2r", law, plant, horizon=1.7, timing=(0.2, d))
               for d in (1.0, 0.25) for plant in tracking.PLANTS for law in s.laws]
    specs = [r.spec() for r in recipes]
    stiff = specs[recipes.index(Recipe("trolley-2r", "natural", "gre", horizon=1.7, timing=(0.2, 0.25)))]
    calls = []

    def stand_in(chain, runs, horizon, *, rtol, method, max_evaluations, **kw):
        calls.append((len(runs), method, rtol, max_evaluations))
        if len(runs) > 1:
            return [tracking.Run(spec, i, "budget", "", 0.1, 400, work=400) for i, spec in enumerate(runs)], None
        slow = runs[0] is stiff and method == "auto"
        return [tracking.Run(runs[0], 0, "budget" if slow else "ok", "", 0.1, 100, method=method,
                             balance_error=0.27 if runs[0] is stiff else 0.0, work=100)], None

    monkeypatch.setattr(tracking, "simulate", stand_in)
    monkeypatch.setattr(Recipe, "spec", lambda self: specs[recipes.index(self)])
    app.simulate_recipes(recipes, s)
    share = (s.work - 400 * tracking.evaluation_cost(2, 12)) / 12 / tracking.evaluation_cost(2, 1)
    assert calls[0][0] == 12 and abs(calls[1][3] - int(share)) <= 1  # not (1 - BATCH) s.work / 12
    assert [c[1:3] for c in calls[13:15]] == [("BDF", s.rtol), ("BDF", s.rtol / 10)]  # alone again, then finer
