"""Structural properties (Section 4, Prop1 and Prop2), numerically: skew symmetry and the regressors.

Prop1: N = Mdot - 2C - M(q, Thetadot) and H(q, Psi) are skew-symmetric. Mdot
is the total derivative of M(q(t), Theta(t)) along a motion, taken
independently of the formula: by a complex step in t through
inertiaproof.dynamics.composite on analytic motions, by Richardson-extrapolated
central differences on the built-in scenes (whose ramps are not analytic).
H is also checked against the Lagrangian it comes from: the Psi part of the
Euler-Lagrange equations of T_Psi = qd^T J^T Q^T Psi(t), differentiated by a
complex step, must equal H qd + J^T Q^T Psidot (RoboticEquation).

Prop2: the regressors of inertiaproof.dynamics.regressors, built from QJ alone,
reproduce M a + C v + G and M(q, Thetadot) v.

Residuals are relative to the norms of the terms compared; a residual above
the resolution (TOLERANCE, or the difference error estimate) is a violation,
saved with the chain and the motion. Negative controls (a wrong Christoffel
sign, a symmetric instead of skew H, Mdot without the Thetadot part, a
perturbed regressor term) must be caught, else the check is INCONCLUSIVE.
Both run on built-in chains and are hunted on random chains.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from inertiaproof.checks.forward_kinematics import kinematics_result, with_kinematics
from inertiaproof.checks.pointwise import HUNT_SHARE, NO_SHRINK
from inertiaproof.counterexamples.motions import joint_motion, motions

from inertiaproof.dynamics import composite, regressors
from inertiaproof.dynamics import terms as dynamics
from inertiaproof.dynamics.chain import COMPLEX_STEP, Chain
from inertiaproof.dynamics.trajectory import SineMotion
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.scene import robots
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "analytic_case", "coriolis_regressor_wrong_index", "EPS", "FD_STEP", "mass_regressor_perturbed",
    "partial_mass_rate", "prop1", "PROP1_CONTROLS", "PROP1_INPUTS", "prop1_residuals", "prop1_result",
    "prop1_scenes", "prop2", "PROP2_CONTROLS", "PROP2_INPUTS", "prop2_inputs", "prop2_residuals", "prop2_result",
    "prop2_scenes", "replay_structural_point", "scene_case", "symmetric_lumped", "Terms", "TOLERANCE",
    "wrong_christoffel",
]

TOLERANCE = 1e-10  # relative residual, against the norms of the terms compared
EPS = np.finfo(float).eps
FD_STEP = 1e-3  # time step of the central differences on the built-in scenes (halved once for Richardson)


def _norm(a, axes=(-2, -1)):
    return np.sqrt((np.abs(a) ** 2).sum(axes))


@dataclass(frozen=True)
class Terms:
    """The implementation under test: functions of (RoboticEquation) whose properties Prop1 and Prop2 state."""

    coriolis: Callable = dynamics.coriolis  # (dM/dq, qd) -> C
    mass_rate: Callable = dynamics.mass_matrix_time_derivative  # (qj, dqj, Theta, Thetadot, qd) -> Mdot
    lumped: Callable = dynamics.lumped_velocity_matrix  # (dqj, Psi) -> H
    coriolis_regressor: Callable = regressors.coriolis_regressor
    mass_regressor: Callable = regressors.mass_regressor


# -- Prop1 ---------------------------------------------------------------------------------------

def prop1_residuals(chain, q, q_dot, theta, theta_dot, psi, psi_dot, mass_dot, lagrange, terms=Terms()):
    """Relative residuals at sample points; ``mass_dot`` is Mdot and ``lagrange`` the Psi part of the
    Euler-Lagrange equations, both taken independently (complex step or differences)."""
    qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
    c = terms.coriolis(dynamics.mass_matrix_partials(qj, dqj, theta), q_dot)
    f = dynamics.mass_matrix(qj, theta_dot)
    n = mass_dot - 2 * c - f
    h = terms.lumped(dqj, psi)
    hq = (h @ q_dot[..., None])[..., 0]
    force = dynamics.lumped_acceleration_force(qj, psi_dot)
    formula = terms.mass_rate(qj, dqj, theta, theta_dot, q_dot)
    tiny = np.finfo(float).tiny
    return {
        "N = Mdot - 2C - M(q, Thetadot) skew": _norm(n + np.swapaxes(n, -1, -2))
        / np.maximum(_norm(mass_dot) + 2 * _norm(c) + _norm(f), tiny),
        "Mdot formula = total derivative": _norm(formula - mass_dot) / np.maximum(_norm(mass_dot), tiny),
        "H skew": _norm(h + np.swapaxes(h, -1, -2)) / np.maximum(_norm(h), tiny),
        "H qd + J^T Q^T Psidot = Euler-Lagrange Psi part": _norm(lagrange - hq - force, -1)
        / np.maximum(_norm(lagrange, -1) + _norm(hq, -1) + _norm(force, -1), tiny),
    }


def _complex_step(fn, t):
    """d fn / dt at real times t by a complex step."""
    return fn(t + 1j * COMPLEX_STEP).imag / COMPLEX_STEP


def analytic_case(chain, motion, t):
    """Prop1's inputs along analytic motions {"q", "theta", "psi"} (SineMotion) at times t: derivatives in t by
    complex steps; resolution TOLERANCE everywhere."""
    (q, q_dot), (theta, theta_dot), (psi, psi_dot) = (motion[k].at(t) for k in ("q", "theta", "psi"))
    mass_dot = _complex_step(lambda s: composite.mass_matrix(chain, motion["q"].at(s)[0], motion["theta"].at(s)[0]), t)
    momentum = _complex_step(lambda s: dynamics.lumped_acceleration_force(
        chain.body_jacobian(motion["q"].at(s)[0]), motion["psi"].at(s)[0]), t)
    lagrange = momentum - np.einsum("...pjk,...p,...j->...k", chain.body_jacobian_derivative(q), psi, q_dot)
    return (q, q_dot, theta, theta_dot, psi, psi_dot, mass_dot, lagrange), None


def _richardson(fn, t):
    """(derivative, relative error estimate per time) of fn at times t: central differences at FD_STEP and
    FD_STEP / 2, extrapolated; the estimate |fine - coarse| / 3 bounds the extrapolated value's error from above
    for smooth fn, plus rounding."""
    coarse = (fn(t + FD_STEP) - fn(t - FD_STEP)) / (2 * FD_STEP)
    fine = (fn(t + FD_STEP / 2) - fn(t - FD_STEP / 2)) / FD_STEP
    derivative = (4 * fine - coarse) / 3
    axes = tuple(range(1, derivative.ndim))
    size = _norm(fn(t), axes) + 1e-300
    error = _norm(fine - coarse, axes) / 3 + 8 * EPS * size / FD_STEP
    return derivative, error / (_norm(derivative, axes) + 1e-300)


def scene_case(scene, q_motion, t):
    """Prop1's inputs on a built-in scene: Theta(t), Psi(t) of its trajectory, q(t) analytic; Mdot and the
    Lagrange term by Richardson differences, with their error estimates as resolution (relative)."""
    chain, traj = scene.chain, scene.trajectory
    q, q_dot = q_motion.at(t)
    theta, theta_dot = traj.theta(t)
    psi, psi_dot = traj.psi(t)
    mass_dot, m_err = _richardson(lambda s: composite.mass_matrix(chain, q_motion.at(s)[0], traj.theta(s)[0]), t)
    momentum, p_err = _richardson(lambda s: dynamics.lumped_acceleration_force(
        chain.body_jacobian(q_motion.at(s)[0]), traj.psi(s)[0]), t)
    lagrange = momentum - np.einsum("...pjk,...p,...j->...k", chain.body_jacobian_derivative(q), psi, q_dot)
    resolution = {"N = Mdot - 2C - M(q, Thetadot) skew": 2 * m_err + TOLERANCE,
                  "Mdot formula = total derivative": m_err + TOLERANCE,
                  "H skew": np.full(len(t), TOLERANCE),
                  "H qd + J^T Q^T Psidot = Euler-Lagrange Psi part": p_err + TOLERANCE}
    return (q, q_dot, theta, theta_dot, psi, psi_dot, mass_dot, lagrange), resolution


def wrong_christoffel(dm, q_dot):
    """A wrong Christoffel symbol: +dM_ij/dq_k instead of -dM_ij/dq_k (a negative control)."""
    d = np.moveaxis(dm, -1, -3)  # d[i, k, j] = dM_kj / dq_i
    gamma = 0.5 * (np.swapaxes(d, -2, -1) + np.moveaxis(d, -1, -3) + np.moveaxis(d, -3, -1))
    return np.swapaxes(np.einsum("...ijk,...i->...jk", gamma, q_dot), -1, -2)


def symmetric_lumped(dqj, psi):
    """A + A^T instead of A - A^T (a transposed term: a negative control)."""
    a = dynamics.lumped_jacobian_derivative(dqj, psi)
    return a + np.swapaxes(a, -1, -2)


def partial_mass_rate(qj, dqj, theta, theta_dot, q_dot):
    """Mdot without its M(q, Thetadot) part (a negative control)."""
    return dynamics.mass_matrix_time_derivative(qj, dqj, theta, theta_dot, q_dot) - dynamics.mass_matrix(qj, theta_dot)


PROP1_CONTROLS = {
    "Christoffel sign of dM_ij/dq_k flipped": (Terms(coriolis=wrong_christoffel), "N = Mdot - 2C - M(q, Thetadot) skew"),
    "H = A + A^T (transposed term)": (Terms(lumped=symmetric_lumped), "H skew"),
    "Mdot without M(q, Thetadot)": (Terms(mass_rate=partial_mass_rate), "Mdot formula = total derivative"),
}


def _worst(residuals, resolution):
    """(name, index, residual, resolution) of the residual closest to its resolution, relatively."""
    worst = None
    for name, r in residuals.items():
        res = TOLERANCE if resolution is None else np.broadcast_to(resolution[name], r.shape)
        i = int(np.argmax(r / res))
        row = (name, i, float(r[i]), float(np.broadcast_to(res, r.shape)[i]))
        if worst is None or row[2] / row[3] > worst[2] / worst[3]:
            worst = row
    return worst


def prop1_scenes():
    return [robots.panda(payload=2.0), robots.trolley_2r(loop=True, mass=2.0)]


def prop1_result(ctx, terms=Terms(), examples=None):
    """Prop1 on the built-in time-varying scenes (differences) and hunted random chains (complex steps)."""
    rows, verdicts, counterexample, controls, ratios = {}, [], None, {}, []
    for scene in prop1_scenes():
        rng = ctx.rng(f"Prop1:{scene.name}")
        q_motion = joint_motion(scene.chain, 1.0, rng)
        t = np.sort(rng.uniform(*np.clip(scene.trajectory.span, 0, 5), 16))
        inputs, resolution = scene_case(scene, q_motion, t)
        residuals = prop1_residuals(scene.chain, *inputs, terms=terms)
        name, i, r, res = _worst(residuals, resolution)
        bad = r > res
        verdicts.append(Verdict.VIOLATED if bad else Verdict.HOLDS)
        ratios.append(r / res)
        rows[scene.name] = {"samples": quantity(len(t), "count", "times along q(t) (sines) and the scene's Theta(t)"),
                            **{k: quantity(float(v.max()), "residual", "relative, worst over the samples")
                               for k, v in residuals.items()},
                            "worst_against_resolution": {"property": name, "residual": quantity(r, "residual"),
                                                         "resolution": quantity(res, "tolerance", "difference error "
                                                                                "estimate + TOLERANCE")}}
        if bad and counterexample is None:
            counterexample = _point_counterexample("Prop1", scene.chain, PROP1_INPUTS, inputs, i, name, r, res)
        for label, (wrong, prop) in PROP1_CONTROLS.items():
            wrong_r = prop1_residuals(scene.chain, *inputs, terms=wrong)[prop]
            worst_i = int(np.argmax(wrong_r))
            caught = bool(wrong_r[worst_i] > np.broadcast_to(resolution[prop], wrong_r.shape)[worst_i])
            controls.setdefault(label, {"property": prop, "caught": False, "residual": 0.0})
            controls[label]["caught"] |= caught
            controls[label]["residual"] = max(controls[label]["residual"], float(wrong_r.max()))

    def margin(example):
        chain, motion, t = example
        residuals = prop1_residuals(chain, *analytic_case(chain, motion, t)[0], terms=terms)
        worst = max(float(v.max()) for v in residuals.values())
        return float(np.log10(TOLERANCE / max(worst, 1e-300)))

    found = hunt(motions(), margin, ctx, label="Prop1 numeric", max_examples=examples or _hunt_examples(ctx),
                 phases=NO_SHRINK)
    if found.violation is not None:
        chain, motion, t = found.violation
        inputs = analytic_case(chain, motion, t)[0]
        name, i, r, res = _worst(prop1_residuals(chain, *inputs, terms=terms), None)
        counterexample = counterexample or _point_counterexample("Prop1", chain, PROP1_INPUTS, inputs, i, name, r, res)
        verdicts.append(Verdict.VIOLATED)
    missed = [label for label, c in controls.items() if not c["caught"]]
    verdicts.append(Verdict.INCONCLUSIVE if missed else Verdict.HOLDS)
    verdict = combine(verdicts)
    evidence = {"scenes": rows, "tolerance": quantity(TOLERANCE, "tolerance", "relative to the norms of the terms"),
                "hunt": _hunt_evidence(found),
                "negative_controls": {label: {"property": c["property"], "caught": c["caught"],
                                              "residual": quantity(c["residual"], "residual", "worst relative residual "
                                                                   "of the wrong term on the built-in scenes")}
                                      for label, c in controls.items()}}
    summary = (f"N and H skew, Mdot = the total derivative and H qd = the Lagrangian's Psi part: on {', '.join(rows)} "
               f"(Richardson differences in t) the worst residual is {max(ratios):.1e} of its resolution; on "
               f"{found.examples} random chains (complex steps in t) the worst relative residual is "
               f"{10 ** -found.worst_margin * TOLERANCE:.1e} (tolerance {TOLERANCE:g}); "
               f"{len(controls) - len(missed)}/{len(controls)} wrong terms caught")
    if verdict == Verdict.VIOLATED:
        summary = "a residual exceeds its resolution: " + summary
    return Result("Prop1", verdict, summary, evidence, counterexample=counterexample)


# -- Prop2 ---------------------------------------------------------------------------------------

def prop2_residuals(chain, q, q_dot, v, a, theta, theta_dot, terms=Terms()):
    """Relative residuals of (RoboticRegressor) and (RoboticRegressorVel) at sample points."""
    qj, dqj = chain.body_jacobian(q), chain.body_jacobian_derivative(q)
    rot, _ = chain.forward_kinematics(q)
    m_a = (dynamics.mass_matrix(qj, theta) @ a[..., None])[..., 0]
    c_v = (dynamics.coriolis(dynamics.mass_matrix_partials(qj, dqj, theta), q_dot) @ v[..., None])[..., 0]
    g = dynamics.gravity(qj, rot, theta, chain.gravity)
    r = terms.mass_regressor(qj, a) + terms.coriolis_regressor(qj, dqj, q_dot, v) + \
        regressors.gravity_regressor(qj, rot, chain.gravity)
    f_v = (dynamics.mass_matrix(qj, theta_dot) @ v[..., None])[..., 0]
    r_m = terms.mass_regressor(qj, v)
    tiny = np.finfo(float).tiny
    return {
        "M a + C v + G = sum R_l Phi_l": _norm(m_a + c_v + g - regressors.apply_regressor(r, theta), -1)
        / np.maximum(_norm(m_a, -1) + _norm(c_v, -1) + _norm(g, -1), tiny),
        "M(q, Thetadot) v = sum R_M,l Phidot_l": _norm(f_v - regressors.apply_regressor(r_m, theta_dot), -1)
        / np.maximum(_norm(f_v, -1), tiny),
    }


def prop2_inputs(chain, motion, t, rng):
    """(q, qd, v, a, Theta, Thetadot) at times t of a motion, with random v and a of the size of qd."""
    (q, q_dot), (theta, theta_dot) = motion["q"].at(t), motion["theta"].at(t)
    scale = np.abs(q_dot).max() + 1.0
    return q, q_dot, scale * rng.standard_normal(q.shape), scale * rng.standard_normal(q.shape), theta, theta_dot


def coriolis_regressor_wrong_index(qj, dqj, q_dot, v):
    """(T1 - T2 - T3) / 2: the second Christoffel term with the wrong sign (a negative control)."""
    t1, t2, t3 = regressors.christoffel_terms(qj, dqj, q_dot, v)
    return 0.5 * (t1 - t2 - t3)


def mass_regressor_perturbed(qj, a):
    """B^T Y(B a) perturbed by one part in a million (a negative control of the tolerance)."""
    return regressors.mass_regressor(qj, a) * (1 + 1e-6)


PROP2_CONTROLS = {
    "Christoffel term dM_ki/dq_j with the wrong sign": (Terms(coriolis_regressor=coriolis_regressor_wrong_index),
                                                        "M a + C v + G = sum R_l Phi_l"),
    "mass regressor perturbed by 1e-6": (Terms(mass_regressor=mass_regressor_perturbed),
                                         "M(q, Thetadot) v = sum R_M,l Phidot_l"),
}


def prop2_scenes():
    return [robots.panda(payload=2.0), robots.ur5(), robots.revolute_prismatic(1.0), robots.non_normal_2r()]


def prop2_result(ctx, terms=Terms(), examples=None):
    """Prop2 on built-in chains with their bodies and random motions, and hunted on random chains."""
    rows, verdicts, counterexample, controls = {}, [], None, {}
    for scene in prop2_scenes():
        rng = ctx.rng(f"Prop2:{scene.name}")
        chain = scene.chain
        motion = {"q": joint_motion(chain, 1.0, rng),
                  "theta": SineMotion(scene.trajectory.base, 0.2 * rng.standard_normal((chain.bodies, 10)),
                                      rng.uniform(0.2, 5.0, (chain.bodies, 10)), rng.uniform(0, 6, (chain.bodies, 10)))}
        t = rng.uniform(0, 10, 32)
        inputs = prop2_inputs(chain, motion, t, rng)
        residuals = prop2_residuals(chain, *inputs, terms=terms)
        name, i, r, res = _worst(residuals, None)
        verdicts.append(Verdict.VIOLATED if r > res else Verdict.HOLDS)
        rows[scene.name] = {k: quantity(float(v.max()), "residual", "relative, worst over 32 random points")
                            for k, v in residuals.items()}
        if r > res and counterexample is None:
            counterexample = _point_counterexample("Prop2", chain, PROP2_INPUTS, inputs, i, name, r, res)
        for label, (wrong, prop) in PROP2_CONTROLS.items():
            wrong_r = float(prop2_residuals(chain, *inputs, terms=wrong)[prop].max())
            c = controls.setdefault(label, {"property": prop, "caught": False, "residual": 0.0})
            c["caught"] |= wrong_r > TOLERANCE
            c["residual"] = max(c["residual"], wrong_r)

    def margin(example):
        chain, motion, t = example
        rng = np.random.default_rng(len(t) + chain.n)
        residuals = prop2_residuals(chain, *prop2_inputs(chain, motion, t, rng), terms=terms)
        return float(np.log10(TOLERANCE / max(max(float(v.max()) for v in residuals.values()), 1e-300)))

    found = hunt(motions(), margin, ctx, label="Prop2 numeric", max_examples=examples or _hunt_examples(ctx),
                 phases=NO_SHRINK)
    if found.violation is not None:
        chain, motion, t = found.violation
        rng = np.random.default_rng(len(t) + chain.n)
        inputs = prop2_inputs(chain, motion, t, rng)
        name, i, r, res = _worst(prop2_residuals(chain, *inputs, terms=terms), None)
        counterexample = counterexample or _point_counterexample("Prop2", chain, PROP2_INPUTS, inputs, i, name, r, res)
        verdicts.append(Verdict.VIOLATED)
    missed = [label for label, c in controls.items() if not c["caught"]]
    verdicts.append(Verdict.INCONCLUSIVE if missed else Verdict.HOLDS)
    verdict = combine(verdicts)
    worst_scene = max(v["value"] for row in rows.values() for v in row.values())
    summary = (f"regressors R_l (n x 10 per body, from QJ and dQJ/dq alone) reproduce M a + C v + G and M(q, Thetadot) v "
               f"on {', '.join(rows)} (worst relative residual {worst_scene:.1e}) and on {found.examples} random chains "
               f"(worst {10 ** -found.worst_margin * TOLERANCE:.1e}); {len(controls) - len(missed)}/{len(controls)} "
               "wrong terms caught")
    if verdict == Verdict.VIOLATED:
        summary = "a residual exceeds the tolerance: " + summary
    evidence = {"chains": rows, "tolerance": quantity(TOLERANCE, "tolerance", "relative to the norms of the terms"),
                "hunt": _hunt_evidence(found),
                "negative_controls": {label: {"property": c["property"], "caught": c["caught"],
                                              "residual": quantity(c["residual"], "residual")}
                                      for label, c in controls.items()}}
    return Result("Prop2", verdict, summary, evidence, counterexample=counterexample)


# -- shared ----------------------------------------------------------------------------------------

def _hunt_examples(ctx):
    return max(ctx.profile.examples // HUNT_SHARE, 10)


def _hunt_evidence(found):
    return {**found.summary(), "margins": [float(m) for m in found.margins[:500]],
            "what": "random chains (n <= 7, revolute and prismatic, DH and general axes, 1 mm to 30 m) with sine "
                    "motions q(t), Theta(t), Psi(t); margin = decades of the worst relative residual below the tolerance"}


PROP1_INPUTS = ("q", "q_dot", "theta", "theta_dot", "psi", "psi_dot", "mass_dot", "lagrange")
PROP2_INPUTS = ("q", "q_dot", "v", "a", "theta", "theta_dot")


def _point_counterexample(check_id, chain, names, inputs, i, name, residual, resolution):
    """A replayable point: the chain and every input of the residuals there (for Prop1 also the independently
    differentiated Mdot and Lagrange term), the property and its residual."""
    return {"kind": "structural-point", "data": {
        "id": check_id, "chain": chain.to_data(), "property": name, "residual": residual, "resolution": resolution,
        "inputs": {k: np.asarray(v[i]).tolist() for k, v in zip(names, inputs)}}}


@replayer("structural-point")
def replay_structural_point(data, ctx):
    chain = Chain.from_data(data["chain"])
    names, fn = (PROP1_INPUTS, prop1_residuals) if data["id"] == "Prop1" else (PROP2_INPUTS, prop2_residuals)
    r = float(fn(chain, *(np.asarray(data["inputs"][k], float)[None] for k in names))[data["property"]][0])
    verdict = Verdict.VIOLATED if r > data["resolution"] else Verdict.HOLDS
    return Result(data["id"], verdict, f"{data['property']}: relative residual {r:.3g} (resolution "
                  f"{data['resolution']:.3g})", {"residual": quantity(r, "residual"),
                                                  "resolution": quantity(data["resolution"], "tolerance")})


@check("Prop1", needs={"chain"}, variant="numeric")
def prop1(ctx):
    chains = {s.name: s.chain for s in ([ctx.scene] if ctx.scene is not None else prop1_scenes())}
    return with_kinematics(prop1_result(ctx), kinematics_result(ctx, "Prop1", chains))


@check("Prop2", needs={"chain"}, variant="numeric")
def prop2(ctx):
    return prop2_result(ctx)
