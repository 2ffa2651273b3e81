"""GRE from first principles: mass-carrying particles on a chain, sharing nothing with Z(Phi) or QJ.

Body l carries point masses i of mass m_li(t) at body-frame positions x_li(t):
a moving x is the paper's internal motion, a changing m its loading. Their
positions in the Newtonian frame come from the chain's homogeneous transforms
alone (Layout),

    p_li = T_l(q) (x_li; 1),   T_l = T_{l-1} B_l X_l(g_l(q_l)) A_l,

with B_l, A_l the joint's fixed transforms and X_l Rodrigues' rotation about
(or the slide along) its axis. The system's energies are

    T = sum_li 1/2 m_li |d/dt p_li|^2,   U = -sum_li m_li a_g . p_li

(a_g the chain's gravitational acceleration: the paper's field g of
(RespectivePotenitalEnergy) is -a_g), and Lagrange's equations
(LagrangeFormalism) of this system are compared with the paper's form
(RoboticEquation) evaluated at Theta, Thetadot, Psi, Psidot of the same
particles by the paper's definitions (Defml)-(DefIl) and psi_l:

    Phi_l = sum_i m_li (1, x_li, S(x_li)^T S(x_li)),   psi_l = sum_i m_li (xdot_li, S(x_li) xdot_li).

Every object is linear in the particles (T, U, Theta and Psi are sums over
them and the paper's form is linear in Theta, Thetadot, Psi, Psidot), so the
identity for symbolic m_li(t), x_li(t) holds for any finite set of particles.

Loading needs an assumption. Per particle, Lagrange's equations with a
time-varying mass give d/dt(m pdot) = F: Newton's law for a body taking up mass
that arrives at rest in the inertial frame (Meshchersky: m pddot = F + mdot (u - pdot)
with arrival velocity u = 0), projected on the virtual displacements J_li = dp_li/dq
(d'Alembert; the internal drive of x_li(t) is an ideal rheonomic constraint).
Mass arriving with velocity u adds sum mdot J^T u, which the Lagrangian misses;
for mass arriving with its body's velocity (u = pdot) that difference is
sum mdot J^T pdot, on pure loading (xdot = 0) exactly M(q, Thetadot) qd.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import cached_property
from types import SimpleNamespace

from inertiaproof.symbolic.derivations import derivation
from inertiaproof.symbolic.jets import JetSpace
from inertiaproof.symbolic.kinematics import rational, rational_axis, rational_transform, to_qq
from inertiaproof.symbolic.robotics_equation import left_side, matvec
from inertiaproof.symbolic.systems import SystemKey, chain_of

__all__ = [
    "derivation_of_particles", "derive_particles", "euler_lagrange", "forget", "lagrangian", "newton",
    "onto_particles", "ParticleDerivation", "ParticleKey", "particle_key", "particle_keys", "particle_moments", "positions",
    "without_internal_motion", "world_transforms",
]

PARAMETER_ROLES = ("theta", "theta_dot", "psi", "psi_dot")
INTERNAL_ROLES = ("x_dot", "x_ddot")


@dataclass(frozen=True)
class ParticleKey:
    """A chain (a :data:`~inertiaproof.symbolic.systems.CHAINS` name) with ``particles`` point masses per body."""

    chain: str
    particles: int = 1

    @property
    def label(self):
        return f"{self.chain} particles x{self.particles}"


def particle_key(chain_name):
    """Two particles per body on a chain of up to two joints, one beyond (linearity covers any number)."""
    return ParticleKey(chain_name, 2 if chain_of(SystemKey.chain(chain_name)).n <= 2 else 1)


def particle_keys(profile):
    """The particle route on the profile's concrete chains."""
    return [particle_key(name) for name in profile.concrete_chains]


def _identity(ring):
    return [[ring.one if i == j else ring.zero for j in range(4)] for i in range(4)]


def _homogeneous(ring, rotation, translation):
    return [[ring(to_qq(x)) for x in row] + [ring(to_qq(t))] for row, t in zip(rotation, translation)] + \
        [[ring.zero, ring.zero, ring.zero, ring.one]]


def _product(a, b):
    return [[sum((a[i][k] * b[k][j] for k in range(1, 4)), a[i][0] * b[0][j]) for j in range(4)] for i in range(4)]


def _joint_motion(jets, k, joint):
    """X_k: Rodrigues' rotation c I + s [u]x + (1 - c) u u^T about the unit axis u, or the slide x u."""
    ring = jets.ring
    u = [ring(to_qq(a)) for a in rational_axis(joint.axis)]
    out = _identity(ring)
    if joint.revolute:
        c, s = jets.joint_variable(k)
        cross = [[ring.zero, -u[2], u[1]], [u[2], ring.zero, -u[0]], [-u[1], u[0], ring.zero]]
        for i in range(3):
            for j in range(3):
                out[i][j] = (c if i == j else ring.zero) + s * cross[i][j] + (1 - c) * u[i] * u[j]
    else:
        x = jets.joint_variable(k)
        for i in range(3):
            out[i][3] = x * u[i]
    return out


def world_transforms(jets, chain):
    """T_l(q) (4x4, ring elements) of every body, products of the chain's homogeneous transforms."""
    t, out = _identity(jets.ring), []
    for k, joint in enumerate(chain.joints, 1):
        for factor in (_homogeneous(jets.ring, *rational_transform(joint.before)), _joint_motion(jets, k, joint),
                       _homogeneous(jets.ring, *rational_transform(joint.after))):
            t = _product(t, factor)
        t = [[jets.canonical(x) for x in row] for row in t]
        out.append(t)
    return out


def positions(jets, transforms):
    """{(l, i): p_li} with p_li = T_l (x_li; 1) in the Newtonian frame."""
    out = {}
    for l, t in enumerate(transforms, 1):
        for i in range(1, jets.particles + 1):
            x = jets.particle(l, i)[2]
            out[l, i] = [jets.canonical(t[r][3] + sum((t[r][a] * x[a] for a in range(3)), jets.zero))
                         for r in range(3)]
    return out


def _gravity(jets, chain):
    return [jets.ring(to_qq(rational(x))) for x in chain.gravity]


def _dot(a, b, zero):
    return sum((x * y for x, y in zip(a, b)), zero)


def lagrangian(jets, where, gravity):
    """L = sum 1/2 m |d/dt p|^2 + sum m a_g . p."""
    total = jets.zero
    for (l, i), p in where.items():
        m = jets.particle(l, i)[0]
        velocity = [jets.d_t(x) for x in p]
        total += m * (_dot(velocity, velocity, jets.zero) / 2 + _dot(gravity, p, jets.zero))
    return jets.canonical(total)


def euler_lagrange(jets, lagrangian_):
    """(d/dt dL/dqd_k - dL/dq_k)_k (LagrangeFormalism)."""
    return tuple(jets.canonical(jets.d_t(jets.d_qd(lagrangian_, k)) - jets.d_q(lagrangian_, k))
                 for k in range(1, jets.n + 1))


def newton(jets, where, gravity):
    """Meshchersky's law m pddot = F + mdot (u - pdot) of every particle projected on the virtual
    displacements J_li = dp_li/dq (d'Alembert), for mass arriving at rest (u = 0) and with its body (u = pdot):

        (sum J^T (m pddot + mdot pdot - m a_g),  sum J^T (m pddot - m a_g)).
    """
    rest, with_body = [jets.zero] * jets.n, [jets.zero] * jets.n
    for (l, i), p in where.items():
        m, m_dot = jets.particle(l, i)[:2]
        velocity = [jets.d_t(x) for x in p]
        inertial = [m * (jets.d_t(v) - g) for v, g in zip(velocity, gravity)]
        for k in range(1, jets.n + 1):
            column = [jets.d_q(x, k) for x in p]
            body = _dot(column, inertial, jets.zero)
            with_body[k - 1] += body
            rest[k - 1] += body + m_dot * _dot(column, velocity, jets.zero)
    return tuple(jets.canonical(x) for x in rest), tuple(jets.canonical(x) for x in with_body)


def particle_moments(jets):
    """{(role, (l, index)): polynomial}: Theta, Thetadot, Psi, Psidot of the particles, (Defml)-(DefIl) and psi_l."""
    out = {}
    for l in range(1, jets.bodies + 1):
        z = jets.zero
        phi, psi = [z] * 10, [z] * 6
        for i in range(1, jets.particles + 1):
            m, _, x, x_dot, _ = jets.particle(l, i)
            square = _dot(x, x, z)
            inertia = [[(square if a == b else z) - x[a] * x[b] for b in range(3)] for a in range(3)]
            cross = [x[1] * x_dot[2] - x[2] * x_dot[1], x[2] * x_dot[0] - x[0] * x_dot[2],
                     x[0] * x_dot[1] - x[1] * x_dot[0]]
            moments = [jets.one, *x, inertia[0][0], inertia[1][1], inertia[2][2], inertia[0][1], inertia[1][2],
                       inertia[0][2]]
            phi = [a + m * b for a, b in zip(phi, moments)]
            psi = [a + m * b for a, b in zip(psi, list(x_dot) + cross)]
        for index, e in enumerate(phi):
            out["theta", (l, index)] = e
            out["theta_dot", (l, index)] = jets.d_t(e)
        for index, e in enumerate(psi):
            out["psi", (l, index)] = e
            out["psi_dot", (l, index)] = jets.d_t(e)
    return out


def onto_particles(calc, jets, polynomials, moments):
    """Polynomials of a chain's jet ring, each term linear in Theta, Thetadot, Psi, Psidot, moved into the
    particles' ring with those coordinates replaced by the particles' moments."""
    names = {g.name: i for i, g in enumerate(jets.generators)}
    target = [names.get(g.name) for g in calc.generators]
    parameter = {i: (g.role, g.index) for i, g in enumerate(calc.generators) if g.role in PARAMETER_ROLES}
    width, out = len(jets.generators), []
    for p in polynomials:
        groups = {}
        for monom, coeff in p.items():
            which = [i for i, e in enumerate(monom) if e and i in parameter]
            if len(which) != 1 or monom[which[0]] != 1:
                raise ValueError("a term of the paper's form is not linear in Theta, Thetadot, Psi, Psidot")
            m = [0] * width
            for i, e in enumerate(monom):
                if e and i not in parameter:
                    m[target[i]] = e
            groups.setdefault(which[0], {})[tuple(m)] = coeff
        total = jets.zero
        for g, terms in groups.items():
            total += jets.ring.from_dict(terms) * moments[parameter[g]]
        out.append(jets.canonical(total))
    return tuple(out)


def without_internal_motion(jets, p):
    """p at xdot = xddot = 0 (pure loading)."""
    drop = [i for i, g in enumerate(jets.generators) if g.role in INTERNAL_ROLES]
    return jets.ring.from_dict({m: c for m, c in p.items() if not any(m[i] for i in drop)}) if p else p


@dataclass
class ParticleDerivation:
    """The particle route on one chain and what the paper's form says about the same particles."""

    key: ParticleKey
    calc: JetSpace
    chain_derivation: object  # the chain's :class:`~inertiaproof.symbolic.derivations.Derivation`
    euler_lagrange: tuple  # Lagrange's equations of the particles (LagrangeFormalism)
    paper: tuple  # M qdd + (C + M(q, Thetadot) + H) qd + G + J^T Q^T Psidot at the particles' moments
    newton_at_rest: tuple  # d'Alembert-Meshchersky, added mass arriving at rest (u = 0)
    newton_with_the_body: tuple  # added mass arriving with its body's velocity (u = pdot)
    loading_difference: tuple  # (newton_at_rest - newton_with_the_body) at xdot = 0
    loading_term: tuple  # M(q, Thetadot) qd at the particles' moments, at xdot = 0
    moments: dict
    seconds: dict = field(default_factory=dict)
    cached: bool = False
    system: SimpleNamespace = field(default_factory=lambda: SimpleNamespace(v=(), a=(), block=10))

    def paper_form(self, equation):
        """The left side of (RoboticEquation) for the chain's terms ``equation``, at the particles' moments."""
        d = self.chain_derivation
        return onto_particles(d.calc, self.calc, left_side(d.calc, equation), self.moments)

    @cached_property
    def difference_terms(self):
        """Terms of sum mdot J^T pdot: what the Lagrangian adds when mass arrives with its body's velocity."""
        return sum(len(a - b) for a, b in zip(self.newton_at_rest, self.newton_with_the_body))


def derive_particles(key, chain_derivation):
    """The particle route of ``key`` on the chain of ``chain_derivation``."""
    seconds = {}

    def stage(name, fn, *args):
        t0 = time.perf_counter()
        value = fn(*args)
        seconds[name] = seconds.get(name, 0.0) + time.perf_counter() - t0
        return value

    chain = chain_of(chain_derivation.key)
    jets = JetSpace([j.kind for j in chain.joints], [j.coordinate.name for j in chain.joints],
                    with_free_vectors=False, particles=key.particles)
    gravity = _gravity(jets, chain)
    where = stage("kinematics", lambda: positions(jets, world_transforms(jets, chain)))
    el = stage("lagrange", lambda: euler_lagrange(jets, lagrangian(jets, where, gravity)))
    rest, moving = stage("newton", newton, jets, where, gravity)
    moments = stage("moments", particle_moments, jets)
    d = chain_derivation
    paper = stage("paper_form", onto_particles, d.calc, jets, left_side(d.calc, d.equation), moments)
    rates = stage("paper_form", onto_particles, d.calc, jets,
                  matvec(d.calc, d.equation.M_rates, d.calc.q_dot), moments)
    return ParticleDerivation(
        key, jets, d, el, paper, rest, moving,
        tuple(without_internal_motion(jets, a - b) for a, b in zip(rest, moving)),
        tuple(without_internal_motion(jets, x) for x in rates), moments, seconds)


_MEMO: dict = {}


def derivation_of_particles(key, progress=None):
    """The particle route of ``key`` (memoised per process; the chain's derivation comes from its cache)."""
    if key not in _MEMO:
        chain_derivation = derivation(SystemKey.chain(key.chain), progress=progress)
        (progress or (lambda m: None))(f"{key.label}: Lagrange's equations of the particles ...")
        _MEMO[key] = derive_particles(key, chain_derivation)
    return _MEMO[key]


def forget():
    _MEMO.clear()
