"""QJ against the motion it describes: the chain's QJ, dQJ/dq and body twists against forward kinematics.

The forward kinematics here are products of the chain's homogeneous transforms
(Layout), T_l = T_{l-1} B_l X_l(g_l(q_l)) A_l, with X_l Rodrigues' rotation
about the joint's axis (or the slide along it) and g_l the coordinate map's
value only: nothing of :meth:`Chain.body_jacobian` (its twist maps, turns and
the map's derivative g_l') is used. Their derivatives are taken by complex
steps (exact to round-off):

- the chain's frames (:meth:`Chain.forward_kinematics`): R_l and z_l themselves;
- QJ (Kinematics, DefBlockmatrixQ): column k of body l is
  (R_l^T dz_l/dq_k, vee(R_l^T dR_l/dq_k));
- the body twists (VelocityRigidMass) of a motion through q with velocity qd:
  (R_l^T zdot_l, vee(R_l^T Rdot_l)) = QJ qd;
- dQJ/dq: twice Richardson-extrapolated central differences of the complex-step
  QJ, with their error estimate as resolution.

Def2, CX-normal and Prop1 use this cross-check on their own chains and on random
chains of every joint kind and coordinate map the chains support, so a wrong
rate factor g_l' turns them VIOLATED. Negative controls (QJ and dQJ/dq off by
one part in a million of their size, never a null perturbation: :func:`off_by`)
must be caught, else the cross-check is INCONCLUSIVE.
"""

from __future__ import annotations

import numpy as np
from inertiaproof.checks.pointwise import NO_SHRINK
from inertiaproof.counterexamples.chains import chains_with_configurations

from inertiaproof.dynamics.chain import COMPLEX_STEP, COORDINATE_MAPS, Chain
from inertiaproof.model.inertia import skew
from inertiaproof.result import Result, Verdict, combine, quantity
from inertiaproof.suite.hunt import hunt
from inertiaproof.suite.registry import replayer

__all__ = [
    "EPS", "FD_STEP", "forward_kinematics", "FORWARD_KINEMATICS_CONTROLS", "kinematics_residuals", "kinematics_result",
    "off_by", "PART", "PROPERTIES", "references", "replay_forward_kinematics", "TOLERANCE",
    "twists_of_forward_kinematics", "with_kinematics",
]

TOLERANCE = 1e-10  # relative, against the norm of the quantity compared
EPS = np.finfo(float).eps
FD_STEP = 1e-3  # step of the central differences of QJ (halved twice for Richardson), relative to max(1, |q|)
PROPERTIES = ("frames R_l, z_l = the forward kinematics", "QJ = twists of the forward kinematics",
              "QJ qd = body twists of the forward kinematics along qd", "dQJ/dq = derivative of the forward kinematics' twists")


def _joint_transform(joint, q):
    """X(g(q)) as homogeneous transforms (..., 4, 4), generic in dtype."""
    x = np.asarray(joint.coordinate.value(q))
    u = np.asarray(joint.axis, float)
    out = np.zeros(x.shape + (4, 4), dtype=np.result_type(x, float))
    out[..., 3, 3] = 1.0
    if joint.revolute:
        c, s = np.cos(x)[..., None, None], np.sin(x)[..., None, None]
        out[..., :3, :3] = c * np.eye(3) + s * skew(u) + (1.0 - c) * np.outer(u, u)
    else:
        out[..., :3, :3] = np.eye(3)
        out[..., :3, 3] = x[..., None] * u
    return out


def forward_kinematics(chain, q):
    """T_l(q) (..., N, 4, 4) of every body: products of homogeneous transforms (Layout)."""
    q = np.asarray(q)
    t = np.broadcast_to(np.eye(4), q.shape[:-1] + (4, 4))
    out = []
    for k, joint in enumerate(chain.joints):
        t = t @ joint.before @ _joint_transform(joint, q[..., k]) @ joint.after
        out.append(t)
    return np.stack(out, -3)


def _vee(w):
    return np.stack([w[..., 2, 1], w[..., 0, 2], w[..., 1, 0]], -1)


def _body_twist(t, dt):
    """(R^T dz, vee(R^T dR)) (..., 6) of frames t and their derivatives dt (..., 4, 4)."""
    rt = np.swapaxes(t[..., :3, :3], -1, -2)
    return np.concatenate([(rt @ dt[..., :3, 3:])[..., 0], _vee(rt @ dt[..., :3, :3])], -1)


def twists_of_forward_kinematics(chain, q):
    """QJ (..., 6N, n) from complex steps of the forward kinematics in each coordinate."""
    q = np.asarray(q, float)
    n = chain.n
    t = forward_kinematics(chain, q)  # (..., N, 4, 4)
    steps = q[..., None, :] + 1j * COMPLEX_STEP * np.eye(n)  # (..., n_k, n)
    dt = forward_kinematics(chain, steps).imag / COMPLEX_STEP  # (..., n_k, N, 4, 4)
    columns = _body_twist(t[..., None, :, :, :], dt)  # (..., n_k, N, 6)
    return np.moveaxis(columns, -3, -1).reshape(q.shape[:-1] + (6 * n, n))


def _relative(a, b, axes):
    return np.sqrt((np.abs(a - b) ** 2).sum(axes)) / np.maximum(np.sqrt((np.abs(b) ** 2).sum(axes)),
                                                                np.finfo(float).tiny)


def _jacobian_derivative(chain, q):
    """(dQJ/dq (..., 6N, n, n) of the forward kinematics' QJ, relative error estimate (...,)).

    Central differences at steps h, h/2, h/4 (h = FD_STEP max(1, |q_j|)), Richardson-extrapolated twice; the
    difference of the two extrapolations bounds the error of the finer one for smooth QJ, plus rounding."""
    n = chain.n
    h = FD_STEP * np.maximum(1.0, np.abs(q))[..., None, :] * np.eye(n)  # (..., n_j, n)
    width = np.diagonal(h, axis1=-2, axis2=-1)[..., :, None, None]

    def central(scale):
        step = h * scale
        plus = twists_of_forward_kinematics(chain, q[..., None, :] + step)  # (..., n_j, 6N, n)
        return (plus - twists_of_forward_kinematics(chain, q[..., None, :] - step)) / (2 * width * scale)

    d1, d2, d4 = central(1.0), central(0.5), central(0.25)
    coarse, fine = (4 * d2 - d1) / 3, (4 * d4 - d2) / 3
    size = np.sqrt((twists_of_forward_kinematics(chain, q) ** 2).sum((-2, -1)))
    error = np.sqrt(((fine - coarse) ** 2).sum((-3, -2, -1))) + 64 * EPS * size / (FD_STEP / 4)
    derivative = np.moveaxis(fine, -3, -1)
    return derivative, error / np.maximum(np.sqrt((derivative ** 2).sum((-3, -2, -1))), np.finfo(float).tiny)


def references(chain, q, q_dot):
    """What the forward kinematics say at configurations q and velocities q_dot (K, n): frames (K, N, 3, 4), QJ,
    the body twists along q_dot, dQJ/dq and its relative error estimate."""
    frames = forward_kinematics(chain, q)
    moved = forward_kinematics(chain, q + 1j * COMPLEX_STEP * q_dot).imag / COMPLEX_STEP
    dqj, error = _jacobian_derivative(chain, q)
    return {"frames": frames[..., :3, :], "qj": twists_of_forward_kinematics(chain, q),
            "twists": _body_twist(frames, moved).reshape(len(q), -1), "dqj": dqj, "error": error}


def kinematics_residuals(chain, q, q_dot, qj=None, dqj=None, reference=None):
    """{property: (relative residuals (K,), resolutions (K,))} of the chain's frames, QJ (``qj``), body twists and
    dQJ/dq (``dqj``) against :func:`references` (each computed when None)."""
    qj = chain.body_jacobian(q) if qj is None else qj
    dqj = chain.body_jacobian_derivative(q) if dqj is None else dqj
    ref = references(chain, q, q_dot) if reference is None else reference
    rotations, origins = chain.forward_kinematics(q)
    tolerance = np.full(len(q), TOLERANCE)
    return {PROPERTIES[0]: (_relative(np.concatenate([rotations, origins[..., None]], -1), ref["frames"],
                                      (-3, -2, -1)), tolerance),
            PROPERTIES[1]: (_relative(qj, ref["qj"], (-2, -1)), tolerance),
            PROPERTIES[2]: (_relative((qj @ q_dot[..., None])[..., 0], ref["twists"], (-1,)), tolerance),
            PROPERTIES[3]: (_relative(dqj, ref["dqj"], (-3, -2, -1)), 10 * ref["error"] + TOLERANCE)}


FORWARD_KINEMATICS_CONTROLS = {  # label: (whether QJ, whether dQJ/dq is put off, the property that must see it)
    "QJ off by one part in a million": (True, False, PROPERTIES[1]),
    "dQJ/dq off by one part in a million": (False, True, PROPERTIES[3]),
}
PART = 1e-6  # the negative controls' size


def off_by(x, size):
    """``x`` put off elementwise by PART (|x| + size), with the sign of x (0 counts as +): a perturbation of at least
    one part in a million of x that is never null, also where x vanishes identically (dQJ/dq of a chain of slides
    with identity maps is 0, so a control that only scaled it would change nothing and could not be caught).
    ``size`` (K,) is the size of QJ per configuration (its largest entry)."""
    size = np.reshape(size, np.shape(size) + (1,) * (np.ndim(x) - np.ndim(size)))
    return x + PART * np.where(x < 0, -1.0, 1.0) * (np.abs(x) + size)


def _worst(residuals):
    """(property, index, residual, resolution) closest to its resolution."""
    rows = [(name, int(np.argmax(r / res)), r, res) for name, (r, res) in residuals.items()]
    name, i, r, res = max(rows, key=lambda row: row[2][row[1]] / row[3][row[1]])
    return name, i, float(r[i]), float(res[i])


def _counterexample(check_id, chain, q, q_dot, name, residual, resolution):
    return {"kind": "forward-kinematics", "data": {
        "id": check_id, "chain": chain.to_data(), "q": np.asarray(q).tolist(), "q_dot": np.asarray(q_dot).tolist(),
        "property": name, "residual": residual, "resolution": resolution}}


def _samples(chain, rng, count):
    """Configurations uniform in the chain's box and velocities of unit size per coordinate."""
    lo, hi = chain.coordinate_box()
    return lo + (hi - lo) * rng.random((count, chain.n)), rng.uniform(-1.0, 1.0, (count, chain.n))


def _on_chains(ctx, check_id, chains):
    """Rows, verdicts, first counterexample and controls on named chains, 16 configurations each."""
    rows, verdicts, counterexample, controls = {}, [], None, {label: False for label in FORWARD_KINEMATICS_CONTROLS}
    for name, chain in chains.items():
        q, q_dot = _samples(chain, ctx.rng(f"{check_id}:forward-kinematics:{name}"), 16)
        qj, dqj, reference = chain.body_jacobian(q), chain.body_jacobian_derivative(q), references(chain, q, q_dot)
        residuals = kinematics_residuals(chain, q, q_dot, qj, dqj, reference)
        prop, i, r, res = _worst(residuals)
        verdicts.append(Verdict.VIOLATED if r > res else Verdict.HOLDS)
        rows[name] = {p: quantity(float(v.max()), "residual", "relative, worst over 16 configurations")
                      for p, (v, _) in residuals.items()}
        if r > res and counterexample is None:
            counterexample = _counterexample(check_id, chain, q[i], q_dot[i], prop, r, res)
        size = np.abs(qj).max((-2, -1))
        for label, (a, b, prop) in FORWARD_KINEMATICS_CONTROLS.items():
            wrong, resolution = kinematics_residuals(chain, q, q_dot, off_by(qj, size) if a else qj,
                                                     off_by(dqj, size) if b else dqj, reference)[prop]
            controls[label] |= bool((wrong > resolution).any())
    return rows, verdicts, counterexample, controls


def _hunt_every_map(ctx, check_id):
    """Hunts over random chains of each joint kind with each coordinate map: the worst residual against its
    resolution, as decades of margin."""
    def margin(example):
        chain, q, q_dot = example
        prop, i, r, res = _worst(kinematics_residuals(chain, q, q_dot))
        return float(np.log10(res / max(r, 1e-300)))

    out = {}
    for kind, word in (("R", "revolute"), ("P", "prismatic")):
        for name in COORDINATE_MAPS:
            found = hunt(chains_with_configurations(kind, (name,)), margin, ctx,
                         label=f"forward kinematics {word} {name}", max_examples=max(ctx.profile.examples // 20, 3),
                         phases=NO_SHRINK)
            out[f"{word} joints, {name} map"] = found
    return out


def kinematics_result(ctx, check_id, chains):
    """QJ, dQJ/dq and body twists against forward kinematics on ``chains`` ({name: Chain}) and, in a run
    without a scene, on random chains of every joint kind and coordinate map (hunted once per run)."""
    rows, verdicts, counterexample, controls = _on_chains(ctx, check_id, chains)
    hunts = {} if ctx.scene is not None else ctx.shared(("forward-kinematics hunts",),
                                                        lambda: _hunt_every_map(ctx, check_id))
    for label, found in hunts.items():
        if found.violation is not None:
            chain, q, q_dot = found.violation
            prop, i, r, res = _worst(kinematics_residuals(chain, q, q_dot))
            verdicts.append(Verdict.VIOLATED)
            counterexample = counterexample or _counterexample(check_id, chain, q[i], q_dot[i], prop, r, res)
    missed = [label for label, caught in controls.items() if not caught]
    verdict = combine(verdicts + [Verdict.INCONCLUSIVE if missed else Verdict.HOLDS])
    examples = sum(f.examples for f in hunts.values())
    worst = min((f.worst_margin for f in hunts.values()), default=np.inf)
    summary = (f"QJ, dQJ/dq and body twists agree with the forward kinematics on {', '.join(chains)}"
               + (f" and {examples} random chains of every joint kind and coordinate map (worst margin "
                  f"{worst:.1f} decades)" if hunts else "")
               + f"; {len(controls) - len(missed)}/{len(controls)} perturbations caught")
    if verdict == Verdict.VIOLATED:
        summary = "QJ disagrees with the forward kinematics: " + summary
    evidence = {
        "method": "forward kinematics from homogeneous transforms and the coordinate maps' values only; complex steps "
                  "for QJ and body twists, Richardson central differences of that QJ for dQJ/dq",
        "chains": rows, "tolerance": quantity(TOLERANCE, "tolerance", "relative; dQJ/dq: 10 x the difference error "
                                              "estimate + this"),
        "hunts": {label: {**f.summary(), "margin": "decades of the worst residual below its resolution"}
                  for label, f in hunts.items()},
        "negative_controls": dict(controls),
    }
    return Result(check_id, verdict, summary, evidence, counterexample=counterexample)


def with_kinematics(result, kinematics):
    """``result`` joined with the forward-kinematics cross-check: the combined verdict, its evidence under
    ``QJ_against_forward_kinematics`` and its counterexample where the result has none."""
    verdict = combine([result.verdict, kinematics.verdict])
    result.evidence["QJ_against_forward_kinematics"] = {"verdict": str(kinematics.verdict),
                                                        "summary": kinematics.summary, **kinematics.evidence}
    if kinematics.verdict != Verdict.HOLDS:
        result.summary = f"{kinematics.summary}; {result.summary}"
    if verdict == Verdict.VIOLATED and not (result.verdict == Verdict.VIOLATED and result.counterexample):
        result.counterexample = kinematics.counterexample
    result.verdict = verdict
    return result


@replayer("forward-kinematics")
def replay_forward_kinematics(data, ctx):
    chain = Chain.from_data(data["chain"])
    q, q_dot = (np.asarray(data[k], float)[None] for k in ("q", "q_dot"))
    r = float(kinematics_residuals(chain, q, q_dot)[data["property"]][0][0])
    verdict = Verdict.VIOLATED if r > data["resolution"] else Verdict.HOLDS
    return Result(data["id"], verdict, f"{data['property']}: relative residual {r:.3g} (resolution "
                  f"{data['resolution']:.3g})", {"residual": quantity(r, "residual"),
                                                  "resolution": quantity(data["resolution"], "tolerance")})
