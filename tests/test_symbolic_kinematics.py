"""The symbolic twin is the project's chain: QJ against Chain.body_jacobian, D_t against SymPy's d/dt."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from inertiaproof.symbolic.identity import fixed_point
from inertiaproof.symbolic.jets import JetSpace
from inertiaproof.symbolic.kinematics import ChainTwin, rational_rotation
from inertiaproof.symbolic.lagrangian import chain_lagrangian

from inertiaproof.dynamics.chain import Chain, Coordinate, Joint
from inertiaproof.errors import InputError
from inertiaproof.scene import robots


@pytest.mark.parametrize("scene", [robots.planar_2r, robots.spatial_3r, robots.ur5, robots.panda])
def test_body_jacobian_matches_the_chain(scene):
    twin = ChainTwin(scene().chain)
    point = fixed_point(twin.jets, 3)
    exact = np.array([[float(twin.jets.evaluate(x, point)) for x in row] for row in twin.body_jacobian])
    numeric = twin.chain.body_jacobian(twin.numeric_point(point))
    assert np.max(np.abs(exact - numeric)) < 1e-12
    assert twin.rationalisation_error < 1e-12


def test_rational_rotation_is_exactly_orthogonal():
    from inertiaproof.model.inertia import rotation_rpy

    r = rational_rotation(rotation_rpy((0.3, -1.1, 2.0)))
    product = [[sum(r[k][i] * r[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    assert product == [[Fraction(int(i == j)) for j in range(3)] for i in range(3)]
    assert np.max(np.abs(np.array(r, dtype=float) - rotation_rpy((0.3, -1.1, 2.0)))) < 1e-9


def test_irrational_axis_is_a_clear_error():
    chain = Chain((Joint("revolute", (1.0, 1.0, 0.0)),), name="tilted")
    with pytest.raises(InputError, match="not a rational unit vector"):
        ChainTwin(chain)


def test_non_polynomial_coordinate_map_is_a_clear_error():
    chain = Chain((Joint("revolute", (0, 0, 1), coordinate=Coordinate("arctan")),), name="arctan")
    with pytest.raises(ValueError, match="not polynomial"):
        ChainTwin(chain)


def test_total_derivative_is_sympy_d_dt_along_functions_of_t():
    """D_t on the jet ring equals SymPy's d/dt with q(t), Theta(t), Psi(t) as functions of t (2R Lagrangian)."""
    twin = ChainTwin(robots.planar_2r().chain)
    jets = twin.jets
    t = sp.Symbol("t")
    motion = []
    for g in jets.generators:
        if g.role in ("cos", "sin"):
            q = sp.Function(f"q{g.index[0]}")(t)
            motion.append(sp.cos(q) if g.role == "cos" else sp.sin(q))
        elif g.role in ("qd", "qdd"):
            q = sp.Function(f"q{g.index[0]}")(t)
            motion.append(q.diff(t, 1 if g.role == "qd" else 2))
        elif g.role.endswith("_dot"):
            base = next(h for h in jets.generators if h.role == g.role[:-4] and h.index == g.index)
            motion.append(sp.Function(base.name)(t).diff(t))
        elif g.role in ("theta", "psi", "nu"):
            motion.append(sp.Function(g.name)(t))
        else:
            motion.append(sp.Symbol(g.name))
    lagrangian = chain_lagrangian(twin)
    by_sympy = sp.diff(lagrangian.as_expr(*motion), t)
    by_jets = jets.d_t(lagrangian).as_expr(*motion)
    assert sp.expand(by_sympy - by_jets) == 0


def test_normal_form_decides_sin_cos_identities():
    jets = JetSpace(["revolute", "revolute"])
    c1, s1 = jets.gen("cos", 1), jets.gen("sin", 1)
    assert jets.is_zero(c1**4 - s1**4 - c1**2 + s1**2)
    assert not jets.is_zero(c1**2 - s1**2)
