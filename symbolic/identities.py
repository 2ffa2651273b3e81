"""Section 2 identities as SymPy objects: each function returns (lhs, rhs, symbols).

The checks in ``inertiaproof.checks.identities`` decide lhs == rhs exactly
(expand to a canonical polynomial form); tests feed them perturbed
right-hand sides to see VIOLATED.
"""

from __future__ import annotations

import sympy as sp

__all__ = [
    "geometric_fact", "inertia_of", "inverse_after_sigma", "phi_symbols", "pseudo_inertia",
    "pseudo_inertia_coordinate_matrix", "schur_factorisation", "sigma_after_inverse", "sigma_of", "skew",
    "spectrum_of_inertia", "spectrum_of_sigma", "sym4_coordinates", "symmetric", "translation_invariance",
]


def skew(x):
    """S(x) (paper, Notation)."""
    return sp.Matrix([[0, -x[2], x[1]], [x[2], 0, -x[0]], [-x[1], x[0], 0]])


def symmetric(name):
    """A generic symmetric 3x3 matrix and its six symbols (11, 22, 33, 12, 23, 13), as in (eq:I)."""
    a11, a22, a33, a12, a23, a13 = sp.symbols(f"{name}11 {name}22 {name}33 {name}12 {name}23 {name}13", real=True)
    return sp.Matrix([[a11, a12, a13], [a12, a22, a23], [a13, a23, a33]]), (a11, a22, a33, a12, a23, a13)


def sigma_of(inertia):
    """Sigma = tr(I)/2 I3 - I (DefTrafoInertialParameters)."""
    return inertia.trace() / 2 * sp.eye(3) - inertia


def inertia_of(sigma):
    """I = tr(Sigma) I3 - Sigma (Theorem 1, second part)."""
    return sigma.trace() * sp.eye(3) - sigma


def phi_symbols():
    """m, h (3x1), I (3x3) and the ten symbols of Phi in the paper's order (eq:Phi)."""
    m = sp.Symbol("m", real=True)
    h = sp.Matrix(sp.symbols("h1:4", real=True))
    inertia, (i11, i22, i33, i12, i23, i13) = symmetric("I")
    return m, h, inertia, (m, *h, i11, i22, i33, i12, i23, i13)


def pseudo_inertia(m, h, inertia, sigma=sigma_of):
    """f(Phi) = [[Sigma, h], [h^T, m]] (DefTrafoInertialParameters)."""
    return sp.Matrix(sp.BlockMatrix([[sigma(inertia), h], [h.T, sp.Matrix([[m]])]]))


def geometric_fact():
    """(Tjaja): S(x)^T S(x) = tr(x x^T) I3 - x x^T."""
    x = sp.Matrix(sp.symbols("x1:4", real=True))
    lhs = skew(x).T * skew(x)
    rhs = (x * x.T).trace() * sp.eye(3) - x * x.T
    return lhs, rhs, tuple(x)


def inverse_after_sigma(inverse=inertia_of):
    """Theorem 1, second part: tr(Sigma) I3 - Sigma = I for Sigma = tr(I)/2 I3 - I."""
    inertia, symbols = symmetric("I")
    return inverse(sigma_of(inertia)), inertia, symbols


def sigma_after_inverse(inverse=inertia_of):
    """The other composition: tr(I)/2 I3 - I = Sigma for I = tr(Sigma) I3 - Sigma (both maps are bijections of sym(3))."""
    sigma, symbols = symmetric("S")
    return sigma_of(inverse(sigma)), sigma, symbols


def sym4_coordinates(matrix):
    """The ten coordinates of a symmetric 4x4 matrix: its upper triangle, row by row."""
    return [matrix[i, j] for i in range(4) for j in range(i, 4)]


def pseudo_inertia_coordinate_matrix(sigma=sigma_of):
    """The 10x10 matrix A with coordinates(f(Phi)) = A Phi, and f(Phi) - (the linear map A) as a residual.

    f is linear iff the residual vanishes; a bijection R^10 -> sym(4) iff also det A != 0.
    """
    m, h, inertia, symbols = phi_symbols()
    coords = sp.Matrix(sym4_coordinates(pseudo_inertia(m, h, inertia, sigma)))
    a = coords.jacobian(symbols)
    return a, coords - a * sp.Matrix(symbols), symbols


def schur_factorisation(schur=None):
    """(fPosDef_IFF_PosMassPosDefSigmaCoM): f = L diag(Sigma_CoM, m) L^T with L = [[I3, h/m], [0, 1]].

    L is invertible, so by Sylvester's law of inertia f > 0 iff m > 0 and
    Sigma_CoM = Sigma - h h^T / m > 0 (for m <= 0, e4^T f e4 = m <= 0 already).
    """
    m, h, inertia, symbols = phi_symbols()
    sigma_com = sigma_of(inertia) - h * h.T / m if schur is None else schur(m, h, inertia)
    lower = sp.Matrix(sp.BlockMatrix([[sp.eye(3), h / m], [sp.zeros(1, 3), sp.Matrix([[1]])]]))
    middle = sp.diag(sigma_com, m)
    return lower * middle * lower.T, pseudo_inertia(m, h, inertia), symbols


def translation_invariance(inertia_com=None):
    """(I_Sigma_IsTranslationInvariant): Sigma - h h^T / m = tr(I_CoM)/2 I3 - I_CoM, I_CoM = I - S(h)^T S(h) / m."""
    m, h, inertia, symbols = phi_symbols()
    i_com = inertia - skew(h).T * skew(h) / m if inertia_com is None else inertia_com(m, h, inertia)
    return sigma_of(inertia) - h * h.T / m, sigma_of(i_com), symbols


def spectrum_of_sigma(sigma=sigma_of):
    """(SigmaCoMPosDef_IFF_StricTriangleCoM), spectral form: det(t I3 - Sigma(J)) = -det((tr(J)/2 - t) I3 - J).

    So the eigenvalues of Sigma_CoM are tr(I_CoM)/2 - lambda_i(I_CoM)
    = (lambda_j + lambda_k - lambda_i)/2, half the slacks of the triangle
    inequalities: Sigma_CoM > 0 iff they hold strictly.
    """
    j, symbols = symmetric("J")
    t = sp.Symbol("t", real=True)
    lhs = (t * sp.eye(3) - sigma(j)).det()
    rhs = -((j.trace() / 2 - t) * sp.eye(3) - j).det()
    return sp.Matrix([lhs]), sp.Matrix([rhs]), (*symbols, t)


def spectrum_of_inertia(inverse=inertia_of):
    """Footnote of Section 2: det(t I3 - I(S)) = -det((tr(S) - t) I3 - S) for I = tr(S) I3 - S.

    So lambda_i(I_CoM) = sigma_j + sigma_k with sigma the eigenvalues of
    Sigma_CoM: strict triangle inequalities (Sigma_CoM > 0) give I_CoM > 0.
    """
    s, symbols = symmetric("S")
    t = sp.Symbol("t", real=True)
    lhs = (t * sp.eye(3) - inverse(s)).det()
    rhs = -((s.trace() - t) * sp.eye(3) - s).det()
    return sp.Matrix([lhs]), sp.Matrix([rhs]), (*symbols, t)
