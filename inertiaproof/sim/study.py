"""Error against run time, and stability, of simulating a scene with SciPy's solve_ivp methods.

For each method and relative tolerance one closed-loop run
(:mod:`inertiaproof.sim.simulate`) gives a point (seconds, error): the error is
the largest deviation of q from a tight-tolerance reference run, relative to
the range q sweeps. Independently of any reference, every run carries the
power-balance residual that Prop1 implies (inertiaproof.dynamics.energy).

Besides the statuses of inertiaproof.sim.simulate, a row may read ``not run`` (the
method already failed at a looser tolerance), ``clock`` (not run: the check's time is
spent) or ``ill-conditioned`` (cond(M) beyond 1e-6 / eps at the home posture: forward
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
    "BALANCE_FLOOR", "cheapest", "classify", "EPS", "LOST_ENERGY", "REFERENCE_BALANCE", "REPEAT_BELOW", "STIFF",
    "Study", "study", "StudySettings", "substitute_reference", "trajectory_error", "WRONG_ENERGY",
]

EPS = np.finfo(float).eps
BALANCE_FLOOR = 1e3 * EPS  # round-off of the relative balance E - E0 - W
WRONG_ENERGY = 1e3  # a finished run whose balance residual exceeds this many rtol has the wrong energy
REFERENCE_BALANCE = 1e2  # the reference run (DOP853 or Radau) must keep the balance within this many rtol
REPEAT_BELOW = 5.0  # seconds: shorter runs are repeated for a median time; longer ones average their own noise
LOST_ENERGY = 1e-2  # a run that loses or gains more than this share of the energy in play is wrong at any rtol
STIFF = 1e4  # fastest closed-loop rate x horizon above which the reference run uses an implicit method


@dataclass(frozen=True)
class StudySettings:
    methods: tuple = simulate.METHODS
    tolerances: tuple = (1e-6,)
    reference_rtol: float = 1e-10
    reference_method: str = "DOP853"
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
        return [{"scene": self.scene, "method": r.method, "rtol": r.rtol, "seconds": r.seconds, "error": e,
                 "balance_error": r.balance_error, "steps": r.steps, "evaluations": r.evaluations,
                 "status": r.status, "note": r.note} for r, e in self.runs]

    def stability_rows(self):
        return [{"scene": self.scene, "method": r.method, "rtol": r.rtol, "status": r.status, "seconds": r.seconds,
                 "steps": r.steps, "evaluations": r.evaluations, "note": r.note} for r, _ in self.runs]

    def balance_verdict(self):
        """(verdict, coarse residual, reference residual, why) from the reference method's runs.

        HOLDS: some run of the reference method at a tolerance at least 10x below the loosest one (the reference
        run first, then the others, tightest first) keeps its residual within REFERENCE_BALANCE x its rtol, below
        the loosest run's: the balance follows the tolerance down to that run's resolution (said in the reason;
        a reference at a still tighter rtol may level off at the round-off of the dynamics).
        VIOLATED: the reference run's residual is far beyond that and did not fall by more than a factor 3: no
        tolerance removes it; but INCONCLUSIVE if a run of the reference method was stopped by the wall clock
        (status ``clock``: machine-dependent), which might have shown the residual falling.
        """
        ref = self.reference
        same = [r for r, _ in self.runs if r.method == ref.method and r.finished]
        if not ref.finished or not [r for r in same if r.rtol > 10 * ref.rtol]:
            why = (f"the reference run ({ref.method}, rtol {ref.rtol:g}) ended as '{ref.status}': {ref.note}"
                   if not ref.finished else "no finished run of the reference method at a looser tolerance")
            return Verdict.INCONCLUSIVE, None, ref.balance_error, why
        loose = max(same, key=lambda r: r.rtol)
        b_coarse, b_ref = loose.balance_error, ref.balance_error
        change = f"rtol {loose.rtol:g} -> {ref.rtol:g}: residual {b_coarse:.2e} -> {b_ref:.2e}"
        tighter = sorted((r for r in same if r.rtol <= loose.rtol / 10), key=lambda r: r.rtol)
        for run in [ref, *tighter]:
            allowed = max(REFERENCE_BALANCE * run.rtol, BALANCE_FLOOR)
            b = run.balance_error
            if b <= allowed and (b < b_coarse or b <= BALANCE_FLOOR):
                if run is ref:
                    return Verdict.HOLDS, b_coarse, b_ref, f"{change} (<= {allowed:.0e} allowed)"
                return Verdict.HOLDS, b_coarse, b, (
                    f"rtol {loose.rtol:g} -> {run.rtol:g}: residual {b_coarse:.2e} -> {b:.2e} (<= {allowed:.0e} "
                    f"allowed): the balance holds to {b:.1e} of the energy in play; the reference at rtol "
                    f"{ref.rtol:g} levels off at {b_ref:.2e}, beyond {REFERENCE_BALANCE:g} x its rtol")
        allowed = max(REFERENCE_BALANCE * ref.rtol, BALANCE_FLOOR)
        if b_ref > allowed and b_ref > 0.3 * b_coarse and b_ref > 100 * BALANCE_FLOOR:
            clocked = [r for r, _ in self.runs if r.method == ref.method and r.status == simulate.CLOCK]
            if clocked:
                return Verdict.INCONCLUSIVE, b_coarse, b_ref, (f"{change}: level, but {len(clocked)} runs of "
                                                              f"{ref.method} were stopped by the wall clock (no "
                                                              "evidence)")
            return Verdict.VIOLATED, b_coarse, b_ref, (f"{change}: it stays far above {allowed:.0e}, so the simulated "
                                                      "equation breaks the power balance of Prop1")
        return Verdict.INCONCLUSIVE, b_coarse, b_ref, f"{change}: neither clearly at the tolerance nor level"


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
    method = settings.reference_method if rate * horizon <= STIFF else "Radau"
    out = Study(scene.name, horizon, None, rate)
    condition = simulate.conditioning(scene.chain, scene.trajectory, system.control, (t0, t0 + horizon))
    if condition > simulate.MAX_CONDITION:
        note = f"cond(M) = {condition:.1e} at home: forward dynamics keeps fewer than 6 digits in float64; not run"
        progress(note)
        out.reference = simulate.Run(method, settings.reference_rtol, "ill-conditioned", 0.0, 0, 0, note)
        out.runs = [(simulate.Run(m, rtol, "ill-conditioned", 0.0, 0, 0, note), None)
                    for m in settings.methods for rtol in settings.tolerances]
        return out
    progress(f"reference: {method} at rtol {settings.reference_rtol:g} over {horizon:g} s "
             f"(fastest closed-loop mode {rate:.3g} rad/s)")
    out.reference = classify(simulate.simulate(system, horizon, method, settings.reference_rtol, **reference_budget,
                                               max_seconds=budget.capped(settings.max_seconds * 3)))
    if not out.reference.finished and method != "Radau" and not budget.expired:
        progress(f"reference {method} {out.reference.status}; trying Radau")
        out.reference = classify(simulate.simulate(system, horizon, "Radau", settings.reference_rtol,
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
            runs = []
            while len(runs) < max(1, settings.repeats) and (not runs or runs[0].seconds < REPEAT_BELOW):
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
