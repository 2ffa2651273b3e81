"""Tell-tale signs of common authoring mistakes in a link's ``<inertial>``.

Patterns, read off the numbers as written:

- ``negative_mass``; ``massless_with_inertia`` (m = 0 and an inertia);
- ``point_mass`` (m > 0, inertia all zero: degenerate, Thm1-boundary);
- ``negligible_inertia`` (every |I_ij| <= 1e-12 m, in kg m^2 per kg: a body
  smaller than a micrometre; rounding noise around a point mass, often negative);
- ``all_entries_equal`` (the six entries equal: a placeholder; the matrix
  a 11^T has rank one, so its triangle inequality fails).

Hypotheses, tested on a link that is inconsistent and has m > 0 by asking
``physical_consistency`` whether the corrected numbers are consistent (a
degenerate link is not tested: almost any change lifts it off the boundary,
so a hit would explain nothing):

- ``parallel_axis``: the inertia was shifted away from the CoM, e.g. taken
  about the link origin with the parallel-axis term subtracted instead of
  added; W + m S(d)^T S(d), d the CoM offset, is tried. Only this direction
  can help: Sigma(W +- m S(d)^T S(d)) = Sigma(W) +- m d d^T
  (I_Sigma_IsTranslationInvariant), and subtracting a positive semidefinite
  term never makes Sigma positive definite;
- ``power_of_ten``: one entry off by a factor 10^p, |p| <= 3;
- ``products_sign``: products of inertia written with the opposite sign
  convention (+integral of x y instead of -integral of x y).
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.consistency import CONSISTENT, INCONSISTENT, physical_consistency
from inertiaproof.model.inertia import pack, skew

from .repair import ENTRIES, NEGLIGIBLE

__all__ = ["diagnose", "ENTRIES", "entries", "HYPOTHESES", "POWERS"]

POWERS = (-1, 1, -2, 2, -3, 3)
HYPOTHESES = ("parallel_axis", "power_of_ten", "products_sign")


def entries(inertia):
    """The six URDF attributes of a 3x3 inertia, as a dict."""
    return {name: float(inertia[i, j]) for name, (i, j) in ENTRIES.items()}


def _patterns(mass, inertia):
    six = np.array(list(entries(inertia).values()))
    found = []
    if mass < 0:
        found.append({"sign": "negative_mass", "text": f"negative mass {mass:g}"})
    if mass == 0 and six.any():
        found.append({"sign": "massless_with_inertia",
                      "text": "massless link with an inertia: give it its mass, or drop the inertia (a massless frame)"})
    if mass > 0 and not six.any():
        found.append({"sign": "point_mass", "text": "inertia all zero: a point mass, not a solid body"})
    if mass > 0 and six.any() and np.abs(six).max() <= NEGLIGIBLE * mass:
        found.append({"sign": "negligible_inertia",
                      "text": f"inertia entries at most {np.abs(six).max():.2g} kg m^2: rounding noise around a point mass"})
    if six[0] != 0 and np.all(six == six[0]):
        found.append({"sign": "all_entries_equal",
                      "text": f"all six entries equal {six[0]:g}: a placeholder (rank-one matrix)"})
    return found


def _candidates(mass, inertia, offset):
    """(hypothesis, detail, corrected inertia) for one link."""
    shift = mass * (skew(offset).T @ skew(offset))
    if np.any(shift):
        yield "parallel_axis", {}, inertia + shift
    for name, (i, j) in ENTRIES.items():
        if inertia[i, j] == 0:
            continue
        for p in POWERS:
            fixed = inertia.copy()
            fixed[i, j] = fixed[j, i] = inertia[i, j] * 10.0**p
            yield "power_of_ten", {"entry": name, "factor": 10.0**p}, fixed
    flip = 2 * np.diag(np.diag(inertia)) - inertia
    if np.any(flip != inertia):
        yield "products_sign", {}, flip


def _describe(hypothesis, hits, mass, offset):
    if hypothesis == "parallel_axis":
        (detail, inertia, _), = hits
        return {"sign": "parallel_axis", "inertia": entries(inertia),
                "text": f"consistent once the parallel-axis term m(|d|^2 I - d d^T) for the CoM offset "
                        f"|d| = {np.linalg.norm(offset):.3g} m is added: inertia shifted away from the CoM"}
    if hypothesis == "products_sign":
        (detail, inertia, _), = hits
        return {"sign": "products_sign", "inertia": entries(inertia),
                "text": "consistent with ixy, iyz, ixz negated: products of inertia in the opposite sign convention"}
    ranked = sorted(hits, key=lambda h: (abs(np.log10(h[0]["factor"])), -h[2]))
    fixes = [dict(d, triangle_slack_rel=float(s)) for d, _, s in ranked]
    words = [f"{f['entry']} x {f['factor']:g}" for f in fixes]
    more = f" (also {', '.join(words[1:3])}{', ...' if len(words) > 3 else ''})" if len(words) > 1 else ""
    return {"sign": "power_of_ten", "fixes": fixes,
            "text": f"one entry off by a power of ten? consistent with {words[0]}{more}"}


def _testable(mass, verdict):
    return verdict == INCONSISTENT and mass > 0


def diagnose(mass, inertia, offset, verdict):
    """Signs per link: ``mass`` (N,), ``inertia`` (N, 3, 3) about the CoM as written,
    ``offset`` (N, 3) the CoM in inertial axes, ``verdict`` (N,) codes of the as-written Phi.

    Returns per link (signs found, hypotheses tested); every candidate of every
    link goes through one batched ``physical_consistency`` call.
    """
    owners, records, phis = [], [], []
    for k in range(len(mass)):
        if not _testable(mass[k], verdict[k]):
            continue
        for hypothesis, detail, fixed in _candidates(mass[k], inertia[k], offset[k]):
            owners.append(k)
            records.append((hypothesis, detail, fixed))
            phis.append(pack(mass[k], np.zeros(3), fixed))
    found = [_patterns(mass[k], inertia[k]) for k in range(len(mass))]
    tested = [list(HYPOTHESES) if _testable(mass[k], verdict[k]) else [] for k in range(len(mass))]
    if phis:
        check = physical_consistency(np.array(phis), margins=False)
        hits = {}
        for k, (hypothesis, detail, fixed), v, s in zip(owners, records, check.verdict, check.triangle_slack):
            if v == CONSISTENT:
                hits.setdefault((k, hypothesis), []).append((detail, fixed, s))
        for (k, hypothesis), group in sorted(hits.items(), key=lambda kv: (kv[0][0], HYPOTHESES.index(kv[0][1]))):
            found[k].append(_describe(hypothesis, group, mass[k], offset[k]))
    return found, tested
