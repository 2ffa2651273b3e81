"""The log-Cholesky fit (Rucker and Wensing, "Smooth Parameterization of Rigid-Body Inertia", IEEE RA-L 7(2), 2022)
beside ordinary least squares and the consistent fit of `inertiaproof identify`, on the same rows.

    python bench/log_cholesky_fit.py ROBOT.urdf DATA.csv [--markdown OUT.md]   (LC_METHOD=trf: trust-region)

Each body's pseudo-inertia f(Phi_l) = U U^T, U = e^alpha [[e^d1, s12, s13, t1], [0, e^d2, s23, t2], [0, 0, e^d3, t3],
[0, 0, 0, 1]] (upper triangular, log-diagonal): every theta in R^10 gives a consistent body, and the fit minimises
|A Phi(theta) - b|^2 over theta unconstrained by scipy.optimize.least_squares (Levenberg-Marquardt, LC_METHOD=trf for trust-region reflective; Jacobian by
the analytic one of U U^T) on the residual's factor R Phi - d (R = diag(lambda)^(1/2) V^T over H = A^T A's eigen-directions
above 1e-11 lambda_max, d = diag(lambda)^(-1/2) V^T A^T b: |A Phi - b|^2 = |R Phi - d|^2 + const; with the consistent
fit's weak pull toward zero along the others), tolerances 1e-10, at most MAX_EVALUATIONS evaluations, from a generic
start (each body 1 kg at its origin, I = 0.01 I3 kg m^2), not from the file's values. It gives no certificate: its
optimum's quality and its consistency margin are what the consistent fit's certificates add.

Reported per fit: the torque residual |A theta - b|^2, the largest error against the truth (the file's values, which
the data were simulated from) over all parameters and over the base parameters (in OLS's standard errors), each
body's lambda_min(f(Phi_l)) sign, and the wall-clock seconds of the fit alone (the rows formed once beforehand).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares as scipy_least_squares

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from inertiaproof.identify import data as data_io
from inertiaproof.identify.bounding import body_ellipsoids
from inertiaproof.identify.consistent import NULL_WEIGHT, consistent_fit
from inertiaproof.identify.ols import least_squares
from inertiaproof.identify.problem import NormalEquations
from inertiaproof.identify.robot import robot_model
from inertiaproof.identify.rows import regressor_blocks, stacked
from inertiaproof.identify.session import file_traces
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse

CUT = 1e-11
MAX_EVALUATIONS = 20000
METHOD = os.environ.get("LC_METHOD", "lm")  # MINPACK Levenberg-Marquardt (the residual has 10 N rows)
UPPER = [(0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3)]  # s12, s13, s23, t1, t2, t3


def upper_factor(theta):
    """U (N, 4, 4) of log-Cholesky parameters (N, 10): alpha, d1, d2, d3, s12, s13, s23, t1, t2, t3."""
    theta = np.asarray(theta, float).reshape(-1, 10)
    u = np.zeros((len(theta), 4, 4))
    for k in range(3):
        u[:, k, k] = np.exp(theta[:, 1 + k])
    for k, (i, j) in enumerate(UPPER):
        u[:, i, j] = theta[:, 4 + k]
    u[:, 3, 3] = 1.0
    return np.exp(theta[:, 0])[:, None, None] * u


def phi_of(theta):
    """Phi (N, 10) of log-Cholesky parameters: f^-1(U U^T)."""
    u = upper_factor(theta)
    return pseudo_inertia_inverse(u @ np.swapaxes(u, -1, -2))


def parameters_of(phi):
    """Log-Cholesky parameters (N, 10) of consistent Phi (N, 10): U from the Cholesky factor of the reversed J."""
    j = pseudo_inertia(np.asarray(phi, float).reshape(-1, 10))
    flip = np.eye(4)[::-1]
    u = flip @ np.linalg.cholesky(flip @ j @ flip) @ flip  # upper triangular, J = U U^T
    scale = u[:, 3, 3]
    out = np.zeros((len(j), 10))
    out[:, 0] = np.log(scale)
    for k in range(3):
        out[:, 1 + k] = np.log(u[:, k, k] / scale)
    for k, (i, jj) in enumerate(UPPER):
        out[:, 4 + k] = u[:, i, jj] / scale
    return out


def phi_jacobian(theta):
    """dPhi_l / dtheta_l (N, 10, 10): d(U U^T) = dU U^T + U dU^T, f^-1 linear; dU/dalpha = U, dU/dd_k = e^alpha e^d_k
    E_kk, dU/ds_ij = e^alpha E_ij."""
    theta = np.asarray(theta, float).reshape(-1, 10)
    u = upper_factor(theta)
    scale = np.exp(theta[:, 0])
    du = np.zeros((len(theta), 10, 4, 4))
    du[:, 0] = u
    for k in range(3):
        du[:, 1 + k, k, k] = scale * np.exp(theta[:, 1 + k])
    for k, (i, j) in enumerate(UPPER):
        du[:, 4 + k, i, j] = scale
    dj = du @ np.swapaxes(u, -1, -2)[:, None] + u[:, None] @ np.swapaxes(du, -1, -2)
    return np.swapaxes(pseudo_inertia_inverse(dj), 1, 2)  # (N, 10 Phi entries, 10 parameters)


def factor(ne):
    """(R, d): R Phi - d stacks the excited part and the consistent fit's pull NULL_WEIGHT toward zero along the
    directions the data do not excite (:mod:`inertiaproof.identify.consistent`), so both minimise the same r."""
    lam, v = np.linalg.eigh(ne.H)
    keep = lam > CUT * lam[-1]
    pull = np.sqrt(NULL_WEIGHT * lam[-1]) * v[:, ~keep].T
    return (np.vstack([np.sqrt(lam[keep])[:, None] * v[:, keep].T, pull]),
            np.concatenate([(v[:, keep].T @ ne.g) / np.sqrt(lam[keep]), np.zeros(len(pull))]))


def log_cholesky_fit(ne, start):
    r, d = factor(ne)
    n = len(ne.bodies)

    def jacobian(x):
        blocks = phi_jacobian(x)
        return np.concatenate([r[:, 10 * l:10 * l + 10] @ blocks[l] for l in range(n)], axis=1)

    found = scipy_least_squares(lambda x: r @ phi_of(x).ravel() - d, parameters_of(start).ravel(), jac=jacobian,
                                method=METHOD, x_scale="jac", xtol=1e-10, ftol=1e-10, gtol=1e-10, max_nfev=MAX_EVALUATIONS)
    return phi_of(found.x).ravel(), found


def rows_of(robot_path, data_path):
    header, values, lines = data_io.read_table(data_path)
    keys, numbered = data_io.joint_keys(data_path, header)
    robot = robot_model(robot_path, None if numbered else keys, len(keys) if numbered else None)
    samples = data_io.samples(data_path, header, values, lines, list(robot.joints), 10.0)
    a = stacked(regressor_blocks(robot.chain, samples.q, samples.qd, samples.qdd))
    return robot, a, samples.tau.reshape(-1)


def compare(robot_path, data_path):
    robot, a, b = rows_of(robot_path, data_path)
    names = [f"{body}.{k}" for body in robot.bodies for k in range(10)]
    truth = robot.theta.ravel()
    ne = NormalEquations.of_rows(a, b, robot.bodies)
    start = time.perf_counter()
    ls = least_squares(a, b, names, truth)
    fits = {"ordinary least squares (file's values along the null space)": (ls.theta, time.perf_counter() - start, "")}
    start = time.perf_counter()
    zero = least_squares(a, b, names)
    fits["ordinary least squares (minimum norm)"] = (zero.theta, time.perf_counter() - start, "")
    start = time.perf_counter()
    ellipsoids = body_ellipsoids(robot)
    fit = consistent_fit(ne, ellipsoids=dict(ellipsoids), trace_bounds=file_traces(robot, 10.0))
    fits["consistent fit (SDP, ellipsoids grown, traces 10x; certified)"] = (
        fit.theta, time.perf_counter() - start, f"{fit.status}; certified lower bound {fit.lower_bound:.6g}"
        if fit.lower_bound is not None else fit.status)
    generic = np.tile([1.0, 0, 0, 0, 0.01, 0.01, 0.01, 0, 0, 0], len(robot.bodies))
    start = time.perf_counter()
    theta, found = log_cholesky_fit(ne, generic)
    fits["log-Cholesky (scipy least_squares, generic start)"] = (theta, time.perf_counter() - start,
                                                                 f"{found.nfev} evaluations, {found.njev} Jacobians: {found.message}")
    base_truth = ls.excitation.base_values(truth)
    rows = []
    for name, (theta, seconds, note) in fits.items():
        lmin = np.linalg.eigvalsh(pseudo_inertia(theta.reshape(-1, 10)))[:, 0]
        base = np.abs(ls.excitation.base_values(theta) - base_truth) / ls.base_errors
        rows.append({"fit": name, "residual": ne.residual(theta), "max_error": float(np.abs(theta - truth).max()),
                     "max_base_error_se": float(base.max()), "consistent": int((lmin > 0).sum()), "lmin": float(lmin.min()),
                     "bodies": len(lmin), "seconds": seconds, "note": note})
    return robot, ls, rows


def markdown(robot_path, data_path, robot, ls, rows):
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    head = (f"Robot {Path(robot_path).name} ({robot.name}, {len(robot.joints)} joints), data {data_path} "
            f"({ls.rows // len(robot.joints)} samples; OLS torque noise {ls.sigma:.4g} N m; rank {ls.excitation.rank} of "
            f"{len(ls.theta)}); load average {load}.")
    columns = ("| fit | residual | max error vs truth | max base-parameter error (OLS s.e.) | bodies consistent "
               "| min lambda_min(f) | seconds | note |")
    out = [head, "", columns, "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['fit']} | {r['residual']:.6g} | {r['max_error']:.3g} | {r['max_base_error_se']:.3g} | "
                   f"{r['consistent']} of {r['bodies']} | {r['lmin']:.3g} | {r['seconds']:.2f} | {r['note']} |")
    return "\n".join(out)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("robot")
    p.add_argument("data")
    p.add_argument("--markdown")
    a = p.parse_args(argv)
    robot, ls, rows = compare(a.robot, a.data)
    text = markdown(a.robot, a.data, robot, ls, rows)
    print(text)
    if a.markdown:
        Path(a.markdown).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
