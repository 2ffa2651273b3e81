"""Loading as the limit of many small plastic captures (GRE-physics, loading).

The paper's Lagrangian with Thetadot (KineticEnergy, LagrangeFormalism) gives
d/dt (M qd + J^T Q^T Psi) = tau + w - G + 1/2 d(qd^T M qd)/dq + ..., with no
momentum brought in by the mass that appears: the added mass arrives *at rest
in the Newtonian frame*. To see that physically, the mass is added instead in
K pieces, each a rigid body that joins its body in a perfectly plastic
capture. Between captures the chain is an ordinary rigid multibody system
(Pinocchio, :class:`inertiaproof.multibody.RigidChain`); at a capture the
joint torques stay finite, so the generalized momentum is continuous:

- a piece lying at rest brings no momentum: M(q, Theta+) qd+ = M(q, Theta-) qd-;
- a piece already moving with the point it joins (e.g. carried along by the
  end-effector) needs no impulse: qd+ = qd-.

As K grows the first converges to the solution of (RoboticEquation); the
second converges to the equation *without* M(q, Thetadot) qd for the added
mass, a mismatch of order one. The same formulas hold for mass that leaves
(Thetadot < 0): the equation then has it leave at rest in the Newtonian frame.

All solutions use one fixed grid of steps of one scheme (inertiaproof.sim.fixedstep); captures sit on grid
points, so the integration error is the same O(h^p) for every variant and is estimated by halving the steps
(Richardson, with p the smaller of the scheme's order and the order observed over h, 2h, 4h). The scheme is
classical Runge-Kutta (p = 4) unless the fastest closed-loop mode would need more steps than the study may take
(h x rate <= 1); then it is the L-stable 2-stage Radau IIA (p = 3), whose steps only the slow motion sets.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from inertiaproof.budget import UNLIMITED
from inertiaproof.dynamics import motion
from inertiaproof.dynamics.forward import solve_mass
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Payload, Scaling
from inertiaproof.result import Verdict

from . import fixedstep, simulate
from .control import FeedforwardPD
from .multibody import RigidChain

__all__ = [
    "ARRIVALS", "CaptureStudy", "convergence_verdict", "distance", "FLOOR_BELOW", "mass_window", "MAX_FLOOR",
    "integration_floor", "observed_order", "Pieces", "PLACEMENTS", "refined_steps", "scheme_for", "Solution", "solve",
    "steps_for", "study",
]

PLACEMENTS = ("start", "middle")  # where in its time slice a piece joins
ARRIVALS = ("rest", "carried")  # at rest in the Newtonian frame, or moving with the point it joins
MAX_FLOOR = 1e-3  # an integration floor above this leaves nothing to compare
FLOOR_BELOW = 1e-2  # the steps double until the floor is this far below the smallest capture error


def mass_window(trajectory, horizon=2.0):
    """[a, b]: the times over which mass is added or removed, cut to the span (an endless span at a + horizon)."""
    t0, t1 = trajectory.span
    t1 = min(t1, t0 + horizon) if np.isfinite(t1) else t0 + horizon
    starts, ends = [], []
    for load in trajectory.loads:
        if isinstance(load, (Payload, Scaling)) and load.profile.shape != "constant":
            p = load.profile
            if p.shape == "exp":
                starts.append(t0)
                ends.append(t1)
            else:
                starts.append(max(t0, p.start))
                ends.append(min(t1, p.start + p.duration))
    if not starts or max(ends) <= min(starts):
        raise ValueError("the trajectory adds or removes no mass inside its time span")
    return min(starts), max(ends)


@dataclass(frozen=True)
class Pieces:
    """K pieces over [a, b]; piece j holds the mass change over [t_j, t_{j+1}] and joins at its slice's start or
    middle, arriving at ``rest`` or ``carried`` with the body it joins."""

    count: int
    placement: str = "middle"
    arrival: str = "rest"

    def __post_init__(self):
        if self.placement not in PLACEMENTS or self.arrival not in ARRIVALS or self.count < 1:
            raise ValueError(f"pieces: count >= 1, placement in {PLACEMENTS}, arrival in {ARRIVALS}; got {self}")

    def schedule(self, a, b, steps):
        """(grid index of each capture, the mass time in force after it)."""
        if steps % (2 * self.count):
            raise ValueError(f"{steps} steps do not put every capture of {self.count} pieces on the grid")
        per_piece = steps // self.count
        offset = 0 if self.placement == "start" else per_piece // 2
        index = np.arange(self.count) * per_piece + offset
        return index, a + (b - a) * (np.arange(self.count) + 1) / self.count

    @property
    def name(self):
        return f"{self.count} pieces, {self.placement}, {self.arrival}"


@dataclass
class Solution:
    """States at the end of the window: GRE (ours), the continuous rigid model without the rate term, captures."""

    window: tuple
    steps: int
    equation: np.ndarray  # (2n,) q, qd of (RoboticEquation) at b
    equation_half_steps: np.ndarray  # the same with steps / 2 (integration error estimate)
    without_rate: np.ndarray  # the rigid chain with Theta(t) and no momentum brought in or taken: qd+ = qd-
    captures: dict = field(default_factory=dict)  # Pieces -> (2n,)
    scale: np.ndarray = None  # per-component scale of the motion over the window (for relative errors)
    equation_quarter_steps: np.ndarray = None  # (RoboticEquation) with steps / 4 (the observed order)
    mode: complex = complex(np.nan)  # the fastest eigenvalue of (RoboticEquation)'s closed loop at b
    scheme: fixedstep.Scheme = fixedstep.RK4
    work: fixedstep.Work = field(default_factory=fixedstep.Work)  # counts over every model
    equation_points: int = 0  # states at which this call built dQJ/dq: the equation's evaluations, the feedforward's


def jacobian_entries(chain, points):
    """Entries of dQJ/dq (6N x n x n, one complex step per coordinate) built at ``points`` states of ``chain``: the
    count the loading study's budget is in (a right-hand side of the equation and a feedforward point build one)."""
    return 6 * chain.bodies * chain.n**2 * int(points)


def least_points(steps, scheme):
    """The fewest states at which a :func:`solve` with ``steps`` not in its memo builds dQJ/dq: the equation at
    steps, steps / 2 and steps / 4 (RK4 four evaluations a step, Radau IIA at least one Newton iteration of its two
    stages) and the feedforward at the scheme's nodes of those grids."""
    grids = steps + steps // 2 + steps // 4
    return grids * ((2 if scheme.implicit else 4) + len(scheme.nodes))


def solve(scene_chain, trajectory, control, pieces, steps=256, forces=motion.generalized_forces, horizon=2.0,
          progress=lambda message: None, scheme=fixedstep.RK4, work=None, memo=None):
    """Integrate (RoboticEquation) and every capture model over the mass window with ``scheme``, counting into
    ``work``; see :class:`Solution`. Raises fixedstep.NewtonFailure when an implicit step does not converge.

    ``memo`` (a dict the caller keeps for one chain, trajectory, control, forces and horizon) holds the runs that
    depend on the steps and the scheme alone (the equation at steps, steps / 2 and steps / 4, the rigid chain
    without momentum exchange, the closed loop's fastest mode) and each capture by (steps, scheme, pieces): a
    later call with the same steps integrates only the captures it has not seen, and ``work`` counts only what
    was integrated."""
    a, b = mass_window(trajectory, horizon)
    n = scene_chain.n
    pd = FeedforwardPD(scene_chain, control)
    mass_only = ParameterTrajectory(trajectory.base, tuple(load for load in trajectory.loads
                                                           if not isinstance(load, MovingMass)), trajectory.span)
    q0, qd0, _ = control.reference(np.array(a))
    start = np.concatenate([q0, qd0])

    work = work if work is not None else fixedstep.Work()
    memo = {} if memo is None else memo

    def grid(count):
        times = np.linspace(a, b, count + 1)
        ff = pd.feedforward(times[:-1, None] + np.diff(times)[:, None] * np.asarray(scheme.nodes))
        return times, ff

    points = [0]  # states at which dQJ/dq is built: the equation's evaluations and the feedforward's points

    def run(rhs, grid_times, inputs, jumps=None):
        return fixedstep.integrate(scheme, rhs, start, grid_times, inputs, jumps, work)

    def run_equation(grid_times, inputs):
        before = work.evaluations
        state = run(equation_rhs, grid_times, inputs)
        points[0] += work.evaluations - before + inputs.shape[0] * inputs.shape[1]
        return state

    def equation_rhs(t, state, ff):
        q, qd = state[..., :n], state[..., n:]
        kin = motion.kinematics(scene_chain, q)
        p = motion.parameters(trajectory, np.broadcast_to(t, q.shape[:-1]))
        tau = pd.torque(ff, t, q, qd)
        return np.concatenate([qd, simulate.accelerations(kin, scene_chain.gravity, p, qd, tau, forces)], -1)

    base = memo.get((steps, scheme.name))
    if base is None:
        times, ff = grid(steps)
        progress(f"(RoboticEquation) over [{a:g}, {b:g}] s in {steps} steps of {scheme.name}")
        equation = run_equation(times, ff)
        equation_half, equation_quarter = (run_equation(*grid(steps // k)) for k in (2, 4))
    else:
        times, ff, equation, equation_half, equation_quarter, without_rate, mode = base

    rigid = RigidChain(scene_chain, trajectory)
    rider_cache = {}

    def rider(t):
        if t not in rider_cache:
            rider_cache[t] = rigid.rider_motion(t)
        return rider_cache[t]

    inertias = {}

    def set_mass_time(mass_time):
        if mass_time not in inertias:
            rigid.set_theta(mass_only.theta(np.array(mass_time))[0])
            inertias[mass_time] = [rigid.pin.Inertia(i) for i in rigid.model.inertias]
        else:
            for k, inertia in enumerate(inertias[mass_time]):
                rigid.model.inertias[k] = inertia

    def rigid_rhs(mass_time_at):
        def one(t, state, f):
            q, qd = state[:n], state[n:]
            return np.concatenate([qd, rigid.accelerations(q, qd, pd.torque(f, t, q, qd), rider(t))])

        def rhs(t, state, f):  # Pinocchio takes one state at a time
            if state.ndim == 1:
                set_mass_time(mass_time_at(t))
                return one(t, state, f)
            times, inputs = np.broadcast_to(t, len(state)), np.broadcast_to(f, (len(state), n))
            return np.stack([rhs(ti, row, fi) for ti, row, fi in zip(times, state, inputs)])
        return rhs

    if base is None:
        progress("rigid chain with Theta(t), no momentum exchanged with the added mass")
        without_rate = run(rigid_rhs(lambda t: t), times, ff)

    out = Solution((a, b), steps, equation, equation_half, without_rate, equation_quarter_steps=equation_quarter,
                   scheme=scheme, work=work)
    for piece in pieces:
        if (steps, scheme.name, piece) in memo:
            out.captures[piece] = memo[steps, scheme.name, piece]
            continue
        index, mass_times = piece.schedule(a, b, steps)
        current = {"mass_time": a}

        def jumps(i, state, index=index, mass_times=mass_times, piece=piece, current=current):
            hits = np.flatnonzero(index == i)
            if not hits.size:
                return state
            q, qd = state[:n], state[n:]
            new_time = mass_times[hits[-1]]
            if piece.arrival == "rest":
                set_mass_time(current["mass_time"])
                momentum = rigid.mass_matrix(q) @ qd
                set_mass_time(new_time)
                qd = solve_mass(rigid.mass_matrix(q), momentum)
            current["mass_time"] = new_time
            return np.concatenate([q, qd])

        progress(piece.name)
        out.captures[piece] = memo[steps, scheme.name, piece] = run(rigid_rhs(lambda t, c=current: c["mass_time"]),
                                                                    times, ff, jumps)
    span = np.abs(equation - start)
    tiny = np.finfo(float).tiny
    out.scale = np.concatenate([np.full(n, max(span[:n].max(), np.abs(qd0).max() * (b - a), tiny)),
                                np.full(n, max(np.abs(equation[n:]).max(), np.abs(qd0).max(), tiny))])
    if base is None:
        ff_end = pd.feedforward(np.array(b))

        def at_end(states):
            points[0] += len(states)
            return np.stack([equation_rhs(b, s, ff_end) for s in states])

        mode = simulate.fastest_eigenvalue(at_end, equation, out.scale)
        points[0] += 1
        memo[steps, scheme.name] = times, ff, equation, equation_half, equation_quarter, without_rate, mode
    out.mode, out.equation_points = mode, points[0]
    return out


def distance(x, y, scale):
    """max over components of |x - y| / scale."""
    return float(np.max(np.abs(np.asarray(x) - np.asarray(y)) / scale))


def observed_order(counts, errors):
    """Least-squares slope p of log(error) against -log(K)."""
    k, e = np.log(np.asarray(counts, float)), np.log(np.asarray(errors, float))
    return float(-np.polyfit(k, e, 1)[0])


def convergence_verdict(counts, errors, floor):
    """Do the captures converge to the equation? (verdict, observed order, why, settled).

    The order is fitted over the finest three piece counts whose error is above ten times the integration
    floor; it is *settled* when the last two pairwise orders agree within 0.5. HOLDS: the errors reach the
    floor, or fall with a settled order >= 0.8. VIOLATED: they level off (settled order < 0.3) clearly above
    the floor, so the limit is another motion. Otherwise INCONCLUSIVE (more pieces may settle it).
    """
    counts, errors = np.asarray(counts, float), np.asarray(errors, float)
    if not np.all(np.isfinite(errors)) or not np.isfinite(floor):
        return Verdict.INCONCLUSIVE, None, "a solution is not finite (the fixed-step integration blew up)", True
    if floor > MAX_FLOOR:
        return Verdict.INCONCLUSIVE, None, (f"the fixed-step solutions themselves are uncertain by {floor:.1e} "
                                            "(relative): nothing can be compared"), True
    above = errors > 10 * floor
    if not above[-1]:
        return Verdict.HOLDS, None, (f"the captures reach the integration floor {floor:.1e} at K = "
                                     f"{int(counts[np.argmin(above)])} pieces"), True
    usable = np.flatnonzero(above)[-3:]
    if usable.size < 2:
        return Verdict.INCONCLUSIVE, None, "fewer than two piece counts above the integration floor", True
    order = observed_order(counts[usable], errors[usable])
    pairwise = -np.diff(np.log(errors[usable])) / np.diff(np.log(counts[usable]))
    settled = pairwise.size < 2 or abs(pairwise[-1] - pairwise[-2]) <= 0.5
    if not settled:
        return Verdict.INCONCLUSIVE, order, (f"the order has not settled (pairwise {np.round(pairwise, 2).tolist()} "
                                             f"up to K = {int(counts[-1])})"), False
    if order >= 0.8:
        return Verdict.HOLDS, order, (f"the error falls as K^-{order:.2f} down to {errors[-1]:.1e} "
                                      f"at K = {int(counts[-1])}"), True
    if order < 0.3:
        return Verdict.VIOLATED, order, (f"the error levels off at {errors[-1]:.1e} (order {order:.2f}), "
                                         f"far above the integration floor {floor:.1e}: the limit of the captures "
                                         "is another motion"), True
    return Verdict.INCONCLUSIVE, order, f"the error falls only as K^-{order:.2f}", True


def steps_for(window, rate, counts, minimum):
    """Grid steps: at least ``minimum``, a multiple of 2 max(counts), with h x rate <= 1 (inside RK4's stability
    interval, 2.78, and accurate for the slow motion that the study compares)."""
    unit = 2 * max(counts)
    needed = max(minimum, (window[1] - window[0]) * rate)
    return int(unit * max(1, 2 ** int(np.ceil(np.log2(max(needed / unit, 1.0))))))


def scheme_for(window, rate, counts, minimum, max_steps):
    """(scheme, rate the steps must resolve): RK4 when h x rate <= 1 fits in ``max_steps``; else the L-stable Radau
    IIA, whose steps only the slow motion sets (rate 0: the fastest mode is damped, not resolved)."""
    if steps_for(window, rate, counts, minimum) <= max_steps:
        return fixedstep.RK4, rate
    return fixedstep.RADAU_IIA, 0.0


def integration_floor(sol):
    """(floor, observed order): 2 x the Richardson estimate |y_h - y_2h| / (2^p - 1) of the error of y_h, relative
    to the motion's scale, with p the scheme's order, or the order observed over 4h, 2h, h where that is lower
    (order reduction on a stiff scene), but at least 1."""
    fine = distance(sol.equation_half_steps, sol.equation, sol.scale)
    coarse = distance(sol.equation_quarter_steps, sol.equation_half_steps, sol.scale)
    observed = float(np.log2(coarse / fine)) if fine > 0 and coarse > 0 else np.nan
    order = sol.scheme.order if not np.isfinite(observed) else float(np.clip(observed, 1.0, sol.scheme.order))
    return 2 * fine / (2**order - 1), observed


def refined_steps(steps, excess, observed, order, max_steps):
    """Steps that bring the integration floor down by ``excess`` at the observed order (at most the scheme's, at
    least 1): ``steps`` times a power of 2, at least 2, at most what ``max_steps`` allows."""
    rate = float(np.clip(observed, 1.0, order)) if np.isfinite(observed) else order
    doublings = max(1, int(np.ceil(np.log2(excess) / rate)))
    return steps * 2 ** min(doublings, int(np.log2(max_steps // steps)))


@dataclass
class CaptureStudy:
    """Errors of the captures against the equation at the window's end, refined until the order settles."""

    window: tuple
    steps: int
    counts: tuple
    rate: float
    floor: float
    at_rest: list  # centred pieces at rest -> equation
    fine: tuple  # the finest three counts
    at_start: list  # pieces at rest joining at their slice's start -> equation
    carried: list  # pieces carried with the body -> equation
    carried_limit: list  # pieces carried -> the rigid chain without momentum exchange
    mismatch: float  # equation vs the carried limit
    verdict: object
    order: float | None
    why: str
    history: list  # (steps, counts) tried
    scheme: fixedstep.Scheme = fixedstep.RK4
    integration_order: float = np.nan  # observed over 4h, 2h, h (against scheme.order)
    work: fixedstep.Work = field(default_factory=fixedstep.Work)  # counts over every solve
    entries: int = 0  # dQJ/dq entries built (jacobian_entries), what ``max_entries`` of :func:`study` counts


def study(chain, trajectory, control, counts, steps, forces=motion.generalized_forces, horizon=2.0, max_steps=2048,
          max_count=256, progress=lambda message: None, budget=UNLIMITED, scheme=None, max_entries=None):
    """Captures of pieces at rest (and carried) against (RoboticEquation). The scheme (unless given) is RK4 unless
    the fastest closed-loop mode needs more than ``max_steps`` of it (then Radau IIA, :func:`scheme_for`). The steps
    double until the integration floor lies FLOOR_BELOW under the smallest error (or an implicit step's Newton
    iterations did not converge); K doubles while the order is unsettled or between the bands of convergence and
    levelling off, but not once the floor is above MAX_FLOOR with the steps at ``max_steps``. Every limit is a
    count (steps, pieces, Newton iterations, and ``max_entries``: the entries of dQJ/dq the study may build,
    :func:`jacobian_entries`, so that the steps a long chain gets shrink with its n^3 cost; a solve that the entries
    left cannot pay for at :func:`least_points` ends the study INCONCLUSIVE), except the wall-clock safety net
    ``budget``."""
    window = mass_window(trajectory, horizon)
    rate = simulate.fastest_rate(chain, trajectory, control, window)
    condition = simulate.conditioning(chain, trajectory, control, window)
    counts, history, work, memo, spent = tuple(counts), [], fixedstep.Work(), {}, 0
    chosen, resolved = scheme_for(window, rate, counts, steps, max_steps)
    if scheme is not None and scheme is not chosen:
        resolved = rate if scheme is fixedstep.RK4 else 0.0
    scheme = scheme or chosen

    def unanswered(need, why):
        return CaptureStudy(window, need, counts, rate, np.nan, [], counts[-3:], [], [], [], np.nan,
                            Verdict.INCONCLUSIVE, None, why, history, scheme, work=work, entries=spent)

    if condition > simulate.MAX_CONDITION:
        return unanswered(steps, f"M is numerically singular for forward dynamics (scaled cond {condition:.1e}): qdd "
                                 f"keeps fewer than 6 correct digits in float64")
    if scheme.implicit and chosen is scheme:
        progress(f"fastest closed-loop mode {rate:.3g} rad/s: RK4 would need "
                 f"{steps_for(window, rate, counts, steps)} steps; {scheme.name} instead")
    while True:
        need = steps_for(window, resolved, counts, steps)
        fine = counts[-3:]
        if budget.expired:
            return unanswered(need, f"the time budget ({budget.describe()}) ran out before K = {counts[-1]} pieces "
                                    f"with {need} steps" + (" (refining)" if history else ""))
        if need > max_steps:
            return unanswered(need, f"too stiff for the fixed-step study: the fastest closed-loop mode ({rate:.3g} "
                                    f"rad/s) needs {need} {scheme.name} steps over the window, more than {max_steps}")
        if max_entries is not None and (need, scheme.name) not in memo:
            cost = jacobian_entries(chain, least_points(need, scheme))
            if spent + cost > max_entries:
                return unanswered(need, f"the study's count of {max_entries:.3g} dQJ/dq entries does not pay for "
                                        f"{need} {scheme.name} steps on {chain.n} joints (at least {cost:.3g} more, "
                                        f"{spent:.3g} spent)" + (" (refining)" if history else ""))
        history.append((need, counts))
        pieces = ([Pieces(k, "middle", "rest") for k in counts] + [Pieces(k, "start", "rest") for k in fine]
                  + [Pieces(k, "middle", "carried") for k in fine])
        try:
            with np.errstate(all="ignore"):
                sol = solve(chain, trajectory, control, pieces, need, forces, horizon, progress, scheme, work, memo)
        except fixedstep.NewtonFailure as failure:
            if 2 * need > max_steps:
                return unanswered(need, f"{failure}, and {2 * need} steps would exceed {max_steps}")
            steps = 2 * need
            progress(f"{failure}; {steps} steps")
            continue
        spent += jacobian_entries(chain, sol.equation_points)
        d = lambda x, y=None: distance(x, sol.equation if y is None else y, sol.scale)  # noqa: E731
        floor, integration_order = integration_floor(sol)
        at_rest = [d(sol.captures[Pieces(k, "middle", "rest")]) for k in counts]
        if floor > FLOOR_BELOW * min(at_rest) and 2 * need <= max_steps:
            steps = refined_steps(need, floor / (FLOOR_BELOW * min(at_rest)), integration_order, sol.scheme.order,
                                  max_steps)
            progress(f"integration floor {floor:.1e} too close to the errors; {steps} steps")
            continue
        verdict, order, why, settled = convergence_verdict(counts, at_rest, floor)
        if ((settled and verdict != Verdict.INCONCLUSIVE) or counts[-1] * 2 > max_count
                or floor > MAX_FLOOR and 2 * need > max_steps):  # more pieces leave a capped floor where it is
            break
        counts = counts[1:] + (counts[-1] * 2,)
        progress(f"{why}; refining to K = {counts[-1]}")
    if floor > MAX_FLOOR and np.isfinite(sol.mode):
        h = (window[1] - window[0]) / need
        why += (f"; at the window's end the equation's fastest mode is {simulate.mode_in_words(sol.mode)}: "
                f"{need} steps of {h:.2g} s take |lambda| h = {abs(sol.mode) * h:.2g} each")
    return CaptureStudy(
        window, need, counts, rate, floor, at_rest, fine,
        [d(sol.captures[Pieces(k, "start", "rest")]) for k in fine],
        [d(sol.captures[Pieces(k, "middle", "carried")]) for k in fine],
        [d(sol.captures[Pieces(k, "middle", "carried")], sol.without_rate) for k in fine],
        d(sol.without_rate), verdict, order, why, history, scheme, integration_order, work, spent)
