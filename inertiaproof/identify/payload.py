"""A payload's Phi_p identified with the robot's own parameters fixed (the paper's time-dependent case).

The body l that carries the link gets Theta_l + Phi_p; with the robot's Theta fixed (the file's), the data give
b - A Theta = A_l T Phi_p (+ friction), where A_l are body l's ten columns and T (10 x 10) maps Phi_p in the
link's frame to body l's frame (:func:`inertiaproof.audit.kinematic_tree.phi_in_frame` is linear in Phi). Taken up
at time T0 over a ramp R with the smootherstep s(t) (:class:`inertiaproof.dynamics.trajectory.Profile`), the
generalized equation (RoboticEquation) reads tau = R(q, qd, qd, qdd) (Theta + s Phi_p) + M(q, s' Phi_p) qd: the
columns become s(t) A_l T + s'(t) A_M,l T over the whole run, A_M,l the mass regressor R_M,l(q, qd) of Thetadot.

What `inertiaproof envelope` needs of the result: the payload's mass m, its CoM c = h / m in the link's frame,
and the radius R0 = sqrt(tr(Sigma_CoM) / m) = sqrt(tr(I_CoM) / (2 m)) of the smallest ball about c whose LMI set
(tr(Q f(Phi)) >= 0: m R^2 >= tr Sigma about the centre) holds Phi_p. The confidence: each of m, c, R0 plus
:data:`SIGMAS` standard errors of the linearised fit (numerical gradient against the covariance), and the radius
sqrt(R0^2 + |k sigma_c|^2) covering the CoM's uncertainty about the centre.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass

import numpy as np

from inertiaproof.audit.kinematic_tree import phi_in_frame
from inertiaproof.dynamics.trajectory import Profile

from .ols import least_squares
from .problem import PHI_NAMES
from .rows import LinearRows, friction_columns, regressor_blocks, stacked

__all__ = ["SIGMAS", "PayloadFit", "envelope_arguments", "link_map", "payload_fit", "payload_rows"]

SIGMAS = 3.0


def link_map(pose):
    """T (10, 10): Phi in the link's frame -> Phi in the body's frame, for the link's pose (4 x 4) in the body."""
    return phi_in_frame(np.eye(10), pose).T


@dataclass(frozen=True)
class PayloadFit:
    link: str
    body: str
    window: str
    phi: np.ndarray  # (10,) in the link's frame
    covariance: np.ndarray  # (10, 10)
    sigma: float
    samples: int
    friction: np.ndarray | None
    ls: object = None

    def summary(self):
        m = float(self.phi[0])
        c = self.phi[1:4] / m if m != 0 else np.full(3, np.nan)
        return {"mass": m, "com": c.tolist(), "phi": self.phi.tolist(),
                "standard_errors": np.sqrt(np.clip(np.diag(self.covariance), 0, None)).tolist(),
                "torque_noise": self.sigma, "samples": self.samples, "window": self.window}


def payload_rows(robot, samples, link, *, friction=False, pickup=None, blocks=None):
    """LinearRows of the payload's ten parameters (named ``link.m`` ...) plus friction, and b - A Theta_file.
    ``pickup``: (T0, ramp) for the generalized equation over a run that takes the payload up."""
    body, pose = robot.body_of(link)
    if pickup is None:
        r = regressor_blocks(robot.chain, samples.q, samples.qd, samples.qdd) if blocks is None else blocks
        carried = stacked(r[:, body:body + 1])
    else:
        r, r_rate = regressor_blocks(robot.chain, samples.q, samples.qd, samples.qdd, rate=True)
        s, s_dot, _ = Profile("smootherstep", pickup[0], pickup[1]).derivatives(samples.t)
        n = robot.chain.n
        carried = (np.repeat(s, n)[:, None] * stacked(r[:, body:body + 1])
                   + np.repeat(s_dot, n)[:, None] * stacked(r_rate[:, body:body + 1]))
    a = carried @ link_map(pose)
    b = samples.tau.reshape(-1) - stacked(r) @ robot.theta.reshape(-1)
    extra = ()
    if friction:
        cols, extra = friction_columns(samples.qd, robot.joints)
        a = np.concatenate([a, cols], 1)
    return LinearRows(a, b, (link,), tuple(extra), robot.chain.n)


def payload_fit(robot, samples, link, *, friction=False, pickup=None, window="all samples"):
    """The :class:`PayloadFit` by ordinary least squares (:func:`.ols.least_squares`, reference 0)."""
    rows = payload_rows(robot, samples, link, friction=friction, pickup=pickup)
    ls = least_squares(rows.a, rows.b, rows.column_names())
    body = robot.bodies[robot.body_of(link)[0]]
    fr = ls.theta[10:] if friction else None
    return PayloadFit(link, body, window, ls.theta[:10], ls.covariance[:10, :10], ls.sigma, samples.count, fr, ls)


def _gradient(f, x, cov):
    """f(x) and its standard error sqrt(g^T cov g), g by central differences."""
    value = f(x)
    g = np.zeros_like(x)
    for j in range(len(x)):
        h = 1e-6 * max(1.0, abs(x[j]))
        e = np.zeros_like(x)
        e[j] = h
        g[j] = (f(x + e) - f(x - e)) / (2 * h)
    return value, float(np.sqrt(max(g @ cov @ g, 0.0)))


def _radius(phi):
    m = phi[0]
    i = np.array([[phi[4], phi[7], phi[9]], [phi[7], phi[5], phi[8]], [phi[9], phi[8], phi[6]]])
    c = phi[1:4] / m
    i_com = i - m * (c @ c * np.eye(3) - np.outer(c, c))
    return float(np.sqrt(max(np.trace(i_com) / (2 * m), 0.0)))


def envelope_arguments(fit, robot_path, sigmas=SIGMAS):
    """The payload's mass, CoM and radius with their confidence, and the `inertiaproof envelope` command for every
    payload within it (mass at most m + k sigma_m within sqrt(R0^2 + |k sigma_c|^2) of the CoM found)."""
    phi, cov = fit.phi, fit.covariance
    m, sm = _gradient(lambda p: p[0], phi, cov)
    if not m > sigmas * sm:
        return {"mass": m, "mass_error": sm, "note": f"no payload found: the identified mass {m:.4g} kg is within "
                f"{sigmas:g} standard errors ({sm:.2g} kg) of 0; no envelope"}
    c = phi[1:4] / m
    sc = [_gradient(lambda p, k=k: p[1 + k] / p[0], phi, cov)[1] for k in range(3)]
    r0, sr = _gradient(_radius, phi, cov)
    mass = m + sigmas * sm
    radius = float(np.sqrt((r0 + sigmas * sr) ** 2 + (sigmas ** 2) * sum(s * s for s in sc)))
    argv = ["envelope", str(robot_path), "--link", fit.link, "--mass", f"{mass:.4g}", "--radius", f"{radius:.4g}",
            "--centre", *(f"{x:.4g}" for x in c)]
    command = "inertiaproof " + " ".join(shlex.quote(a) for a in argv)
    return {"mass": float(m), "mass_error": sm, "com": c.tolist(), "com_errors": sc, "radius": r0, "radius_error": sr,
            "sigmas": sigmas, "mass_bound": float(mass), "radius_bound": radius, "command": command, "argv": argv,
            "parameter_names": [f"{fit.link}.{p}" for p in PHI_NAMES]}
