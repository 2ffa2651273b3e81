"""The physically consistent fit: minimise the torque residual r(Theta) over parameters whose bodies are
consistent, f(Phi_l) >= eps I4 (DefTrafoInertialParameters; consistent exactly when f(Phi_l) > 0, Section 2), as an
SDP (CVXPY and Clarabel), with its certificates (:mod:`.certify`).

r(Theta) = Theta^T H Theta - 2 g^T Theta + c (:class:`.problem.NormalEquations`) enters through a factor of H: with
H = V diag(lambda) V^T and the eigenvalues above a rank cut kept, r = s |R Theta - d|^2 + r_0 up to the directions
the data do not excite (R = diag(lambda / s)^(1/2) V^T, d = diag(lambda s)^(-1/2) V^T g, s the least-squares
residual as a scale), minimised as a second-order cone. The unexcited directions N get a regularising weight
``NULL_WEIGHT`` toward the prior (zero without one), so the solution is unique and bounded. Options:

- ``prior`` (a Theta) with ``prior_weight`` w: adds w sum_l D(Phi_l, Phi0_l) (``prior_metric`` "logdet": the log-det
  (Bregman) divergence of the natural adaptive law, -log det f(Phi) + log det f(Phi0) + tr(f(Phi0)^-1 f(Phi)) - 4,
  :class:`inertiaproof.sim.adaptive.NaturalAdaptation`) or w |Phi_l - Phi0_l|^2 ("euclidean"), and w |x - x0|^2 for
  the extra (friction) columns;
- ``ellipsoids`` {body name: Q (4 x 4)}: the bounding-ellipsoid condition tr(Q_l f(Phi_l)) >= 0 (Wensing, Kim and
  Slotine 2017), Q = [[-S^-1, S^-1 c], [c^T S^-1, 1 - c^T S^-1 c]] for the ellipsoid (x - c)^T S^-1 (x - c) <= 1.

The certificates (:mod:`.certify`): each body's f(Phi_l) > 0 for the decimals written, a lower bound on the residual
of every consistent Theta (within the trace bounds and the ellipsoids given) from the dual of the fit without prior
(solved again where one was given), and, where that bound exceeds the least-squares residual beyond the noise, that the
data demand inconsistent inertia.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import cvxpy as cp
import numpy as np

from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse

from .certify import RANK_CUT, certify_fit, default_traces
from .problem import NormalEquations

__all__ = ["ConsistentFit", "consistent_fit", "solve_consistent"]

NULL_WEIGHT = 1e-12  # the weight (relative to lambda_max / s) of the pull toward the prior along them
UNIT_F = pseudo_inertia(np.eye(10))  # f(e_k), (10, 4, 4): f(Phi) = sum_k Phi_k f(e_k)
STATUSES = ("certified", "not certified", "inconsistent data")


@dataclass(frozen=True)
class ConsistentFit:
    """The consistent fit: theta (bodies' Phi, then the extra columns), its residual r(theta) (float64), the
    certified lower bound L on r over every consistent Theta (None where not certified), the format-2 certificates
    (dicts), the status (:data:`STATUSES`), the reason in words, and ``details`` (the numbers behind them: the
    least-squares residual, the rank, the excess threshold kappa, the bounds T_l and B_j of the certified set)."""

    theta: np.ndarray
    residual: float
    lower_bound: float | None
    certificates: list
    status: str
    reason: str
    details: dict = field(default_factory=dict)


def _body_matrices(theta_var, n):
    return [sum(theta_var[10 * l + k] * UNIT_F[k] for k in range(10)) for l in range(n)]


def solve_consistent(ne: NormalEquations, *, eps=1e-6, prior=None, prior_weight=0.0, prior_metric="logdet",
                     ellipsoids=None, trace_bounds=None, cut=RANK_CUT):
    """(theta, mu, nu, the solver's status): the SDP of the module docstring solved by Clarabel, with tr f(Phi_l) <= T_l
    (``trace_bounds``) where given (mu >= 0: their multipliers in r's units; nu those of the ellipsoids); theta with each body's f(Phi_l) clipped to eigenvalues
    >= eps (the solver's tolerance) and the extra columns solved given the bodies."""
    n, p = len(ne.bodies), ne.size
    lam, v = np.linalg.eigh(ne.H)
    top = max(lam[-1], 1e-300)
    keep = lam > cut * top
    vk, lk = v[:, keep], lam[keep]
    theta_ls = vk @ ((vk.T @ ne.g) / lk)
    scale = max(ne.c - float(ne.g @ theta_ls), 1e-12 * abs(ne.c), 1e-300)  # r = scale |R theta - d|^2 + r_0
    reference = np.zeros(p) if prior is None else np.asarray(prior, float)
    theta = cp.Variable(p)
    r_part = np.sqrt(lk / scale)[:, None] * vk.T
    d_part = (vk.T @ ne.g) / np.sqrt(lk * scale)
    null = v[:, ~keep]
    pull = np.sqrt(NULL_WEIGHT * top / scale)
    stack = cp.hstack([r_part @ theta - d_part] + ([pull * (null.T @ (theta - reference))] if null.shape[1] else []))
    f = _body_matrices(theta, n)
    constraints = [fl >> eps * np.eye(4) for fl in f]
    traces = [cp.trace(fl) <= t for fl, t in zip(f, trace_bounds)] if trace_bounds is not None else []
    inside = {ne.bodies.index(name): cp.trace(np.asarray(q, float) @ f[ne.bodies.index(name)]) >= 0
              for name, q in (ellipsoids or {}).items()}
    objective = cp.sum_squares(stack)
    if prior is not None and prior_weight > 0:
        w = prior_weight / scale
        objective += w * cp.sum_squares(theta[10 * n:] - reference[10 * n:])
        for l in range(n):
            phi0 = reference[10 * l:10 * l + 10]
            if prior_metric == "logdet":
                inv0 = np.linalg.inv(pseudo_inertia(phi0))
                objective += w * (cp.trace(inv0 @ f[l]) - cp.log_det(f[l]))
            else:
                objective += w * cp.sum_squares(theta[10 * l:10 * l + 10] - phi0)
    sdp = cp.Problem(cp.Minimize(objective), constraints + traces + list(inside.values()))
    with warnings.catch_warnings():  # an inaccurate solution is no error here: its certificates say what holds
        warnings.simplefilter("ignore", UserWarning)
        sdp.solve(solver="CLARABEL")
    if theta.value is None:
        raise ArithmeticError("the consistent fit's SDP was not solved (Clarabel returned no point)")
    mu = np.array([max(float(c.dual_value), 0.0) * scale for c in traces]) if traces else np.zeros(n)
    nu = np.array([max(float(inside[l].dual_value), 0.0) * scale if l in inside else 0.0 for l in range(n)])
    return _polished(ne, np.asarray(theta.value, float), eps), mu, nu, sdp.status


def _polished(ne, theta, eps):
    """theta with each body's f(Phi_l) clipped to eigenvalues >= eps and the extra columns minimising r given them."""
    n = len(ne.bodies)
    w, u = np.linalg.eigh(pseudo_inertia(theta[:10 * n].reshape(n, 10)))
    bodies = pseudo_inertia_inverse(u @ (np.maximum(w, eps)[..., None] * np.swapaxes(u, -1, -2)))
    theta = np.concatenate([bodies.ravel(), theta[10 * n:]])
    if ne.size > 10 * n:
        b, e = slice(0, 10 * n), slice(10 * n, ne.size)
        rhs = ne.g[e] - ne.H[e, b] @ theta[b]
        theta[e] = np.linalg.lstsq(ne.H[e, e], rhs, rcond=None)[0]
    return theta


def consistent_fit(ne: NormalEquations, *, eps=1e-6, prior=None, prior_weight=0.0, ellipsoids=None,
                   prior_metric="logdet", level=1e-3, trace_bounds=None, extra_bounds=None) -> ConsistentFit:
    """The consistent fit of ``ne`` and its certificates (:func:`.certify.certify_fit`): ``level`` the
    significance of the excess test, ``trace_bounds`` (T_l per body: m_l + tr(I_l)/2 <= T_l, a constraint of the
    fit too) and ``extra_bounds`` (B_j per extra column) the certified set's stated physical bounds (default
    :func:`.certify.default_traces` of the prior, or of a fit without them; B_j ten times the largest |x_j|)."""
    if trace_bounds is None:
        trace = default_traces(ne, prior if prior is not None else solve_consistent(ne, eps=eps, ellipsoids=ellipsoids)[0])
    else:
        trace = np.asarray(trace_bounds, float)
    theta, mu, nu, status = solve_consistent(ne, eps=eps, prior=prior, prior_weight=prior_weight,
                                             prior_metric=prior_metric, ellipsoids=ellipsoids, trace_bounds=trace)
    plain, solver = theta, {"fit": status}
    if prior is not None and prior_weight > 0:
        plain, mu, nu, solver["without prior"] = solve_consistent(ne, eps=eps, ellipsoids=ellipsoids, trace_bounds=trace)
    found = certify_fit(ne, theta, plain, mu, nu, ellipsoids, level=level, trace_bounds=trace,
                        extra_bounds=extra_bounds)
    found["details"]["solver"] = solver
    return ConsistentFit(theta, ne.residual(theta), **found)
