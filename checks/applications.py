"""Beyond the paper: the applications it names (abstract, introduction), checked with adaptive laws
(``APP-euclidean-escape``, which simulates runs of its own, in inertiaproof.checks.euclidean_escape).

- ``APP-estimate-bounds``: along adaptive runs whose estimate is uniformly physically consistent and upper bounded
  (Definition 3 applied to Theta_hat over the run's samples: xi_hat, zeta_hat), M(q, Theta_hat(t)) obeys
  Theorem 2's alpha1 = xi_hat inf_q sigma_min(QJ)^2 and Theorem 3's alpha2 = 2 zeta_hat sup_q sigma_max(QJ)^2 with
  the chain's certified QJ brackets (inertiaproof.bounds.configuration), at the run's configurations and at sampled
  ones.
- ``APP-robustness``: tracking and parameter error against the loads' rate of change (payload ramps, trolley
  traverses) on the three plants (inertiaproof.sim.tracking): where Eq. (1) and Eq. (2) mislead about the
  controller on the generalized equation. Every run's Lyapunov balance (Prop1, Prop2 and the law's divergence)
  must close; one that does not, also at a tenth of the tolerance, simulated something else than its plant.

The runs of the robustness study are shared with APP-estimate-bounds (Context.shared). What decides a verdict is
budgeted in counts (evaluations, examples), the same on every machine; a run that did not finish is never evidence
against the paper or a law, and one stopped by the wall-clock safety net (status ``clock``) is no evidence either way.
"""

from __future__ import annotations

import dataclasses
import hashlib
import time
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from inertiaproof.bounds import formulas
from inertiaproof.bounds.certificate import pseudo_exact
from inertiaproof.bounds.configuration import jacobian_normality, jacobian_sup
from inertiaproof.bounds.premises import unsimulable
from inertiaproof.checks.normality import refutations, unit_bodies
from inertiaproof.dynamics import composite, motion
from inertiaproof.dynamics.forward import jacobi_scaling
from inertiaproof.model.exact import definiteness, integer_matrix
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.presentation import bracket_evidence
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.scene import robots
from inertiaproof.sim import estimates, tracking
from inertiaproof.sim.recipe import Recipe, scene_of
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "AppSettings", "BALANCE", "balance_verdict", "bound_case", "eigh_resolution", "estimate_bounds",
    "estimate_bounds_result", "LEVEL", "qj_brackets", "replay_bound", "robustness", "robustness_result", "scene_keys",
    "settings_for", "SETTINGS", "simulate_recipes", "stream_name", "study",
]

EPS = np.finfo(float).eps
BALANCE = 1000.0  # a run's Lyapunov balance error may reach BALANCE x rtol (integration error)
LEVEL = 0.3  # a residual that does not fall below LEVEL x itself when rtol falls tenfold is no integration error


@dataclass(frozen=True)
class AppSettings:
    scenes: tuple  # (built-in scene, durations of its loads in the robustness study) without --scene
    hunts: tuple  # (built-in scene, Hypothesis examples) of the escape hunt without --scene
    hunt_runs: int  # distinct runs one scene's hunt may simulate, its shrinking included (a count; examples drawn
    # after it are skipped)
    hunt_horizon: float
    shrink: bool  # let Hypothesis shrink an escape to a simpler run
    ramps: tuple  # durations (s) of payload ramps of a --scene
    traverses: tuple  # durations (s) of moving-mass traverses of a --scene
    start: float  # when the loads start (s)
    settle: float  # seconds simulated after the slowest load
    laws: tuple
    samples_per_second: float
    configurations: int  # sampled configurations for the extremes of M(q, Theta_hat) over q
    rtol: float
    work: float  # counted work (tracking.evaluation_cost's work units, an operation count) of simulate_recipes on a
    # 2R chain: its batch, its runs alone and the finer re-run share it (BATCH of it, the rest, FINER of it more); a
    # chain of n joints gets as many evaluations of a run alone (_work)
    max_seconds: float  # wall-clock safety net of one simulate_recipes (every phase), no evidence when it strikes


SETTINGS = {
    "ci": AppSettings(scenes=(("planar-2r-payload", (1.0, 0.1, 0.01)), ("trolley-2r", (1.0, 0.25))),
                      hunts=(("planar-2r-payload", 3),), hunt_runs=6, hunt_horizon=2.0, shrink=False,
                      ramps=(1.0, 0.1, 0.01), traverses=(1.0, 0.25), start=0.2, settle=0.5,
                      laws=("slotine-li", "natural"), samples_per_second=50, configurations=128, rtol=3e-5,
                      work=36_000, max_seconds=180.0),
    "deep": AppSettings(scenes=(("planar-2r-payload", (10.0, 3.0, 1.0, 0.3, 0.1, 0.03, 0.01)),
                                ("trolley-2r", (4.0, 2.0, 1.0, 0.5, 0.25, 0.1)),
                                ("panda-payload-3kg", (1.0, 0.1, 0.01))),
                        hunts=(("planar-2r-payload", 60), ("trolley-2r", 40), ("panda-payload-3kg", 10)),
                        hunt_runs=120, hunt_horizon=3.0, shrink=True,
                        ramps=(10.0, 3.0, 1.0, 0.3, 0.1, 0.03, 0.01), traverses=(4.0, 2.0, 1.0, 0.5, 0.25, 0.1),
                        start=0.5, settle=1.5, laws=("slotine-li", "natural"), samples_per_second=100,
                        configurations=1024, rtol=1e-6, work=1_500_000, max_seconds=3600.0),
}


def settings_for(ctx):
    return SETTINGS.get(ctx.profile.name, SETTINGS["ci"])


def scene_keys(ctx, default):
    """The built-in scenes ``default`` (pairs of key and a setting), or the run's scene file with None."""
    if ctx.scene is None:
        return dict(default)
    if not ctx.scene.source:
        raise ValueError(f"scene {ctx.scene.name!r} has no file: a run of it could not be replayed")
    return {ctx.scene.source: None}


def stream_name(key):
    """What names a scene in its random streams and hunt seeds: a built-in scene's key, or a scene file's name and
    the digest of its text, not its path (the same file draws the same examples wherever it lives)."""
    if key in robots.BUILTIN:
        return key
    with open(key, "rb") as f:
        return f"{scene_of(key).name}#{hashlib.sha256(f.read()).hexdigest()[:12]}"


def _samples(s, horizon):
    return int(np.ceil(horizon * s.samples_per_second)) + 1


def eigh_resolution(n):
    """Relative rounding of eigvalsh of a symmetric n x n matrix, against its largest eigenvalue."""
    return 64 * EPS * n


# -- runs ---------------------------------------------------------------------------------------

BATCH = 2 / 3  # of the work, a batch of several runs may spend this; if it stops early, its runs alone the rest (ci:
# Panda's 12 runs finish as one batch in 5,375 counted BDF evaluations, 16,600 units)
BATCH_JOINTS = 12  # on longer chains several runs are simulated alone, not as a batch first: a run's own work
# outweighs what a batch shares (its Jacobian's n + 1 states a run cost most; bench/results/machine_timings.md)
FINER = 1 / 2  # of the work, the runs simulated again at rtol / 10 may spend this more (ci: Panda's two natural-law
# runs of the 10 ms ramp need more than 5,289 evaluations at rtol 3e-6)
SECOND_OPINION = {"BDF": "Radau", "RK45": "Radau", "DOP853": "Radau", "Radau": "DOP853"}  # the method that must find
# a residual level too before it is claimed: BDF's on trolley_2r's natural run (gre, 0.25 s traverse) stays at 0.27 ->
# 0.24 from rtol 3e-5 to 3e-6, where Radau's falls 0.088 -> 0.020 (it converges: integration error, no wrong plant)


def simulate_recipes(recipes, s, forces=motion.generalized_forces):
    """Simulate recipes of one chain and horizon together, within ``_work(s, n)`` units of counted work
    (:func:`inertiaproof.sim.tracking.evaluation_cost`) and one wall-clock safety net ``s.max_seconds`` for it all,
    with the scene's ``[adaptive] integrator``; its ``[adaptive] work``, if larger, replaces ``s.work``.
    When the batch stops early (one stiff run holds up all: the step is the whole state's), or on a chain of more
    than BATCH_JOINTS joints, each run is simulated alone (:func:`_alone`), unless the batch was not started
    (ill-conditioned: its runs share the chain); the runs whose Lyapunov balance error exceeds BALANCE x rtol, or
    that stepped over their law's barrier, are simulated again, likewise, at a tenth of the tolerance, keeping the
    first residual as ``looser_balance_error`` (balance_verdict), alone at once if the batch did not finish the
    first time or one of them crossed its barrier (nearing it again, it would hold up the batch); a residual that
    stays level is simulated at that tolerance once more with the SECOND_OPINION method, largest first and alone,
    within another FINER of the work (``second_opinion`` names the first method's): one integrator's failure to
    converge is no wrong plant.
    Returns (runs, batches) in the recipes' order."""
    horizon, chain, adaptive = recipes[0].run_horizon(), recipes[0].chain(), recipes[0].scene_object().adaptive
    method, s = adaptive.integrator, dataclasses.replace(s, work=max(s.work, adaptive.work))
    deadline = time.perf_counter() + s.max_seconds
    cost = tracking.evaluation_cost(chain.n, 1)
    total = _work(s, chain.n)  # RK45 or not is decided as on a 2R chain, by s.work: explicit_budget

    def simulate(specs, work, rtol, again=False, how=None):
        evaluations = max(int(work / tracking.evaluation_cost(chain.n, len(specs))), 1)
        return tracking.simulate(chain, specs, horizon, rtol=rtol, samples=_samples(s, horizon), forces=forces,
                                 max_evaluations=evaluations, max_seconds=max(deadline - time.perf_counter(), 0.0),
                                 method=how or (tracking.IMPLICIT_DEFAULT if again and method == "auto" else method),
                                 explicit_budget=max(int(evaluations * s.work / total), 1))

    def together_then_alone(specs, work, rtol, together=True, methods=None):
        methods = methods or [None] * len(specs)
        if len(specs) == 1:
            runs, batch = simulate(specs, work, rtol, how=methods[0])
            return runs, [batch]
        runs, batches = [None] * len(specs), [None] * len(specs)
        if together and chain.n <= BATCH_JOINTS:
            runs, batch = simulate(specs, work * BATCH, rtol)
            batches = [batch] * len(runs)
            if batch_finished(runs) or runs[0].status in tracking.NOT_STARTED:
                return runs, batches
            work -= runs[0].work * tracking.evaluation_cost(chain.n, len(specs))  # what the batch left, the runs alone
        _alone(runs, batches, work, lambda i, share, again: simulate([specs[i]], share, rtol, again, methods[i]), cost)
        return runs, batches

    runs, batches = together_then_alone([r.spec() for r in recipes], total, s.rtol)
    again = [i for i, r in enumerate(runs) if r.finished and r.balance_error > BALANCE * s.rtol
             or r.status == tracking.BARRIER]  # the barrier too: the exact solution stays clear of it
    if again:
        crossed = any(runs[i].status == tracking.BARRIER for i in again)
        finer, finer_batches = together_then_alone(
            [runs[i].spec for i in again], total * FINER, s.rtol / 10,
            together=all(b is batches[0] for b in batches) and not crossed,
            methods=[runs[i].method if runs[i].method in tracking.IMPLICIT else None for i in again])
        for i, run, batch in zip(again, finer, finer_batches):
            run.looser_balance_error = runs[i].balance_error
            runs[i], batches[i] = run, batch
    work = total * FINER
    for i in sorted(again, key=lambda i: -runs[i].balance_error):
        first = runs[i]
        if work <= 0:
            break
        if not level(first, s.rtol):
            continue
        (run,), batches[i] = simulate([first.spec], work, s.rtol / 10, how=SECOND_OPINION[first.method])
        work -= run.work * cost
        run.looser_balance_error = first.looser_balance_error
        run.second_opinion = f"{first.method}'s {first.balance_error:.2e}"
        runs[i] = run
        if level(run, s.rtol):
            break  # one confirmed is enough: the others stay unconfirmed, INCONCLUSIVE
    return runs, batches


WORK_JOINTS = 12  # a study on a longer chain gets the work of one on this many joints, so the work stops growing
# as n^3 with the chain: its runs that need more end by the count, INCONCLUSIVE with no evidence, on every machine


def _work(s, n):
    """The counted work of a study on an n-joint chain: ``s.work`` is a 2R chain's; a longer chain takes about as many
    evaluations, each costing more (tracking.evaluation_cost of a run alone), up to the work of a chain of
    WORK_JOINTS joints."""
    ratio = tracking.evaluation_cost(min(n, WORK_JOINTS), 1) / tracking.evaluation_cost(2, 1)
    return s.work * max(ratio, 1.0)


def _alone(runs, batches, work, simulate, cost):
    """Each run simulated alone (into runs[i], batches[i]), in order, with an equal share of the work
    left (a run that finishes early leaves the rest of its share to those after it); then the runs the count stopped
    once more, in order and afresh, each with all the work left where that is more than it had, ``again``: with the
    implicit method unless the scene fixes its integrator (a run that outgrew an explicit method's budget stiffened
    on the way, as a natural-law estimate nearing its barrier does). Counts only: the same runs finish on every
    machine. ``simulate(i, share, again)`` simulates run i; ``cost``: the work of one evaluation of a run alone."""
    had = {}

    def alone(i, share, again=False):
        nonlocal work
        (runs[i],), batches[i] = simulate(i, share, again)
        had[i] = share
        work -= min(share, runs[i].work * cost)

    for k in range(len(runs)):
        alone(k, work / (len(runs) - k))
    for i in [i for i, r in enumerate(runs) if r.status == "budget"]:
        if work > had[i]:
            alone(i, work, again=True)


def level(run, rtol):
    """Whether a finished run's residual exceeds BALANCE x rtol and did not follow the tolerance down to rtol / 10 (by
    more than 1 / LEVEL; a run never simulated finer counts as level)."""
    return run.finished and run.balance_error > BALANCE * rtol and not (
        run.balance_error <= LEVEL * run.looser_balance_error)


def balance_verdict(run, rtol):
    """(verdict, why) of a run's Lyapunov balance (module docstring) at the study's ``rtol``.

    Only a finished run is evidence: one stopped by a counted budget, by the wall clock (machine-dependent) or by
    the integrator is INCONCLUSIVE. HOLDS: the residual is within BALANCE x rtol; or the run, simulated again at
    rtol / 10 (simulate_recipes), brought it down by more than 1 / LEVEL: it follows the tolerance, so it is
    integration error (an ill-scaled state, e.g. a rod's 1e-13 eigenvalue of f(Phi_hat)) and the balance closes
    in the limit. VIOLATED: it stayed within a factor 1 / LEVEL of where it was with two methods (``second_opinion``
    names the other's residual): no tolerance removes it, the run simulated something else than its plant; with one
    method only it is INCONCLUSIVE."""
    if not run.finished:
        again = (f"simulated again at rtol {rtol / 10:g} (balance error {run.looser_balance_error:.2e} at {rtol:g}): "
                 if np.isfinite(run.looser_balance_error) else "")
        return Verdict.INCONCLUSIVE, f"{again}{run.status}: {run.note}"
    if run.balance_error <= BALANCE * rtol:
        return Verdict.HOLDS, f"balance error {run.balance_error:.2e} <= {BALANCE * rtol:.0e}"
    change = (f"balance error {run.looser_balance_error:.2e} -> {run.balance_error:.2e} from rtol {rtol:g} to "
              f"{rtol / 10:g}")
    if not level(run, rtol):
        return Verdict.HOLDS, f"{change} with {run.method}: it follows the tolerance (integration error)"
    if not run.second_opinion:
        return Verdict.INCONCLUSIVE, f"{change} with {run.method}: level, not confirmed by a second method"
    return Verdict.VIOLATED, (f"{change} with {run.method} (and {run.second_opinion}): level, far above "
                              f"{BALANCE * rtol:.0e}")


def batch_finished(runs):
    """Whether the batch reached its horizon (a run past its law's barrier did, alone it would again)."""
    return all(r.finished or r.status == tracking.BARRIER for r in runs)


def study(ctx, key, forces=motion.generalized_forces):
    """The robustness study of a scene, once per run (shared): recipes, runs and their batches, load durations.
    Its wall-clock safety net is capped at 0.9 of what the check's budget has left: the study ends inside it."""
    s = settings_for(ctx)
    s = dataclasses.replace(s, max_seconds=min(s.max_seconds, 0.9 * ctx.budget.remaining()))

    def compute():
        moving = scene_of(key).trajectory.internal_motion
        durations = dict(s.scenes).get(key) or (s.traverses if moving else s.ramps)
        plants = tracking.PLANTS if moving else ("gre", "classical")  # Eq. (2) is the generalized one when Psi = 0
        horizon = s.start + max(durations) + s.settle
        recipes = [Recipe(key, law, plant, horizon=horizon, timing=(s.start, d))
                   for d in durations for plant in plants for law in s.laws]
        runs, batches = simulate_recipes(recipes, s, forces)
        return {"recipes": recipes, "runs": runs, "batches": batches, "durations": durations, "plants": plants,
                "moving": moving}

    return compute() if forces is not motion.generalized_forces else ctx.shared(("APP study", key), compute)


def _rate(recipe):
    """max_l sup_t sigma_max(f(Phidot_l(t))), the rate of change as Theorem 4 measures it, on 201 times across the
    loads' profiles (the smooth profiles peak in the middle, which is one of them)."""
    start, duration = recipe.timing
    _, theta_dot = recipe.spec().trajectory.theta(np.linspace(start, start + duration, 201))
    return float(np.abs(np.linalg.eigvalsh(pseudo_inertia(theta_dot))).max())


def _summary(recipe, run, batch):
    chain = recipe.chain()
    row = {"law": recipe.law, "plant": recipe.plant, "duration_s": recipe.timing[1] if recipe.timing else None,
           "status": run.status, "balance_error": run.balance_error, "rate": _rate(recipe)}
    if run.t is None or len(run.t) < 2:
        return row
    x = estimates.series(chain, run, batch)
    row.update(rms_tracking_error=float(np.sqrt(np.mean(x["tracking_error"] ** 2))),
               final_parameter_error=float(x["parameter_error"][-1]),
               min_lambda_min_f_hat=float(x["lambda_min_f_hat"].min()),
               min_lambda_min_M_hat=float(x["lambda_min_M_hat"].min()))
    return row


# -- APP-robustness -------------------------------------------------------------------------------

TABLE = (("scene", "scene"), ("law", "law"), ("plant", "plant"), ("load_s", "duration_s"), ("rate", "rate"),
         ("rms_e", "rms_tracking_error"), ("vs_gre", "vs_gre"), ("param_err", "final_parameter_error"),
         ("min_lmin_f", "min_lambda_min_f_hat"), ("min_lmin_M", "min_lambda_min_M_hat"), ("balance", "balance_error"))
LEGEND = ("load_s: duration of the payload ramp or the trolley's traverse; rate: max_l sup_t sigma_max(f(Phidot_l)); "
          "rms_e: RMS of |q - q_d| (rad); vs_gre: rms_e / (rms_e on gre) - 1; param_err: sum_l |f(Phi_hat_l - "
          "Phi_l)|_F / sum_l |f(Phi_l)|_F at the end; min_lmin_f: min_t,l lambda_min(f(Phi_hat_l)); min_lmin_M: "
          "min_t lambda_min(M(q(t), Theta_hat(t))); balance: max_t |V - V(0) - W| / max(max_t |V|, rtol E), E: the "
          "energy scale of W's tolerance")


def robustness_result(ctx, keys, forces=motion.generalized_forces):
    s = settings_for(ctx)
    rows, recipes, verdicts, unbalanced, figures, notes = [], [], [], [], {}, []
    for key in keys:
        st = study(ctx, key, forces)
        recipes += st["recipes"]
        summaries = [dict(_summary(r, run, b), scene=key)
                     for r, run, b in zip(st["recipes"], st["runs"], st["batches"])]
        gre = {(x["law"], x["duration_s"]): x.get("rms_tracking_error") for x in summaries if x["plant"] == "gre"}
        for x, run in zip(summaries, st["runs"]):
            ref = gre.get((x["law"], x["duration_s"]))
            x["vs_gre"] = (x["rms_tracking_error"] / ref - 1) if ref and "rms_tracking_error" in x else None
            verdict, why = balance_verdict(run, s.rtol)
            verdicts.append(verdict)
            if verdict != Verdict.HOLDS or run.balance_error > BALANCE * s.rtol:
                notes.append(f"{key} {x['law']} {x['plant']} {x['duration_s']:g} s: {why}")
            if verdict == Verdict.VIOLATED:
                unbalanced.append(x)
        notes += list(dict.fromkeys(f"{key}: {run.note}" for run in st["runs"] if run.status in tracking.NOT_STARTED))
        rows += summaries
        if not st["moving"]:
            notes.append(f"{key}: no pagilla runs: with Psi = 0 Eq. (2) with F = M(q, Thetadot) is the generalized "
                         "equation")
        for metric, label, log in (("rms_tracking_error", "RMS tracking error (rad)", True),
                                   ("final_parameter_error", "parameter error at the end (relative, f-norm)", False)):
            figures[f"{key}: {metric}"] = {"series": {
                "title": f"{key}: {label} against the load's duration", "x_label": "duration of the load (s)",
                "y_label": label, "x_log": True, "y_log": log,
                "lines": {f"{law}, {plant}": [[x["duration_s"], x.get(metric, np.nan)] for x in summaries
                                              if x["law"] == law and x["plant"] == plant]
                          for law in s.laws for plant in st["plants"]}}}
    table = [{name: _rounded(x.get(key)) for name, key in TABLE} for x in rows]
    verdict = combine(verdicts) if verdicts else Verdict.HOLDS
    singular = [found for found in (unsimulable(r.chain()) for r in {r.scene: r for r in recipes}.values()) if found]
    if verdict == Verdict.INCONCLUSIVE and singular:  # only unfinished runs, on a chain whose M(q) is singular
        verdict = Verdict.HOLDS
        notes.insert(0, singular[0][1])
    misled = _misled(rows)
    not_started = [x for x in rows if x["status"] in tracking.NOT_STARTED]
    summary = ("; ".join(misled) if misled else "no run finished" + (
        f" ({len(not_started)} of {len(rows)} not started: {not_started[0]['status']}, see the notes)"
        if not_started else "")) + (
        f"; {len(unbalanced)} runs do not close their Lyapunov balance" if unbalanced else "") + _unfinished(rows) + (
        f"; {singular[0][1]}" if verdict == Verdict.HOLDS and singular else "")
    evidence = {
        "table": table, "columns": LEGEND, "figures": figures, "notes": notes,
        **({"premises_failed": singular[0][0]} if singular else {}),
        "balance_tolerance": quantity(BALANCE * s.rtol, "tolerance",
                                      "largest Lyapunov balance error a resolved run may have (BALANCE x rtol)"),
        "worst_balance_error": quantity(max((x["balance_error"] for x in rows if np.isfinite(x["balance_error"])),
                                            default=np.nan), "residual",
                                        "max_t |V - V(0) - W| / max(max_t |V|, rtol E) over the runs"),
    }
    counterexample = None
    if unbalanced:
        worst = max(unbalanced, key=lambda x: x["balance_error"])
        recipe = recipes[rows.index(worst)]
        counterexample = {"kind": "adaptive-balance", "data": {"recipe": recipe.to_data(), "rtol": s.rtol,
                                                               "balance_error": worst["balance_error"]}}
    return Result("APP-robustness", verdict, summary, evidence, counterexample=counterexample)


def _unfinished(rows):
    """'; k of K runs did not finish (status: count, ...)' or ''."""
    statuses = [x["status"] for x in rows if x["status"] != "ok"]
    if not statuses:
        return ""
    counts = ", ".join(f"{status}: {statuses.count(status)}" for status in dict.fromkeys(statuses))
    return f"; {len(statuses)} of {len(rows)} runs did not finish ({counts}; no evidence either way, see the notes)"


def _rounded(x):
    return float(f"{x:.4g}") if isinstance(x, float) else x


def _misled(rows):
    """One phrase per scene and law: how far Eq. (1) and Eq. (2) put the RMS tracking error at the fastest load."""
    out = []
    for key in dict.fromkeys(x["scene"] for x in rows):
        for law in dict.fromkeys(x["law"] for x in rows if x["scene"] == key):
            mine = [x for x in rows if x["scene"] == key and x["law"] == law and x.get("vs_gre") is not None
                    and x["plant"] != "gre"]
            if not mine:
                continue
            fastest = min(x["duration_s"] for x in mine)
            parts = [f"{x['plant']} {x['vs_gre']:+.0%}" for x in mine if x["duration_s"] == fastest]
            out.append(f"{key}, {law}, {fastest:g} s load: RMS tracking error vs gre " + ", ".join(parts))
    return out


@check("APP-robustness", needs={"time_varying"})
def robustness(ctx):
    try:
        keys = list(scene_keys(ctx, settings_for(ctx).scenes))
    except ValueError as exc:
        return Result("APP-robustness", Verdict.INCONCLUSIVE, str(exc))
    return robustness_result(ctx, keys)


@replayer("adaptive-balance")
def replay_balance(data, ctx):
    """Simulate the saved run again at the saved tolerance (and a tenth of it) and judge its Lyapunov balance as the
    check does (balance_verdict)."""
    recipe = Recipe.from_data(data["recipe"])
    s = dataclasses.replace(settings_for(ctx), rtol=data["rtol"])
    (run,), _ = simulate_recipes([recipe], s)
    verdict, why = balance_verdict(run, s.rtol)
    return Result("APP-robustness", verdict, f"Lyapunov balance: {why} ({run.status}, {run.method})",
                  {"balance_error": quantity(run.balance_error, "residual")})


# -- APP-estimate-bounds ----------------------------------------------------------------------------

def qj_brackets(ctx, chain, key):
    """(inf_q sigma_min(QJ)^2, sup_q sigma_max(QJ)) brackets of the chain (shared by the checks of a run)."""
    def compute():
        kw = dict(samples=ctx.profile.samples, rounds=ctx.profile.rounds, progress=ctx.progress)
        name = stream_name(key)
        return (jacobian_normality(chain, rng=ctx.rng(f"{name}:APP gamma"), **kw),
                jacobian_sup(chain, rng=ctx.rng(f"{name}:APP sigma"), **kw))
    return ctx.shared(("APP QJ brackets", key), compute)


def bound_case(chain, run, q_samples, gamma, sigma, xi=None, zeta=None):
    """Theorems 2 and 3 along one run, with Definition 3 applied to its estimate.

    ``gamma`` is a certified lower bound of inf_q sigma_min(QJ)^2, ``sigma`` a certified upper bound of
    sup_q sigma_max(QJ); xi_hat and zeta_hat are the extremes of the spectra of f(Phi_hat_l) over the run's samples
    unless given (a test passes wrong ones); one below float's resolution is proved in rationals (:func:`_proved_xi`).
    Returns plain data: applicable, alpha1, alpha2, margins (relative to the largest eigenvalue of M_hat at that
    time, the lower one in its Jacobi scaling, :func:`_lower_margin`; > 0 holds), resolution and the witness of the
    smaller margin."""
    theta_hat = estimates.estimates(run)
    f = np.linalg.eigvalsh(pseudo_inertia(theta_hat))
    given, xi = xi is not None, float(f[..., 0].min()) if xi is None else xi
    zeta = float(f[..., -1].max()) if zeta is None else zeta
    resolution = eigh_resolution(chain.n + 4)
    out = {"xi_hat": xi, "zeta_hat": zeta, "samples": len(run.t), "status": run.status,
           "applicable": bool(xi > resolution * zeta), "resolution": resolution}
    if not out["applicable"] and not given and 0 < xi:  # below float's resolution: decide it in rationals
        proved = _proved_xi(theta_hat, f[..., 0], xi, resolution * zeta)
        if proved is not None:
            out.update(xi_hat=proved[0], applicable=True, xi_proof=proved[1])
            xi = proved[0]
    if not out["applicable"]:
        out["why"] = (f"Theta_hat is not uniformly consistent over the run: min lambda_min(f(Phi_hat_l)) = {xi:.3g} "
                      f"at t = {run.t[np.unravel_index(np.argmin(f[..., 0]), f.shape[:-1])[0]]:.4g}")
        return out
    q = np.concatenate([run.y[:, None, :chain.n], np.broadcast_to(q_samples, (len(run.t),) + q_samples.shape)], 1)
    mass = composite.mass_matrix(chain, q, theta_hat[:, None])
    low, high = estimates.mass_matrix_spectrum(mass)
    alpha1, alpha2 = formulas.alpha1(xi, max(gamma, 0.0)), formulas.alpha2(zeta, sigma)  # sigma = inf: unchecked
    scale = np.maximum(high.max(-1), alpha2 if np.isfinite(alpha2) else 0.0)
    lower, upper = _lower_margin(mass, alpha1), (alpha2 - high) / scale[:, None]
    margin = np.minimum(lower, upper)
    ti, qi = np.unravel_index(np.argmin(margin), margin.shape)
    out.update(alpha1=alpha1, alpha2=alpha2, lower_margin=float(lower.min()), upper_margin=float(upper.min()),
               inf_lambda_min_M_hat=float(low.min()), sup_lambda_max_M_hat=float(high.max()),
               tightness_lower=float(alpha1 / low.min()) if low.min() > 0 else np.nan,
               tightness_upper=float(high.max() / alpha2),
               witness={"t": float(run.t[ti]), "q": q[ti, qi].tolist(), "theta_hat": theta_hat[ti].tolist(),
                        "bound": "lower" if lower[ti, qi] <= upper[ti, qi] else "upper"},
               series={"t": run.t, "low": low.min(-1), "high": high.max(-1)})
    return out


def _lower_margin(mass, alpha1):
    """lambda_min(s (M - alpha1 1) s) / lambda_max(s M s) with s the Jacobi scaling of M by powers of two
    (:mod:`inertiaproof.dynamics.forward`): by Sylvester's law of inertia its sign is that of M - alpha1 1, and it
    is resolved to rounding of the scaled M, whose condition is that of M freed of its units (extreme_lengths:
    cond(M) 1e20, scaled 2.3), where lambda_min(M) itself is below rounding of lambda_max(M)."""
    s = jacobi_scaling(mass)
    outer = s[..., :, None] * s[..., None, :]
    shifted = np.linalg.eigvalsh((mass - alpha1 * np.eye(mass.shape[-1])) * outer)[..., 0]
    return shifted / np.linalg.eigvalsh(mass * outer)[..., -1]


def _proved_xi(theta_hat, lambda_min, xi, error):
    """(x, how) with 0 < x <= lambda_min(f(Phi_hat_l(t_k))) for every sample k and body l: proved in rational
    arithmetic (:func:`_exceeds`) wherever the float eigenvalue lambda_min, within ``error``, does not show it.
    x is 15/16 or 1/2 of the float minimum xi; None if neither is proved."""
    for x in (xi * 15 / 16, xi / 2):
        unresolved = np.argwhere(lambda_min < x + error)
        if all(_exceeds(theta_hat[tuple(i)], x) for i in unresolved):
            return x, (f"{len(unresolved)} of {lambda_min.size} samples x bodies below float resolution: "
                       f"f(Phi_hat) - {x:.4g} 1 proved positive definite in rational arithmetic")
    return None


def _exceeds(phi, x):
    """Whether f(phi) - x 1 is positive definite (DefTrafoInertialParameters), by its minors in exact rationals
    (:func:`inertiaproof.model.exact.definiteness`)."""
    x = Fraction(x)
    shifted = [[e - x if i == j else e for j, e in enumerate(row)] for i, row in enumerate(pseudo_exact(phi))]
    return definiteness(integer_matrix(shifted))[0] == "pd"


def estimate_bounds_result(ctx, keys, gamma_override=None, sigma_override=None, xi_override=None):
    """APP-estimate-bounds on the GRE runs of the scenes' studies; the overrides feed wrong inputs (tests).
    A QJ bracket whose certified side lies beyond the value attained at its witness (an inverted bracket) refutes
    the certificate the constants rest on: VIOLATED whatever the runs show, with a "bound-bracket" counterexample
    (checks.normality.bracket_refuted)."""
    s = settings_for(ctx)
    cases, verdicts, figures, brackets = {}, [], {}, {}
    violation, refuted = None, []
    for key in keys:
        st = study(ctx, key)
        scene = scene_of(key)
        chain = scene.chain
        stiff = [(r, run) for r, run in zip(st["recipes"], st["runs"])
                 if r.plant == "gre" and run.status in tracking.NOT_STARTED]
        if stiff and len(stiff) == sum(r.plant == "gre" for r in st["recipes"]):  # no run to check: no brackets
            for recipe, run in stiff:
                cases[f"{key}, {recipe.law}, {recipe.timing[1]:g} s load"] = {
                    "status": run.status, "applicable": False, "why": run.note}
            continue
        gamma_b, sigma_b = qj_brackets(ctx, chain, key)
        found = refutations("APP-estimate-bounds", [(scene, gamma_b, unit_bodies(chain)[None], "lmin"),
                                                    (scene, sigma_b, unit_bodies(chain)[None], "lmax", True)])
        verdicts += [f[0] for f in found]
        refuted += found
        gamma = gamma_b.lower if gamma_override is None else gamma_override
        sigma = sigma_b.upper if sigma_override is None else sigma_override
        brackets[key] = {
            "inf_sigma_min_QJ_sq": bracket_evidence(gamma_b)["lower"],
            "inf_sigma_min_QJ_sq_observed": quantity(gamma_b.upper, "sampled", "attained at a witness"),
            "sup_sigma_max_QJ": bracket_evidence(sigma_b)["upper"],
            "sup_sigma_max_QJ_observed": quantity(sigma_b.lower, "sampled", "attained at a witness")}
        drawn = estimates.configurations(chain, s.configurations, ctx.rng(f"{stream_name(key)}:APP q"))
        q_samples = np.concatenate([drawn, np.atleast_2d(gamma_b.witness), np.atleast_2d(sigma_b.witness)])
        for recipe, run, batch in zip(st["recipes"], st["runs"], st["batches"]):
            if recipe.plant != "gre" or run.t is None:
                continue
            name = f"{key}, {recipe.law}, {recipe.timing[1]:g} s load"
            if run.status in tracking.NOT_STARTED:  # only its initial sample: nothing to check along a run
                cases[name] = {"status": run.status, "applicable": False, "why": run.note}
                continue
            xi = None if xi_override is None else xi_override(recipe, run, batch)
            case = bound_case(chain, run, q_samples, gamma, sigma, xi=xi)
            series = case.pop("series", None)
            cases[name] = case
            if not case["applicable"]:
                continue
            margin = min(case["lower_margin"], case["upper_margin"])
            if not run.finished and (margin < -case["resolution"] or run.status == tracking.CLOCK):
                verdicts.append(Verdict.INCONCLUSIVE)  # a prefix may support the bounds (counted), never refute
                case["unfinished"] = f"{run.status}: {run.note}"
            elif margin < -case["resolution"]:
                verdicts.append(Verdict.VIOLATED)
                if violation is None:
                    violation = {"kind": "estimate-bound", "data": {
                        "recipe": recipe.to_data(), "rtol": s.rtol, "samples": len(run.t), **case["witness"],
                        "gamma": gamma, "sigma": sigma, "xi_hat": case["xi_hat"], "zeta_hat": case["zeta_hat"]}}
            else:
                verdicts.append(Verdict.HOLDS)
            if series is not None and recipe.law == "natural" and recipe.timing[1] == min(st["durations"]):
                figures[name] = {"series": {
                    "title": f"{name}: the estimated mass matrix against Theorems 2 and 3", "x_label": "t (s)",
                    "y_label": "eigenvalue", "y_log": True, "lines": {
                        "sampled inf_q lambda_min(M(q, Theta_hat(t)))": np.c_[series["t"], series["low"]].tolist(),
                        "alpha1 = xi_hat gamma": [[series["t"][0], case["alpha1"]], [series["t"][-1], case["alpha1"]]],
                        "sampled sup_q lambda_max(M(q, Theta_hat(t)))": np.c_[series["t"], series["high"]].tolist(),
                        "alpha2 = 2 zeta_hat sigma^2": [[series["t"][0], case["alpha2"]],
                                                        [series["t"][-1], case["alpha2"]]]}}}
    applicable = [c for c in cases.values() if c["applicable"]]
    rows = {name: _case_row(c) for name, c in cases.items()}
    if not verdicts:
        verdicts = [Verdict.INCONCLUSIVE]
    verdict = combine(verdicts)
    lead = next((f for f in refuted if f[0] == Verdict.VIOLATED), refuted[0] if refuted else None)
    if lead is not None and lead[3] is not None:  # the refuted certificate before any run's margin
        violation = lead[3]
    worst = min(applicable, key=lambda c: min(c["lower_margin"], c["upper_margin"])) if applicable else None
    natural = [c for name, c in cases.items() if ", natural," in name]
    stiff = [c for c in cases.values() if c["status"] in tracking.NOT_STARTED]
    first = next(iter(cases.values()), {})
    summary = (f"{len(applicable)} of {len(cases)} runs uniformly consistent ({sum(c['applicable'] for c in natural)} "
               f"of the natural law's {len(natural)}): "
               + (f"smallest relative margin {min(worst['lower_margin'], worst['upper_margin']):.3g} "
                  f"(tightness alpha1 / inf lambda_min {worst['tightness_lower']:.2g}, "
                  f"sup lambda_max / alpha2 {worst['tightness_upper']:.2g})" if worst else
                  "no run to check" + (f" ({first['why']})" if "why" in first else ""))
               + (f"; {len(stiff)} runs {stiff[0]['status']}, {stiff[0]['why']}" if stiff else "")
               + _unfinished([c for c in cases.values() if c["status"] not in tracking.NOT_STARTED]))
    if lead is not None:
        summary = f"{lead[1]}; {summary}"
    evidence = {"runs": rows, "qj_brackets": brackets, "figures": figures,
                "smallest_margin": quantity(min((min(c["lower_margin"], c["upper_margin"]) for c in applicable),
                                                default=np.nan), "margin",
                                            "min over the consistent runs, times and sampled q (> 0 holds)"),
                "resolution": quantity(eigh_resolution(max(scene_of(k).chain.n for k in keys) + 4), "tolerance",
                                       "rounding of the eigenvalues against the largest one"),
                "note": "Margins are relative to the largest eigenvalue of M_hat at that time (the lower one in "
                        "M_hat's Jacobi scaling, where it is resolved whatever the units); the extremes over q "
                        "are sampled (the run's configurations, random ones and the brackets' witnesses): a sampled "
                        "inf is an upper estimate, so a negative margin is a true violation, a positive one is not "
                        "a proof."}
    if refuted:
        evidence["refuted_certificates"] = {f[1]: f[2] for f in refuted}
    return Result("APP-estimate-bounds", verdict, summary, evidence,
                  counterexample=violation if verdict == Verdict.VIOLATED else None)


def _case_row(case):
    """One run of APP-estimate-bounds as a flat row of the evidence table."""
    keys = ("status", "xi_hat", "xi_proof", "zeta_hat", "alpha1", "inf_lambda_min_M_hat", "sup_lambda_max_M_hat",
            "alpha2", "unfinished")
    row = {k: _rounded(case[k]) for k in keys if k in case}
    if case["applicable"]:
        row["margin"] = _rounded(min(case["lower_margin"], case["upper_margin"]))
    else:
        row["why"] = case["why"]
    return row


@check("APP-estimate-bounds", needs={"chain"})
def estimate_bounds(ctx):
    try:
        keys = list(scene_keys(ctx, settings_for(ctx).scenes))
    except ValueError as exc:
        return Result("APP-estimate-bounds", Verdict.INCONCLUSIVE, str(exc))
    return estimate_bounds_result(ctx, keys)


@replayer("estimate-bound")
def replay_bound(data, ctx):
    """Recompute M(q, Theta_hat) at the saved configuration and estimate against the saved constants, and the run."""
    recipe = Recipe.from_data(data["recipe"])
    chain = recipe.chain()
    s = dataclasses.replace(settings_for(ctx), rtol=data["rtol"])
    (run,), _ = simulate_recipes([recipe], s)
    case = bound_case(chain, run, np.atleast_2d(data["q"]), data["gamma"], data["sigma"], xi=data["xi_hat"],
                      zeta=data["zeta_hat"])
    mass = composite.mass_matrix(chain, np.asarray(data["q"]), np.asarray(data["theta_hat"]))
    low, high = estimates.mass_matrix_spectrum(mass)
    alpha1, alpha2 = data["xi_hat"] * max(data["gamma"], 0.0), 2 * data["zeta_hat"] * data["sigma"] ** 2
    point = min(_lower_margin(mass, alpha1), (alpha2 - high) / max(high, alpha2))
    margin = min(point, case.get("lower_margin", np.inf), case.get("upper_margin", np.inf))
    verdict = Verdict.VIOLATED if margin < -eigh_resolution(chain.n + 4) else Verdict.HOLDS
    return Result("APP-estimate-bounds", verdict, f"relative margin {margin:.3g} at t = {data['t']:g}",
                  {"lambda_min": float(low), "lambda_max": float(high), "alpha1": alpha1, "alpha2": alpha2})
