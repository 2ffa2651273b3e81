"""The nearest consistent inertia: a repair suggestion for a link that is not physically consistent.

With the mass m > 0 and the centre of mass kept, f(Phi) > 0 depends on the
inertia about the CoM alone (fPosDef_IFF_PosMassPosDefSigmaCoM,
I_Sigma_IsTranslationInvariant), so the smallest repair changes I_CoM only.
The suggestion solves the convex program

    minimise ||I - W||_F   subject to   Sigma(I) = tr(I)/2 I3 - I  >=  eps tr(Sigma(I)) I3,

W the inertia about the CoM as written (inertial axes). The constraint asks
for the strict triangle inequalities with a relative slack eps
(SigmaCoMPosDef_IFF_StricTriangleCoM): the ``triangle_slack`` that
``physical_consistency`` reports is then at least eps, far above rounding.
The Frobenius norm is invariant under rotations of the inertial frame, and
||I - W||_2 bounds the change of the rotational kinetic energy
1/2 w^T I w by ||I - W||_2 |w|^2 / 2 for every angular velocity w.

The program is a 3x3 linear matrix inequality with a quadratic objective,
solved by Clarabel on W scaled to unit norm. Where W is zero or negligible
(a point mass, up to rounding noise) or the optimum shrinks to zero, no
nearest consistent inertia exists (every small enough sphere is consistent
and closer), and none is suggested.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from inertiaproof.model.consistency import CONSISTENT, physical_consistency
from inertiaproof.model.inertia import pack

__all__ = [
    "DEFAULT_SLACK", "DIAGONAL", "ENTRIES", "nearest_consistent_inertia", "NEGLIGIBLE", "Repair", "SQRT2", "SVEC",
    "SVEC_SCALE", "written_inertia",
]

DEFAULT_SLACK = 1e-3
# |I_ij| <= 1e-12 m (kg m^2 per kg): a body smaller than a micrometre, i.e. a point mass with rounding noise
NEGLIGIBLE = 1e-12
SQRT2 = np.sqrt(2.0)
# svec order of Clarabel's PSD triangle cone: upper triangle, column by column
SVEC = ((0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2))
SVEC_SCALE = np.array([1.0, SQRT2, 1.0, SQRT2, SQRT2, 1.0])
DIAGONAL = np.array([1.0, 0.0, 1.0, 0.0, 0.0, 1.0])
# URDF's six <inertia> attributes and their places in the 3x3 matrix
ENTRIES = {"ixx": (0, 0), "iyy": (1, 1), "izz": (2, 2), "ixy": (0, 1), "iyz": (1, 2), "ixz": (0, 2)}


@dataclass(frozen=True)
class Repair:
    inertia: np.ndarray | None  # (3, 3) the suggested I_CoM, inertial axes; None: no suggestion
    change_frobenius_rel: float  # ||I - W||_F / ||W||_F
    change_spectral: float  # ||I - W||_2, kg m^2
    triangle_slack: float  # of the suggestion, as physical_consistency reports it
    note: str


def _svec(a):
    return np.array([a[i, j] for i, j in SVEC])


def _matrix(x):
    a = np.zeros((3, 3))
    for k, (i, j) in enumerate(SVEC):
        a[i, j] = a[j, i] = x[k]
    return a


@lru_cache(maxsize=8)
def _program(slack):
    """P, A of Clarabel's form min 1/2 x'Px + q'x, A x + s = 0, s in PSD(3), x = svec entries of I."""
    from scipy import sparse

    p = sparse.csc_matrix(np.diag(2.0 * (1.0 + (1.0 - DIAGONAL))))  # ||X||_F^2 counts off-diagonals twice
    c = 0.5 * (1.0 - slack)
    sigma_of = np.outer(DIAGONAL, c * DIAGONAL) - np.eye(6)  # x -> svec entries of c tr(X) I3 - X
    return p, sparse.csc_matrix(-SVEC_SCALE[:, None] * sigma_of)


def nearest_consistent_inertia(mass, inertia_com, slack=DEFAULT_SLACK):
    """The repair of one link: see the module docstring. ``inertia_com`` is W (3x3)."""
    import clarabel

    w = np.asarray(inertia_com, dtype=float)
    scale = np.linalg.norm(w)
    if not mass > 0:
        return Repair(None, np.nan, np.nan, np.nan, "no repair of the inertia: the mass must be positive first")
    if np.abs(w).max() <= NEGLIGIBLE * mass:
        return Repair(None, np.nan, np.nan, np.nan,
                      "no nearest consistent inertia: a point mass is the limit of ever smaller solids; give the body its size")
    p, a = _program(slack)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-11
    wn = _svec(w / scale)
    q = -(p @ wn)
    solution = clarabel.DefaultSolver(p, q, a, np.zeros(6), [clarabel.PSDTriangleConeT(3)], settings).solve()
    if str(solution.status) != "Solved":
        return Repair(None, np.nan, np.nan, np.nan, f"the convex program ended with status {solution.status}")
    fixed = _matrix(np.asarray(solution.x)) * scale
    if not (w - np.diag(np.diag(w))).any():  # the projection of a diagonal W is diagonal (it commutes with sign flips)
        fixed = np.diag(np.diag(fixed))
    if np.trace(fixed) <= 1e-9 * scale:
        return Repair(None, np.nan, np.nan, np.nan,
                      "no nearest consistent inertia: the closest one shrinks to a point mass")
    verdict = physical_consistency(pack(mass, np.zeros(3), fixed), margins=False)
    if verdict.verdict != CONSISTENT:
        return Repair(None, np.nan, np.nan, np.nan, "the solver's answer is not consistent on its float values")
    change = fixed - w
    return Repair(fixed, float(np.linalg.norm(change) / scale), float(np.linalg.norm(change, 2)),
                  float(verdict.triangle_slack), f"mass and CoM kept; triangle slack >= {slack:g} of tr(I_CoM)")


def written_inertia(mass, inertia, slack=DEFAULT_SLACK):
    """The six entries of a repaired ``inertia`` as decimal strings that are themselves consistent.

    A repair is read back from the file as written, so its printed numbers,
    not its floats, must be consistent: the fewest significant digits (six at
    least) whose values keep a triangle slack of at least ``slack`` / 2,
    decided by :func:`physical_consistency` on the rounded numbers (exact near
    the boundary); else ``repr``, which round-trips the floats themselves.
    Returns ({attribute: text}, triangle slack of the written numbers), or
    None when not even the floats are consistent.
    """
    inertia = np.asarray(inertia, dtype=float)
    for digits in range(6, 18):
        text = {name: _decimal(inertia[i, j], digits) for name, (i, j) in ENTRIES.items()}
        back = np.zeros((3, 3))
        for name, (i, j) in ENTRIES.items():
            back[i, j] = back[j, i] = float(text[name])
        check = physical_consistency(pack(mass, np.zeros(3), back), margins=False)
        if check.verdict == CONSISTENT and (check.triangle_slack >= slack / 2 or digits == 17):
            return text, float(check.triangle_slack)
    return None


def _decimal(x, digits):
    """``x`` with ``digits`` significant digits; at 17, the shortest string that round-trips it."""
    return repr(float(x)) if digits == 17 else f"{x:.{digits}g}"
