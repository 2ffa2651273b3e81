"""Error against run time, and stability, of simulating a scene with SciPy's solve_ivp methods.

For each method and relative tolerance one closed-loop run
(:mod:`inertiaproof.sim.simulate`) gives a point (seconds, error): the error is
the largest deviation of q from a tight-tolerance reference run, relative to
the range q sweeps. Independently of any reference, every run carries the
power-balance residual that Prop1 implies (inertiaproof.dynamics.energy).

Besides the statuses of inertiaproof.sim.simulate, a row may read ``not run`` (the
method already failed at a looser tolerance), ``clock`` (not run: the check's time is
spent) or ``ill-conditioned`` (scaled cond(M) beyond 1e-6 / eps at the home posture: forward
dynamics cannot be trusted in float64, so nothing is run).

The balance also yields a verdict: integrating a correct equation more
tightly drives the residual down (to round-off); an equation inconsistent
with Prop1's balance (a wrong term) leaves a residual that no tolerance
removes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from inertiaproof.budget import UNLIMITED
from inertiaproof.dynamics import motion
from inertiaproof.result import Verdict

from . import simulate
from .control import controller

__all__ = [
    "AT_ROUND_OFF", "BALANCE_FLOOR", "balance_rule", "beyond_budget", "cheapest", "classify", "COVER", "EPS",
    "EXPLICIT", "FAR_ABOVE", "IMPLICIT", "least_evaluations", "LEVEL_ORDER", "LOST_ENERGY", "PREDICTED_BEYOND",
    "REPEAT_BELOW", "residual_order", "round_off", "STIFF", "Study", "study", "StudySettings", "substitute_reference",
    "trajectory_error", "WRONG_ENERGY",
]

EPS = np.finfo(float).eps
BALANCE_FLOOR = 1e3 * EPS  # round-off of the relative balance E - E0 - W
WRONG_ENERGY = 1e3  # a finished run whose balance residual exceeds this many rtol has the wrong energy
COVER = 2  # decades of rtol the reference method's finished runs must span (and the tail judged level or falling)
LEVEL_ORDER = 0.25  # an observed order of the residual in rtol below this is level (falls < 3x over two decades)
AT_ROUND_OFF = 10.0  # a residual within this many round-off estimates has reached round-off
FAR_ABOVE = 1e3  # a level residual beyond this many round-off estimates in every run is a wrong term
REPEAT_BELOW = 5.0  # seconds: shorter runs are repeated for a median time; longer ones average their own noise
LOST_ENERGY = 1e-2  # a run that loses or gains more than this share of the energy in play is wrong at any rtol
STIFF = 1e4  # fastest closed-loop rate x horizon above which the reference run uses an implicit method
EXPLICIT, least_evaluations = simulate.EXPLICIT, simulate.least_evaluations
IMPLICIT = ("Radau", "BDF", "LSODA")  # LSODA switches to BDF when it detects stiffness
PREDICTED_BEYOND = 10.0  # an explicit run is not started when it would need this many times its budget


@dataclass(frozen=True)
class StudySettings:
    methods: tuple = simulate.METHODS
    tolerances: tuple = (1e-6,)
    reference_rtol: float = 1e-10
    reference_method: str = "DOP853"
    stiff_method: str = "Radau"  # the reference's method when rate x horizon > STIFF (implicit; BDF selectable)
    horizon: float | None = None  # default: the scene's
    samples: int = 101
    max_evaluations: int = 5_000  # per run (the reference gets three times as many); deterministic
    max_seconds: float = 120.0  # a safety net only: runs stopped by it depend on the machine
    repeats: int = 1  # runs per point (if shorter than REPEAT_BELOW); the median time is kept
    give_up: bool = True  # a method that failed at a looser tolerance is not run at tighter ones


@dataclass
class Study:
    scene: str
    horizon: float
    reference: simulate.Run | None
    fastest_rate: float = np.nan  # rad/s, the closed loop's fastest mode at home
    runs: list = field(default_factory=list)  # (Run, error)
    substitute: simulate.Run | None = None  # the run errors are measured against when the reference failed

    def work_precision_rows(self):
        """One row per run: error against seconds and counted work (right-hand sides, Jacobians, LU factorizations);
        ``predicted``: the right-hand sides an explicit method not started would have needed (else None)."""
        return [{"scene": self.scene, "method": r.method, "rtol": r.rtol, "seconds": r.seconds, "error": e,
                 "balance_error": r.balance_error, "steps": r.steps, "evaluations": r.evaluations,
                 "jacobians": r.jacobians, "lus": r.lus, "work": r.work, "predicted": r.predicted,
                 "implicit": r.method in IMPLICIT, "status": r.status, "note": r.note} for r, e in self.runs]

    def stability_rows(self):
        return [{"scene": self.scene, "method": r.method, "rtol": r.rtol, "status": r.status, "seconds": r.seconds,
                 "steps": r.steps, "evaluations": r.evaluations, "note": r.note} for r, _ in self.runs]

    def balance_verdict(self):
        """(verdict, coarse residual, reference residual, why): the power balance of Prop1, d/dt (T_q + U) = supplied
        power ((KineticEnergy), (PotentialEnergy) along (RoboticEquation)), judged by the residual's observed order
        across tolerances (:func:`balance_rule`) over the finished runs of the reference method."""
        ref = self.reference
        if not ref.finished:
            return Verdict.INCONCLUSIVE, None, ref.balance_error, (
                f"the reference run ({ref.method}, rtol {ref.rtol:g}) ended as '{ref.status}': {ref.note}")
        same = [r for r, _ in self.runs if r.method == ref.method and r.finished and r.rtol != ref.rtol] + [ref]
        finished = [r for r, _ in self.runs if r.finished] + [ref]
        clocked = sum(r.method == ref.method and r.status == simulate.CLOCK for r, _ in self.runs)
        verdict, why = balance_rule(same, finished, clocked)
        return verdict, max(same, key=lambda r: r.rtol).balance_error, ref.balance_error, why


def round_off(run):
    """An upper estimate of the round-off in a run's relative balance residual: eps per right-hand side (each step
    adds a relative eps to the state, hence to E and W), at least BALANCE_FLOOR."""
    return max(BALANCE_FLOOR, EPS * run.evaluations)


def residual_order(runs):
    """Least-squares slope of log(balance residual) against log(rtol): how the residual falls with the tolerance
    (about 1 for integration error, 0 for a residual that no tolerance removes)."""
    rtol = np.log([r.rtol for r in runs])
    residual = np.log(np.maximum([r.balance_error for r in runs], np.finfo(float).tiny))
    return float(np.polyfit(rtol, residual, 1)[0])


def balance_rule(same, finished, clocked=0):
    """(verdict, why) from ``same`` (finished runs of one method at several tolerances), ``finished`` (every finished
    run of the study, any method) and ``clocked`` (runs of that method stopped by the wall clock).

    A correct equation's residual is integration error: it falls with the tolerance until round-off; a wrong term
    leaves a residual at its own size, the same for every method and tolerance. So:
    INCONCLUSIVE when the runs of ``same`` do not cover COVER decades of rtol (named);
    HOLDS when some finished run's residual is within AT_ROUND_OFF of its round-off estimate (:func:`round_off`);
    VIOLATED when over the tightest COVER decades of ``same`` the residual is level (observed order < LEVEL_ORDER)
    and every finished run stays beyond FAR_ABOVE round-off estimates (INCONCLUSIVE instead if runs of the method
    were stopped by the wall clock: machine-dependent, they might have shown it falling);
    HOLDS when the residual falls with order >= LEVEL_ORDER (over the tail, or over all tolerances before it
    levels off within FAR_ABOVE round-off estimates); else INCONCLUSIVE: level from the loosest tolerance at a
    size between AT_ROUND_OFF and FAR_ABOVE round-off estimates.
    """
    same = sorted(same, key=lambda r: -r.rtol)
    method, tight = same[-1].method, same[-1].rtol
    covered = f"{method} finished at rtol {', '.join(f'{r.rtol:g}' for r in same)}"
    if same[0].rtol < 0.99 * 10**COVER * tight:
        return Verdict.INCONCLUSIVE, (f"{covered}: the rule needs runs of one method over {COVER} decades of rtol "
                                      "to see whether the residual falls with the tolerance")
    best = min(finished, key=lambda r: r.balance_error)
    level_at, floor = best.balance_error, round_off(best)
    if level_at <= AT_ROUND_OFF * floor:
        return Verdict.HOLDS, (f"the residual reaches round-off: {level_at:.2e} ({best.method}, rtol {best.rtol:g}), "
                               f"within {AT_ROUND_OFF:g} x the estimate {floor:.1e}; {_falls(same)}")
    anchor = min(r.rtol for r in same if r.rtol >= 0.99 * 10**COVER * tight)
    tail = [r for r in same if r.rtol <= anchor]
    tail_order, order = residual_order(tail), residual_order(same)
    trend = (f"{_falls(same)}; over rtol {anchor:g} -> {tight:g} order {tail_order:.2f}; smallest residual "
             f"{level_at:.2e} ({best.method}, rtol {best.rtol:g}) = {level_at / floor:.0f} x its round-off estimate")
    if tail_order < LEVEL_ORDER and level_at > FAR_ABOVE * floor:
        if clocked:
            return Verdict.INCONCLUSIVE, (f"{trend}: level, but {clocked} runs of {method} were stopped by the "
                                          "wall clock (no evidence)")
        return Verdict.VIOLATED, (f"{trend}: level far above round-off in every run, so the simulated equation "
                                  "breaks the power balance of Prop1")
    if tail_order >= LEVEL_ORDER:
        return Verdict.HOLDS, f"{trend}: the residual follows the tolerance (integration error)"
    if order >= LEVEL_ORDER:
        return Verdict.HOLDS, (f"{trend}: it follows the tolerance, then levels off within {FAR_ABOVE:g} round-off "
                               "estimates")
    return Verdict.INCONCLUSIVE, (f"{trend}: level at every tolerance, between {AT_ROUND_OFF:g} and {FAR_ABOVE:g} "
                                  "round-off estimates: too close to round-off to call")


def _falls(runs):
    """How the residual falls over ``runs`` (sorted loosest first): endpoints and observed order."""
    return (f"{runs[0].method} rtol {runs[0].rtol:g} -> {runs[-1].rtol:g}: residual {runs[0].balance_error:.2e} -> "
            f"{runs[-1].balance_error:.2e} (observed order {residual_order(runs):.2f} over {len(runs)} tolerances)")


def trajectory_error(run, reference, n):
    """max_t ||q - q_ref||_inf over the range q_ref sweeps."""
    q, q_ref = run.y[:, :n], reference.y[:, :n]
    sweep = max(float(np.ptp(q_ref, axis=0).max()), float(np.abs(q_ref).max()) * EPS, np.finfo(float).tiny)
    return float(np.abs(q - q_ref).max() / sweep)


def classify(run):
    """Mark a finished run as 'wrong energy' when its balance residual is far beyond its tolerance
    (WRONG_ENERGY x rtol) or beyond LOST_ENERGY of the energy in play whatever the tolerance."""
    allowed = max(min(WRONG_ENERGY * run.rtol, LOST_ENERGY), 100 * BALANCE_FLOOR)
    if run.status == "ok" and run.balance_error > allowed:
        run.status = "wrong energy"
        run.note = f"power-balance residual {run.balance_error:.2e} > {allowed:.0e} allowed at rtol {run.rtol:g}"
    return run


def study(scene, settings=StudySettings(), forces=motion.generalized_forces, progress=lambda message: None,
          budget=UNLIMITED):
    """Reference run, then every method at every tolerance; see :class:`Study`. Runs end as ``clock`` when the
    ``budget``'s time is up (a safety net; those not started too); ``budget`` is the counted limit of evaluations."""
    system = simulate.System(scene.chain, scene.trajectory,
                             controller(scene.chain, scene.trajectory, scene.control), forces)
    horizon = settings.horizon or scene.horizon()
    n = scene.chain.n
    reference_budget = dict(samples=settings.samples, max_evaluations=settings.max_evaluations * 3)
    t0 = scene.trajectory.span[0]
    rate = simulate.fastest_rate(scene.chain, scene.trajectory, system.control, (t0, t0 + horizon))
    stiff = rate * horizon > STIFF
    method = settings.stiff_method if stiff else settings.reference_method
    out = Study(scene.name, horizon, None, rate)
    condition = simulate.conditioning(scene.chain, scene.trajectory, system.control, (t0, t0 + horizon))
    if condition > simulate.MAX_CONDITION:
        note = (f"scaled cond(M) = {condition:.1e} at home: forward dynamics keeps fewer than 6 digits in float64; "
                "not run")
        progress(note)
        out.reference = simulate.Run(method, settings.reference_rtol, "ill-conditioned", 0.0, 0, 0, note)
        out.runs = [(simulate.Run(m, rtol, "ill-conditioned", 0.0, 0, 0, note), None)
                    for m in settings.methods for rtol in settings.tolerances]
        return out
    progress(f"reference: {method} at rtol {settings.reference_rtol:g} over {horizon:g} s "
             f"(fastest closed-loop mode {rate:.3g} rad/s)")
    out.reference = classify(simulate.simulate(system, horizon, method, settings.reference_rtol, **reference_budget,
                                               max_seconds=budget.capped(settings.max_seconds * 3)))
    if not out.reference.finished and method != settings.stiff_method and not budget.expired:
        progress(f"reference {method} {out.reference.status}; trying {settings.stiff_method}")
        out.reference = classify(simulate.simulate(system, horizon, settings.stiff_method, settings.reference_rtol,
                                                   **reference_budget,
                                                   max_seconds=budget.capped(settings.max_seconds * 3)))
    reference = out.reference
    for method in settings.methods:
        failed = None
        for rtol in sorted(settings.tolerances, reverse=True):
            if budget.expired:
                why = f"not run: the time budget ({budget.describe()}) is spent (a machine-dependent stop)"
                out.runs.append((simulate.Run(method, rtol, simulate.CLOCK, 0.0, 0, 0, why), None))
                continue
            if failed is not None and settings.give_up:
                why = f"{failed.status} at the looser rtol {failed.rtol:g}"
                out.runs.append((simulate.Run(method, rtol, "not run", 0.0, 0, 0, why), None))
                continue
            predicted = beyond_budget(method, rtol, rate, horizon, settings) if stiff else None
            runs = [predicted] if predicted else []
            while not predicted and len(runs) < max(1, settings.repeats) and (not runs or
                                                                               runs[0].seconds < REPEAT_BELOW):
                runs.append(classify(simulate.simulate(system, horizon, method, rtol, samples=settings.samples,
                                                       max_evaluations=settings.max_evaluations,
                                                       max_seconds=budget.capped(settings.max_seconds))))
            run = sorted(runs, key=lambda r: r.seconds)[len(runs) // 2]
            if not run.finished:
                failed = run
            error = trajectory_error(run, reference, n) if run.finished and reference.finished else None
            progress(f"{method} rtol {rtol:g}: {run.status}, {run.seconds:.2f} s, error "
                     f"{'-' if error is None else f'{error:.1e}'}")
            out.runs.append((run, error))
    if not reference.finished:
        out.runs, out.substitute = substitute_reference(out.runs, n)
        if out.substitute is not None:
            progress(f"errors against the tightest finished run instead: {out.substitute.method} "
                     f"rtol {out.substitute.rtol:g}")
    return out


def beyond_budget(method, rtol, rate, horizon, settings):
    """A ``budget`` Run without running it when the stiffness estimate says the method would need more than
    PREDICTED_BEYOND x its budget of right-hand sides (a count, like the budget itself); else None."""
    need = least_evaluations(method, rate, horizon)
    if need <= PREDICTED_BEYOND * settings.max_evaluations:
        return None
    return simulate.Run(method, rtol, "budget", 0.0, 0, 0, (
        f"not run: the fastest closed-loop mode ({rate:.3g} rad/s) keeps {method} stable only with at least "
        f"{need:.2g} right-hand sides over {horizon:g} s, more than {PREDICTED_BEYOND:g} x its budget "
        f"{settings.max_evaluations}"), predicted=float(need))


def substitute_reference(runs, n):
    """When the reference run failed: errors against the tightest finished run (its own error is then 0 by
    construction, and every error is only an estimate relative to it)."""
    finished = [r for r, _ in runs if r.status == "ok"]
    if not finished:
        return runs, None
    best = min(finished, key=lambda r: (r.rtol, r.balance_error))
    return [(r, trajectory_error(r, best, n) if r.finished else None) for r, _ in runs], best


def cheapest(rows, error, scene=None, cost="seconds"):
    """The method reaching ``error`` at the least ``cost`` ("seconds", or "evaluations": right-hand sides, a
    machine-independent count) among finished rows: (method, cost) or None.

    Between two tolerances of one method the cost is interpolated log-log at the wanted error.
    """
    best = None
    by_method = {}
    for row in rows:
        if (scene is None or row["scene"] == scene) and row["status"] in ("ok", "wrong energy") and row["error"]:
            by_method.setdefault(row["method"], []).append((row["error"], row[cost]))
    for method, points in by_method.items():
        points.sort()
        seconds = _time_at(points, error)
        if seconds is not None and (best is None or seconds < best[1]):
            best = (method, seconds)
    return best


def _time_at(points, error):
    """Seconds to reach ``error`` along (error, seconds) points sorted by error; None if never reached."""
    reached = [(e, s) for e, s in points if e <= error]
    if not reached:
        return None
    e_lo, s_lo = max(reached)
    above = [(e, s) for e, s in points if e > error]
    if not above:
        return s_lo
    e_hi, s_hi = min(above)
    if e_lo <= 0 or s_lo <= 0 or s_hi <= 0:
        return s_lo
    w = np.log(error / e_lo) / np.log(e_hi / e_lo)
    return float(np.exp((1 - w) * np.log(s_lo) + w * np.log(s_hi)))
