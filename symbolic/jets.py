"""Jet coordinates of a chain's motion, and the derivations d/dq, d/dqd, d/dt on them.

Along a motion q(t), Theta(t), Psi(t) the Lagrangian (Lagrangian) and every
term of (RoboticEquation) are polynomials over Q in the jet coordinates

    c_k = cos x_k, s_k = sin x_k      (revolute joint, joint variable x_k = g_k(q_k))
    q_k                               (prismatic joint, or a revolute one with g_k != identity)
    qd_k, qdd_k                       (joint velocities and accelerations)
    Theta_h, Thetadot_h               (inertial parameters (eq:Phi) of every body and their rates)
    Psi_r, Psidot_r, nu, nudot        (lumped internal velocity (KineticEnergy) and its rate)
    v_k, a_k                          (free vectors of the regressors (RoboticRegressor))

or, for the particle route (:mod:`~inertiaproof.symbolic.particles`), in place of
Theta, Psi and nu the particles of every body: their masses and rates m_li,
mdot_li and body-frame positions x_li, xdot_li, xddot_li.

The time derivative along the motion is the derivation

    D_t = sum_k qd_k d/dq_k + qdd_k d/dqd_k + sum_h Thetadot_h d/dTheta_h + sum_r Psidot_r d/dPsi_r + nudot d/dnu
          (+ sum_i mdot_i d/dm_i + xdot_i d/dx_i + xddot_i d/dxdot_i),

with d/dq_k c_k = -g_k'(q_k) s_k and d/dq_k s_k = g_k'(q_k) c_k. Functions of q are
the quotient by the ideal I = (c_k^2 + s_k^2 - 1); every derivation above maps I
into I (d/dq_k (c_k^2 + s_k^2) = 0), so they are well defined on the quotient.
The normal form modulo I (c_k^2 -> 1 - s_k^2, a Groebner basis in any order as
the leading terms are coprime) is canonical: an element is the zero function
iff its normal form is the zero polynomial.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property
from math import comb

import numpy as np
from sympy.polys.domains import QQ
from sympy.polys.rings import PolyRing

from inertiaproof.model.inertia import PHI_FIELDS

__all__ = ["COORDINATE_POLYNOMIALS", "Generator", "JetSpace"]

# g_k(q) and g_k'(q) as coefficient lists (lowest degree first) of polynomial coordinate maps
COORDINATE_POLYNOMIALS = {
    "identity": ((0, 1), (1,)),
    "cubic": ((0, 0, 0, 1), (0, 0, 3)),
}


@dataclass(frozen=True)
class Generator:
    """One jet coordinate: its role (e.g. 'cos', 'qd', 'theta'), its indices and its printed name."""

    role: str
    index: tuple
    name: str


def _generators(kinds, coordinates, bodies, with_free_vectors, particles):
    out = []
    for k, (kind, coord) in enumerate(zip(kinds, coordinates), 1):
        if kind == "revolute":
            out += [Generator("cos", (k,), f"c{k}"), Generator("sin", (k,), f"s{k}")]
        if kind == "prismatic" or coord != "identity":
            out.append(Generator("q", (k,), f"q{k}"))
    n = len(kinds)
    out += [Generator("qd", (k,), f"qd{k}") for k in range(1, n + 1)]
    out += [Generator("qdd", (k,), f"qdd{k}") for k in range(1, n + 1)]
    if with_free_vectors:
        out += [Generator("v", (k,), f"v{k}") for k in range(1, n + 1)]
        out += [Generator("a", (k,), f"a{k}") for k in range(1, n + 1)]
    if particles:
        for role, prefix in (("mass", "m"), ("mass_dot", "Dm")):
            out += [Generator(role, (l, i), f"{prefix}{l}_{i}") for l in range(1, bodies + 1)
                    for i in range(1, particles + 1)]
        for role, prefix in (("x", "x"), ("x_dot", "Dx"), ("x_ddot", "DDx")):
            out += [Generator(role, (l, i, a), f"{prefix}{a}_{l}_{i}") for l in range(1, bodies + 1)
                    for i in range(1, particles + 1) for a in range(1, 4)]
        return tuple(out)
    for role, prefix in (("theta", ""), ("theta_dot", "D")):
        out += [Generator(role, (l, i), f"{prefix}{field}_{l}") for l in range(1, bodies + 1)
                for i, field in enumerate(PHI_FIELDS)]
    for role, prefix in (("psi", "psi"), ("psi_dot", "Dpsi")):
        out += [Generator(role, (l, i), f"{prefix}{i + 1}_{l}") for l in range(1, bodies + 1) for i in range(6)]
    out += [Generator("nu", (), "nu"), Generator("nu_dot", (), "Dnu")]
    return tuple(out)


class JetSpace:
    """The polynomial ring of jet coordinates of one chain, with its derivations and normal form.

    Implements the calculus protocol of :mod:`inertiaproof.symbolic.calculus`. With ``particles`` > 0
    every body carries that many point masses instead of the generators Theta, Psi and nu.
    """

    def __init__(self, kinds, coordinates=None, *, with_free_vectors=True, particles=0):
        self.kinds = tuple(kinds)
        self.coordinates = tuple(coordinates or ("identity",) * len(self.kinds))
        for c in self.coordinates:
            if c not in COORDINATE_POLYNOMIALS:
                raise ValueError(f"coordinate map {c!r} is not polynomial: no symbolic twin (supported: "
                                 f"{', '.join(COORDINATE_POLYNOMIALS)})")
        self.n = len(self.kinds)
        self.bodies = self.n
        self.particles = particles
        self.generators = _generators(self.kinds, self.coordinates, self.bodies, with_free_vectors, particles)
        self.ring = PolyRing([g.name for g in self.generators], QQ)
        self.gens = self.ring.gens
        self.zero, self.one = self.ring.zero, self.ring.one
        self._position = {(g.role, g.index): i for i, g in enumerate(self.generators)}

    # -- coordinates -------------------------------------------------------

    def gen(self, role, *index):
        return self.gens[self._position[(role, tuple(index))]]

    def has(self, role, *index):
        return (role, tuple(index)) in self._position

    def vector(self, role):
        return tuple(self.gen(role, k) for k in range(1, self.n + 1))

    @property
    def q_dot(self):
        return self.vector("qd")

    @property
    def q_ddot(self):
        return self.vector("qdd")

    def body_parameters(self, l, role="theta"):
        """Phi_l (or its rate with role='theta_dot') as ten generators in the order of (eq:Phi)."""
        return tuple(self.gen(role, l, i) for i in range(10))

    def body_psi(self, l, role="psi"):
        return tuple(self.gen(role, l, i) for i in range(6))

    def _stacked(self, role):
        return tuple(self.gens[i] for i, g in enumerate(self.generators) if g.role == role)

    @cached_property
    def theta(self):
        return self._stacked("theta")

    @cached_property
    def theta_dot(self):
        return self._stacked("theta_dot")

    @cached_property
    def psi(self):
        return self._stacked("psi")

    @cached_property
    def psi_dot(self):
        return self._stacked("psi_dot")

    def particle(self, l, i):
        """(m, mdot, x, xdot, xddot) of particle i of body l: two generators and three 3-vectors."""
        vector = lambda role: tuple(self.gen(role, l, i, a) for a in range(1, 4))  # noqa: E731
        return (self.gen("mass", l, i), self.gen("mass_dot", l, i), vector("x"), vector("x_dot"),
                vector("x_ddot"))

    def joint_variable(self, k):
        """(cos x_k, sin x_k) for a revolute joint, x_k for a prismatic one, as ring elements."""
        if self.kinds[k - 1] == "revolute":
            return self.gen("cos", k), self.gen("sin", k)
        return self._polynomial(COORDINATE_POLYNOMIALS[self.coordinates[k - 1]][0], k)

    def _polynomial(self, coefficients, k):
        if len(coefficients) == 1:
            return self.ring(coefficients[0])
        q = self.gen("q", k)
        return sum((c * q**e for e, c in enumerate(coefficients) if c), self.zero)

    def coordinate_derivative(self, k):
        """g_k'(q_k) as a ring element."""
        return self._polynomial(COORDINATE_POLYNOMIALS[self.coordinates[k - 1]][1], k)

    # -- derivations -------------------------------------------------------

    def present(self, p):
        """Indices of the generators that occur in p."""
        if not p:
            return set()
        return set(np.flatnonzero(np.array(list(p.itermonoms()), dtype=np.int64).any(axis=0)).tolist())

    def _coordinate_images(self, k, with_velocity):
        """d/dq_k (times qd_k if with_velocity) of joint k's coordinates, as {generator: [(coeff, {gen: exp})]}."""
        qd = {self._position[("qd", (k,))]: 1} if with_velocity else {}
        images = {}
        if self.kinds[k - 1] == "revolute":
            c, s = self._position[("cos", (k,))], self._position[("sin", (k,))]
            q = self._position.get(("q", (k,)))
            for power, coeff in enumerate(COORDINATE_POLYNOMIALS[self.coordinates[k - 1]][1]):
                if not coeff:
                    continue
                extra = {q: power} if power else {}
                images.setdefault(c, []).append((-coeff, {s: 1, **extra, **qd}))
                images.setdefault(s, []).append((coeff, {c: 1, **extra, **qd}))
        if self.has("q", k):
            images[self._position[("q", (k,))]] = [(1, dict(qd))]
        return images

    @cached_property
    def _time_images(self):
        images = {}
        for k in range(1, self.n + 1):
            images.update(self._coordinate_images(k, with_velocity=True))
        rates = {"qd": "qdd", "theta": "theta_dot", "psi": "psi_dot", "nu": "nu_dot", "mass": "mass_dot",
                 "x": "x_dot", "x_dot": "x_ddot"}
        for i, g in enumerate(self.generators):
            if g.role in rates:
                images[i] = [(1, {self._position[(rates[g.role], g.index)]: 1})]
            elif g.role in rates.values():
                images[i] = None  # a second derivative of the motion: not a jet coordinate here
        return images

    def _derivation(self, p, images):
        """D p for the derivation with D x_i = images[i] (a Leibniz rule applied term by term in one pass)."""
        out = {}
        for monom, coeff in p.items():
            for i, e in enumerate(monom):
                if not e or i not in images:
                    continue
                if images[i] is None:
                    raise ValueError(f"D_t of {self.generators[i].name}: second derivatives of the motion are not "
                                     "jet coordinates here")
                for c, delta in images[i]:
                    m = list(monom)
                    m[i] -= 1
                    for j, d in delta.items():
                        m[j] += d
                    key = tuple(m)
                    out[key] = out.get(key, 0) + coeff * (e * c)
        return self.ring.from_dict({m: c for m, c in out.items() if c}) if out else self.zero

    def d_q(self, p, k):
        """The partial derivative d p / d q_k at fixed qd, Theta, Psi."""
        return self._derivation(p, self._coordinate_images(k, with_velocity=False))

    def d_qd(self, p, k):
        return p.diff(self.gen("qd", k))

    def d_theta(self, p, h):
        """d p / d Theta_h, h = 0 .. 10N-1 in the order of Theta."""
        return p.diff(self.theta[h])

    def d_t(self, p):
        """D_t p: the total time derivative along q(t), Theta(t), Psi(t), nu(t)."""
        return self._derivation(p, self._time_images)

    def at_rates(self, p):
        """p with Theta replaced by Thetadot: for p linear in Theta, p(q, Thetadot) (e.g. M(q, Thetadot))."""
        return self.rename(p, dict(zip(self.theta, self.theta_dot)))

    def rename(self, p, mapping):
        """p with generators swapped for other generators (a permutation of exponent positions)."""
        index = {g: i for i, g in enumerate(self.gens)}
        perm = list(range(len(self.gens)))
        for a, b in mapping.items():
            perm[index[a]], perm[index[b]] = index[b], index[a]
        return self.ring.from_dict({tuple(m[perm[i]] for i in range(len(m))): c for m, c in p.items()})

    # -- normal form, evaluation ---------------------------------------------

    @cached_property
    def _circles(self):
        return [(self._position[("cos", (k,))], self._position[("sin", (k,))])
                for k in range(1, self.n + 1) if self.kinds[k - 1] == "revolute"]

    def canonical(self, p):
        """Normal form modulo sin^2 + cos^2 = 1: every c_k^(2a+b) becomes c_k^b (1 - s_k^2)^a, b < 2.

        The result has no c_k^2 left, so it is the unique normal form for the
        Groebner basis {c_k^2 + s_k^2 - 1} (leading terms c_k^2): zero iff p is
        the zero function on the torus.
        """
        if not self._circles or not p:
            return p
        out = {}
        for monom, coeff in p.items():
            if all(monom[c] < 2 for c, _ in self._circles):
                out[monom] = out.get(monom, 0) + coeff
                continue
            terms = [(list(monom), coeff)]
            for c, s in self._circles:
                a, b = divmod(monom[c], 2)
                if not a:
                    continue
                expanded = []
                for m, k in terms:
                    for j in range(a + 1):
                        m2 = list(m)
                        m2[c], m2[s] = b, m[s] + 2 * j
                        expanded.append((m2, k * (comb(a, j) * (-1) ** j)))
                terms = expanded
            for m, k in terms:
                key = tuple(m)
                out[key] = out.get(key, 0) + k
        return self.ring.from_dict({m: k for m, k in out.items() if k}) if out else self.zero

    def is_zero(self, p):
        return not self.canonical(p)

    def size(self, p):
        return len(p)

    def free_roles(self, p):
        """The roles of the generators p depends on (e.g. to see that a regressor is free of 'theta')."""
        return {self.generators[i].role for i in self.present(self.canonical(p))}

    def evaluate(self, p, point, memo=None):
        """Exact value of p at a point {(role, index): Fraction}; cos and sin come from the point's 'tan_half'.

        ``memo`` (a dict kept by the caller for one point) saves the coordinates' powers between calls.
        """
        memo = {} if memo is None else memo
        if "values" not in memo:
            values = []
            for g in self.generators:
                if g.role in ("cos", "sin"):
                    t = Fraction(point[("tan_half", g.index)])
                    values.append((1 - t * t) / (1 + t * t) if g.role == "cos" else 2 * t / (1 + t * t))
                else:
                    values.append(Fraction(point.get((g.role, g.index), 0)))
            memo["values"], memo["powers"] = values, {}
        values, powers = memo["values"], memo["powers"]
        total = Fraction(0)
        for monom, coeff in p.items():
            term = Fraction(int(coeff.numerator), int(coeff.denominator))
            for i, e in enumerate(monom):
                if e:
                    key = (i, e)
                    if key not in powers:
                        powers[key] = values[i] ** e
                    term *= powers[key]
            total += term
        return total

    def point_keys(self, leaves=()):
        """The (role, index) keys a point must give: tan(x_k/2) for revolute joints, every other coordinate."""
        keys = []
        for g in self.generators:
            key = ("tan_half", g.index) if g.role in ("cos", "sin") else (g.role, g.index)
            if key not in keys:
                keys.append(key)
        return keys

    def degree_profile(self, p):
        """({k: degree of p in (c_k, s_k) jointly}, degree in the other coordinates), for Schwartz-Zippel bounds."""
        trig, rest = {}, 0
        pairs = [(k, self._position[("cos", (k,))], self._position[("sin", (k,))])
                 for k in range(1, self.n + 1) if self.kinds[k - 1] == "revolute"]
        trig_positions = {i for _, c, s in pairs for i in (c, s)}
        for monom in p.itermonoms():
            rest = max(rest, sum(e for i, e in enumerate(monom) if e and i not in trig_positions))
            for k, c, s in pairs:
                trig[k] = max(trig.get(k, 0), monom[c] + monom[s])
        return trig, rest

    def printed(self, p):
        """The canonical form as text in the ring's monomial order (deterministic, hash-seed independent)."""
        return str(self.canonical(p))
