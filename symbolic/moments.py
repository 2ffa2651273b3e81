"""Exact moments of the primitive solids in their canonical pose, by SymPy integration (EQ-moments).

Each solid is a parametrised region with symbolic dimensions; the uniform
density M / V (V = int 1) is integrated against 1, x and x x^T over the
region (MassDistributionToInertialParam). The integrands are polynomials in
the parameters (and in cos(phi), sin(phi)), so each is integrated monomial by
monomial, every monomial once, exactly. The results are compared with the
closed forms of :mod:`inertiaproof.model.solids` evaluated on the same symbols.
"""

from __future__ import annotations

import functools
import operator
from functools import lru_cache

import sympy as sp

__all__ = ["bernstein_moments", "canonical_moments", "COS", "PHI", "SHAPES", "SIN"]

SHAPES = ("box", "ellipsoid", "sphere", "cylinder", "cone", "tetrahedron")
PHI = sp.Symbol("phi", real=True)
COS, SIN = sp.symbols("C S", real=True)  # cos(phi), sin(phi)


def _region(shape):
    """(dims symbols, point, weight, iterated limits innermost first) of the canonical solid.

    The weight is the Jacobian of the parametrisation up to a constant factor
    (a b c, det of the edges), which cancels in the density M / V.
    """
    rho, s = sp.symbols("rho s", real=True)
    if shape == "box":
        a, b, c = dims = sp.symbols("a b c", positive=True)
        u, v, w = sp.symbols("u v w", real=True)
        return dims, (u, v, w), 1, [(u, -a / 2, a / 2), (v, -b / 2, b / 2), (w, -c / 2, c / 2)]
    if shape in ("ellipsoid", "sphere"):
        dims = sp.symbols("a b c", positive=True) if shape == "ellipsoid" else (sp.Symbol("r", positive=True),)
        a, b, c = dims if shape == "ellipsoid" else dims * 3
        return dims, (a * rho * COS, b * rho * SIN, c * s), rho, [(rho, 0, sp.sqrt(1 - s**2)), (s, -1, 1)]
    if shape == "cylinder":
        r, h = dims = sp.symbols("r h", positive=True)
        return dims, (rho * COS, rho * SIN, s), rho, [(rho, 0, r), (s, -h / 2, h / 2)]
    if shape == "cone":
        r, h = dims = sp.symbols("r h", positive=True)
        return dims, (rho * COS, rho * SIN, s), rho, [(rho, 0, r * (1 - s / h)), (s, 0, h)]
    if shape == "tetrahedron":
        vertices = sp.Matrix(4, 3, sp.symbols("v0:12", real=True))
        u, v, w = sp.symbols("u v w", real=True)
        edges = (vertices[1:, :] - sp.Matrix([vertices[0, :]] * 3)).T
        point = tuple(sp.Matrix(vertices[0, :]).T + edges * sp.Matrix([u, v, w]))
        return tuple(vertices), point, 1, [(w, 0, 1 - u - v), (v, 0, 1 - u), (u, 0, 1)]
    raise ValueError(f"unknown solid {shape!r}")


def _iterated(polynomial, limits):
    """Iterated integral of a polynomial, innermost limit first, by exact antiderivatives."""
    expr = polynomial
    for var, lo, hi in limits:
        antiderivative = sp.Poly(expr, var).integrate().as_expr()
        expr = sp.expand(antiderivative.subs(var, hi) - antiderivative.subs(var, lo))
    return expr


@lru_cache(maxsize=None)
def _angular(i, j):
    """int_0^{2 pi} cos^i sin^j dphi."""
    return sp.integrate(sp.cos(PHI) ** i * sp.sin(PHI) ** j, (PHI, 0, 2 * sp.pi))


def _integrator(limits):
    """(g1, g2, ...) -> int g1 g2 ... over the region (the full turn in phi, then ``limits``).

    The factors are polynomials in C, S and the parameters; their product is
    formed as a SymPy Poly and integrated monomial by monomial.
    """
    params = tuple(lim[0] for lim in limits)
    gens = (COS, SIN, *params)

    @lru_cache(maxsize=None)
    def monomial(exponents):
        i, j, *rest = exponents
        turn = _angular(i, j)
        return turn * _iterated(sp.Mul(*[p**e for p, e in zip(params, rest)]), limits) if turn != 0 else turn

    def integrate(*factors):
        poly = functools.reduce(operator.mul, [sp.Poly(f, *gens) for f in factors])
        return sp.expand(sum(poly.domain.to_sympy(c) * monomial(e) for e, c in poly.terms()))

    return integrate


@lru_cache(maxsize=None)
def canonical_moments(shape):
    """(dims symbols, mass symbol M, m, h, Sigma) of the uniform solid of mass M, by exact integration.

    A full turn in phi contributes 2 pi to the volume of the angular regions; the
    tetrahedron has no angle, so its factor 2 pi is divided out again.
    """
    dims, point, weight, limits = _region(shape)
    angular = any(sp.sympify(x).has(COS, SIN) for x in point)
    integrate = _integrator(limits)
    turn = 1 if angular else 2 * sp.pi
    mass = sp.Symbol("M", positive=True)
    density = mass * turn / integrate(weight)

    def moment(*g):
        return sp.expand(density / turn * integrate(weight, *g))

    sigma = sp.zeros(3, 3)
    for i in range(3):
        for j in range(i, 3):
            sigma[i, j] = sigma[j, i] = moment(point[i], point[j])
    return dims, mass, moment(1), sp.Matrix([moment(x) for x in point]), sigma


def bernstein_moments(degree):
    """(L, [[int y^j B_{k,d}(y / L + 1/2) dy over [-L/2, L/2] for k = 0..d] for j = 0, 1, 2]), exactly."""
    side = sp.Symbol("L", positive=True)
    t = sp.Symbol("t", real=True)

    return side, [[_iterated(sp.expand(side * (side * (t - sp.Rational(1, 2))) ** j * sp.binomial(degree, k)
                            * t**k * (1 - t) ** (degree - k)), [(t, 0, 1)]) for k in range(degree + 1)] for j in range(3)]
