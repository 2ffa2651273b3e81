"""GRE-physics: does (RoboticEquation) describe real moving and added mass? And the stability study.

- ``GRE-physics:internal-motion``: a trolley or passenger as its own rigid body on prismatic joints in
  Pinocchio, against the equation with Theta, Thetadot, Psi, Psidot integrated from the moving body's
  density (inertiaproof.sim.crosscheck).
- ``GRE-physics:loading``: mass added in K plastic captures of pieces at rest converges to the equation
  (inertiaproof.sim.capture); pieces that arrive with the body's velocity converge elsewhere.
- ``stability``: solve_ivp methods on the scene, error against run time, and the power balance of Prop1
  (inertiaproof.sim.study).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from inertiaproof.bounds.premises import unsimulable
from inertiaproof.dynamics import motion
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory
from inertiaproof.errors import InputError
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.scene import robots
from inertiaproof.scene.format import load_scene
from inertiaproof.sim import capture, crosscheck, fixedstep, study
from inertiaproof.sim.control import controller
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "ASSUMPTION", "internal_motion", "internal_motion_result", "INTERNAL_SCENES", "label", "loading",
    "loading_result", "LOADING_SCENES", "LOADING_SETTINGS", "moving_masses_only", "replay_internal",
    "replay_loading", "replay_stability", "scene_from", "scenes_for", "stability", "stability_result",
    "STABILITY_SCENES", "STUDY_SETTINGS",
]

INTERNAL_SCENES = ("trolley-2r", "passenger-platform")
LOADING_SCENES = ("planar-2r-payload",)
STABILITY_SCENES = (("planar-2r-early-payload", 1.0),)  # (built-in scene, horizon covering its payload ramp)

ASSUMPTION = ("The equation's term M(q, Thetadot) qd (with no momentum carried by the mass that appears) is the "
              "physics of mass that arrives AT REST in the Newtonian frame and joins its body in a perfectly "
              "plastic capture; mass that leaves (Thetadot < 0) leaves at rest in the Newtonian frame, i.e. it is "
              "thrown backwards relative to the body. Mass that arrives with the velocity of the point it joins "
              "exchanges no momentum and obeys the equation without that term.")


# -- scenes and replays ----------------------------------------------------------

def scenes_for(ctx, builtin):
    """[(reference, scene)]: the run's scene, or the built-in ones (a reference rebuilds a scene in a replay)."""
    if ctx.scene is not None:
        ref = {"source": ctx.scene.source} if ctx.scene.source else {"name": ctx.scene.name}
        return [(ref, ctx.scene)]
    return [({"builtin": key}, robots.BUILTIN[key]()) for key in builtin]


def label(ref, scene):
    """How evidence names a scene: the built-in key, else the scene's name."""
    return ref.get("builtin", scene.name)


def scene_from(ref):
    if "builtin" in ref:
        return robots.BUILTIN[ref["builtin"]]()
    if "source" in ref:
        return load_scene(ref["source"])
    raise InputError(f"counterexample names scene {ref!r}, which cannot be rebuilt (not a file, not built in)")


def _engine_missing():
    try:
        import pinocchio  # noqa: F401
    except ImportError:
        return "Pinocchio (PyPI package 'pin') is not installed: there is no independent engine to compare with"
    return None


# -- internal motion ---------------------------------------------------------------

@check("GRE-physics", needs=("chain", "time_varying", "internal_motion"), variant="internal-motion")
def internal_motion(ctx):
    return internal_motion_result(scenes_for(ctx, INTERNAL_SCENES), ctx)


def moving_masses_only(trajectory):
    return ParameterTrajectory(trajectory.base, tuple(load for load in trajectory.loads
                                                      if isinstance(load, MovingMass)), trajectory.span)


def internal_motion_result(scenes, ctx, forces=motion.generalized_forces, samples=None):
    """Compare the equation with Pinocchio's augmented model on every scene along a random smooth motion."""
    missing = _engine_missing()
    if missing:
        return Result("GRE-physics", Verdict.INCONCLUSIVE, missing)
    samples = samples or max(50, ctx.profile.samples // 10)
    evidence = {
        "method": ("each moving mass is a rigid body on its own prismatic joints in Pinocchio, driven along its "
                   "path; Pinocchio's RNEA torques on the original joints against (RoboticEquation) with "
                   "Theta, Thetadot, Psi, Psidot of the carrying body integrated from the moving body's density "
                   "(a uniform box with its mass and inertia, 8 Gauss points) and again from the closed forms of "
                   "trajectory.MovingMass"),
        "resolution": ("measured: both engines recomputed with lengths rescaled by 3, 0.7, 1.3 (a physically "
                       f"identical scene); resolution = {crosscheck.SAFETY:g} x their spread + "
                       f"{crosscheck.FLOOR:g} eps, relative to the sum of |terms|; a residual above "
                       f"{crosscheck.VIOLATION_RATIO:g} resolutions is a violation, between 1 and that inconclusive"),
        "scenes": {},
    }
    verdicts, worst_error, counterexample = [], 0.0, None
    for ref, scene in scenes:
        trajectory = moving_masses_only(scene.trajectory)
        times = trajectory.times(samples, horizon=scene.horizon())
        ctx.progress(f"{scene.name}: {samples} samples over [{times[0]:g}, {times[-1]:g}] s")
        rng = ctx.rng(f"GRE-physics:internal:{label(ref, scene)}")
        q, qd, qdd = crosscheck.smooth_motion(scene.chain, times, rng)
        cc = crosscheck.cross_check(scene.chain, trajectory, times, q, qd, qdd, forces)
        verdict = cc.verdict()
        verdicts.append(verdict)
        error = float(cc.relative_error().max())
        worst_error = max(worst_error, error)
        evidence["scenes"][label(ref, scene)] = {
            "samples": quantity(samples, "count"),
            "joints": quantity(scene.chain.n, "count"),
            "moving_masses": quantity(sum(isinstance(load, MovingMass) for load in trajectory.loads), "count"),
            "loads_left_out": quantity(len(scene.trajectory.loads) - len(trajectory.loads), "count",
                                       "payloads and scalings: the loading variant checks those"),
            "max_relative_torque_error": quantity(
                error, "residual", "max over samples and joints of |tau_GRE - tau_Pinocchio| / sum |terms|"),
            "closed_form_max_relative_error": quantity(float(cc.relative_error("closed_form").max()), "residual",
                                                       "the same with trajectory.MovingMass's closed forms"),
            "max_torque": quantity(float(np.abs(cc.engine).max()), "value", unit="N m or N"),
            "resolution": quantity(float((cc.resolution / cc.scale).max()), "tolerance", cc.spread_note),
            "worst_ratio": quantity(float(max(cc.ratio().max(), cc.ratio("closed_form").max())), "ratio",
                                    "residual over resolution; <= 1 holds"),
            "verdict": str(verdict),
        }
        if verdict == Verdict.VIOLATED and counterexample is None:
            i, k = np.unravel_index(np.argmax(cc.ratio()), cc.ratio().shape)
            counterexample = {"kind": "gre-physics-internal", "data": {
                "scene": ref, "time": float(times[i]), "joint": int(k) + 1, "q": q[i].tolist(), "qd": qd[i].tolist(),
                "qdd": qdd[i].tolist(), "tau_equation": cc.equation[i].tolist(), "tau_engine": cc.engine[i].tolist(),
                "ratio": float(cc.ratio()[i, k])}}
    evidence["max_relative_torque_error"] = quantity(worst_error, "residual", "over all scenes")
    verdict = combine(verdicts)
    names = ", ".join(evidence["scenes"])
    summary = {
        Verdict.HOLDS: f"moving mass as its own body in Pinocchio = (RoboticEquation) to {worst_error:.1e} "
                       f"(relative torque) on {names}",
        Verdict.VIOLATED: f"(RoboticEquation) differs from Pinocchio's moving body by {worst_error:.1e} "
                          f"(relative torque) on {names}",
        Verdict.INCONCLUSIVE: f"residual {worst_error:.1e} is above the measured round-off but too small to "
                              f"call a difference on {names}",
    }[verdict]
    return Result("GRE-physics", verdict, summary, evidence, counterexample)


@replayer("gre-physics-internal")
def replay_internal(data, ctx):
    """Recompute both engines at the saved sample with the current code."""
    scene = scene_from(data["scene"])
    trajectory = moving_masses_only(scene.trajectory)
    arrays = [np.atleast_2d(np.asarray(data[k], dtype=float)) for k in ("q", "qd", "qdd")]
    cc = crosscheck.cross_check(scene.chain, trajectory, np.array([data["time"]]), *arrays)
    verdict = cc.verdict()
    return Result("GRE-physics", verdict, f"at t = {data['time']:g}: relative torque error "
                  f"{cc.relative_error().max():.1e}, {cc.ratio().max():.2g} resolutions",
                  {"tau_equation": cc.equation[0].tolist(), "tau_engine": cc.engine[0].tolist()})


# -- loading -------------------------------------------------------------------------

LOADING_SETTINGS = {  # initial RK4 steps, piece counts, most steps, most pieces, most dQJ/dq entries (6 N n^2 for
    # each state where the equation or the feedforward is evaluated, inertiaproof.sim.capture.jacobian_entries; ci:
    # a 24-joint chain's 128 and 512 steps, 6.5e8, fit and a 30-joint chain's 512 steps after its 128, 1.6e9, do not)
    "ci": (128, (4, 8, 16, 32, 64), 2048, 256, 1e9),
    "deep": (512, (4, 8, 16, 32, 64, 128, 256), 16384, 1024, 4e10),
}


@check("GRE-physics", needs=("chain", "time_varying", "mass_change"), variant="loading")
def loading(ctx):
    return loading_result(scenes_for(ctx, LOADING_SCENES), ctx)


def _fmt(x, spec):
    return format(x, spec) if isinstance(x, (int, float)) and np.isfinite(x) else "n/a"


def loading_result(scenes, ctx, forces=motion.generalized_forces, steps=None, counts=None, scheme=None):
    """Captures of pieces at rest against the equation's solution over each scene's mass window."""
    missing = _engine_missing()
    if missing:
        return Result("GRE-physics", Verdict.INCONCLUSIVE, missing)
    default_steps, default_counts, max_steps, max_count, max_entries = LOADING_SETTINGS.get(ctx.profile.name,
                                                                                            LOADING_SETTINGS["ci"])
    steps, counts = steps or default_steps, tuple(counts or default_counts)
    evidence = {
        "assumption": ASSUMPTION,
        "method": ("the equation (ours) against a rigid multibody model (Pinocchio) that gains the mass in K pieces, "
                   "each joining in a plastic capture with the generalized momentum continuous; one fixed grid of "
                   "steps over the window for every model: classical Runge-Kutta (order 4, h x fastest closed-loop "
                   "rate <= 1), or on a scene too stiff for that within the study's steps the L-stable 2-stage Radau "
                   "IIA (order 3, simplified Newton, finite-difference Jacobian); captures on grid points; distances "
                   "at the window's end, relative to the motion's range and speed; K doubles until the observed "
                   "order settles"),
        "scenes": {},
    }
    verdicts, counterexample, series = [], None, None
    for ref, scene in scenes:
        control = controller(scene.chain, scene.trajectory, scene.control)
        cs = capture.study(scene.chain, scene.trajectory, control, counts, steps, forces, scene.horizon(), max_steps,
                           max_count, progress=ctx.progress, budget=ctx.budget, scheme=scheme,
                           max_entries=max_entries)
        verdicts.append(cs.verdict)
        _, order_start, _, _ = capture.convergence_verdict(cs.fine, cs.at_start, cs.floor) if cs.at_start else (
            None, None, None, None)
        _, order_carried, _, _ = capture.convergence_verdict(cs.fine, cs.carried_limit, cs.floor) if cs.carried else (
            None, None, None, None)
        evidence["scenes"][label(ref, scene)] = {
            "window": [float(cs.window[0]), float(cs.window[1])],
            "verdict": str(cs.verdict),
            "why": cs.why,
            "steps": quantity(cs.steps, "count", "steps of the scheme over the window"),
            "scheme": cs.scheme.name,
            "scheme_order": quantity(cs.scheme.order, "count", "the scheme's order of accuracy"),
            "observed_integration_order": quantity(cs.integration_order, "estimate",
                                                   "order observed over 4h, 2h, h (the floor uses the lower of the "
                                                   "two, at least 1)"),
            "work": {k: quantity(v, "count") for k, v in cs.work.as_dict().items()}
            | {"dqj_entries": quantity(cs.entries, "count", "entries of dQJ/dq built (6 N n^2 a state)")},
            "fastest_rate": quantity(cs.rate, "estimate", "fastest closed-loop mode, rad/s"),
            "pieces": list(cs.counts),
            "error_at_rest_centred": [quantity(e, "residual") for e in cs.at_rest],
            "order_at_rest_centred": quantity(cs.order, "estimate", "pieces join at the middle of their time slice"),
            "order_at_rest_slice_start": quantity(order_start, "estimate", "pieces join at the start of their slice"),
            "integration_floor": quantity(cs.floor, "tolerance", "2 x Richardson estimate of the scheme's error"),
            "mismatch_if_carried": quantity(cs.mismatch, "value",
                                            "distance between (RoboticEquation) and the limit of pieces that arrive "
                                            "with the velocity of the point they join (no M(q, Thetadot) qd term)"),
            "carried_pieces_vs_equation": [quantity(e, "residual") for e in cs.carried],
            "carried_pieces_vs_their_limit": [quantity(e, "residual") for e in cs.carried_limit],
            "order_carried_to_their_limit": quantity(order_carried, "estimate"),
            "refinements": [[int(st), list(c)] for st, c in cs.history],
        }
        if series is None and cs.at_rest:
            series = {"title": f"Loading as captures ({label(ref, scene)}): distance at the window's end",
                      "x_label": "pieces K", "y_label": "relative distance", "x_log": True, "y_log": True,
                      "lines": {"at rest, centred -> (RoboticEquation)": list(map(list, zip(cs.counts, cs.at_rest))),
                                "at rest, slice start -> (RoboticEquation)": list(map(list, zip(cs.fine, cs.at_start))),
                                "carried -> (RoboticEquation)": [[k, e] for k, e in zip(cs.fine, cs.carried)],
                                "carried -> without M(q, Thetadot) qd": [[k, e] for k, e in
                                                                         zip(cs.fine, cs.carried_limit)]}}
        if cs.verdict == Verdict.VIOLATED and counterexample is None:
            counterexample = {"kind": "gre-physics-loading", "data": {
                "scene": ref, "steps": cs.steps, "pieces": list(cs.counts), "errors": cs.at_rest, "floor": cs.floor,
                "scheme": cs.scheme.name}}
    if series:
        evidence["series"] = series
    verdict = combine(verdicts)
    first = next(iter(evidence["scenes"].values()))
    order = first["order_at_rest_centred"]["value"]
    summary = {
        Verdict.HOLDS: ("pieces captured at rest converge to (RoboticEquation)"
                        + (f" with order {_fmt(order, '.2f')}" if order is not None else "")
                        + f"; arriving with the body's velocity instead misses it by "
                          f"{_fmt(first['mismatch_if_carried']['value'], '.2g')}"),
        Verdict.VIOLATED: f"pieces captured at rest do not converge to (RoboticEquation): {first['why']}",
        Verdict.INCONCLUSIVE: f"captures at rest: {first['why']}",
    }[verdict]
    return Result("GRE-physics", verdict, summary, evidence, counterexample)


@replayer("gre-physics-loading")
def replay_loading(data, ctx):
    """Re-run the captures on the saved scene with the current code."""
    scheme = next((x for x in (fixedstep.RK4, fixedstep.RADAU_IIA) if x.name == data.get("scheme")), None)
    return loading_result([(data["scene"], scene_from(data["scene"]))], ctx, steps=data["steps"],
                          counts=data["pieces"], scheme=scheme)


# -- stability and error against run time -------------------------------------------

STUDY_SETTINGS = {
    "ci": study.StudySettings(tolerances=(1e-5,), reference_rtol=1e-7, max_evaluations=5_000),
    "deep": study.StudySettings(tolerances=(1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10),
                                reference_rtol=1e-12, max_evaluations=200_000, max_seconds=600.0),
}


@check("stability", needs=("chain",))
def stability(ctx):
    if ctx.scene is not None:
        scenes = [(ref, scene, None) for ref, scene in scenes_for(ctx, ())]
    else:
        scenes = [({"builtin": key}, robots.BUILTIN[key](), horizon) for key, horizon in STABILITY_SCENES]
    return stability_result(scenes, ctx)


def stability_result(scenes, ctx, forces=motion.generalized_forces, settings=None):
    """The study on every (reference, scene, horizon); the verdict is the power balance's."""
    base = settings or STUDY_SETTINGS.get(ctx.profile.name, STUDY_SETTINGS["ci"])
    wp_rows, stab_rows, verdicts, evidence, counterexample = [], [], [], {"scenes": {}}, None
    for ref, scene, horizon in scenes:
        chosen = base if horizon is None else dataclasses.replace(base, horizon=horizon)
        st = study.study(scene, chosen, forces, progress=ctx.progress, budget=ctx.budget)
        verdict, coarse, fine, why = st.balance_verdict()
        singular = unsimulable(scene.chain) if verdict == Verdict.INCONCLUSIVE else None
        if singular:  # decided by the mathematics: the runs cannot cross where M(q) is singular
            verdict, why = Verdict.HOLDS, f"{singular[1]} ({why})"
        verdicts.append(verdict)
        wp_rows += st.work_precision_rows()
        stab_rows += st.stability_rows()
        evidence["scenes"][label(ref, scene)] = {
            "horizon": quantity(st.horizon, "value", unit="s"),
            "fastest_rate": quantity(st.fastest_rate, "estimate", "fastest closed-loop mode at home, rad/s"),
            "verdict": str(verdict),
            "why": why,
            **({"premises_failed": singular[0]} if singular else {}),
            "reference": {"method": st.reference.method, "rtol": st.reference.rtol, "status": st.reference.status,
                          "seconds": quantity(st.reference.seconds, "seconds"),
                          "balance_residual": quantity(fine, "residual", "max_t |E - E0 - W| / energy in play")},
            "coarse_balance_residual": quantity(coarse, "residual"),
            "errors_against": (f"{st.reference.method} rtol {st.reference.rtol:g}" if st.substitute is None else
                               f"{st.substitute.method} rtol {st.substitute.rtol:g} (the reference failed)"),
            "methods": {f"{r.method} rtol {r.rtol:g}": {
                "status": r.status, "seconds": quantity(r.seconds, "seconds"), "steps": quantity(r.steps, "count"),
                "error": quantity(e, "estimate", "max_t ||q - q_ref|| / range of q_ref"),
                "balance_residual": quantity(r.balance_error, "residual")} for r, e in st.runs},
        }
        if verdict == Verdict.VIOLATED and counterexample is None:
            counterexample = {"kind": "stability-balance", "data": {
                "scene": ref, "horizon": st.horizon, "tolerances": list(chosen.tolerances),
                "methods": [st.reference.method], "reference_rtol": chosen.reference_rtol,
                "coarse_residual": coarse, "reference_residual": fine}}
    files = [ctx.outputs.write_data("work_precision.json", wp_rows), ctx.outputs.write_data("stability.json", stab_rows)]
    evidence["data_files"] = [f for f in files if f]
    evidence["method"] = ("closed loop (PD or computed torque tracking a sinusoid) integrated with solve_ivp; error "
                          "against a tight-tolerance reference run; the power balance d/dt (T_q + U) = supplied power "
                          "(Prop1) integrated alongside the state judges every run without a reference")
    verdict = combine(verdicts)
    first = next(iter(evidence["scenes"].values()))
    ok = sum(row["status"] == "ok" for row in stab_rows)
    summary = (f"power balance of Prop1: {first['why']}; {ok} of {len(stab_rows)} solver runs finished with the "
               "right energy")
    return Result("stability", verdict, summary, evidence, counterexample)


@replayer("stability-balance")
def replay_stability(data, ctx):
    """Re-run the reference method at the saved tolerances on the saved scene."""
    settings = study.StudySettings(methods=tuple(data["methods"]), tolerances=tuple(data["tolerances"]),
                                   reference_rtol=data["reference_rtol"], horizon=data["horizon"])
    return stability_result([(data["scene"], scene_from(data["scene"]), data["horizon"])], ctx, settings=settings)
