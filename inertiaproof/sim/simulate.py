"""Forward dynamics of the generalized robotics equation (RoboticEquation) under a controller, with SciPy.

    M(q, Theta) qdd = tau + w - J^T Q^T Psidot - (C + M(q, Thetadot) + H(q, Psi)) qd - G

The state is (q, qd, W) with W the work supplied so far (inertiaproof.dynamics.energy):
the power balance E(t) - E(t0) = W(t) that Prop1 implies measures a run's
accuracy without a reference solution. :func:`simulate` integrates with one
of SciPy's ``solve_ivp`` methods and reports how the run ended: ``ok``,
``step collapse`` (the step size fell to round-off), ``solver failure`` (the
method gave up otherwise, e.g. LSODA's "unexpected istate"), ``nan``,
``budget`` (too many right-hand-side evaluations, a count: the same on every machine), ``clock`` (stopped by the
wall-clock safety net ``max_seconds``: machine-dependent, so no evidence either way), ``error`` (an exception),
or, judged afterwards by inertiaproof.sim.study, ``wrong energy`` (finished, but
the power balance is off by more than the tolerance allows).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau, solve_ivp

from inertiaproof.dynamics import energy, motion, terms
from inertiaproof.dynamics.forward import scaled_condition, solve_mass

__all__ = [
    "accelerations", "balance_error", "CLOCK", "conditioning", "dominant_eigenvalue", "EXPLICIT", "fastest_eigenvalue",
    "fastest_mode", "fastest_rate", "least_evaluations", "MAX_CONDITION", "METHODS", "mode_in_words", "Run",
    "simulate", "System",
]

METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA")
_SOLVERS = {"RK45": RK45, "DOP853": DOP853, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}
EPS = np.finfo(float).eps
CLOCK = "clock"  # status of a run stopped by the wall-clock safety net: machine-dependent, no evidence either way
EXPLICIT = {"RK45": (3.3, 6), "DOP853": (6.0, 12)}  # real stability interval (h |lambda|), right-hand sides per step


def least_evaluations(method, rate, horizon):
    """Right-hand sides an explicit method needs at least to stay stable on a mode of ``rate`` rad/s over
    ``horizon``: steps h <= (stability interval) / rate, each of EXPLICIT's evaluations; 0 for implicit methods."""
    if method not in EXPLICIT:
        return 0.0
    interval, per_step = EXPLICIT[method]
    return rate * horizon / interval * per_step


def fastest_rate(chain, trajectory, control, times):
    """rad/s of the fastest closed-loop mode about the home posture over the parameters at ``times``:
    max(sqrt(lambda_max(Kp, M)), lambda_max(Kd, M)) as generalized eigenvalues; inf if M is not positive definite."""
    from scipy.linalg import eigh

    kp, kd = control.gain_matrices(chain)
    qj = chain.body_jacobian(control.home)
    sym = lambda a: 0.5 * (a + a.T)  # noqa: E731
    rate = 0.0
    for t in times:
        m = terms.mass_matrix(qj, trajectory.theta(np.array(t))[0])
        try:
            stiff = eigh(sym(kp), m, eigvals_only=True).max()
            damp = eigh(sym(kd), m, eigvals_only=True).max()
        except np.linalg.LinAlgError:
            return np.inf
        rate = max(rate, np.sqrt(max(stiff, 0.0)), damp)
    return float(rate)


def conditioning(chain, trajectory, control, times):
    """max over ``times`` of the scaled cond(M(home, Theta(t))) (:func:`forward.scaled_condition`): qdd keeps about
    -log10(cond x eps) digits."""
    qj = chain.body_jacobian(control.home)
    return float(max(scaled_condition(terms.mass_matrix(qj, trajectory.theta(np.array(t))[0])) for t in times))


MAX_CONDITION = 1e-6 / np.finfo(float).eps  # beyond this, forward dynamics keeps fewer than 6 digits


# -- the equation as an ODE ----------------------------------------------------

def accelerations(kin, gravity, p, qd, tau, forces=motion.generalized_forces):
    """qdd solving (RoboticEquation) with w = 0; ``forces`` is the equation's inverse dynamics."""
    bias = forces(kin, gravity, p, qd, np.zeros_like(qd))
    return solve_mass(terms.mass_matrix(kin.qj, p.theta), tau - bias)


@dataclass
class System:
    """The closed loop of one scene: chain, parameter trajectory, controller, and the forces used (replaceable
    so that tests can feed a deliberately wrong equation)."""

    chain: object
    trajectory: object
    control: object  # a controller (inertiaproof.sim.control)
    forces: object = staticmethod(motion.generalized_forces)
    evaluations: int = 0

    def parameters(self, t):
        return motion.parameters(self.trajectory, t)

    def rhs(self, t, y):
        """d/dt (q, qd, W); ``y`` may be (2n + 1,) or (2n + 1, k) (solve_ivp's vectorized Jacobians)."""
        n = self.chain.n
        y = np.asarray(y, dtype=float)
        states = y.T if y.ndim == 2 else y
        q, qd = states[..., :n], states[..., n:2 * n]
        self.evaluations += 1
        kin = motion.kinematics(self.chain, q)
        p = self.parameters(np.full(q.shape[:-1], t))
        tau = self.control.torque(kin, self.chain.gravity, t, q, qd)
        qdd = accelerations(kin, self.chain.gravity, p, qd, tau, self.forces)
        work_rate = energy.supplied_power(kin, self.chain.gravity, p, qd, tau)
        out = np.concatenate([qd, qdd, work_rate[..., None]], -1)
        return out.T if y.ndim == 2 else out

    def energy(self, t, q, qd):
        """E = T_q + U along samples."""
        kin = motion.kinematics(self.chain, q)
        p = self.parameters(t)
        return (energy.kinetic_energy(kin.qj, p.theta, qd)
                + energy.potential_energy(kin.rotations, kin.origins, p.theta, self.chain.gravity))

    def initial_state(self):
        q0, qd0, _ = self.control.reference(np.array(self.trajectory.span[0]))
        return np.concatenate([q0, qd0, [0.0]])


# -- one run -------------------------------------------------------------------

class _Budget(Exception):
    """The counted budget (right-hand sides) is spent; ``clock``: the wall-clock safety net struck instead."""

    def __init__(self, clock=False):
        super().__init__()
        self.clock = clock


@dataclass
class Run:
    method: str
    rtol: float
    status: str  # ok, step collapse, nan, budget, clock, wrong energy, error
    seconds: float
    steps: int
    evaluations: int
    note: str = ""
    t: np.ndarray = field(default=None, repr=False)
    y: np.ndarray = field(default=None, repr=False)
    balance_error: float = np.nan  # max_t |E - E0 - W| / energy scale
    jacobians: int = 0  # Jacobian evaluations (Radau, BDF: finite differences, one vectorized call each; LSODA's own)
    lus: int = 0  # LU factorizations (Radau: one per real + complex pair)
    predicted: float | None = None  # right-hand sides a run not started was predicted to need (its stiffness)

    @property
    def finished(self):
        return self.status in ("ok", "wrong energy")

    @property
    def work(self):
        """Counted work: right-hand sides + Jacobians + LU factorizations (each counted as one, as the tracking
        batches count it)."""
        return self.evaluations + self.jacobians + self.lus


def simulate(system, horizon, method="DOP853", rtol=1e-8, samples=101, max_evaluations=200_000, max_seconds=60.0,
             atol_scale=None):
    """Integrate the closed loop over [t0, t0 + horizon]; state samples at ``samples`` equally spaced times.

    A run stops as ``budget`` after ``max_evaluations`` right-hand sides, as ``clock`` (CLOCK) after ``max_seconds``
    (a safety net)."""
    t0 = system.trajectory.span[0]
    t_eval = np.linspace(t0, t0 + horizon, samples)
    y0 = system.initial_state()
    scale = atol_scale if atol_scale is not None else _state_scale(system, y0)
    system.evaluations = 0
    deadline = time.perf_counter() + max_seconds

    def fun(t, y):
        if system.evaluations > max_evaluations or time.perf_counter() > deadline:
            raise _Budget(clock=system.evaluations <= max_evaluations)
        return system.rhs(t, y)

    vectorized = method in ("Radau", "BDF")
    solvers = []  # the solver solve_ivp makes, to read its Jacobian and LU counts however the run ends

    if method not in _SOLVERS:
        return Run(method, rtol, "error", 0.0, 0, 0, f"ValueError: method must be one of {METHODS}, not {method!r}")

    class Counted(_SOLVERS[method]):
        def __init__(self, *args, **kwargs):
            solvers.append(self)
            super().__init__(*args, **kwargs)

    def counts():
        solver = solvers[0] if solvers else None
        return {"jacobians": int(getattr(solver, "njev", 0) or 0), "lus": int(getattr(solver, "nlu", 0) or 0)}

    start = time.perf_counter()
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(fun, (t0, t0 + horizon), y0, method=Counted, dense_output=True, rtol=rtol,
                            atol=rtol * scale, vectorized=vectorized)
    except _Budget as stop:
        if stop.clock:
            return Run(method, rtol, CLOCK, time.perf_counter() - start, 0, system.evaluations,
                       f"stopped by the wall-clock safety net ({max_seconds:g} s) after {system.evaluations} "
                       "right-hand-side evaluations (a machine-dependent stop: no evidence)", **counts())
        solver = solvers[0] if solvers else None
        found = np.nan if solver is None else fastest_mode(system, solver.t, solver.y, scale)
        mode = (f" at t = {solver.t:.4g}; the closed loop's fastest mode was then {mode_in_words(found)}"
                if np.isfinite(found) else "")
        return Run(method, rtol, "budget", time.perf_counter() - start, 0, system.evaluations,
                   f"stopped after {system.evaluations} right-hand-side evaluations (budget {max_evaluations}){mode}",
                   **counts())
    except (np.linalg.LinAlgError, ValueError, FloatingPointError) as exc:
        return Run(method, rtol, "error", time.perf_counter() - start, 0, system.evaluations,
                   f"{type(exc).__name__}: {exc}", **counts())
    seconds = time.perf_counter() - start
    steps = max(len(sol.t) - 1, 0)
    if sol.status != 0:
        if not np.all(np.isfinite(sol.y)):
            status = "nan"
        else:
            status = "step collapse" if "step size" in sol.message else "solver failure"
        return Run(method, rtol, status, seconds, steps, system.evaluations,
                   f"{sol.message} (reached t = {sol.t[-1] if sol.t.size else t0:.6g})", **counts())
    y = sol.sol(t_eval).T
    if not (np.all(np.isfinite(sol.y)) and np.all(np.isfinite(y))):
        return Run(method, rtol, "nan", seconds, steps, system.evaluations, "non-finite state", **counts())
    run = Run(method, rtol, "ok", seconds, steps, system.evaluations, t=t_eval, y=y, **counts())
    run.balance_error = balance_error(system, sol.t, sol.y.T)
    return run


def fastest_eigenvalue(rhs, y, scale):
    """The eigenvalue of largest modulus of d rhs / d y at y, by central differences of steps sqrt(eps) x
    max(|y_i|, scale_i); ``rhs`` maps states (k, m) to their derivatives (k, m). The mode a solver must follow, or
    step over if it decays; nan where it cannot be had (a state or derivative not finite)."""
    m = len(y)
    h = np.sqrt(EPS) * np.maximum(np.abs(y), scale)
    with np.errstate(all="ignore"):
        f = rhs(np.concatenate([y + np.diag(h), y - np.diag(h)]))
        jacobian = (f[:m] - f[m:]) / (2 * h[:, None])  # row i: d rhs / d y_i
    return complex(dominant_eigenvalue(jacobian))


def dominant_eigenvalue(matrices):
    """The eigenvalue of largest modulus of each square matrix (..., m, m); nan for one not finite."""
    finite = np.isfinite(matrices).all((-2, -1))
    eigenvalues = np.linalg.eigvals(np.where(finite[..., None, None], matrices, 0.0))
    dominant = np.take_along_axis(eigenvalues, np.abs(eigenvalues).argmax(-1)[..., None], -1)[..., 0]
    return np.where(finite, dominant, np.nan)


def fastest_mode(system, t, y, scale):
    """:func:`fastest_eigenvalue` of d(qd, qdd) / d(q, qd) of the closed loop at the state y (one vectorized
    right-hand side; W left as it is)."""
    n2, rest = 2 * system.chain.n, y[2 * system.chain.n:]

    def rhs(states):
        full = np.concatenate([states, np.broadcast_to(rest, (len(states), len(rest)))], 1)
        return system.rhs(t, full.T).T[:, :n2]

    return fastest_eigenvalue(rhs, y[:n2], scale[:n2])


def mode_in_words(eigenvalue):
    """An eigenvalue of a closed loop's Jacobian in words."""
    rate, frequency = eigenvalue.real, abs(eigenvalue.imag)
    if frequency > abs(rate):
        return f"an oscillation of {frequency:.2g} rad/s, {'growing' if rate > 0 else 'decaying'} at {abs(rate):.2g} /s"
    return f"{'growing' if rate > 0 else 'decaying'} at {abs(rate):.2g} /s"


def _state_scale(system, y0):
    """Absolute tolerance per state component, from the system itself: the reference's amplitude (else the
    coordinate box), that amplitude per second at the reference's frequency (at least 1/s), and an energy scale
    max(|E0|, 1/2 qd_s^T M qd_s, |G^T q_s|)."""
    n = system.chain.n
    c = system.control
    lo, hi = system.chain.coordinate_box()
    q_scale = np.full(n, max(c.amplitude, np.abs(c.home).max(initial=0.0)))
    q_scale = np.where(q_scale > 0, q_scale, hi - lo)
    qd_scale = q_scale * max(2 * np.pi * c.frequency, 1.0)
    q0, qd0 = y0[:n], y0[n:2 * n]
    kin = motion.kinematics(system.chain, q0)
    p = system.parameters(np.array(system.trajectory.span[0]))
    m = terms.mass_matrix(kin.qj, p.theta)
    g = terms.gravity(kin.qj, kin.rotations, p.theta, system.chain.gravity)
    e0 = float(system.energy(np.array(system.trajectory.span[0]), q0, qd0))
    e_scale = max(abs(e0), 0.5 * qd_scale @ m @ qd_scale, abs(g @ q_scale), np.finfo(float).tiny)
    return np.concatenate([q_scale, qd_scale, [e_scale]])


def balance_error(system, t, y):
    """max over the integrator's own steps of |E(t) - E(t0) - W(t)| over the energy in play
    (max |E - E0|, |W|, |E0|)."""
    n = system.chain.n
    q, qd, work = y[:, :n], y[:, n:2 * n], y[:, 2 * n]
    e = system.energy(t, q, qd)
    scale = max(np.abs(e - e[0]).max(), np.abs(work).max(), np.abs(e[0]), np.finfo(float).tiny)
    return float(np.abs(e - e[0] - work).max() / scale)
