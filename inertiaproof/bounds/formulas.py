"""The constants of Section 4 as functions of their ingredients: one function per constant, used everywhere.

Each constant the suite reports as a bound is computed here and nowhere else, both where the checks evaluate
it with the bracketed ingredients of a chain (inertiaproof.bounds.constants, checks.other_components) and where
the pointwise checks and hunts (checks.pointwise) evaluate it with the ingredients at one configuration q and
time t. The proofs establish each bound pointwise: e.g. (UpperBoundedness) holds because
lambda_max(M(q, Theta(t))) <= 2 max_l lambda_max(f(Phi_l(t))) sigma_max(QJ(q))^2 at every (q, t), and every
formula here is nondecreasing in its ingredients (nonincreasing for the lower bound's), so the pointwise
inequality at every (q, t) with the formula below gives the bound with the suprema (infima) as ingredients.
A formula made false in general (a factor dropped, the constant divided by 10) is therefore broken at some
(q, t) of some chain, which is what the hunts look for.

The paper's constants (as printed in its Theorems 2-5 and Eq. (LumpedAccelerationBounding)):

- ``alpha1(xi, gamma) = xi gamma``: Theorem 2 (LowerBoundedness), xi = min_l inf_t lambda_min(f(Phi_l)),
  gamma = inf_q lambda_min((QJ)^T QJ) = inf_q sigma_min(QJ)^2;
- ``alpha2(zeta, s) = 2 zeta s^2``: Theorem 3 (UpperBoundedness), zeta = max_l sup_t lambda_max(f(Phi_l)),
  s = sup_q sigma_max(QJ); the 2 is the key step f <= zeta I4 => Z <= 2 zeta I6;
- ``chi(mu, s, bodies) = sqrt(69 N) mu s^2``: Theorem 4 (BoundedEffectofVaryingParam), mu = max_l sup_t
  sigma_max(f(Phidot_l));
- ``acceleration(dpsi, s) = dPsi* s``: (LumpedAccelerationBounding), dPsi* = sup_t ||Psidot||;
- ``lumped_velocity(psi, y, rows) = sqrt(6N) Psi* y``: Theorem 5 (BoundedEffectOfLumpedVel), Psi* = sup_t ||Psi||,
  y = max_p sup_q sigma_max(dK_p/dq - dK_p/dq^T), ``rows`` = 6N.

The sharpest constants the suite certifies (the same proofs, one step sharper):

- ``alpha1_z(z_min, gamma) = z_min gamma``: the proof of Theorem 2 at the level of Z, z_min = min_l inf_t
  lambda_min(Z(Phi_l));
- ``alpha2_z(z_max, s) = z_max s^2``: likewise for Theorem 3;
- ``chi_sharp(mu, s) = 2 mu s^2``: the key step's sharp factor 2 (sigma_max(Z(F)) <= 2 sigma_max(F)) and a
  block-diagonal Z, no sqrt(69 N);
- ``chi_z(zdot, s) = zdot s^2``: zdot = max_l sup_t sigma_max(Z(Phidot_l));
- ``lumped_velocity_sharp(psi, y_rss) = Psi* y_rss``: Cauchy-Schwarz before the max over p,
  y_rss = sup_q (sum_p sigma_max(Y_p)^2)^(1/2).

Callers use these through the module (``formulas.alpha2(...)``), so that a test can replace one of them and see
every check that reports or tests it change.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "acceleration", "alpha1", "alpha1_z", "alpha2", "alpha2_z", "chi", "chi_sharp", "chi_z", "KEY_STEP_UPPER",
    "lumped_velocity", "lumped_velocity_sharp",
]

KEY_STEP_UPPER = 2.0  # f <= zeta I4 => Z <= 2 zeta I6 (UpperBoundedness, key step; certified in model.positive_map)


def alpha1(xi, gamma):
    """Theorem 2 (LowerBoundedness): alpha1 = xi gamma."""
    return xi * gamma


def alpha1_z(z_min, gamma):
    """The proof of Theorem 2 at the level of Z: lambda_min(M) >= min_l lambda_min(Z(Phi_l)) sigma_min(QJ)^2."""
    return z_min * gamma


def alpha2(zeta, s):
    """Theorem 3 (UpperBoundedness): alpha2 = 2 zeta s^2 (the 2 of the key step Z <= 2 zeta I6)."""
    return KEY_STEP_UPPER * zeta * s**2


def alpha2_z(z_max, s):
    """The proof of Theorem 3 at the level of Z: lambda_max(M) <= max_l lambda_max(Z(Phi_l)) sigma_max(QJ)^2."""
    return z_max * s**2


def chi(mu, s, bodies):
    """Theorem 4 (BoundedEffectofVaryingParam): chi = sqrt(69 N) mu s^2."""
    return np.sqrt(69.0 * bodies) * mu * s**2


def chi_sharp(mu, s):
    """Theorem 4 with the key step's sharp factor: sigma_max(M(q, Thetadot)) <= 2 mu s^2."""
    return KEY_STEP_UPPER * mu * s**2


def chi_z(zdot, s):
    """Theorem 4 at the level of Z: sigma_max(M(q, Thetadot)) <= max_l sigma_max(Z(Phidot_l)) s^2."""
    return zdot * s**2


def acceleration(dpsi, s):
    """(LumpedAccelerationBounding): ||J^T Q^T Psidot|| <= dPsi* sup_q sigma_max(QJ)."""
    return dpsi * s


def lumped_velocity(psi, y, rows):
    """Theorem 5 (BoundedEffectOfLumpedVel): sqrt(6N) Psi* max_p sup_q sigma_max(Y_p); ``rows`` = 6N."""
    return np.sqrt(rows) * psi * y


def lumped_velocity_sharp(psi, y_rss):
    """Theorem 5, Cauchy-Schwarz before the max over p: Psi* sup_q (sum_p sigma_max(Y_p)^2)^(1/2)."""
    return psi * y_rss
