"""One identification from a robot file and a data file: the fits side by side and what they rest on, as a document.

Robot mode: ordinary least squares (:mod:`.ols`, the file's values along what the data do not excite) with its
base parameters (:mod:`.excitation`), and the consistent fit (:func:`.consistent.consistent_fit`, with its
certificates) on the same normal equations (:mod:`.problem`), its certified set stated: each body's bounding ellipsoid
from its links' geometry (:mod:`.bounding`, ``geometry``) and trace bounds a factor over the file's
(:func:`file_traces`); the certificates name the data file by path and SHA-256 (:func:`data_source`). Payload mode (``payload``): the robot's Theta fixed
to the file's, the payload's Phi_p by least squares and by the consistent fit of that one body (:mod:`.payload`);
with ``pickup`` (T0) the windows before T0 and after T0 + ramp, and with a ramp the generalized equation over the
whole run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.errors import InputError
from inertiaproof.model.inertia import center_of_mass, inertia_com

from . import data as data_io
from .ols import body_verdicts, least_squares
from .payload import PayloadFit, envelope_arguments, payload_rows
from .robot import robot_model
from .rows import LinearRows, friction_columns, regressor_blocks, stacked

__all__ = ["SCHEMA", "STILL", "Identification", "identify"]

SCHEMA = "inertiaproof.identify/1"
STILL = 1e-9  # a joint whose |qd| and range of q stay at or below this does not move


@dataclass(frozen=True)
class Identification:
    """The document (JSON-ready), the robot, the samples and the torques: measured and fitted (S, n) of the fit the
    table shows, and the certificates (dicts) to write."""

    document: dict
    robot: object
    samples: object
    fitted: np.ndarray
    theta: np.ndarray | None  # bodies' Phi (N, 10) of the fit shown (robot mode), for a repaired copy
    certificates: list
    fit: object = None  # the robot's LeastSquares (robot mode)


def _floats(x):
    return [float(v) for v in np.asarray(x, dtype=float).ravel()]


def _consistent(ne, eps, prior, prior_weight, ellipsoids=None, trace_bounds=None):
    """(ConsistentFit or None, the document's entry)."""
    try:
        from .consistent import consistent_fit
    except ImportError as exc:
        return None, {"status": "not run", "reason": f"the consistent fit is not available: {exc}"}
    fit = consistent_fit(ne, eps=eps, prior=prior if prior_weight > 0 else None, prior_weight=prior_weight,
                         ellipsoids=ellipsoids or None, trace_bounds=trace_bounds)
    entry = {"status": fit.status, "reason": fit.reason, "residual": float(fit.residual),
             "lower_bound": None if fit.lower_bound is None else float(fit.lower_bound), "theta": _floats(fit.theta),
             "eps": eps, "prior_weight": prior_weight}
    return fit, entry


def _table(bodies, theta, file_theta):
    """Rows per body: mass, CoM and the inertia about the CoM, identified, the file's and the difference."""
    rows = []
    quantities = [("m", lambda p: p[0])] + [(f"c{k + 1}", lambda p, k=k: center_of_mass(p)[k]) for k in range(3)] + [
        (name, lambda p, a=a, b=b: inertia_com(p)[a, b]) for name, (a, b) in
        (("Ic11", (0, 0)), ("Ic22", (1, 1)), ("Ic33", (2, 2)), ("Ic12", (0, 1)), ("Ic23", (1, 2)), ("Ic13", (0, 2)))]
    for name, phi, old in zip(bodies, theta, file_theta):
        for q, f in quantities:
            with np.errstate(all="ignore"):
                a, b = float(f(phi)), float(f(old))
            rows.append({"body": name, "quantity": q, "identified": a, "file": b, "difference": a - b})
    return rows


def _excitation_entry(ex, samples, joints):
    still = [j for k, j in enumerate(joints) if np.abs(samples.qd[:, k]).max() <= STILL
             and np.ptp(samples.q[:, k]) <= STILL]
    return {"rank": ex.rank, "parameters": len(ex.names), "condition": ex.condition,
            "null_tolerance": "sigma_i <= 1e-8 sigma_max of the column-scaled regressor",
            "null_directions": ex.null_directions(), "weakly_excited": ex.weak(), "still_joints": still,
            "identifiable": [n for n, ok in zip(ex.names, ex.identifiable()) if ok]}


def file_traces(robot, factor):
    """T_l = ``factor`` (m_l + tr(I_l)/2) of the file's body l (``factor`` times the largest where that is not
    positive): the certified set's stated trace bounds."""
    traces = robot.theta[:, 0] + robot.theta[:, 4:7].sum(1) / 2
    top = float(traces.max()) if traces.max() > 0 else 1.0
    return [float(factor * (t if t > 0 else top)) for t in traces]


def data_source(data_path, robot_path):
    """{path, sha256, robot} of the data file: the certificates name the data they rest on."""
    import hashlib

    return {"path": str(data_path), "sha256": hashlib.sha256(open(data_path, "rb").read()).hexdigest(),
            "robot": str(robot_path)}


def identify(robot_path, data_path, *, payload=None, pickup=None, ramp=None, friction=False, cutoff=10.0,
             consistent=True, eps=1e-6, prior_weight=0.0, geometry="grown", trace_factor=10.0):
    """The :class:`Identification` of the module docstring; ``geometry`` ("grown", "strict", "off"): each body's
    bounding ellipsoid (:mod:`.bounding`) in the consistent fit; ``trace_factor``: its trace bounds
    (:func:`file_traces`)."""
    header, values, lines = data_io.read_table(data_path)
    keys, numbered = data_io.joint_keys(data_path, header)
    robot = robot_model(robot_path, None if numbered else keys, len(keys) if numbered else None)
    order = [str(k + 1) for k in range(robot.chain.n)] if numbered else list(robot.joints)
    samples = data_io.samples(data_path, header, values, lines, order, cutoff)
    doc = {"schema": SCHEMA, "robot": str(robot_path), "chain": robot.name, "joints": list(robot.joints),
           "bodies": list(robot.bodies), "locked_joints": list(robot.locked), "friction": friction,
           "data": {"path": str(data_path), "samples": samples.count, "t": [float(samples.t[0]), float(samples.t[-1])],
                    "units": "SI: s, rad or m, rad/s or m/s, rad/s^2 or m/s^2, N m or N",
                    "velocities": "given" if samples.derived is None else samples.derived}}
    if payload is not None:
        return _payload_mode(doc, robot, samples, payload, pickup, ramp, friction, consistent, eps)
    if pickup is not None:
        raise InputError("--pickup needs --payload LINK (the link that takes the payload up)")
    blocks = regressor_blocks(robot.chain, samples.q, samples.qd, samples.qdd)
    a, extra = stacked(blocks), ()
    if friction:
        cols, extra = friction_columns(samples.qd, robot.joints)
        a = np.concatenate([a, cols], 1)
    rows = LinearRows(a, samples.tau.reshape(-1), robot.bodies, tuple(extra), robot.chain.n)
    names = rows.column_names()
    reference = np.concatenate([robot.theta.reshape(-1), np.zeros(len(extra))])
    ls = least_squares(rows.a, rows.b, names, reference)
    doc["excitation"] = _excitation_entry(ls.excitation, samples, robot.joints)
    doc["ols"] = {"residual": ls.residual, "torque_noise": ls.sigma, "theta": _floats(ls.theta),
                  "standard_errors": _floats(ls.standard_errors), "bodies": body_verdicts(ls.theta, robot.bodies),
                  "base_parameters": [{"name": n, "value": float(v), "standard_error": float(e)} for n, v, e in
                                      zip(ls.excitation.base_names(), ls.base, ls.base_errors)],
                  "null_space": "the file's values"}
    doc["parameter_names"] = names
    shown, certificates = ls.theta, []
    if consistent:
        ellipsoids, notes = {}, {b: "no ellipsoid: --geometry off" for b in robot.bodies}
        if geometry != "off":
            from .bounding import body_ellipsoids

            ellipsoids = body_ellipsoids(robot, mode=geometry)
            notes = ellipsoids.notes
        traces = file_traces(robot, trace_factor)
        fit, entry = _consistent(rows.normal_equations(data_source(data_path, robot_path)), eps, reference,
                                 prior_weight, dict(ellipsoids), traces)
        entry["geometry"] = {"mode": geometry, "with_ellipsoid": [b for b in robot.bodies if b in ellipsoids],
                             "bodies": notes}
        entry["trace_bounds"] = {"factor": trace_factor, "T": traces,
                                 "meaning": "m_l + tr(I_l)/2 <= T_l = factor (m_l + tr(I_l)/2 of the file)"}
        doc["consistent"] = entry
        if fit is not None:
            entry["bodies"] = body_verdicts(fit.theta, robot.bodies)
            shown, certificates = np.asarray(fit.theta, dtype=float), list(fit.certificates)
    else:
        doc["consistent"] = {"status": "not run", "reason": "--ols: ordinary least squares only"}
    doc["shown"] = "consistent" if shown is not ls.theta else "ols"
    bodies_theta = shown[:10 * robot.chain.n].reshape(robot.chain.n, 10)
    doc["table"] = _table(robot.bodies, bodies_theta, robot.theta)
    if friction:
        doc["friction_parameters"] = dict(zip(extra, _floats(shown[10 * robot.chain.n:])))
    return Identification(doc, robot, samples, rows.torques(shown), bodies_theta, certificates, ls)


def _payload_entry(fit_ls, rows, link, robot_path, consistent, eps, window, data_path=None):
    entry = {"window": window, "samples": rows.b.size // rows.joints, "ols": {
        "phi": _floats(fit_ls.theta[:10]), "standard_errors": _floats(fit_ls.standard_errors[:10]),
        "residual": fit_ls.residual, "torque_noise": fit_ls.sigma,
        "verdict": body_verdicts(fit_ls.theta[:10], (link,))[0]}}
    if len(fit_ls.theta) > 10:
        entry["ols"]["friction"] = dict(zip(rows.extra, _floats(fit_ls.theta[10:])))
    theta, cert = fit_ls.theta, []
    if consistent:
        source = {"window": window, **(data_source(data_path, robot_path) if data_path else {})}
        fit, c = _consistent(rows.normal_equations(source), eps, None, 0.0)
        entry["consistent"] = c
        if fit is not None:
            c["verdict"] = body_verdicts(fit.theta[:10], (link,))[0]
            theta, cert = np.asarray(fit.theta, dtype=float), list(fit.certificates)
    shown = PayloadFit(link, "", window, fit_ls.theta[:10], fit_ls.covariance[:10, :10], fit_ls.sigma,
                       entry["samples"], None)
    entry["envelope"] = envelope_arguments(shown, robot_path)
    return entry, theta, cert


def _payload_mode(doc, robot, samples, link, pickup, ramp, friction, consistent, eps):
    body, _ = robot.body_of(link)
    doc["payload"] = {"link": link, "body": robot.bodies[body], "frame": f"{link}'s frame (Phi about its origin)",
                      "fits": []}
    windows = [("all samples", np.ones(samples.count, dtype=bool))]
    if pickup is not None:
        after = pickup + (ramp or 0.0)
        windows = [(f"before t = {pickup:g} s", samples.t < pickup), (f"after t = {after:g} s", samples.t >= after)]
    certificates, fitted, theta_shown = [], np.full_like(samples.tau, np.nan), None
    for window, keep in windows:
        if keep.sum() < 2:
            raise InputError(f"{samples.path}: the window {window} holds {int(keep.sum())} samples")
        part = samples.window(keep)
        rows = payload_rows(robot, part, link, friction=friction)
        ls = least_squares(rows.a, rows.b, rows.column_names())
        entry, theta, cert = _payload_entry(ls, rows, link, doc["robot"], consistent, eps, window,
                                            doc["data"]["path"])
        entry["excitation"] = _excitation_entry(ls.excitation, part, robot.joints)
        doc["payload"]["fits"].append(entry)
        certificates += cert
        fitted[keep] = rows.torques(theta) + (part.tau - rows.b.reshape(-1, rows.joints))  # + A Theta_file
        theta_shown = theta
    if pickup is not None and ramp:
        rows = payload_rows(robot, samples, link, friction=friction, pickup=(pickup, ramp))
        ls = least_squares(rows.a, rows.b, rows.column_names())
        entry, theta, cert = _payload_entry(ls, rows, link, doc["robot"], consistent, eps,
                                            f"whole run, taken up at t = {pickup:g} s over {ramp:g} s (smootherstep; "
                                            "the generalized equation with Thetadot)", doc["data"]["path"])
        doc["payload"]["fits"].append(entry)
        certificates += cert
        fitted = rows.torques(theta) + (samples.tau - rows.b.reshape(-1, rows.joints))
        theta_shown = theta
    doc["payload"]["shown"] = doc["payload"]["fits"][-1]["window"]
    doc["payload"]["phi"] = _floats(theta_shown[:10])
    return Identification(doc, robot, samples, fitted, None, certificates)
