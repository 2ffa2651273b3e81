"""An exact decision of physical consistency independent of inertiaproof.model.exact: SymPy characteristic
polynomials over QQ and Descartes' rule of signs (the roots of a symmetric matrix's characteristic
polynomial are real, so sign changes count positive roots exactly)."""

from fractions import Fraction

from sympy import QQ
from sympy.polys.matrices import DomainMatrix


def _q(x):
    n, d = (x if isinstance(x, Fraction) else Fraction(float(x))).as_integer_ratio()
    return QQ(n, d)


def _sign_changes(coefficients):
    signs = [c > 0 for c in coefficients if c != 0]
    return sum(a != b for a, b in zip(signs, signs[1:]))


def inertia_signature(matrix):
    """(positive, zero, negative) eigenvalue counts of a symmetric matrix of floats, exactly."""
    n = len(matrix)
    cp = DomainMatrix([[_q(x) for x in row] for row in matrix], (n, n), QQ).charpoly()
    zero = 0
    while cp and cp[-1] == 0:
        cp = cp[:-1]
        zero += 1
    positive = _sign_changes(cp)
    negative = _sign_changes([c * (-1) ** (len(cp) - 1 - k) for k, c in enumerate(cp)])
    assert positive + zero + negative == n
    return positive, zero, negative


def _exact(x):
    """A Fraction as itself (a decimal as written), anything else as its float's exact value."""
    return x if isinstance(x, Fraction) else Fraction(float(x))


def verdict_of_phi(phi):
    """'consistent', 'degenerate' or 'inconsistent' of Phi (paper order), exactly on its values (floats, or
    Fractions for decimals as written)."""
    m, h1, h2, h3, i11, i22, i33, i12, i23, i13 = (_exact(x) for x in phi)
    half = (i11 + i22 + i33) / 2
    f = [[half - i11, -i12, -i13, h1], [-i12, half - i22, -i23, h2], [-i13, -i23, half - i33, h3], [h1, h2, h3, m]]
    positive, zero, negative = inertia_signature(f)
    if positive == 4:
        return "consistent"
    if negative == 0 and m > 0:
        return "degenerate"
    return "inconsistent"


def verdict_about_com(mass, ixx, iyy, izz, ixy, iyz, ixz):
    """The same for a URDF inertia about the CoM: m > 0 and Sigma_c = tr(I_c)/2 I3 - I_c."""
    m = _exact(mass)
    i = [[_exact(ixx), _exact(ixy), _exact(ixz)], [_exact(ixy), _exact(iyy), _exact(iyz)],
         [_exact(ixz), _exact(iyz), _exact(izz)]]
    half = (i[0][0] + i[1][1] + i[2][2]) / 2
    sigma = [[(half if r == c else 0) - i[r][c] for c in range(3)] for r in range(3)]
    positive, zero, negative = inertia_signature(sigma)
    if not m > 0 or negative:
        return "inconsistent"
    return "consistent" if positive == 3 else "degenerate"
