"""What an adaptive run did, as time series: tracking error, parameter error, the spectra of f(Phi_hat_l) and of
the estimated mass matrix M(q, Theta_hat(t)) (MassMatrix), along the run and over sampled configurations.

All functions are batched over the run's samples; eigenvalues of the symmetric 4x4 and n x n matrices by eigvalsh.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.dynamics import composite
from inertiaproof.model.inertia import pseudo_inertia

__all__ = ["configurations", "estimates", "mass_matrix_spectrum", "series", "spectrum_over"]


def estimates(run):
    """Theta_hat (T, N, 10) of a run's samples."""
    n = run.spec.reference.home.size
    z = run.y[:, 2 * n:-1].reshape(len(run.t), -1, 10)
    return run.spec.law.estimate(z)


def configurations(chain, count, rng):
    """``count`` configurations drawn uniformly from the chain's coordinate box."""
    lo, hi = chain.coordinate_box()
    return lo + (hi - lo) * rng.random((count, chain.n))


def mass_matrix_spectrum(mass):
    """(lambda_min, lambda_max) of mass matrices (..., n, n), e.g. M(q, Theta_hat) of composite.mass_matrix."""
    w = np.linalg.eigvalsh(mass)
    return w[..., 0], w[..., -1]


def spectrum_over(chain, q_run, theta_hat, q_samples):
    """Per sample time: (lambda_min, lambda_max) of M(q, Theta_hat(t)) over q in {q(t)} and ``q_samples``, and the
    configuration attaining the minimum: a sampled inf and sup over configurations (one-sided estimates)."""
    q = np.concatenate([q_run[:, None, :], np.broadcast_to(q_samples, (len(q_run),) + q_samples.shape)], 1)
    low, high = mass_matrix_spectrum(composite.mass_matrix(chain, q, theta_hat[:, None]))
    at = np.argmin(low, -1)
    return low.min(-1), high.max(-1), q[np.arange(len(q_run)), at]


def series(chain, run, batch, q_samples=None):
    """The time series of a run (plain arrays keyed by name): t, q, q_d, e, |e|, parameter error, the spectra of
    f(Phi_hat_l) (T, N) and of M(q(t), Theta_hat(t)), with ``q_samples`` also their sampled extremes over q."""
    n = chain.n
    t, q = run.t, run.y[:, :n]
    index = run.index
    q_d = batch.reference(t[:, None])[0][:, index]
    theta = batch.parameters(t[:, None] * np.ones(len(batch.specs))).theta[:, index]
    theta_hat = estimates(run)
    f_hat = np.linalg.eigvalsh(pseudo_inertia(theta_hat))
    low, high = mass_matrix_spectrum(composite.mass_matrix(chain, q, theta_hat))
    error = pseudo_inertia(theta_hat - theta)
    out = {
        "t": t, "q": q, "q_d": q_d, "e": q - q_d, "tracking_error": np.linalg.norm(q - q_d, axis=-1),
        "parameter_error": np.linalg.norm(error, axis=(-2, -1)).sum(-1) / np.linalg.norm(
            pseudo_inertia(theta), axis=(-2, -1)).sum(-1),
        "lambda_min_f_hat": f_hat[..., 0], "lambda_max_f_hat": f_hat[..., -1],
        "lambda_min_M_hat": low, "lambda_max_M_hat": high,
    }
    if q_samples is not None:
        out["inf_lambda_min_M_hat"], out["sup_lambda_max_M_hat"], _ = spectrum_over(chain, q, theta_hat, q_samples)
    return out
