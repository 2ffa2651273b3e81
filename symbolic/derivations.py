"""Every derived object of Section 3 and Property 1-2, derived once per process and cached on disk.

:func:`derivation` is the one entry point the checks and the gate share: a
module-level memo keeps a system's derivation for the process, and
:mod:`~inertiaproof.symbolic.cache` keeps it across processes.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

from inertiaproof.symbolic import cache
from inertiaproof.symbolic.lagrangian import euler_lagrange
from inertiaproof.symbolic.properties import Regressors, build_regressors, property1_matrix, total_derivative
from inertiaproof.symbolic.robotics_equation import RoboticEquation, assemble, christoffel, parameter_rate_matrix
from inertiaproof.symbolic.systems import System, SystemKey, abstract_system, build, chain_inputs, chain_of

__all__ = ["Derivation", "derivation", "derive", "forget"]


@dataclass
class Derivation:
    """A system and what is derived from it."""

    system: System
    euler_lagrange: tuple  # (LagrangeFormalism) left side, = tau + w
    equation: RoboticEquation  # the paper's terms
    gamma: tuple  # Christoffel symbols (Cristoffel)
    F: tuple  # (DefF)
    M_dot: tuple  # total derivative of M
    N: tuple  # Mdot - 2C - M(q, Thetadot)
    regressors: Regressors
    seconds: dict = field(default_factory=dict)  # stage -> seconds when it was derived
    cached: bool = False  # read from the disk cache in this process
    load_seconds: float = 0.0

    @property
    def calc(self):
        return self.system.calc

    @property
    def key(self):
        return self.system.key


_MEMO: dict = {}


def derivation(key: SystemKey, progress=None) -> Derivation:
    """The derivation of a system: from this process's memo, the disk cache, or derived now (and stored)."""
    if key in _MEMO:
        return _MEMO[key]
    say = progress or (lambda message: None)
    start = time.perf_counter()
    inputs = _inputs(key)
    k = cache.key(inputs)
    shell = _shell(key)
    stored = cache.load(k, getattr(shell.calc, "ring", None))
    if stored is not None:
        result = _from_stored(shell, stored)
        result.cached, result.load_seconds = True, time.perf_counter() - start
        say(f"{key.label}: read from the derivation cache in {result.load_seconds:.2f} s")
    else:
        say(f"{key.label}: deriving ...")
        result = derive(build(key))
        cache.store(k, _to_stored(result))
        say(f"{key.label}: derived in {sum(result.seconds.values()):.2f} s")
    _MEMO[key] = result
    return result


def forget():
    """Empty the process memo (tests)."""
    _MEMO.clear()


def derive(system: System) -> Derivation:
    """Euler-Lagrange from L, the paper's terms from M, U, QJ, and the Property 1-2 objects."""
    calc, seconds = system.calc, {}

    def stage(name, fn, *args):
        t0 = time.perf_counter()
        value = fn(*args)
        seconds[name] = seconds.get(name, 0.0) + time.perf_counter() - t0
        return value

    el = stage("euler_lagrange", lambda: tuple(calc.canonical(x) for x in euler_lagrange(calc, system.lagrangian)))
    gamma = stage("paper_form", christoffel, calc, system.mass_matrix)
    eq = stage("paper_form", assemble, calc, system.mass_matrix, system.potential, system.body_jacobian, gamma)
    eq = stage("paper_form", _canonical_equation, calc, eq)
    f = stage("DefF", lambda: _canonical(calc, parameter_rate_matrix(calc, system.mass_matrix)))
    m_dot = stage("Prop1", lambda: _canonical(calc, total_derivative(calc, system.mass_matrix)))
    n_matrix = stage("Prop1", lambda: _canonical(calc, property1_matrix(calc, m_dot, eq.C, eq.M_rates)))
    regressors = stage("Prop2", build_regressors, calc, system.mass_matrix, system.potential, system.v, system.a)
    return Derivation(system, el, eq, gamma, f, m_dot, n_matrix, regressors, seconds)


def _canonical(calc, m):
    return tuple(tuple(calc.canonical(x) for x in row) for row in m)


def _canonical_equation(calc, eq):
    return RoboticEquation(M=eq.M, C=_canonical(calc, eq.C), M_rates=eq.M_rates, H=_canonical(calc, eq.H),
                           G=tuple(calc.canonical(x) for x in eq.G),
                           psi_force=tuple(calc.canonical(x) for x in eq.psi_force))


def _inputs(key):
    base = {"kind": key.kind, "name": key.name}
    if key.kind == "abstract":
        return {**base, "n": key.n, "parameters": key.parameters, "rows": key.rows}
    return {**base, "chain": chain_inputs(chain_of(key))}


def _shell(key):
    """The system's calculus and free vectors without deriving anything (to decode a cache entry)."""
    if key.kind == "abstract":
        return abstract_system(key)
    return _LazyChain(key)


class _LazyChain:
    """A chain system whose kinematics are built only if a cache miss needs them."""

    def __init__(self, key):
        from inertiaproof.symbolic.kinematics import ChainTwin

        self.key = key
        self.twin = ChainTwin(chain_of(key))
        self.calc = self.twin.jets


def _to_stored(d):
    s = d.system
    return {
        "lagrangian": s.lagrangian, "mass_matrix": s.mass_matrix, "potential": s.potential,
        "body_jacobian": s.body_jacobian, "euler_lagrange": d.euler_lagrange,
        "equation": {name: getattr(d.equation, name) for name in RoboticEquation.__dataclass_fields__},
        "gamma": d.gamma, "F": d.F, "M_dot": d.M_dot, "N": d.N,
        "R": d.regressors.R, "R_M": d.regressors.R_M_velocity, "seconds": d.seconds,
    }


def _from_stored(shell, stored):
    if isinstance(shell, System):
        system = System(shell.key, shell.description, shell.calc, stored["lagrangian"], stored["mass_matrix"],
                        stored["potential"], stored["body_jacobian"], shell.v, shell.a, shell.block)
    else:
        jets, chain = shell.calc, shell.twin.chain
        system = System(shell.key, f"{chain.name} ({chain.kinds}, {chain.n}-DoF), symbolic Phi_l(t) and Psi(t)",
                        jets, stored["lagrangian"], stored["mass_matrix"], stored["potential"],
                        stored["body_jacobian"], jets.vector("v"), jets.vector("a"), block=10, twin=shell.twin)
    return Derivation(system, stored["euler_lagrange"], RoboticEquation(**stored["equation"]), stored["gamma"],
                      stored["F"], stored["M_dot"], stored["N"], Regressors(stored["R"], stored["R_M"]),
                      dict(stored["seconds"]))
