"""Theorem 5's configuration sups of the skew partials Y_p = dK_p/dq - dK_p/dq^T (DefK): branch and bound with a
first-order Bernstein bound, each certified side citing a ``skew-partials`` certificate."""

from __future__ import annotations

import numpy as np

from .branch import vertex_cost
from .certificate import SkewClaim
from .domain import (
    bernstein_domain,
    certification_obstacle,
    derivative_factors,
    free_coordinates,
    search_box,
)
from .extremes import bracket_extreme
from .families import skew_partials
from .spectral import spectral

__all__ = ["skew_partial_sup"]


def skew_partial_sup(chain, *, samples, rounds, rng, progress=None):
    """Brackets of max_p sup_q sigma_max(Y_p(q)) and of sup_q (sum_p sigma_max(Y_p)^2)^(1/2).

    Y_p has degree <= 1 per coordinate like QJ, so a first-order Bernstein bound
    applies: sigma(Y_p(q)) <= sigma(Y_p(c)) + S rho on a box, with S the sup itself.
    Each certified side cites a ``skew-partials`` certificate (:class:`.certificate.SkewClaim`) carrying the
    partition its branch and bound proved on.
    """
    def sigmas(q):
        return spectral(skew_partials(chain.body_jacobian_derivative(q)), "smax")  # (K, 6N)

    lo, hi = search_box(chain)
    free = free_coordinates(chain)
    obstacle = certification_obstacle(chain)
    factors = derivative_factors(chain, *bernstein_domain(chain), 1)
    same = np.allclose(bernstein_domain(chain)[0][free], lo[free]) and np.allclose(bernstein_domain(chain)[1][free], hi[free])

    def max_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.where(rho < 1, sigmas(c).max(1) / np.maximum(1 - rho, 1e-300), np.inf)

    usable = obstacle is None and same
    worst = bracket_extreme(lambda q: sigmas(q).max(1), max_bound if usable else None, lo, hi, sense="max",
                            quantity_name="max_p sup_q sigma_max(Y_p)", samples=samples, rounds=rounds / 2,
                            rng=rng, free=free, weights=factors, progress=progress, cost=vertex_cost(free),
                            note=obstacle or ("" if same else "joint limits inside a period: no certified side"),
                            partition=True)
    worst.certify = SkewClaim(chain, "max_sigma") if usable else None
    s = worst.certified

    def rss_bound(c, r):
        rho = (r[:, free] * factors[free]).sum(1)
        return np.sqrt(((sigmas(c) + s * rho[:, None]) ** 2).sum(1))

    rss = bracket_extreme(lambda q: np.sqrt((sigmas(q) ** 2).sum(1)),
                          rss_bound if usable and s is not None and np.isfinite(s) else None, lo, hi, sense="max",
                          quantity_name="sup_q (sum_p sigma_max(Y_p)^2)^(1/2)", samples=samples, rounds=rounds / 2,
                          rng=rng, free=free, weights=factors, note=worst.note, cost=vertex_cost(free),
                          partition=True)
    rss.certify = SkewClaim(chain, "rss_sigma") if usable else None
    return worst, rss
