"""Fingerprints of derived objects: their form (a hash of a canonical form) and their meaning (exact values).

The form is the sha256 of the canonical forms' text (jet polynomials printed
in the ring's monomial order; abstract expressions as ``srepr`` of their
expansion), read under PYTHONHASHSEED=0. The meaning is every entry's exact
value at fixed rational points (:func:`~inertiaproof.symbolic.identity.fixed_point`),
whose coordinates are assigned by role (cos q_1, Thetadot of body 2, ...), not by
printed name: renaming a symbol changes the form only, changing a sign or a
factor changes the meaning.
"""

from __future__ import annotations

import hashlib

from inertiaproof.symbolic.identity import fixed_point, leaves

__all__ = ["fingerprints", "form", "meaning", "MEANING_POINTS", "OBJECTS"]

MEANING_POINTS = (0, 1)  # salts of the fixed rational points

OBJECTS = (  # name, catalog ID, what it is, getter
    ("euler_lagrange", "GRE", "d/dt dL/dqd - dL/dq (LagrangeFormalism)", lambda d: d.euler_lagrange),
    ("M", "GRE", "M(q, Theta) (MassMatrix)", lambda d: d.equation.M),
    ("C", "GRE", "C(q, qd, Theta) (DefCoriolis)", lambda d: d.equation.C),
    ("G", "GRE", "G(q, Theta) (DefGravitation)", lambda d: d.equation.G),
    ("H", "GRE", "H(q, Psi) (DefH)", lambda d: d.equation.H),
    ("psi_force", "GRE", "J^T Q^T Psidot", lambda d: d.equation.psi_force),
    ("M_rates", "GRE-F", "M(q, Thetadot)", lambda d: d.equation.M_rates),
    ("F", "GRE-F", "F(q, Theta, Thetadot) (DefF)", lambda d: d.F),
    ("N", "Prop1", "Mdot - 2C - M(q, Thetadot)", lambda d: d.N),
    ("R", "Prop2", "R(q, qd, v, a) (RoboticRegressor)", lambda d: d.regressors.R),
    ("R_M", "Prop2", "R_M(q, v) (RoboticRegressorVel)", lambda d: d.regressors.R_M_velocity),
)


def form(calc, obj):
    text = "\n".join(calc.printed(x) for x in leaves(obj))
    return hashlib.sha256(text.encode()).hexdigest()


def meaning(calc, obj):
    entries, out = leaves(obj), []
    for salt in MEANING_POINTS:
        point, memo = fixed_point(calc, salt), {}
        out.append([str(calc.evaluate(x, point, memo)) for x in entries])
    return out


def fingerprints(derivation):
    """{"<system>/<object>": {"id", "what", "form", "meaning"}} for one derivation."""
    calc, out = derivation.calc, {}
    for name, catalog_id, what, get in OBJECTS:
        obj = get(derivation)
        out[f"{derivation.key.label}/{name}"] = {"id": catalog_id, "what": what, "form": form(calc, obj),
                                                 "meaning": meaning(calc, obj)}
    return out
