"""The calculus a derivation needs, whatever represents its functions.

Two implementations: :class:`~inertiaproof.symbolic.functions_of_time.FunctionsOfTime`
(generic SymPy functions of t, the abstract system) and
:class:`~inertiaproof.symbolic.jets.JetSpace` (polynomials in jet coordinates,
the concrete chains). The derivations of :mod:`~inertiaproof.symbolic.lagrangian`,
:mod:`~inertiaproof.symbolic.robotics_equation` and
:mod:`~inertiaproof.symbolic.properties` are written once against this protocol.
Indices k run 1..n (coordinates), h 0..len(theta)-1 (inertial parameters).
"""

from __future__ import annotations

from typing import Any, Protocol

__all__ = ["Calculus"]


class Calculus(Protocol):
    n: int
    zero: Any
    one: Any
    q_dot: tuple
    q_ddot: tuple
    theta: tuple  # Theta (eq:Phi stacked)
    theta_dot: tuple
    psi: tuple  # Psi (KineticEnergy)
    psi_dot: tuple

    def d_q(self, e, k): """d e / d q_k at fixed qd, Theta, Psi."""

    def d_qd(self, e, k): """d e / d qd_k."""

    def d_theta(self, e, h): """d e / d Theta_h."""

    def d_t(self, e): """The total time derivative along q(t), Theta(t), Psi(t)."""

    def at_rates(self, e): """e with Theta replaced by Thetadot (M(q, Thetadot) from M(q, Theta))."""

    def canonical(self, e): """A canonical form: e is the zero function iff canonical(e) is 0."""

    def is_zero(self, e): ...

    def size(self, e): """Terms of the canonical form."""

    def free_roles(self, e): """Roles ('theta', 'qd', ...) of what e depends on."""

    def evaluate(self, e, point): """Exact rational value at a point."""

    def degree_profile(self, e): """({k: degree in (cos q_k, sin q_k)}, degree in the rest), for Schwartz-Zippel."""

    def point_keys(self, leaves): """The coordinates a point must give to evaluate these expressions."""

    def printed(self, e): """The canonical form as deterministic text (for the gate's form fingerprint)."""
