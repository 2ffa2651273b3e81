"""Adaptive tracking on three plants: the controller of Slotine and Li with a plug-in adaptive law.

    qd_r = qd_d - Lambda e,  s = qd - qd_r,  tau = sum_l R_l(q, qd, qd_r, qdd_r) Phi_hat_l - K_D s

with e = q - q_d (RoboticRegressor for R_l, the law from inertiaproof.sim.adaptive). The plant is

- ``gre``: the generalized equation (RoboticEquation) with M(q, Thetadot), H(q, Psi) and J^T Q^T Psidot;
- ``pagilla``: Eq. (2) (SimpleGeneralizationOfTheRoboticEquation) with F = M(q, Thetadot) (DefF), no particle motion;
- ``classical``: Eq. (1) (ClassicalRoboticEquation) with Theta(t) frozen at every instant (no rate terms).

Along every run V = 1/2 s^T M(q, Theta) s + D(z, Theta) obeys, by Prop1 (skew-symmetry of Mdot - 2C - M(q, Thetadot)
and of H), Prop2 and the law's divergence,

    Vdot = -s^T K_D s - s^T X + 1/2 s^T M(q, Thetadot) s + dD/dTheta . Thetadot

with X the plant's terms beyond Eq. (1) (gre: (M(q, Thetadot) + H) qd + J^T Q^T Psidot; pagilla: M(q, Thetadot) qd;
classical: 0), assembled here from inertiaproof.dynamics.terms independently of the plant's inverse dynamics.
A run integrates the right-hand side as W; max |V - V(0) - W| / max(max |V|, rtol E) is its Lyapunov balance
error, with E the energy scale of W's absolute tolerance (:meth:`Batch.scale`): a run whose V stays at the
round-off of that scale (no load yet, Theta_hat(0) = Theta) has nothing to balance.

Runs on one chain are integrated together (one state vector, batched NumPy; RK45, or BDF / Radau with a block-diagonal
Jacobian when the batch is stiff, or the method the scene asks for); each keeps its own trajectory, law, gains,
reference, initial estimate and plant, and keeps what it reached when the batch stops early.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse
from scipy.integrate import BDF, DOP853, RK45, Radau

from inertiaproof.dynamics import motion, regressors, terms
from inertiaproof.dynamics.forward import scaled_condition, solve_mass

from .adaptive import make_law
from .control import controller, reference_motion
from .simulate import CLOCK, EPS, EXPLICIT, MAX_CONDITION, dominant_eigenvalue, least_evaluations, mode_in_words

__all__ = ["BARRIER", "CLOCK", "choose_method", "evaluation_cost", "IMPLICIT", "IMPLICIT_DEFAULT", "NOT_STARTED",
           "PLANTS", "Batch", "Gains", "Reference", "Run", "RunSpec", "scene_specs", "simulate", "SOLVERS", "spent"]

PLANTS = ("gre", "pagilla", "classical")
NOT_STARTED = ("ill-conditioned", "no start")  # statuses of a batch that simulate() does not integrate
BARRIER = "barrier"  # a run whose law's state crossed a barrier (AdaptiveLaw.outside): integration error, not the law
SOLVERS = {"RK45": RK45, "DOP853": DOP853, "BDF": BDF, "Radau": Radau}
IMPLICIT = ("BDF", "Radau")
MAX_JACOBIAN_BYTES = 2 ** 28  # dense blocks of one batch's Jacobian beyond this: RK45 whatever the stiffness
STIFFNESS_TIMES = 5  # instants over the horizon at which Batch.stiffness looks
STOPPED = ("budget", "step collapse", "error", "nan")  # a batch the integrator or the count stopped
UNRESOLVED_MARGIN = 1e-12  # AdaptiveLaw.barrier_margin below this: the estimate is beyond float64's resolution
RK45_MARGIN = 3  # RK45 only within a third of the budget by its stability bound: near that bound its step control
# rejects steps (the 1e6 mass ratio's batch took 2.4 x the bound; Panda's, predicted at 0.94 of its budget, ran out)
STIFFENED = "stiffened"  # _integrate's stop when _stiffened finds the explicit method will not do (simulate: budget)
STIFFENING_CHECK = 512  # counted evaluations of an explicit batch at which _stiffened first looks (then at 2x, 4x, ...)
IMPLICIT_DEFAULT = "BDF"  # measured faster than Radau on the stiff scenes (README: stiff runs)
KEPT = {"gre": (1.0, 1.0), "pagilla": (1.0, 0.0), "classical": (0.0, 0.0)}  # (Thetadot, Psi) each plant keeps


@dataclass(frozen=True)
class Reference:
    """q_d(t) = home + amplitude sin(2 pi frequency t + k pi / 3) on joint k (inertiaproof.sim.control)."""

    home: np.ndarray
    amplitude: float
    frequency: float


@dataclass(frozen=True)
class Gains:
    lam: np.ndarray  # Lambda (n,), 1/s
    kd: np.ndarray  # K_D (n,)


@dataclass(frozen=True)
class RunSpec:
    trajectory: object  # inertiaproof.dynamics.trajectory.ParameterTrajectory
    law: object  # inertiaproof.sim.adaptive.AdaptiveLaw
    gains: Gains
    reference: Reference
    theta_hat0: np.ndarray  # (N, 10)
    plant: str = "gre"

    def __post_init__(self):
        if self.plant not in PLANTS:
            raise ValueError(f"plant must be one of {PLANTS}, not {self.plant!r}")


def scene_specs(scene, laws, plants, settings=None, trajectory=None):
    """RunSpecs of a scene for every (law, plant): its [control] reference, its [adaptive] gains (or ``settings``),
    Theta_hat(0) = estimate Theta(t0), K_D = kd diag(M(home, Theta(t0))); ``trajectory`` replaces the scene's."""
    s = settings or scene.adaptive
    trajectory = trajectory or scene.trajectory
    c = controller(scene.chain, trajectory, scene.control)
    n = scene.chain.n
    mass_diagonal = np.diagonal(terms.mass_matrix(scene.chain.body_jacobian(c.home), c.nominal))
    gains = Gains(np.full(n, s.lam), s.kd * mass_diagonal)
    reference = Reference(c.home, c.amplitude, c.frequency)
    theta_hat0 = np.asarray(s.estimate, float)[:, None] * c.nominal
    return [RunSpec(trajectory, make_law(law, s.gain(law)), gains, reference, theta_hat0, plant)
            for law in laws for plant in plants]


def _groups(items):
    """[(item, indices)] of the distinct objects (by identity), in first-seen order."""
    out = {}
    for i, item in enumerate(items):
        out.setdefault(id(item), (item, []))[1].append(i)
    return [(item, np.array(idx)) for item, idx in out.values()]


class Batch:
    """The closed loops of several runs on one chain. ``forces`` is the plants' inverse dynamics (replaceable, so
    that tests can feed a wrong equation)."""

    def __init__(self, chain, specs, forces=motion.generalized_forces):
        self.chain, self.specs, self.forces = chain, list(specs), forces
        self.n, self.bodies = chain.n, self.specs[0].trajectory.bodies
        self.size = 2 * self.n + 10 * self.bodies + 1  # q, qd, z, W
        self.home = np.stack([s.reference.home for s in self.specs]).astype(float)
        self.amplitude = np.array([s.reference.amplitude for s in self.specs], float)
        self.frequency = np.array([s.reference.frequency for s in self.specs], float)
        self.qd_scale = np.maximum(self.amplitude, 0.1) * np.maximum(2 * np.pi * self.frequency, 1.0)  # q_d's rate
        self.lam = np.stack([np.broadcast_to(s.gains.lam, (self.n,)) for s in self.specs]).astype(float)
        self.kd = np.stack([np.broadcast_to(s.gains.kd, (self.n,)) for s in self.specs]).astype(float)
        kept = np.array([KEPT[s.plant] for s in self.specs])
        self.keep_rate, self.keep_psi = kept[:, 0], kept[:, 1]
        self.trajectories = _groups([s.trajectory for s in self.specs])
        self.laws = _groups([s.law for s in self.specs])
        self.evaluations = 0
        self.jacobians = 0
        # counted work of one Jacobian, in right-hand sides of the batch: its blocks, and the n + 1 states of
        # velocity_columns at the cost of evaluations (evaluation_cost) of that many runs
        self.jacobian_cost = 1 + evaluation_cost(self.n, len(self.specs) * (self.n + 1)) / evaluation_cost(
            self.n, len(self.specs))

    @property
    def jacobian_bytes(self):
        """The dense blocks of one Jacobian of the batch, in bytes (MAX_JACOBIAN_BYTES)."""
        return len(self.specs) * self.size ** 2 * 8

    def split(self, y):
        """(q, qd, z, W) of states y (..., B * size)."""
        y = y.reshape(y.shape[:-1] + (len(self.specs), self.size))
        n = self.n
        return y[..., :n], y[..., n:2 * n], y[..., 2 * n:-1].reshape(y.shape[:-1] + (self.bodies, 10)), y[..., -1]

    def reference(self, t):
        return reference_motion(self.home, self.amplitude, self.frequency, t)

    def parameters(self, t):
        """Each run's own Theta, Thetadot, Psi, Psidot at times t (scalar or (..., B)), stacked over runs."""
        t = np.asarray(t, float)
        shape = (len(self.specs),) if t.ndim == 0 else t.shape
        parts = [None] * 4
        for trajectory, idx in self.trajectories:
            p = motion.parameters(trajectory, t if t.ndim == 0 else t[..., idx])  # one time: once per trajectory
            for k, x in enumerate((p.theta, p.theta_dot, p.psi, p.psi_dot)):
                tail = x.shape[t.ndim:]
                if parts[k] is None:
                    parts[k] = np.zeros(shape + tail)
                parts[k][(Ellipsis, idx) + (slice(None),) * len(tail)] = x if t.ndim else x[None]
        return motion.Parameters(*parts)

    def per_law(self, method, z, *args):
        """law.method(z, *args) over each law's runs, assembled; the arguments are (..., B, N, 10)."""
        out = None
        for law, idx in self.laws:
            value = getattr(law, method)(z[..., idx, :, :], *(a[..., idx, :, :] for a in args))
            if out is None:
                out = np.zeros(z.shape[:-3] + (len(self.specs),) + value.shape[z.ndim - 2:])
            out[(Ellipsis, idx) + (slice(None),) * (value.ndim - z.ndim + 2)] = value
        return out

    def plant_parameters(self, p):
        """What the plants keep: Eq. (2) drops Psi, Eq. (1) also Thetadot."""
        return motion.Parameters(p.theta, self.keep_rate[:, None, None] * p.theta_dot,
                                 self.keep_psi[:, None] * p.psi, self.keep_psi[:, None] * p.psi_dot)

    def controller(self, t, y, kin=None):
        """(q, qd, z, kin, s, R) at states y: the sliding variable s = qd - qd_r and the regressors R_l(q, qd, qd_r,
        qdd_r) (RoboticRegressor) of the controller of the module docstring; ``kin`` the kinematics at q if known."""
        q, qd, z, _ = self.split(y)
        kin = motion.kinematics(self.chain, q) if kin is None else kin
        q_d, qd_d, qdd_d = self.reference(t)
        e, e_dot = q - q_d, qd - qd_d
        qd_r, qdd_r = qd_d - self.lam * e, qdd_d - self.lam * e_dot
        r = regressors.regressor(kin.qj, kin.dqj, kin.rotations, self.chain.gravity, qd, qd_r, qdd_r)
        return q, qd, z, kin, qd - qd_r, r

    def closed_loop(self, t, y, kin=None):
        """(qd, z, kin, s, R, Parameters, the plants' Parameters, qdd) at states y: the controller's torque on each
        run's plant."""
        _, qd, z, kin, s, r = self.controller(t, y, kin)
        tau = regressors.apply_regressor(r, self.per_law("estimate", z)) - self.kd * s
        p = self.parameters(t)
        plant = self.plant_parameters(p)
        bias = self.forces(kin, self.chain.gravity, plant, qd, np.zeros_like(qd))
        return qd, z, kin, s, r, p, plant, solve_mass(terms.mass_matrix(kin.qj, p.theta), tau - bias)

    def rhs(self, t, y):
        self.evaluations += 1
        qd, z, kin, s, r, p, plant, qdd = self.closed_loop(t, y)
        zdot = self.per_law("rate", z, np.einsum("...lkh,...k->...lh", r, s))
        power = self.lyapunov_power(kin, p, plant, qd, s, z)
        return np.concatenate([qd, qdd, zdot.reshape(zdot.shape[:-2] + (-1,)), power[..., None]], -1).reshape(y.shape)

    def jacobian_blocks(self, t, y, kin=None):
        """Per run, d ydot / dy (B, size, size) at the state y (B * size,): the terms that make the loop stiff.

        In s the closed loop reads M(q, Theta) sdot = -K_D s + sum_l R_l (Phi_hat_l - Phi_l) - C s - X (module
        docstring), with s = qd - qd_d + Lambda e, qdd = sdot + qdd_d - Lambda (qd - qd_d) and zdot = rate(z, R^T s):

            d qdd / dq = -M^-1 K_D Lambda,   d qdd / dqd = -Lambda - M^-1 K_D,
            d qdd / dz_l = M^-1 R_l dPhi_hat_l/dz_l,
            d zdot_l / d(q, qd) = (d rate / dg) R_l^T (Lambda, I),   d zdot_l / dz_l = d rate / dz

        (the law's own linearization). Left out: the derivatives of M, C, G and R in q and qd, which scale with the
        motion's speed, not with K_D or the adaptation gain. For the Newton iterations of Radau and BDF (an
        approximate Jacobian costs iterations, not accuracy) and for the stiffness estimate."""
        _, _, z, kin, s, r = self.controller(t, y, kin)
        n, size, runs = self.n, self.size, len(self.specs)
        minv = np.linalg.inv(terms.mass_matrix(kin.qj, self.parameters(t).theta))
        g = np.einsum("...lkh,...k->...lh", r, s)
        d_estimate, d_rate_z, d_rate_g = (np.zeros(z.shape + (10,)) for _ in range(3))
        for law, idx in self.laws:
            d_estimate[idx], d_rate_z[idx], d_rate_g[idx] = law.linearization(z[idx], g[idx])
        out = np.zeros((runs, size, size))
        zs = slice(2 * n, size - 1)
        out[:, :n, n:2 * n] = np.eye(n)
        out[:, n:2 * n, :n] = -minv * (self.kd * self.lam)[:, None, :]
        out[:, n:2 * n, n:2 * n] = -minv * self.kd[:, None, :] - self.lam[:, :, None] * np.eye(n)
        out[:, n:2 * n, zs] = np.einsum("bij,bljh,blhm->bilm", minv, r, d_estimate).reshape(runs, n, -1)
        rate_s = np.einsum("blih,bljh->blij", d_rate_g, r).reshape(runs, -1, n)
        out[:, zs, :n] = rate_s * self.lam[:, None, :]
        out[:, zs, n:2 * n] = rate_s
        blocks = np.zeros((runs, self.bodies, 10, self.bodies, 10))
        blocks[:, np.arange(self.bodies), :, np.arange(self.bodies), :] = np.moveaxis(d_rate_z, 1, 0)
        out[:, zs, zs] = blocks.reshape(runs, 10 * self.bodies, 10 * self.bodies)
        return out

    def velocity_columns(self, t, y, kin=None):
        """Per run, d qdd / dqd (B, n, n) by forward differences: the n states qd + h_j e_j in one batched
        :meth:`closed_loop` that reuses the kinematics at q (qd does not enter them), h_j = sqrt(eps) max(|qd_j|, the
        reference's rate). The terms :meth:`jacobian_blocks` leaves out there (C, M(q, Thetadot), H and R in qd)
        are the ones that stall Newton on a long chain: on the 24-link snake BDF took 5,584 right-hand sides and
        403 Jacobians for one run, 1,120 and 62 with these columns. For Newton's matrix, not exact: qdd is quadratic
        in qd, and the step's truncation error is h_j/2 d^2 qdd / dqd_j^2 (on the thin rod, with its qdd of 4e4,
        up to 11 % of the block; exact central differences or complex steps take 2n states, with the same steps on
        the snake). The law's rows keep their analytic columns: differences there, against
        micro_2r's tolerances of 1e-13 on its estimate, stalled Newton (t = 0.011 of 1.7 s in 3,000 evaluations)."""
        n, runs = self.n, len(self.specs)
        state = y.reshape(runs, self.size)
        qd = state[:, n:2 * n]
        h = np.sqrt(EPS) * np.maximum(np.abs(qd), self.qd_scale[:, None])
        kin = motion.kinematics(self.chain, state[:, :n]) if kin is None else kin
        kin = motion.Kinematics(*(np.broadcast_to(a, (n + 1,) + a.shape) for a in vars(kin).values()))
        stepped = np.repeat(state[None], n + 1, 0)
        stepped[np.arange(1, n + 1), :, n + np.arange(n)] += h.T
        f = self.closed_loop(t, stepped.reshape(n + 1, -1), kin)[-1]
        return np.moveaxis((f[1:] - f[0]) / h.T[:, :, None], 0, -1)

    def newton_blocks(self, t, y):
        """:meth:`jacobian_blocks` with :meth:`velocity_columns` in place of its d qdd / dqd (B, size, size)."""
        n = self.n
        kin = motion.kinematics(self.chain, y.reshape(len(self.specs), self.size)[:, :n])
        blocks = self.jacobian_blocks(t, y, kin)
        blocks[:, n:2 * n, n:2 * n] = self.velocity_columns(t, y, kin)
        return blocks

    def fastest_modes(self, t, y):
        """Per run, the eigenvalue of largest modulus of :meth:`newton_blocks` at the state y (the derivatives in q
        of M, C, G and R left out): the mode a solver must follow, or step over if it decays; nan for a run whose
        blocks are not finite."""
        with np.errstate(all="ignore"):
            return dominant_eigenvalue(self.newton_blocks(t, y))

    def jacobian(self, t, y):
        """:meth:`jacobian_blocks` with :meth:`velocity_columns` in place of its d qdd / dqd, as one sparse
        block-diagonal matrix (the runs are independent), for SciPy."""
        self.jacobians += 1
        blocks = self.newton_blocks(t, y)
        runs = len(blocks)
        return sparse.bsr_matrix((blocks, np.arange(runs), np.arange(runs + 1)),
                                 shape=(runs * self.size,) * 2).tocsc()

    def stiffness(self, horizon=0.0, times=STIFFNESS_TIMES):
        """Per run, the largest spectral radius of :meth:`jacobian_blocks`, 1/s, at ``times`` instants across
        [t0, t0 + horizon] on the reference's state with the initial estimate (the loads change M as they come):
        the fastest mode of the closed loop, damping (M^-1 K_D) and adaptation (gamma R^T M^-1 R) alike. An explicit
        method must keep h times it inside its stability region."""
        t0 = self.specs[0].trajectory.span[0]
        rho = np.zeros(len(self.specs))
        with np.errstate(all="ignore"):
            for t in np.linspace(t0, t0 + horizon, times if horizon > 0 else 1):
                try:
                    blocks = self.jacobian_blocks(t, self.initial_state(t))
                    rho = np.fmax(rho, np.abs(np.linalg.eigvals(blocks)).max(-1))
                except np.linalg.LinAlgError:
                    return np.full(len(self.specs), np.inf)
        return rho

    def lyapunov_power(self, kin, p, plant, qd, s, z):
        """Vdot by the identity of the module docstring."""
        m_rate = terms.mass_matrix(kin.qj, p.theta_dot)
        extra = (self.keep_rate[:, None] * np.einsum("...ij,...j->...i", m_rate, qd)
                 + np.einsum("...ij,...j->...i", terms.lumped_velocity_matrix(kin.dqj, plant.psi), qd)
                 + terms.lumped_acceleration_force(kin.qj, plant.psi_dot))
        rate_part = 0.5 * np.einsum("...i,...ij,...j->...", s, m_rate, s)
        divergence_part = np.sum(self.per_law("divergence_gradient", z, p.theta) * p.theta_dot, axis=(-2, -1))
        return -np.sum(self.kd * s * s, -1) - np.sum(s * extra, -1) + rate_part + divergence_part

    def balance_errors(self, t, y, floor):
        """(V (T, B), each run's Lyapunov balance error max_t |V - V(0) - W| / max(max_t |V|, floor) (B,)) at states
        y (T, B * size) and times t (T,) (module docstring; ``floor``: W's absolute tolerance)."""
        with np.errstate(all="ignore"):
            v = self.lyapunov(t, y)
            return v, np.abs(v - v[0] - self.split(y)[3]).max(0) / np.maximum(np.abs(v).max(0), floor)

    def lyapunov(self, t, y):
        """V = 1/2 s^T M(q, Theta) s + D at states y (T, B * size) and times t (T,): (T, B)."""
        q, qd, z, _ = self.split(y)
        t = np.asarray(t, float)[:, None] * np.ones(len(self.specs))
        q_d, qd_d, _ = self.reference(t)
        s = qd - qd_d + self.lam * (q - q_d)
        p = self.parameters(t)
        m = terms.mass_matrix(self.chain.body_jacobian(q), p.theta)
        divergence = np.zeros(t.shape)
        for law, idx in self.laws:
            divergence[..., idx] = law.divergence(z[..., idx, :, :], p.theta[..., idx, :, :])
        return 0.5 * np.einsum("...i,...ij,...j->...", s, m, s) + divergence

    def start_mass_matrix(self):
        """M(q0, Theta(t0)) of every run (B, n, n)."""
        t0 = np.array([s.trajectory.span[0] for s in self.specs])
        q0 = self.reference(t0)[0]
        return terms.mass_matrix(self.chain.body_jacobian(q0), self.parameters(t0).theta)

    def initial_state(self, t=None):
        """(q_d, qd_d, z(0), W = 0) at each run's start, or at time t (the reference's state then)."""
        t0 = np.array([s.trajectory.span[0] for s in self.specs]) if t is None else np.full(len(self.specs), t)
        q0, qd0, _ = self.reference(t0)
        z0 = np.stack([s.law.initial(s.theta_hat0) for s in self.specs]).reshape(len(self.specs), -1)
        return np.concatenate([q0, qd0, z0, np.zeros((len(self.specs), 1))], -1).ravel()

    def scale(self):
        """Absolute tolerance per component: the reference's amplitude and its rate, each law state's size, and
        the energy 1/2 K_D / Lambda |qd|^2 of a velocity error of the reference's rate."""
        y0 = self.initial_state().reshape(len(self.specs), self.size)
        q = np.maximum(self.amplitude, 0.1)[:, None] * np.ones(self.n)
        qd = self.qd_scale[:, None] * np.ones(self.n)
        z = np.abs(y0[:, 2 * self.n:-1])
        z = np.maximum(z, 1e-3 * z.max(-1, keepdims=True))
        energy = 0.5 * np.sum(self.kd / self.lam * qd * qd, -1)
        return np.concatenate([q, qd, z, energy[:, None]], -1).ravel()


@dataclass
class Run:
    """One run of a batch: its spec, how the batch ended, the samples it reached, its Lyapunov balance error."""

    spec: RunSpec
    index: int  # in its batch
    status: str  # ok, budget, clock, error, nan, step collapse, barrier, or one of NOT_STARTED
    note: str
    seconds: float  # of the whole batch
    evaluations: int  # right-hand sides of the whole batch
    t: np.ndarray = field(default=None, repr=False)
    y: np.ndarray = field(default=None, repr=False)  # (T, size): q, qd, z, W
    balance_error: float = np.nan
    method: str = "RK45"  # a key of SOLVERS (none: not started)
    jacobians: int = 0  # of the whole batch
    work: float = 0.0  # counted evaluations of the whole batch (spent)
    looser_balance_error: float = np.nan  # the same run's at 10 x its rtol, when it was simulated again finer
    second_opinion: str = ""  # another method's residual at this rtol, when it was level too

    @property
    def finished(self):
        return self.status == "ok"


def simulate(chain, specs, horizon, *, samples=201, rtol=1e-6, max_evaluations=50_000, max_seconds=60.0,
             forces=motion.generalized_forces, method="auto", implicit=IMPLICIT_DEFAULT, explicit_budget=None):
    """Integrate the runs together over [t0, t0 + horizon] (t0 of the first run's trajectory); returns (runs, batch).

    ``method`` "auto" takes RK45 unless the batch is stiff: the spectral radius rho of its Jacobian at the start
    (:meth:`Batch.stiffness`, damping and adaptation) keeps RK45 to steps h <= 3.3 / rho, about 6 horizon rho / 3.3
    evaluations (:func:`inertiaproof.sim.simulate.least_evaluations`); more than ``explicit_budget`` (default
    ``max_evaluations``) / RK45_MARGIN and the batch is integrated with the implicit method ``implicit`` (BDF or
    Radau) and the Jacobian of :meth:`Batch.jacobian` (block diagonal). A run that stiffens on the way
    (:func:`_stiffened`) stops a batch of several as ``budget`` (its runs go on alone); a run alone starts again
    with ``implicit`` within what its count has left (its note says why; its ``work`` counts both).
    A key of SOLVERS ("RK45", "DOP853", "BDF", "Radau") forces a method.

    The decisive budget is counted, the same on every machine: ``max_evaluations`` right-hand sides of the batch,
    each LU factorization counted as one and each Jacobian as Batch.jacobian_cost; a batch past it stops as
    ``budget``. ``max_seconds`` is a safety net only: a batch past it stops as ``clock`` (CLOCK), which depends on
    the machine, so callers take it as no evidence either way. A batch that stops early (``budget``, ``clock``,
    ``nan``, ``step collapse``, ``error``) keeps the samples it reached. The tolerance applies to the whole state
    (all runs): a run alone may be resolved better. A run whose law's state left the law's domain
    (:meth:`AdaptiveLaw.outside`: the natural law's U_l turned indefinite, f(Phi_hat_l) through infinity) ends
    ``barrier``: its exact solution cannot (D <= V(0) plus what Thetadot adds stays finite), so the integrator
    stepped over a pole, and the run is no evidence.

    A batch is not started (only its initial sample) when M(q0, Theta(t0)) of a run has a scaled condition number
    (:mod:`inertiaproof.dynamics.forward`) above inertiaproof.sim.simulate.MAX_CONDITION (``ill-conditioned``: qdd
    would keep fewer than 6 digits, the criterion of the stability and loading studies)."""
    batch = Batch(chain, specs, forces)
    t0 = specs[0].trajectory.span[0]
    with np.errstate(all="ignore"):
        condition = float(scaled_condition(batch.start_mass_matrix()).max())
        try:
            y0 = batch.initial_state()
        except np.linalg.LinAlgError as exc:
            y0 = np.full(len(specs) * batch.size, np.nan)
            unstartable = f"{type(exc).__name__}: {exc}"
    start, last, work, floor = time.perf_counter(), y0, 0, np.finfo(float).tiny
    if condition > MAX_CONDITION:
        status, note = "ill-conditioned", (f"not started: scaled cond(M(q0, Theta(t0))) = {condition:.1e}: forward "
                                           "dynamics keeps fewer than 6 correct digits in float64")
        ys, t_eval, chosen = [y0], np.array([t0]), "none"
    elif not np.all(np.isfinite(y0)):
        status, note = "no start", (f"not started: an adaptive law cannot start from Theta_hat(0) ({unstartable}): "
                                    "the natural law needs f(Phi_hat_l(0)) positive definite (Theorem 1), not so "
                                    "for a body whose mass lies on a line or plane")
        ys, t_eval, chosen = [y0], np.array([t0]), "none"
    else:
        chosen = choose_method(batch, horizon, explicit_budget or max_evaluations, method, implicit)
        kw = dict(jac=batch.jacobian) if chosen in IMPLICIT else {}
        atol = rtol * batch.scale()
        floor = atol.reshape(len(specs), batch.size)[:, -1]  # W's absolute tolerance
        solver = SOLVERS[chosen](batch.rhs, t0, y0, t0 + horizon, rtol=rtol, atol=atol, **kw)
        t_eval = np.linspace(t0, t0 + horizon, samples)
        watch = method == "auto" and chosen in EXPLICIT and batch.jacobian_bytes <= MAX_JACOBIAN_BYTES
        status, note, ys = _integrate(solver, batch, t_eval, max_evaluations, start + max_seconds, watch)
        last, work = solver.y, spent(solver, batch)
        if status == STIFFENED and len(specs) == 1:
            (run,), batch = simulate(chain, specs, horizon, samples=samples, rtol=rtol, forces=forces,
                                     max_evaluations=max(int(max_evaluations - work), 1), method=implicit,
                                     max_seconds=max(start + max_seconds - time.perf_counter(), 0.0))
            run.work, run.seconds = run.work + work, time.perf_counter() - start
            run.note = "; ".join(part for part in (run.note, f"{chosen} first: {note}, so {implicit} from the start")
                                 if part)
            return [run], batch
        status = "budget" if status == STIFFENED else status
    seconds = time.perf_counter() - start
    t, y = t_eval[:len(ys)], np.array(ys)
    v, err = batch.balance_errors(t, y, floor)
    per_run = y.reshape(len(t), len(specs), batch.size)
    runs = [Run(spec, i, status, note, seconds, batch.evaluations, t, per_run[:, i], float(err[i]), chosen,
                batch.jacobians, work) for i, spec in enumerate(specs)]
    if status in STOPPED and np.all(np.isfinite(last)):
        with np.errstate(all="ignore"):
            margins = batch.per_law("barrier_margin", batch.split(last)[2]).min(-1)
            bound = v[0] + batch.split(last)[3]  # V at the stop by the power balance: V(0) + W
        theta = batch.parameters(solver.t).theta
        for run in runs:
            if margins[run.index] < UNRESOLVED_MARGIN:
                run.note += _near_barrier(run, margins[run.index], bound[run.index], theta[run.index])
    if status == "budget" and np.all(np.isfinite(last)) and batch.jacobian_bytes <= MAX_JACOBIAN_BYTES:
        modes, start_rate = batch.fastest_modes(solver.t, last), batch.stiffness()
        for run in runs:
            if np.isfinite(modes[run.index]):
                run.note += (f"; the closed loop's fastest mode was then {mode_in_words(modes[run.index])} "
                             f"(spectral radius {start_rate[run.index]:.2g} /s at the start)")
    z = batch.split(y)[2]
    for run in runs:
        crossed = np.flatnonzero(run.spec.law.outside(z[:, run.index]).any(-1)) if run.finished else []
        if len(crossed):
            run.status, run.note = BARRIER, (
                f"the {run.spec.law.name} law's state left its domain between t = {t[max(crossed[0] - 1, 0)]:.4g} and "
                f"{t[crossed[0]]:.4g} s, across a barrier where its divergence D is infinite; D <= V stays finite "
                "along the exact solution, so the integrator stepped over it: no evidence either way")
    return runs, batch


def _near_barrier(run, margin, bound, theta):
    """What a run stopped ``margin`` (< UNRESOLVED_MARGIN) of its size from its law's barrier says: whether D <= V =
    V(0) + W = ``bound`` at the stop (W: the power integrated along the run) keeps the state off the barrier by more
    than float64 resolves (AdaptiveLaw.margin_floor at the stop's Theta): then the integration drifted there;
    else it is beyond float64."""
    law = run.spec.law
    floor = float(law.margin_floor(bound, theta).min()) if np.isfinite(bound) else 0.0
    near = f"; the {law.name} law's state was then {margin:.1e} of its size from its barrier"
    if floor >= UNRESOLVED_MARGIN:
        return (f"{near}, but D <= V(0) + W = {bound:.3g} (W: the power integrated along the run) keeps it at least "
                f"{floor:.1e} of its size from there: the integration drifted (integration error)")
    return (f"{near}, where float64 no longer resolves the estimate: D <= V(0) + W = {bound:.3g} (W: the power "
            f"integrated along the run) lets it come as near as {floor:.1e} of its size, which float64 cannot follow")


def choose_method(batch, horizon, max_evaluations, method="auto", implicit=IMPLICIT_DEFAULT):
    """The method simulate() integrates with: ``method``, or for "auto" RK45 unless RK45 would need more than
    ``max_evaluations`` / RK45_MARGIN evaluations by the batch's stiffness, then ``implicit`` (RK45 if the
    Jacobian's blocks would take more than MAX_JACOBIAN_BYTES)."""
    if method != "auto":
        if method not in SOLVERS:
            raise ValueError(f"method must be 'auto' or one of {sorted(SOLVERS)}, not {method!r}")
        return method
    if implicit not in IMPLICIT:
        raise ValueError(f"implicit must be one of {IMPLICIT}, not {implicit!r}")
    if batch.jacobian_bytes > MAX_JACOBIAN_BYTES:  # the Jacobian would not fit: explicit
        return "RK45"
    need = least_evaluations("RK45", float(batch.stiffness(horizon).max()), horizon)
    return implicit if not need * RK45_MARGIN <= max_evaluations else "RK45"


FIXED_WORK = 0.5  # work units of one evaluation whatever the chain: the solver's own step
KINEMATICS_WORK = 0.1  # per joint, once per batch: the kinematics of the batch's configuration
PASS_WORK = 0.016  # per joint and run: the recursive passes of the closed loop
SOLVE_WORK = 0.00013  # per joint cubed and run: the dense solve with M(q) (an n x n factorization)


def evaluation_cost(n, runs):
    """The counted work of one evaluation (right-hand side or LU factorization; a Jacobian counts
    Batch.jacobian_cost of them) of a batch of ``runs`` runs on an n-joint chain, in work units: an operation count
    model FIXED_WORK + KINEMATICS_WORK n + runs (PASS_WORK n + SOLVE_WORK n^3) = 0.5 + 0.1 n + runs (0.016 n +
    0.00013 n^3), one term per part of the evaluation and its order in n and runs. A count of operations, not a
    time: a budget in work units stops a run at the same point on every machine (the wall clock stays the safety
    net). How these weights compare with measured seconds: bench/results/machine_timings.md."""
    return FIXED_WORK + KINEMATICS_WORK * n + runs * (PASS_WORK * n + SOLVE_WORK * n**3)


def _stiffened(solver, batch, end, max_evaluations):
    """Why an explicit batch stops now, or "": a run's fastest mode at the state reached
    (:meth:`Batch.fastest_modes`) asks the method for more evaluations over the rest of the horizon than the budget
    has left (least_evaluations: its stability bound alone; steps for accuracy come on top). A batch's runs go on
    alone (checks.applications.simulate_recipes) instead of all of them stepping at the stiff one's pace until the
    budget ends (trolley_2r: a batch of 12 spent all its 21,888 counted evaluations to reach t = 0.68 of 1.7 s); a
    run alone starts again with an implicit method (simulate; trolley's natural run of the 0.25 s traverse spent
    31,355 RK45 evaluations before BDF took it). A count, not the clock: the same on every machine. A look counts
    as a Jacobian."""
    batch.jacobians += 1
    modes = np.nan_to_num(batch.fastest_modes(solver.t, solver.y))
    i = int(np.argmax(np.abs(modes)))
    need = least_evaluations(type(solver).__name__, abs(modes[i]), end - solver.t)
    if need <= max_evaluations - spent(solver, batch):
        return ""
    who = f"run {i} of the batch" if len(modes) > 1 else "the run"
    return (f"{_budget_stop(solver, batch, max_evaluations)}: {who} stiffened, its fastest mode "
            f"({mode_in_words(modes[i])}) would take {need:.3g} more evaluations to the end")


def _budget_stop(solver, batch, max_evaluations):
    """Where and after how much counted work the count stopped ``solver``."""
    return (f"stopped at t = {solver.t:.6g} after {spent(solver, batch):.0f} counted evaluations "
            f"(budget {max_evaluations}; {type(solver).__name__})")


def spent(solver, batch):
    """The counted work of a solver so far, in right-hand sides of the batch: its right-hand sides, Jacobians (each
    Batch.jacobian_cost) and LU factorizations (each one)."""
    return batch.evaluations + batch.jacobians * batch.jacobian_cost + getattr(solver, "nlu", 0)


def _integrate(solver, batch, t_eval, max_evaluations, deadline, watch=False):
    """Step ``solver`` to its end, sampling at ``t_eval``: (status, note, samples reached). With ``watch`` (an
    explicit method chosen by "auto") the batch is looked at each time its count doubles from STIFFENING_CHECK: a
    run that stiffened on the way stops it as STIFFENED (:func:`_stiffened`)."""
    ys, reached, check = [solver.y.copy()], 1, STIFFENING_CHECK
    with np.errstate(all="ignore"):
        while solver.status == "running":
            if spent(solver, batch) > max_evaluations:
                return "budget", _budget_stop(solver, batch, max_evaluations), ys
            if watch and spent(solver, batch) > check:
                check *= 2
                stiffened = _stiffened(solver, batch, t_eval[-1], max_evaluations)
                if stiffened:
                    return STIFFENED, stiffened, ys
            if time.perf_counter() > deadline:
                return CLOCK, (f"stopped at t = {solver.t:.6g} by the wall-clock safety net after "
                               f"{spent(solver, batch):.0f} counted evaluations (a machine-dependent stop: no "
                               "evidence)"), ys
            try:
                message = solver.step()
            except (np.linalg.LinAlgError, ValueError, FloatingPointError, RuntimeError) as exc:
                return "error", f"{type(exc).__name__}: {exc} (at t = {solver.t:.6g})", ys
            if solver.status == "failed":
                return "step collapse", f"{message} (at t = {solver.t:.6g})", ys
            if not np.all(np.isfinite(solver.y)):
                return "nan", f"non-finite state at t = {solver.t:.6g}", ys
            k = np.searchsorted(t_eval, solver.t, side="right")
            if k > reached:
                ys.extend(solver.dense_output()(t_eval[reached:k]).T)
                reached = k
    return "ok", "", ys
