"""Certificates of a consistent fit (issue 50), each re-proved by the independent checker before it is reported.

- Each body: a ``body-spectrum`` certificate (:func:`inertiaproof.bounds.certificate.body_spectrum_certificate`)
  that lambda_min(f(Phi_l)) >= b > 0 for the decimals written: the body is physically consistent (Section 2).
- The fit's quality: a ``residual-bound`` certificate (:mod:`inertiaproof.verify.residual`, whose docstring has the
  proof) that r(Theta) >= L for every Theta in K: f(Phi_l) >= 0, tr f(Phi_l) = m_l + tr(I_l)/2 <= T_l, |x_j| <= B_j
  (the stated bounds, :func:`default_traces`) and tr(Q_l f(Phi_l)) >= 0 for the bounding ellipsoids given. The dual is read off the fit's
  stationarity: at the optimum grad r = 2 (H theta - g) = f^*(Z) with Z_l >= 0 (plus mu_l f^*(I) - nu_l f^*(Q_l), the
  solver's multipliers of the trace bounds and ellipsoids), so Z_l = f^-*(2 (H theta - g)_l + ...),
  clipped to be positive semidefinite (plus tau I, so that the rationals written stay so); y then moves to the
  Lagrangian's minimiser along the excited directions (y - H^+ s), and sigma > -lambda_min(H) (H as written need not
  be semidefinite). L is the checker's own ball's lower end (:func:`inertiaproof.verify.residual.dual_side`).
- Inconsistent data: a ``residual-bound`` certificate of quantity ``excess``: r(Theta) >= (1 + kappa) r(theta_LS)
  on K. If the bodies of the truth are consistent (and in K) and the torques carry independent Gaussian noise, the
  statistic ((r_K - r_LS) / k) / (r_LS / (rows - k)) (k the rank of H) is at most an F(k, rows - k) variable; kappa
  = k / (rows - k) F^-1(1 - level) makes the certified excess a rejection at that level: the data demand an
  inconsistent inertia beyond the noise (wrong kinematics, a missing payload, unmodelled friction).
"""

from __future__ import annotations

import re
from fractions import Fraction

import numpy as np
from scipy import stats

from inertiaproof.bounds.certificate import SCHEMA, body_spectrum_certificate, exact
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.verify import bodies as checked_bodies
from inertiaproof.verify import residual as checked_residual
from inertiaproof.verify.exact import semidefinite
from inertiaproof.verify.outcome import REPROVED

from .problem import NormalEquations

__all__ = ["adjoint_inverse", "body_certificates", "certify_fit", "default_traces", "dual_of", "least_squares",
           "normal_data", "residual_certificate"]

RANK_CUT = 1e-11  # eigenvalues of H below RANK_CUT * lambda_max are directions the data do not excite
SIGMA_MARGIN = 2.0  # sigma = -lambda_min(H) + SIGMA_MARGIN p eps lambda_max, raised 16-fold while not proved
SIGMA_TRIES = 6
BOUND_FACTOR = 10.0  # the default T_l and B_j: this times the largest tr f(Phi_l) and |x_j| of the fit
SYMMETRIC = [(i, j) for i in range(4) for j in range(i, 4)]  # coordinates of sym(4)
ADJOINT = np.array([[pseudo_inertia(np.eye(10)[k])[i, j] * (1 if i == j else 2) for i, j in SYMMETRIC]
                    for k in range(10)])  # f^*(Z)_k = <Z, f(e_k)> = ADJOINT[k] . z over the coordinates z of Z
TRACE = ADJOINT @ [float(i == j) for i, j in SYMMETRIC]  # f^*(I4): tr f(Phi) = TRACE . Phi


def default_traces(ne: NormalEquations, theta):
    """T_l: BOUND_FACTOR times the largest tr f(Phi_l) = m_l + tr(I_l)/2 of the bodies of ``theta`` (the file's
    values, or a fit without trace bounds), for every body."""
    n = len(ne.bodies)
    scale = float(np.abs(np.asarray(theta, float)[:10 * n].reshape(n, 10) @ TRACE).max())
    return np.full(n, BOUND_FACTOR * (scale if scale > 0 else 1.0))


def least_squares(ne: NormalEquations, cut=RANK_CUT):
    """(theta, rank): the minimum-norm minimiser of r over the eigen-directions of H above ``cut`` lambda_max."""
    lam, v = np.linalg.eigh(ne.H)
    keep = lam > cut * max(lam[-1], 0.0)
    return v[:, keep] @ ((v[:, keep].T @ ne.g) / lam[keep]), int(keep.sum())


def adjoint_inverse(x):
    """The symmetric Z (4 x 4) with f^*(Z) = x (f is a bijection of R^10 and sym(4), so is its adjoint)."""
    z = np.linalg.solve(ADJOINT, np.asarray(x, float))
    out = np.zeros((4, 4))
    for value, (i, j) in zip(z, SYMMETRIC):
        out[i, j] = out[j, i] = value
    return out


def _psd(z):
    """z clipped to its positive part plus tau I, tau raised until the float matrix is exactly semidefinite."""
    w, u = np.linalg.eigh(z)
    clipped = (u * np.maximum(w, 0.0)) @ u.T
    tau = 1e-14 * max(np.abs(w).max(), 1e-300)
    while True:
        out = clipped + tau * np.eye(4)
        out = (out + out.T) / 2
        if semidefinite([[Fraction(x) for x in row] for row in out]):
            return out
        tau *= 10


def _star(a):
    return ADJOINT @ [a[i, j] for i, j in SYMMETRIC]


def dual_of(ne: NormalEquations, theta, mu=None, nu=None, qs=None, cut=RANK_CUT):
    """(Z_l, mu_l, nu_l per body, y, sigma) of the module docstring from the fit ``theta`` (float64) and the
    multipliers ``mu`` of its trace bounds and ``nu`` of its ellipsoids ``qs`` (4 x 4 per body, zero where none):
    F^*Z = grad r + mu f^*(I) - nu f^*(Q) at the optimum."""
    n = len(ne.bodies)
    mu = np.zeros(n) if mu is None else np.maximum(np.asarray(mu, float), 0.0)
    nu = np.zeros(n) if nu is None else np.maximum(np.asarray(nu, float), 0.0)
    qs = np.zeros((n, 4, 4)) if qs is None else np.asarray(qs, float)
    grad = 2.0 * (ne.H @ theta - ne.g)
    zs = [_psd(adjoint_inverse(grad[10 * l:10 * l + 10] + mu[l] * TRACE - nu[l] * _star(qs[l]))) for l in range(n)]
    gp = ne.g.copy()
    gp[:10 * n] += 0.5 * np.concatenate([_star(z - m * np.eye(4) + v * q) for z, m, v, q in zip(zs, mu, nu, qs)])
    lam, v = np.linalg.eigh(ne.H)
    keep = lam > cut * max(lam[-1], 0.0)
    y = np.asarray(theta, float).copy()
    for _ in range(2):  # the Lagrangian's minimiser along the excited directions (one refinement step)
        s = ne.H @ y - gp
        y = y - v[:, keep] @ ((v[:, keep].T @ s) / lam[keep])
    sigma = max(0.0, -lam[0]) + SIGMA_MARGIN * ne.size * np.finfo(float).eps * max(abs(lam[-1]), abs(lam[0]), 1e-300)
    return zs, mu, nu, qs, y, sigma


def _rows(a):
    return [[exact(x) for x in row] for row in np.asarray(a, float)]


def normal_data(ne: NormalEquations):
    """The certificate's ``data``: H (symmetrised: (H + H^T)/2 in float64), g, c as the exact rationals of their
    floats, the rows, the names of the columns and the source's path and SHA-256 where it has them."""
    h = np.asarray(ne.H, float)
    data = {"H": _rows((h + h.T) / 2), "g": [exact(x) for x in ne.g], "c": exact(ne.c), "rows": int(ne.rows),
            "bodies": list(ne.bodies), "extra": list(ne.extra)}
    source = ne.source or {}
    if isinstance(source.get("path"), str) and re.fullmatch(r"[0-9a-f]{64}", str(source.get("sha256"))):
        data["source"] = {"path": source["path"], "sha256": source["sha256"]}
    return data


def residual_certificate(data, quantity, bound, dual, trace, extra, reference=None, provenance=""):
    """The ``residual-bound`` certificate (dict) of ``quantity`` ("lower", "excess") and ``bound`` (a Fraction) on
    ``data`` (:func:`normal_data`)."""
    zs, mu, nu, qs, y, sigma = dual
    return {"schema": SCHEMA, "claim": {"kind": "residual-bound", "quantity": quantity, "bound": str(bound)},
            "data": data, "bounds": {"trace": [exact(t) for t in trace], "extra": [exact(b) for b in extra],
                                     **({"ellipsoids": [_rows(q) for q in qs]} if np.any(qs) else {})},
            "dual": {"Z": [_rows(z) for z in zs], "mu": [exact(m) for m in mu], "theta": [exact(x) for x in y],
                     "sigma": exact(sigma), **({"nu": [exact(v) for v in nu]} if np.any(qs) else {})},
            **({} if reference is None else {"reference": [exact(x) for x in reference]}),
            "provenance": provenance}


def body_certificates(ne: NormalEquations, theta):
    """One ``body-spectrum`` certificate per body (None where f(Phi_l) is not found positive definite): lambda_min(
    f(Phi_l)) >= half the float lambda_min, confirmed in exact arithmetic by the checker's own decision."""
    out = []
    for l, name in enumerate(ne.bodies):
        row = np.asarray(theta[10 * l:10 * l + 10], float)
        low = float(np.linalg.eigvalsh(pseudo_inertia(row))[0])
        cert = body_spectrum_certificate(row[None, None, :], "lmin_f", Fraction(low) / 2,
                                         f"consistent fit: body {name}") if low > 0 else None
        ok = cert is not None and checked_bodies.prove(cert).status == REPROVED
        out.append(cert if ok else None)
    return out


def _lower_end(ball):
    """A float at most the lower end of the ball."""
    return float(np.nextafter(np.nextafter(float(ball.lower()), -np.inf), -np.inf))


def certify_fit(ne: NormalEquations, theta, plain=None, mu=None, nu=None, ellipsoids=None, *, level=1e-3,
                trace_bounds=None, extra_bounds=None):
    """The fields lower_bound, certificates, status, reason, details of a :class:`.consistent.ConsistentFit` of
    ``theta``; the dual from ``plain`` (the fit without prior; ``theta`` itself by default) and ``mu``
    (the multipliers of its trace bounds T_l, ``trace_bounds``, default :func:`default_traces`)."""
    n = len(ne.bodies)
    plain = np.asarray(theta if plain is None else plain, float)
    trace = [float(t) for t in (default_traces(ne, plain) if trace_bounds is None else trace_bounds)]
    friction = np.abs(plain[10 * n:])
    extra = list(extra_bounds) if extra_bounds is not None else \
        [BOUND_FACTOR * float(friction.max() if friction.size and friction.max() > 0 else 1.0)] * friction.size
    residual = ne.residual(theta)
    theta_ls, rank = least_squares(ne)
    r_ls = ne.residual(theta_ls)
    dof = ne.rows - rank
    kappa = rank / dof * float(stats.f.ppf(1.0 - level, rank, dof)) * (1 + 1e-9) if dof > 0 else None
    details = {"least_squares_residual": r_ls, "rank": rank, "kappa": kappa, "level": level,
               "trace_bounds": trace, "extra_bounds": extra}
    bodies = body_certificates(ne, theta)
    certificates = [c for c in bodies if c is not None]
    missing = [name for name, c in zip(ne.bodies, bodies) if c is None]
    qs = np.zeros((n, 4, 4))
    for name, q in (ellipsoids or {}).items():
        q = np.asarray(q, float)
        qs[ne.bodies.index(name)] = (q + q.T) / 2
    data, dual = normal_data(ne), dual_of(ne, plain, mu, nu, qs)
    for _ in range(SIGMA_TRIES):  # sigma raised until the checker's LDL^T proves H + sigma I > 0
        low, why = checked_residual.dual_side(checked_residual.parse(residual_certificate(data, "lower", 0, dual, trace,
                                                                                          extra)))
        if low is not None or not why.startswith("H + sigma I"):
            break
        dual = (*dual[:5], dual[5] * 16)
    lower = None
    if low is not None:
        lower = _lower_end(low)
        cert = residual_certificate(data, "lower", Fraction(lower), dual, trace, extra,
                                    provenance="the dual of the consistent fit's stationarity (identify.certify)")
        if checked_residual.prove(cert).status == REPROVED:
            certificates.append(cert)
        else:
            lower, why = None, "the lower bound's certificate was not re-proved"
    details["lower_bound_why"] = why
    status, reason = "not certified", ""
    if lower is not None and kappa is not None:
        excess = residual_certificate(data, "excess", Fraction(kappa), dual, trace, extra, reference=theta_ls,
                                      provenance=f"F test: kappa = k / (rows - k) F^-1(1 - {level}); k = {rank}, "
                                      f"rows - k = {dof})")
        if lower >= (1 + kappa) * r_ls * (1 + 1e-12) and checked_residual.prove(excess).status == REPROVED:
            certificates.append(excess)
            status = "inconsistent data"
            reason = (f"the data demand an inconsistent inertia beyond the noise: no physically consistent parameters "
                      f"fit them better than {lower:.6g}, more than (1 + {kappa:.3g}) times the least-squares residual "
                      f"{r_ls:.6g} (an F test at level {level}, rank {rank}, {ne.rows} rows); ours reach "
                      f"{residual:.6g}")
    if status != "inconsistent data":
        if lower is None or missing:
            reason = "; ".join(([f"body {', '.join(missing)} not certified consistent"] if missing else [])
                               + ([f"no certified lower bound ({why})"] if lower is None else []))
        else:
            status = "certified"
            reason = (f"every body certified consistent; no physically consistent parameters fit these data better "
                      f"than {lower:.6g}; ours reach {residual:.6g} "
                      f"({100 * (residual - lower) / max(residual, 1e-300):.3g}%"
                      f" above)")
    return {"lower_bound": lower, "certificates": certificates, "status": status, "reason": reason,
            "details": details}
