"""Perron-Frobenius bounds of sup |lambda|_max(M(q, Theta)) from the exact Fourier coefficients of M: the spectral
radius of certified entrywise sups of |M_il| over the search box, one or two coordinates on a grid over their joint
limits (:mod:`inertiaproof.bounds.fourier`)."""

from __future__ import annotations

import numpy as np

from .domain import certification_obstacle
from .families import root_up
from .fourier import (
    PAIR_CELLS,
    SINGLE_CELLS,
    FourierFamily,
    certified_entry_sups,
    perron_of,
)
from .memo import memo
from .spectral import EPS
from .taylor import fourier_terms

__all__ = ["FOURIER_DEEP_ROUNDS", "FOURIER_PAIRS_ROUNDS", "FOURIER_TERMS_PER_ROUND", "fourier_fits",
           "fourier_perron_bound", "fourier_step", "fourier_terms", "tighten_by_fourier"]

FOURIER_PAIRS_ROUNDS = 10  # bracket budgets (rounds) from which pairs of coordinates are gridded too (head entries)
FOURIER_DEEP_ROUNDS = 200  # bracket budgets (rounds) from which four coordinates pair up, on grids twice as fine
FOURIER_TERMS_PER_ROUND = 200_000  # terms 5^m n^2 of M's Fourier series (coefficients times entries) one round of a
# bracket's budget pays for (a budget under one round counts as one): ci's 20 rounds pay for 4e6, a 7-joint chain
# with every coordinate free (5^7 49 = 3.8e6) and not an 8-joint one (5^7 64 = 5.0e6); deep's 800 for every chain


def fourier_fits(chain, rounds):
    """Whether the Fourier strategy's terms (:func:`inertiaproof.bounds.taylor.fourier_terms`; each grid cell of
    :func:`inertiaproof.bounds.fourier.certified_entry_sups` sums over them, for every parameter set) fit the count
    ``FOURIER_TERMS_PER_ROUND`` times the bracket's budget of ``rounds`` (at least one)."""
    return fourier_terms(chain) <= FOURIER_TERMS_PER_ROUND * max(float(rounds), 1.0)


def tighten_by_fourier(result, chain, thetas, rounds, square):
    """``result`` with its certified side tightened by :func:`fourier_step`."""
    result.tighten(*fourier_step(chain, thetas, rounds, square))
    return result


def fourier_step(chain, thetas, rounds, square):
    """(bound, how) of :func:`fourier_perron_bound` (its square root when the bracket is of sigma_max(QJ), ``square``
    False: (QJ)^T QJ is M of unit bodies; there pairs of coordinates only from a budget of ``FOURIER_DEEP_ROUNDS``,
    single ones already close most of the bracket); bound None where M has no Fourier series."""
    if not square and rounds < FOURIER_DEEP_ROUNDS:
        rounds = min(rounds, FOURIER_PAIRS_ROUNDS // 2)
    bound = fourier_perron_bound(chain, thetas, rounds)
    if bound is not None and not square:
        bound = root_up(bound)
    return bound, ("spectral radius of certified sups of |M_il(q)| over the search box from the exact Fourier "
                   "coefficients, one or two coordinates on a grid over their joint limits (Perron-Frobenius; "
                   "inertiaproof.bounds.fourier)" + ("" if square else ", unit bodies, square root"))


def fourier_perron_bound(chain, thetas, rounds=0.0):
    """max_v rho(S_v) >= sup over the search box of |lambda|_max(M(q, Theta_v)), with S from
    :func:`inertiaproof.bounds.fourier.certified_entry_sups` (pairs of three coordinates from a budget of
    ``FOURIER_PAIRS_ROUNDS``; of four, on grids twice as fine, from ``FOURIER_DEEP_ROUNDS``); None where M has no Fourier
    series. Cached by content."""
    if certification_obstacle(chain) is not None:
        return None
    pairs, fine = (0, 1) if rounds < FOURIER_PAIRS_ROUNDS else ((4, 2) if rounds >= FOURIER_DEEP_ROUNDS else (3, 1))
    thetas = np.asarray(thetas, float)
    return memo("perron", chain, (thetas, pairs, fine), lambda: _fourier_perron(chain, thetas, pairs, fine))


def _fourier_perron(chain, thetas, pairs, fine):
    kept = []  # |M(q, -Theta)| = |M(q, Theta)| entrywise (M is linear in Theta): one of each pair +-Theta
    for theta in thetas:
        if not any(np.array_equal(theta, t) or np.array_equal(-theta, t) for t in kept):
            kept.append(theta)
    family = FourierFamily(chain, np.array(kept))
    if not family.usable:
        return None
    s = certified_entry_sups(family, pairs, fine * SINGLE_CELLS, fine * PAIR_CELLS)
    return float(perron_of(s).max() * (1 + 4 * EPS))
