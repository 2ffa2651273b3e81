"""Fixed-step Runge-Kutta schemes of known order on one time grid, explicit and implicit.

The loading study (inertiaproof.sim.capture) integrates (RoboticEquation) and the rigid chain between plastic
captures on one fixed grid, so that the captures sit on grid points and every model carries the same
integration error, estimated by halving the steps. Classical Runge-Kutta (order 4) needs h x (fastest
closed-loop rate) below its stability bound; on a stiff scene (a 5e-9 kg m^2 rod under gains tuned for a
heavy joint: 3.7e9 rad/s) that is billions of steps. The 2-stage Radau IIA collocation scheme (order 3, stage
order 2, L-stable: the stiff modes are damped, not merely bounded) has no such bound; its stage equations are
solved by simplified Newton iterations with the Jacobian of the right-hand side by forward differences,
evaluated as one batch of perturbed states.

Work is counted (:class:`Work`: steps, right-hand sides, Jacobians, Newton iterations) and bounded by counts
(NEWTON_MAX iterations a step), the same on every machine. A Jacobian is kept over the steps (h is fixed) while
the iterations converge quickly, as in Hairer and Wanner's RADAU5.

A right-hand side is ``rhs(t, states, f)``: ``states`` (d,) or a batch (m, d), ``f`` the known input at t (the
feedforward torque at the scheme's node), returning d/dt of the states in the same shape; for a batch, ``t`` is
one time or one per state, and ``f`` one input or one per state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import lu_factor, lu_solve

__all__ = ["integrate", "jacobian", "NEWTON_MAX", "NEWTON_REUSE", "NEWTON_RTOL", "NewtonFailure", "RADAU_IIA", "RK4",
           "Scheme", "Work"]

NEWTON_MAX = 10  # simplified Newton iterations a step may take with a fresh Jacobian (a count)
NEWTON_REUSE = 4  # ... with the Jacobian of an earlier step, before it is evaluated afresh
NEWTON_RTOL = 1e-12  # a Newton update below this share of the state's magnitude (per half: q, qd) has converged
DIFFERENCE = np.sqrt(np.finfo(float).eps)  # relative forward-difference step of the Jacobian


class NewtonFailure(ArithmeticError):
    """The stage equations of an implicit step did not converge within NEWTON_MAX iterations."""


@dataclass
class Work:
    """What an integration cost, in counts."""

    steps: int = 0
    evaluations: int = 0  # right-hand sides (a batch of m states counts m)
    jacobians: int = 0
    newton: int = 0  # simplified Newton iterations

    def add(self, other):
        for name in ("steps", "evaluations", "jacobians", "newton"):
            setattr(self, name, getattr(self, name) + getattr(other, name))
        return self

    def as_dict(self):
        return {"steps": self.steps, "evaluations": self.evaluations, "jacobians": self.jacobians,
                "newton_iterations": self.newton}


def _count(rhs, work):
    def counted(t, y, f):
        work.evaluations += 1 if np.ndim(y) == 1 else len(y)
        return rhs(t, y, f)
    return counted


def _rk4_step(rhs, t, h, y, f, work, memo):
    """Classical Runge-Kutta; ``f`` = input at the nodes (0, 1/2, 1)."""
    k1 = rhs(t, y, f[0])
    k2 = rhs(t + h / 2, y + h / 2 * k1, f[1])
    k3 = rhs(t + h / 2, y + h / 2 * k2, f[1])
    k4 = rhs(t + h, y + h * k3, f[2])
    return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def jacobian(rhs, t, y, f, fy):
    """d rhs / d y at (t, y) by forward differences, all columns in one batch of perturbed states."""
    step = DIFFERENCE * np.maximum(np.abs(y), _magnitude(y))
    columns = rhs(t, y[None, :] + np.diag(step), f)  # row j: the state moved along e_j
    return ((columns - fy) / step[:, None]).T


def _magnitude(y):
    """Per component: the largest |y| of its half (q or qd); for a half that is all zero, of the whole state; 1 for
    a zero state."""
    half = y.size // 2
    top = np.abs(y).max(initial=0.0) or 1.0
    parts = [np.abs(y[:half]).max(initial=0.0) or top, np.abs(y[half:]).max(initial=0.0) or top]
    return np.concatenate([np.full(half, parts[0]), np.full(y.size - half, parts[1])])


_RADAU_A = np.array([[5 / 12, -1 / 12], [3 / 4, 1 / 4]])
_RADAU_C = np.array([1 / 3, 1.0])


def _radau_step(rhs, t, h, y, f, work, memo):
    """2-stage Radau IIA (order 3, L-stable); ``f`` = input at the nodes (0, 1/3, 1). Stage increments Z solve
    Z = h (A x I) F(y + Z) by simplified Newton with the LU factors of I - h A x J; J = d rhs/dy is kept in ``memo``
    from an earlier step of the same h while the iterations converge within NEWTON_REUSE, else it is evaluated
    afresh at (t, y) and the step retried. y+ = y + Z_2 (stiffly accurate)."""
    for fresh in (False, True):
        if fresh or memo.get("h") != h:
            work.jacobians += 1
            j = jacobian(rhs, t, y, f[0], rhs(t, y, f[0]))
            memo.update(h=h, lu=lu_factor(np.eye(2 * y.size) - h * np.kron(_RADAU_A, j)))
        z = _radau_stages(rhs, t, h, y, f, work, memo["lu"], NEWTON_MAX if fresh else NEWTON_REUSE)
        if z is not None:
            return y + z[1]
    raise NewtonFailure(f"the Radau IIA stage equations did not converge in {NEWTON_MAX} Newton iterations "
                        f"at t = {t:.6g} (h = {h:.3g})")


def _radau_stages(rhs, t, h, y, f, work, lu, iterations):
    """The stage increments Z (2, d) after at most ``iterations`` simplified Newton iterations; None if they did not
    converge (updates below NEWTON_RTOL of the state's magnitude)."""
    z = np.zeros((2, y.size))
    tolerance = NEWTON_RTOL * _magnitude(y)
    for _ in range(iterations):
        work.newton += 1
        stages = rhs(t + _RADAU_C * h, y + z, np.asarray(f[1:]))  # both stages in one batch
        update = lu_solve(lu, (h * _RADAU_A @ stages - z).ravel()).reshape(2, -1)
        z += update
        if not np.all(np.isfinite(z)):
            return None
        if np.all(np.abs(update) <= tolerance + NEWTON_RTOL * np.abs(z)):
            return z
    return None


@dataclass(frozen=True)
class Scheme:
    """A fixed-step scheme: its name, order, the nodes (fractions of a step) where it needs the input, one step."""

    name: str
    order: int
    nodes: tuple
    step: object
    implicit: bool = False


RK4 = Scheme("classical Runge-Kutta (RK4)", 4, (0.0, 0.5, 1.0), _rk4_step)
RADAU_IIA = Scheme("2-stage Radau IIA", 3, (0.0, 1 / 3, 1.0), _radau_step, implicit=True)


def integrate(scheme, rhs, state, times, inputs, jumps=None, work=None):
    """Steps of ``scheme`` over ``times``; ``inputs[i]`` = the input at t_i + nodes x h_i; ``jumps(i, state)``
    applies captures at grid index i (before step i; index len(times) - 1 after the last). Counts go to ``work``."""
    work = work if work is not None else Work()
    counted, memo = _count(rhs, work), {}
    for i in range(len(times) - 1):
        if jumps is not None:
            state = jumps(i, state)
        state = scheme.step(counted, times[i], times[i + 1] - times[i], state, inputs[i], work, memo)
        work.steps += 1
    if jumps is not None:
        state = jumps(len(times) - 1, state)
    return state
