"""The constants of Theorems 2 and 3 for a chain and parameters, and the entry point for audits (:func:`mass_matrix_bounds`)."""

from __future__ import annotations

import numpy as np

from inertiaproof.citation import Certificate
from inertiaproof.model.inertia import pseudo_inertia, spatial_inertia

from . import formulas
from .certificate import product_certificate
from .configuration import jacobian_normality, jacobian_sup, mass_inf, mass_sup
from .extremes import Bracket
from .spectral import spectral

__all__ = ["bracket_certificate", "lower_constants", "mass_matrix_bounds", "paper_product", "sharpest", "upper_constants"]

ROUNDING = 8 * np.finfo(float).eps  # relative allowance by which a paper constant computed in floats from certified
# ingredients is moved outward before it is reported: its few roundings (eps/2 each) cannot carry it past the exact
# product, which the independent checker compares with it exactly


def mass_matrix_bounds(chain, theta, *, samples=2000, rounds=20, rng=None, progress=None):
    """alpha1 and alpha2 of Theorems 2 and 3 (paper and sharpest certified) and the observed eigenvalue extremes of
    M(q, theta) for constant parameters ``theta`` (N, 10) over the chain's joint limits.

    Returns a plain dict: for each of "lower" and "upper": paper (the paper's
    constant from bracketed ingredients: value, lower, upper), certified (the
    sharpest constant the suite certifies and how), observed (the bracket of the
    true extreme: lower, upper, witness). Unlimited prismatic joints give an
    unbounded domain: the upper extreme may be infinite and is not certified.
    """
    rng = np.random.default_rng(0) if rng is None else rng
    theta = np.asarray(theta, float)
    kw = dict(samples=samples, rounds=rounds, rng=rng, progress=progress)
    f = pseudo_inertia(theta)
    z = spatial_inertia(theta)
    xi, zeta = float(spectral(f, "lmin").min()), float(spectral(f, "lmax").max())
    z_min, z_max = float(spectral(z, "lmin").min()), float(spectral(z, "lmax").max())
    gamma = jacobian_normality(chain, **kw)
    sigma = jacobian_sup(chain, **kw)
    low = mass_inf(chain, theta[None], **kw)
    high = mass_sup(chain, theta[None], **kw)
    return {
        "ingredients": {"xi": xi, "zeta": zeta, "lambda_min_Z": z_min, "lambda_max_Z": z_max,
                        "inf_sigma_min_QJ_sq": _bracket_data(gamma), "sup_sigma_max_QJ": _bracket_data(sigma)},
        "lower": lower_constants(xi, z_min, gamma, low),
        "upper": upper_constants(zeta, z_max, sigma, high),
    }


def bracket_certificate(b: Bracket):
    """The certificate of a bracket's certified side (:meth:`Bracket.certificate`, a
    :class:`inertiaproof.citation.Certificate`), or None."""
    return b.certificate()


def paper_product(sense, value, formula, ingredients, declared=None):
    """(reported, certificate): the paper's constant ``value`` (computed in floats from the certified ingredients)
    moved outward by :data:`ROUNDING` (down for a ``sense`` "lower" bound, up for "upper"), and the ``product``
    certificate of it (:func:`.certificate.product_certificate`; ``formula``, ``ingredients``, ``declared`` as
    there) as a :class:`inertiaproof.citation.Certificate`, or None."""
    if not np.isfinite(value):
        return value, None
    reported = float(value - ROUNDING * abs(value) if sense == "lower" else value + ROUNDING * abs(value))
    return reported, Certificate.of(product_certificate(
        ">=" if sense == "lower" else "<=", reported, formula, ingredients,
        f"the paper's formula on the ingredients' certified sides, computed in floats and moved outward by 8 eps "
        f"relative ({'down' if sense == 'lower' else 'up'}); decided exactly by the checker", declared))


def _bracket_data(b: Bracket):
    return {"lower": b.lower, "upper": b.upper, "witness": np.asarray(b.witness).tolist(), "note": b.note,
            "convergence": b.convergence}


def lower_constants(xi, z_min, gamma: Bracket, observed: Bracket, xi_observed=None, xi_certificate=None,
                    z_certificate=None):
    """Theorem 2: the paper's alpha1 = xi gamma and the sharpest certified constant (formulas.alpha1, alpha1_z).

    ``xi`` is min_l inf_t lambda_min(f(Phi_l)) (a certified lower bound; for constant Phi exact), ``xi_observed``
    its observed value (default: xi), ``z_min`` a certified min_l inf_t lambda_min(Z(Phi_l)), ``gamma`` the
    bracket of inf_q sigma_min(QJ)^2, ``observed`` that of inf lambda_min(M). The paper's alpha1 lies in
    [paper.lower, paper.upper]: its ingredients at their certified sides (moved down by :data:`ROUNDING`) and at
    their observed values; paper.value is the upper end (observed ingredients), an estimate, not the paper's
    constant itself. With ``xi_certificate`` (xi's ``body-spectrum`` certificate) and gamma's, paper.certificate
    is the ``product`` certificate of paper.lower; certified.certificate is that of the sharpest certified constant
    (with ``z_certificate``, z_min's, where the structural product is the sharpest).
    """
    xi_observed = xi if xi_observed is None else xi_observed
    observed_value = formulas.alpha1(xi_observed, gamma.upper)
    lower, certificate = paper_product(
        "lower", formulas.alpha1(xi, max(gamma.lower, 0.0)), "alpha1", [xi_certificate, bracket_certificate(gamma)])
    paper = {"value": observed_value, "lower": lower, "upper": observed_value,
             "note": "min_l inf_t lambda_min(f(Phi_l)) inf_q lambda_min((QJ)^T QJ) lies in [lower, upper] (certified, "
                     "observed ingredients; lower moved down by 8 eps relative for the float product); value = upper, "
                     "an upper estimate", **({"certificate": certificate} if certificate else {})}
    structural = paper_product("lower", formulas.alpha1_z(z_min, max(gamma.lower, 0.0)), "alpha1_z",
                               [z_certificate, bracket_certificate(gamma)])
    direct = observed.lower if np.isfinite(observed.lower) else -np.inf
    certified = sharpest(max, [
        (direct, bracket_certificate(observed), "certified lower side of inf lambda_min(M) (branch and bound, or the "
                                                "proof of Theorem 2 with the block-triangular normality floor)"),
        (*structural, "min_l inf_t lambda_min(Z(Phi_l)) times the certified lower side of inf_q sigma_min(QJ)^2 (the "
                      "proof of Theorem 2 at the level of Z)"),
        (lower, certificate, "the paper's alpha1 with certified ingredients")])
    return {"paper": paper, "certified": certified, "observed": _bracket_data(observed)}


def upper_constants(zeta, z_max, sigma: Bracket, observed: Bracket, zeta_observed=None, zeta_certificate=None,
                    z_certificate=None):
    """Theorem 3: the paper's alpha2 = 2 zeta S^2 and the sharpest certified constant (formulas.alpha2, alpha2_z).

    ``zeta`` is max_l sup_t lambda_max(f(Phi_l)) (a certified upper bound), ``zeta_observed`` its observed value
    (default: zeta), ``z_max`` a certified max_l sup_t lambda_max(Z(Phi_l)), ``sigma`` the bracket of
    sup_q sigma_max(QJ), ``observed`` that of sup lambda_max(M). The paper's alpha2 lies in
    [paper.lower, paper.upper] (upper moved up by :data:`ROUNDING`); paper.value is the lower end (observed
    ingredients), an estimate. With ``zeta_certificate`` and sigma's certificate (of sup lambda_max((QJ)^T QJ) <=
    S^2: power 1), paper.certificate is the ``product`` certificate of paper.upper; certified.certificate is that of
    the sharpest certified constant (with ``z_certificate``, z_max's, where the structural product is the sharpest).
    """
    zeta_observed = zeta if zeta_observed is None else zeta_observed
    observed_value = formulas.alpha2(zeta_observed, sigma.lower)
    upper, certificate = paper_product(
        "upper", formulas.alpha2(zeta, sigma.upper), "alpha2", [zeta_certificate, bracket_certificate(sigma)])
    paper = {"value": observed_value, "lower": observed_value, "upper": upper,
             "note": "2 max_l sup_t lambda_max(f(Phi_l)) sup_q sigma_max(QJ)^2 lies in [lower, upper] (observed, "
                     "certified ingredients; upper moved up by 8 eps relative for the float product); value = lower, "
                     "a lower estimate", **({"certificate": certificate} if certificate else {})}
    structural = paper_product("upper", formulas.alpha2_z(z_max, sigma.upper), "alpha2_z",
                               [z_certificate, bracket_certificate(sigma)])
    certified = sharpest(min, [
        (observed.upper, bracket_certificate(observed), "certified upper side of sup lambda_max(M) by branch and bound "
                                                        "(or from lengths)"),
        (*structural, "max_l sup_t lambda_max(Z(Phi_l)) times the certified sup_q sigma_max(QJ)^2 (the proof at the "
                      "level of Z)"),
        (upper, certificate, "the paper's alpha2 with certified ingredients")])
    return {"paper": paper, "certified": certified, "observed": _bracket_data(observed)}


def sharpest(pick, candidates):
    """{value, how, certificate} of the sharpest of the (value, certificate, how) ``candidates`` (``pick`` max for a
    lower bound, min for an upper one), the first of equals."""
    value, certificate, how = pick(candidates, key=lambda c: c[0])
    return {"value": value, "how": how, **({"certificate": certificate} if certificate else {})}
