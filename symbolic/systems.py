"""The mechanical systems the derivations run on: the abstract n-DoF system and the project's chains.

A :class:`System` bundles what (Lagrangian) and (RoboticEquation) are built
from: its calculus, L, M(q, Theta), U(q, Theta), QJ and the free vectors v, a
of the regressors. Concrete chains are THE project's chains
(:mod:`inertiaproof.scene.robots`), turned exact by
:class:`~inertiaproof.symbolic.kinematics.ChainTwin`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from inertiaproof.symbolic.functions_of_time import FunctionsOfTime
from inertiaproof.symbolic.kinematics import ChainTwin
from inertiaproof.symbolic.lagrangian import abstract_lagrangian, chain_lagrangian, chain_potential
from inertiaproof.symbolic.robotics_equation import mass_matrix

from inertiaproof.scene import robots

__all__ = [
    "abstract_system", "build", "chain_inputs", "chain_of", "chain_system", "CHAINS", "profile_systems",
    "scene_key", "System", "SystemKey",
]

CHAINS = {  # profile name -> the built-in scene whose chain it is
    "2R": robots.planar_2r,
    "3R": robots.spatial_3r,
    "6R": robots.ur5,
}


@dataclass(frozen=True)
class SystemKey:
    """What a system is, hashable: ('abstract', n, parameters, rows) or ('chain', name)."""

    kind: str
    name: str
    n: int = 0
    parameters: int = 0
    rows: int = 0

    @classmethod
    def abstract(cls, n, parameters=2, rows=2):
        return cls("abstract", f"abstract n={n}", n, parameters, rows)

    @classmethod
    def chain(cls, name):
        if name not in CHAINS:
            raise ValueError(f"unknown chain {name!r}; one of {', '.join(CHAINS)}")
        return cls("chain", name)

    @property
    def label(self):
        if self.kind == "chain":
            return self.name
        sizes = "" if (self.parameters, self.rows) == (2, 2) else f"-p{self.parameters}-r{self.rows}"
        return f"abstract-n{self.n}{sizes}"


@dataclass(frozen=True)
class System:
    key: SystemKey
    description: str
    calc: Any
    lagrangian: Any
    mass_matrix: tuple
    potential: Any
    body_jacobian: tuple
    v: tuple
    a: tuple
    block: int  # parameters per body (10 for a chain) for R_l and R_M,l
    twin: Any = None


def abstract_system(key):
    calc = FunctionsOfTime(key.n, key.parameters, key.rows)
    m = tuple(tuple(calc.mass_matrix[k, j] for j in range(key.n)) for k in range(key.n))
    qj = tuple(tuple(calc.body_jacobian[r, k] for k in range(key.n)) for r in range(key.rows))
    return System(key, f"abstract {key.n}-DoF system: M = sum_h M^h(q) Theta_h with {key.parameters} generic "
                       f"M^h, U^h and {key.rows} generic rows of QJ",
                  calc, abstract_lagrangian(calc), m, calc.potential, qj, calc.v, calc.a, block=key.parameters)


def chain_of(key):
    return CHAINS[key.name]().chain


def scene_key(scene):
    """A key for a scene's chain, registered under the scene's name and a digest of its exact kinematics
    (two scenes of one name never share a derivation)."""
    import hashlib
    import json

    digest = hashlib.sha256(json.dumps(chain_inputs(scene.chain), sort_keys=True).encode()).hexdigest()[:10]
    name = f"scene {scene.name} {digest}"
    CHAINS[name] = lambda: scene
    return SystemKey("chain", name)


def chain_system(key, chain=None):
    chain = chain or chain_of(key)
    twin = ChainTwin(chain)
    jets = twin.jets
    qj = tuple(tuple(row) for row in twin.body_jacobian)
    blocks = [jets.body_parameters(l) for l in range(1, jets.bodies + 1)]
    return System(key, f"{chain.name} ({chain.kinds}, {chain.n}-DoF), symbolic Phi_l(t) and Psi(t)", jets,
                  chain_lagrangian(twin), mass_matrix(jets, qj, blocks), chain_potential(twin), qj,
                  jets.vector("v"), jets.vector("a"), block=10, twin=twin)


def build(key):
    return abstract_system(key) if key.kind == "abstract" else chain_system(key)


def chain_inputs(chain):
    """The exact data a chain's derivation depends on (for cache keys)."""
    twin_data = ChainTwin(chain)
    return {
        "kinds": [j.kind for j in chain.joints],
        "coordinates": [j.coordinate.name for j in chain.joints],
        "fixed": [[[[str(x) for x in row] for row in r], [str(x) for x in p]] for pair in twin_data.fixed
                  for r, p in pair],
        "axes": [[str(x) for x in a] for a in twin_data.axes],
        "gravity": [str(x) for x in twin_data.gravity],
    }


def profile_systems(profile):
    """The systems a profile derives: abstract n = 1 .. symbolic_max_n, then its concrete chains."""
    p, r = getattr(profile, "symbolic_parameters", 2), getattr(profile, "symbolic_rows", 2)
    return [SystemKey.abstract(n, p, r) for n in range(1, profile.symbolic_max_n + 1)] + \
        [SystemKey.chain(c) for c in profile.concrete_chains]
