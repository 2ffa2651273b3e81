"""The ``key-step`` claim of Theorems 2-4, decided exactly: L(F) = Z(f^-1(F)) on symmetric 4x4 F is a positive map
and lower I6 <= L(I4) <= upper I6. Then for s >= 0, F >= s I4 gives Z >= s L(I4) >= lower s I6, F <= s I4 gives
Z <= upper s I6, and sigma_max(Z) <= upper sigma_max(F). Positivity: ``choi`` C (24x24, blocks C_ij 6x6) is
symmetric, positive semidefinite and sum_ij X_ij C_ij = L(X) on a basis of sym(4); for X = v v^T that sum is
(v x I6)^T C (v x I6) >= 0, and every X >= 0 is a sum of such.
"""

from flint import fmpq

from .bodies import spatial_inertia
from .exact import rational, rationals, semidefinite
from .outcome import REPROVED, UNPROVED, Outcome, refuted


def _map(f):
    """L(F) = Z(Phi), f(Phi) = F: m = F44, h = F[:3, 3], I = tr(Sigma) I3 - Sigma (theorem:PhysicalConsistency)."""
    tr = f[0][0] + f[1][1] + f[2][2]
    return spatial_inertia([f[3][3], f[0][3], f[1][3], f[2][3], tr - f[0][0], tr - f[1][1], tr - f[2][2], -f[0][1],
                            -f[1][2], -f[0][2]])


def prove(cert):
    """The :class:`Outcome` of the claim."""
    lower, upper = (rational(cert["claim"].get(k), f"claim.{k}") for k in ("lower", "upper"))
    c = rationals(cert.get("choi"), (24, 24), "choi")
    if any(c[i][j] != c[j][i] for i in range(24) for j in range(i)) or not semidefinite(c):
        return Outcome(UNPROVED, "the Choi matrix is not symmetric positive semidefinite (exact arithmetic)", 1)
    for a, b in ((a, b) for a in range(4) for b in range(a, 4)):  # E_ab = (e_a e_b^T + e_b e_a^T) / 2, E_aa
        z = _map([[fmpq(int({r, s} == {a, b})) / (1 if a == b else 2) for s in range(4)] for r in range(4)])
        if any((c[6 * a + r][6 * b + s] + c[6 * b + r][6 * a + s]) / 2 != z[r][s] for r in range(6) for s in range(6)):
            return Outcome(UNPROVED, f"the Choi matrix's map differs from L at the basis element E_{a + 1}{b + 1}", 2)
    z = _map([[fmpq(int(r == s)) for s in range(4)] for r in range(4)])
    for sign, shift, what in ((1, -lower, "L(I4) - lower I6"), (-1, upper, "upper I6 - L(I4)")):
        if not semidefinite(z, sign, shift):
            return refuted(f"{what} is not positive semidefinite (exact arithmetic)", {"F": "I4"},
                           {what: "indefinite"}, 3)
    return Outcome(REPROVED, "the Choi matrix is positive semidefinite and extends L; lower I6 <= L(I4) <= upper "
                   "I6, decided exactly", 3)
