"""dynamics.forward: forward dynamics' solve in the Jacobi scaling, against an exact rational solve."""

from fractions import Fraction
from pathlib import Path

import numpy as np
import sympy

from inertiaproof.dynamics import terms
from inertiaproof.dynamics.forward import jacobi_scaling, scaled_condition, solve_mass
from inertiaproof.scene.format import load_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def _exact(mass, rhs):
    """The float data's exact solution (SymPy rationals)."""
    m = sympy.Matrix([[sympy.Rational(Fraction(x)) for x in row] for row in mass.tolist()])
    b = sympy.Matrix([sympy.Rational(Fraction(x)) for x in rhs.tolist()])
    return np.array([float(x) for x in m.LUsolve(b)])


def test_a_chain_of_kilometres_and_millimetres_is_ill_scaled_not_ill_conditioned():
    scene = load_scene(SCENES / "extreme_lengths.toml")
    rng = np.random.default_rng(0)
    q = rng.uniform(-1, 1, (4, scene.chain.n))
    mass = terms.mass_matrix(scene.chain.body_jacobian(q), scene.trajectory.theta(np.array(0.5))[0])
    assert np.linalg.cond(mass).min() > 1e15 and scaled_condition(mass).max() < 1e3
    s = jacobi_scaling(mass)
    assert np.all(np.log2(s) == np.round(np.log2(s)))  # powers of two: the scaling rounds nothing
    rhs = rng.normal(size=q.shape) * np.sqrt(np.diagonal(mass, axis1=-2, axis2=-1))
    x = solve_mass(mass, rhs)
    exact = np.array([_exact(m, b) for m, b in zip(mass, rhs)])
    assert np.abs(x / exact - 1).max() < 1e-10  # every component, the millimetre joint's too


def test_a_singular_mass_matrix_has_an_infinite_or_huge_scaled_condition():
    mass = np.array([[1.0, 1.0], [1.0, 1.0]])
    assert scaled_condition(mass) > 1e15
    assert jacobi_scaling(np.diag([0.0, 4.0])).tolist() == [1.0, 0.5]
