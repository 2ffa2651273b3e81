"""The abstract n-DoF system of (Lagrangian) with generic (undefined) SymPy functions of t.

q_k(t), Theta_h(t), Psi_r(t) and nu(t) are undefined functions of time; the
mass matrix is M_kj(q, Theta) = sum_h M^h_kj(q) Theta_h (MassMatrixRegressors)
with undefined M^h_kj = M^h_jk of q_1(t), ..., q_n(t); the potential energy is
U = sum_h U^h(q) Theta_h; the lumped term is q_dot^T (QJ)^T Psi with undefined
entries QJ_rk(q). By linearity of (LagrangeFormalism) and of every term of
(RoboticEquation) in (M^h, U^h) and in (QJ_r, Psi_r), ``parameters`` terms and
``rows`` rows stand for any 10N and 6N.

Implements the calculus protocol (:mod:`inertiaproof.symbolic.calculus`):
derivatives are SymPy's ``diff`` (d/dt by the chain rule through q(t),
Theta(t), Psi(t)); the canonical form is ``expand`` over the algebraically
independent atoms (the functions and their partial derivatives).
"""

from __future__ import annotations

import hashlib
from fractions import Fraction
from functools import cached_property

import sympy as sp

__all__ = ["FunctionsOfTime", "point_value", "polynomial_degree_bound", "T"]

T = sp.Symbol("t", real=True)


class FunctionsOfTime:
    """Generic functions of time for an abstract system with n coordinates."""

    def __init__(self, n, parameters=2, rows=2):
        if n < 1 or parameters < 1 or rows < 1:
            raise ValueError("the abstract system needs n, parameters and rows >= 1")
        self.n, self.parameters, self.rows = n, parameters, rows
        self.zero, self.one = sp.S.Zero, sp.S.One
        self.roles = {}  # undefined function class -> (role, indices)
        self.q = tuple(self._function("q", (k,), f"q{k}")(T) for k in range(1, n + 1))
        self.theta = tuple(self._function("theta", (h,), f"Theta{h}")(T) for h in range(1, parameters + 1))
        self.psi = tuple(self._function("psi", (r,), f"Psi{r}")(T) for r in range(1, rows + 1))
        self.nu = self._function("nu", (), "nu")(T)
        self.symbol_roles = {}
        self.v = tuple(self._symbol("v", k) for k in range(1, n + 1))
        self.a = tuple(self._symbol("a", k) for k in range(1, n + 1))

    def _symbol(self, role, k):
        x = sp.Symbol(f"{role}{k}", real=True)
        self.symbol_roles[x] = (role, (k,))
        return x

    def _function(self, role, index, name):
        f = sp.Function(name, real=True)
        self.roles[f] = (role, index)
        return f

    # -- the system's generic ingredients -------------------------------------

    @cached_property
    def mass_matrix_regressors(self):
        """M^h_kj(q) = M^h_jk(q) (MassMatrixRegressors), a list over h of n x n matrices of undefined functions."""
        out = []
        for h in range(1, self.parameters + 1):
            entries = {}
            for k in range(1, self.n + 1):
                for j in range(k, self.n + 1):
                    entries[k, j] = entries[j, k] = self._function("M", (h, k, j), f"M{h}_{k}{j}")(*self.q)
            out.append(sp.Matrix(self.n, self.n, lambda a, b: entries[a + 1, b + 1]))
        return out

    @cached_property
    def mass_matrix(self):
        """M(q, Theta) = sum_h M^h(q) Theta_h."""
        return sum((m * th for m, th in zip(self.mass_matrix_regressors, self.theta)), sp.zeros(self.n, self.n))

    @cached_property
    def potential_regressors(self):
        return tuple(self._function("U", (h,), f"U{h}")(*self.q) for h in range(1, self.parameters + 1))

    @cached_property
    def potential(self):
        """U(q, Theta) = sum_h U^h(q) Theta_h."""
        return sum((u * th for u, th in zip(self.potential_regressors, self.theta)), sp.S.Zero)

    @cached_property
    def body_jacobian(self):
        """QJ with undefined entries QJ_rk(q), rows x n."""
        return sp.Matrix(self.rows, self.n,
                         lambda r, k: self._function("QJ", (r + 1, k + 1), f"QJ{r + 1}_{k + 1}")(*self.q))

    # -- calculus protocol -----------------------------------------------------

    @property
    def q_dot(self):
        return tuple(x.diff(T) for x in self.q)

    @property
    def q_ddot(self):
        return tuple(x.diff(T, 2) for x in self.q)

    @property
    def theta_dot(self):
        return tuple(x.diff(T) for x in self.theta)

    @property
    def psi_dot(self):
        return tuple(x.diff(T) for x in self.psi)

    def d_q(self, e, k):
        return sp.diff(e, self.q[k - 1])

    def d_qd(self, e, k):
        return sp.diff(e, self.q_dot[k - 1])

    def d_theta(self, e, h):
        return sp.diff(e, self.theta[h])

    def d_t(self, e):
        return sp.diff(e, T)

    def at_rates(self, e):
        """e with Theta_h(t) replaced by Thetadot_h(t)."""
        return sp.sympify(e).xreplace(dict(zip(self.theta, self.theta_dot)))

    def canonical(self, e):
        """expand over canonical atoms (partial derivatives with their variables sorted)."""
        e = sp.sympify(e)
        atoms = {d: self._sorted_derivative(d) for d in e.atoms(sp.Derivative)}
        return sp.expand(e.xreplace({a: b for a, b in atoms.items() if a != b}))

    @staticmethod
    def _sorted_derivative(d):
        pairs = sorted(d.variable_count, key=lambda vc: sp.default_sort_key(vc[0]))
        return sp.Derivative(d.expr, *pairs)

    def is_zero(self, e):
        return self.canonical(e) == 0

    def size(self, e):
        e = self.canonical(e)
        return 0 if e == 0 else len(sp.Add.make_args(e))

    def free_roles(self, e):
        """Roles of the functions e depends on (e.g. 'theta' for an inertial parameter)."""
        e = sp.sympify(e)
        roles = {self.roles[type(f)][0] for f in e.atoms(sp.core.function.AppliedUndef)}
        return roles | {self.symbol_roles[x][0] for x in e.free_symbols if x in self.symbol_roles}

    # -- values at points ------------------------------------------------------

    def atom_key(self, atom):
        """(role, indices, derivative orders): what an atom means, independent of its printed name."""
        if atom in self.symbol_roles:
            role, index = self.symbol_roles[atom]
            return role, index, ()
        if isinstance(atom, sp.Derivative):
            base, orders = atom.expr, {}
            for var, count in atom.variable_count:
                key = ("t",) if var == T else ("q", self.roles[type(var)][1][0])
                orders[key] = orders.get(key, 0) + int(count)
            role, index = self.roles[type(base)]
            return role, index, tuple(sorted(orders.items()))
        role, index = self.roles[type(atom)]
        return role, index, ()

    def evaluate(self, e, point, memo=None):
        """Exact value of e at a point {atom key: Fraction}; keys absent from the point take a hashed default.

        ``memo`` (a dict kept by the caller for one point) saves the atoms' values between calls.
        """
        memo = {} if memo is None else memo

        def value(atom):
            if atom not in memo:
                memo[atom] = sp.Rational(point_value(point, self.atom_key(atom)))
            return memo[atom]

        e = sp.sympify(e)
        e = e.xreplace({d: value(d) for d in e.atoms(sp.Derivative)})
        e = e.xreplace({f: value(f) for f in e.atoms(sp.core.function.AppliedUndef)})
        e = e.xreplace({x: value(x) for x in e.free_symbols if x in self.symbol_roles})
        return Fraction(int(sp.numer(e)), int(sp.denom(e)))

    def degree_profile(self, e):
        """({}, total degree in the atoms): the atoms are algebraically independent, there is no circle."""
        return {}, polynomial_degree_bound(sp.sympify(e))

    def point_keys(self, leaves):
        """The atom keys a point must give to evaluate these expressions."""
        keys = set()
        for e in leaves:
            e = sp.sympify(e)
            atoms = e.atoms(sp.Derivative) | e.atoms(sp.core.function.AppliedUndef)
            keys |= {self.atom_key(a) for a in atoms}
            keys |= {self.atom_key(x) for x in e.free_symbols if x in self.symbol_roles}
        return sorted(keys, key=repr)

    def printed(self, e):
        return sp.srepr(self.canonical(e))


def point_value(point, key):
    """The point's value for an atom key, or a deterministic default derived from the key (sha256, seed independent)."""
    if key in point:
        return Fraction(point[key])
    digest = int.from_bytes(hashlib.sha256(repr((point.get("salt", 0), key)).encode()).digest()[:8], "little")
    return Fraction(digest % 17 - 8, 1 + (digest >> 8) % 5)


def polynomial_degree_bound(e):
    """An upper bound of the total degree of e as a polynomial in its atoms (tree walk: + max, * sum, ^ times)."""
    if e.is_Number:
        return 0
    if e.is_Add:
        return max(polynomial_degree_bound(a) for a in e.args)
    if e.is_Mul:
        return sum(polynomial_degree_bound(a) for a in e.args)
    if e.is_Pow and e.exp.is_Integer and e.exp >= 0:
        return int(e.exp) * polynomial_degree_bound(e.base)
    return 1
