"""Beyond the paper: ``APP-euclidean-escape``, a Hypothesis hunt for a Slotine-Li run (Euclidean gradient) whose
M(q, Theta_hat) turns indefinite, i.e. Theta_hat left the consistent set far enough to lose the lower bound; the
natural law of Lee, Kwon and Park on the same run must keep every f(Phi_hat_l) > 0 and M_hat positive definite.

Its runs are its own (no study shared with inertiaproof.checks.applications), so it runs in a lane of its own beside
the robustness study. What decides the verdict is budgeted in counts (runs, examples); a run that did not finish is
never evidence against a law, and one stopped by the wall-clock safety net is no evidence either way.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from hypothesis import Phase

from inertiaproof.checks.applications import (
    BALANCE, eigh_resolution, scene_keys, settings_for, simulate_recipes, stream_name,
)
from inertiaproof.counterexamples.adaptive_runs import euclidean_runs
from inertiaproof.dynamics import motion
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.sim import estimates, tracking
from inertiaproof.sim.recipe import Recipe, scene_of
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import check, replayer

__all__ = ["escape_margin", "euclidean_escape", "euclidean_escape_result", "natural_fails", "natural_twin",
           "replay_escape"]


def natural_twin(recipe):
    """The natural law on the same run, its gain matched so that its fastest direction at Theta_hat(0) is no faster
    than Slotine-Li's: gamma_nat = gamma / max_l lambda_max(f(Phi_hat_l(0)))^2 (the law moves f(Phi_hat) by
    gamma_nat f(Phi_hat) G f(Phi_hat))."""
    spec = recipe.spec()
    top = np.linalg.eigvalsh(pseudo_inertia(spec.theta_hat0))[..., -1].max()
    return dataclasses.replace(recipe, law="natural", gamma=float(spec.law.gain / top**2))


def escape_margin(recipe, s, q_samples, forces=motion.generalized_forces, twin=natural_twin):
    """Simulate a Slotine-Li recipe with its natural twin. Returns plain data: the Slotine-Li margin
    min_t min_q lambda_min(M(q, Theta_hat(t))) / max lambda_max (< 0: indefinite), its witness, and per law the
    smallest lambda_min(f(Phi_hat_l)) and of M_hat."""
    twin_recipe = twin(recipe)
    runs, batches = simulate_recipes([recipe, twin_recipe], s, forces)
    chain = recipe.chain()
    out = {"recipes": [recipe.to_data(), twin_recipe.to_data()], "laws": {},
           "resolution": eigh_resolution(chain.n + 4)}
    out["stiff"] = next((f"{r.status}, {r.note}" for r in runs if r.status in tracking.NOT_STARTED), "")  # no margin
    if out["stiff"]:
        out["resolved"] = False
        return out
    for name, run in zip(("euclidean", "natural"), runs):
        theta_hat = estimates.estimates(run)
        spectrum = np.linalg.eigvalsh(pseudo_inertia(theta_hat))
        f = spectrum[..., 0].min(-1)
        low, high, at = estimates.spectrum_over(chain, run.y[:, :chain.n], theta_hat, q_samples)
        ti = int(np.argmin(low / high.max()))
        out["laws"][name] = {
            "status": run.status, "note": run.note, "balance_error": run.balance_error,
            "min_lambda_min_f_hat": float(f.min()), "max_lambda_max_f_hat": float(spectrum[..., -1].max()),
            "inf_lambda_min_M_hat": float(low.min()),
            "sup_lambda_max_M_hat": float(high.max()), "margin": float(low.min() / high.max()),
            "witness": {"t": float(run.t[ti]), "q": at[ti].tolist()},
            "series": {"t": run.t.tolist(), "lambda_min_f_hat": f.tolist(), "inf_lambda_min_M_hat": low.tolist()}}
    out["resolved"] = not out["stiff"] and all(r.status != tracking.CLOCK for r in runs) and all(
        r.balance_error <= BALANCE * s.rtol for r in runs if r.finished)  # a clock stop: no margin either way
    return out


def natural_fails(data):
    """Whether the natural law's f(Phi_hat_l) or M_hat lost definiteness by more than rounding on a finished run (a
    run that did not finish is no evidence against the law)."""
    law = data["laws"]["natural"]
    lost = law["min_lambda_min_f_hat"] < -data["resolution"] * law["max_lambda_max_f_hat"] or (
        law["margin"] < -data["resolution"])
    return law["status"] == "ok" and lost


def euclidean_escape_result(ctx, hunts, twin=natural_twin, elsewhere=None):
    """One hunt per scene of ``hunts`` ({scene: Hypothesis examples, None: the profile's}), each simulating at most
    the profile's ``hunt_runs`` runs. ``twin`` gives the law compared with Slotine-Li (a test passes a wrong one).
    ``elsewhere`` (the same form) is hunted only if ``hunts`` found no escape: that Slotine-Li *may* leave the
    consistent set is existential, one replayable run on any chain proves it; that the natural law cannot is read
    off every run of both.
    The check's wall-clock budget is a safety net: once it strikes no run starts, and a hunt it cut short is
    INCONCLUSIVE (only a finished run that breaks the natural law stays evidence)."""
    s = settings_for(ctx)
    phases = (Phase.explicit, Phase.reuse, Phase.generate, Phase.target) + ((Phase.shrink,) if s.shrink else ())
    seen, failures, scenes, witnesses, stiff, clocked = {}, [], {}, {}, [], []
    for key, examples in [*hunts.items(), *(elsewhere or {}).items()]:
        if key not in hunts and (witnesses or failures or clocked):
            break
        name = stream_name(key)
        q_samples = estimates.configurations(scene_of(key).chain, s.configurations, ctx.rng(f"{name}:APP escape q"))
        runs = []

        def margin(recipe):
            if recipe not in seen:  # Hypothesis replays a failing example once more
                left = 0.75 * ctx.budget.remaining()
                if len(runs) >= s.hunt_runs or clocked:
                    return np.nan
                if left <= 0:
                    clocked.append(key)
                    return np.nan
                runs.append(recipe)
                seen[recipe] = escape_margin(recipe, dataclasses.replace(s, max_seconds=min(s.max_seconds, left)),
                                             q_samples, twin=twin)
                clocked.extend(key for r in seen[recipe].get("laws", {}).values() if r["status"] == tracking.CLOCK)
                if seen[recipe]["stiff"]:
                    stiff.append(seen[recipe]["stiff"])
                elif natural_fails(seen[recipe]):
                    failures.append(seen[recipe])
            data = seen[recipe]
            return (data["laws"]["euclidean"]["margin"], data["resolution"]) if data["resolved"] else np.nan

        found = hunt(euclidean_runs((key,), s.hunt_horizon), margin, ctx, label=f"APP-euclidean-escape:{name}",
                     max_examples=examples or max(n for _, n in s.hunts), phases=phases)
        scenes[key] = {"runs": len(runs), **found.summary()}
        if found.violation is not None:
            witnesses[key] = seen[found.violation]
    searched = {"scenes": scenes, "horizon_s": s.hunt_horizon, "runs_budget": s.hunt_runs,
                "space": " ".join(euclidean_runs.__doc__.split(": ", 1)[1].split())}
    if failures:
        data = failures[0]
        nat = data["laws"]["natural"]
        t = nat["series"]["t"][int(np.argmin(nat["series"]["lambda_min_f_hat"]))]
        gain = data["recipes"][1].get("gamma")
        gain = "the scene's gain" if gain is None else f"gain {gain:.3g}"
        return Result("APP-euclidean-escape", Verdict.VIOLATED,
                      f"the natural law left the consistent set: min lambda_min(f(Phi_hat)) = "
                      f"{nat['min_lambda_min_f_hat']:.3g} at t = {t:.3g} s ({gain}); its mirror variable U_l = "
                      "f(Phi_hat_l)^-1 moves continuously, so f(Phi_hat_l) leaves the cone only where U_l turns "
                      "singular: the estimate blew up in finite time (a finished run; replay it)",
                      {"searched": searched, "run": _brief(data)},
                      counterexample={"kind": "adaptive-escape", "data": _replay_data(data, s)})
    if clocked:
        return Result("APP-euclidean-escape", Verdict.INCONCLUSIVE,
                      f"the check's wall-clock safety net cut the hunt on {clocked[0]} short after {len(seen)} runs "
                      f"(its counted budget: {s.hunt_runs} runs per scene): what it drew would depend on the machine",
                      {"searched": searched})
    natural = [d["laws"]["natural"] for d in seen.values() if d.get("laws")]
    barrier = [law["note"] for law in natural if law["status"] == tracking.BARRIER]
    if not witnesses:
        worst = min((v["smallest_margin"]["value"] for v in scenes.values()), default=np.nan)
        return Result("APP-euclidean-escape", Verdict.INCONCLUSIVE,
                      f"no Slotine-Li run with an indefinite M(q, Theta_hat) in {len(seen)} runs on "
                      f"{', '.join(scenes)} (smallest relative lambda_min {worst}); the natural law stayed consistent "
                      f"in all {sum(law['status'] == 'ok' for law in natural)} it finished"
                      + (f"; {len(barrier)} natural run(s) stepped over its barrier: {barrier[0]}" if barrier else "")
                      + (f"; {len(stiff)} of the runs not simulated (no margin): {stiff[0]}" if stiff else ""),
                      {"searched": searched,
                       "not_simulated": quantity(len(stiff), "count", "runs not started (ill-conditioned, no start)"),
                       "barrier": quantity(len(barrier), "count", "natural runs that stepped over their barrier")})
    found = {}
    for key, data in witnesses.items():
        path = ctx.save_counterexample(Result(
            "APP-euclidean-escape", Verdict.HOLDS, f"{key}: a Slotine-Li run whose M(q, Theta_hat) turns indefinite",
            counterexample={"kind": "adaptive-escape", "data": _replay_data(data, s)}))
        found[key] = {"run": _brief(data), "figures": _escape_figures(data), "witness_file": str(path),
                      "replay": f"inertiaproof replay {path}"}
    key, data = next(iter(witnesses.items()))
    e, nat = data["laws"]["euclidean"], data["laws"]["natural"]
    margins = [scenes[k]["smallest_margin"]["value"] for k in hunts]
    margins = [m for m in margins if isinstance(m, (int, float)) and np.isfinite(m)]  # a scene whose runs could
    home = "" if key in hunts else (  # not start has no margin (a line mass: no Theta_hat(0) for the natural law)
        f"no escape on {', '.join(hunts)} in {sum(scenes[k]['runs'] for k in hunts)} runs (smallest relative "
        f"lambda_min {f'{min(margins):.3g}' if margins else 'none: no run started'}); the law may escape: ")
    evidence = {"searched": searched, "escapes": found, "replay": found[key]["replay"],
                "escape_margin": quantity(e["margin"], "margin", "min_t,q lambda_min(M(q, Theta_hat)) / "
                                          "max lambda_max under Slotine-Li (< 0: indefinite)"),
                "natural_margin": quantity(nat["margin"], "margin", "the same under the natural law (> 0)")}
    return Result("APP-euclidean-escape", Verdict.HOLDS,
                  f"{home}{key}: Slotine-Li's lambda_min(M(q, Theta_hat)) = {e['inf_lambda_min_M_hat']:.3g} at t = "
                  f"{e['witness']['t']:.3g} s (min lambda_min(f(Phi_hat)) {e['min_lambda_min_f_hat']:.3g}); "
                  f"the natural law on the same run: min lambda_min(f(Phi_hat)) {nat['min_lambda_min_f_hat']:.3g} > 0, "
                  f"lambda(M_hat) in [{nat['inf_lambda_min_M_hat']:.3g}, {nat['sup_lambda_max_M_hat']:.3g}]; escapes "
                  f"on {len(witnesses)} of {len(scenes)} scenes in {len(seen)} runs", evidence)


def _replay_data(data, s):
    return {"recipes": data["recipes"], "rtol": s.rtol, "samples_per_second": s.samples_per_second,
            "witness_q": data["laws"]["euclidean"]["witness"]["q"]}


def _brief(data):
    """The run's two recipes and, per law, a flat row of what it did."""
    keys = ("status", "balance_error", "min_lambda_min_f_hat", "inf_lambda_min_M_hat", "sup_lambda_max_M_hat",
            "margin")
    return {"recipes": data["recipes"],
            "laws": {name: {**{k: law[k] for k in keys}, "witness_t": law["witness"]["t"]}
                     for name, law in data["laws"].items()}}


def _escape_figures(data):
    laws = data["laws"]
    lines = lambda key: {name: np.c_[law["series"]["t"], law["series"][key]].tolist()  # noqa: E731
                         for name, law in laws.items()}
    return {"f": {"series": {"title": "min_l lambda_min(f(Phi_hat_l(t))): Slotine-Li (euclidean) and natural",
                             "x_label": "t (s)", "y_label": "lambda_min", "lines": lines("lambda_min_f_hat")}},
            "M": {"series": {"title": "sampled inf_q lambda_min(M(q, Theta_hat(t)))", "x_label": "t (s)",
                             "y_label": "lambda_min", "lines": lines("inf_lambda_min_M_hat")}}}


@check("APP-euclidean-escape", needs={"chain"})
def euclidean_escape(ctx):
    built_in = settings_for(ctx).hunts
    try:
        hunts = scene_keys(ctx, built_in)
    except ValueError as exc:
        return Result("APP-euclidean-escape", Verdict.INCONCLUSIVE, str(exc))
    return euclidean_escape_result(ctx, hunts, elsewhere=None if ctx.scene is None else dict(built_in))


@replayer("adaptive-escape")
def replay_escape(data, ctx):
    """Simulate the saved Slotine-Li run and its natural twin again: the escape must recur at the saved
    configuration (or a sampled one) and the natural law must stay consistent."""
    euclidean, natural = (Recipe.from_data(r) for r in data["recipes"])
    s = dataclasses.replace(settings_for(ctx), rtol=data["rtol"], samples_per_second=data["samples_per_second"])
    found = escape_margin(euclidean, s, np.atleast_2d(data["witness_q"]), twin=lambda _: natural)
    e, nat = found["laws"]["euclidean"], found["laws"]["natural"]
    if natural_fails(found):
        verdict = Verdict.VIOLATED
    else:
        verdict = Verdict.HOLDS if e["margin"] < -found["resolution"] else Verdict.INCONCLUSIVE
    return Result("APP-euclidean-escape", verdict,
                  f"Slotine-Li: inf lambda_min(M_hat) {e['inf_lambda_min_M_hat']:.3g}, min lambda_min(f(Phi_hat)) "
                  f"{e['min_lambda_min_f_hat']:.3g}; natural: min lambda_min(f(Phi_hat)) "
                  f"{nat['min_lambda_min_f_hat']:.3g}, inf lambda_min(M_hat) {nat['inf_lambda_min_M_hat']:.3g}",
                  {"run": _brief(found)})
