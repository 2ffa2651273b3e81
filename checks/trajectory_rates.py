"""The rates the equation is fed: Thetadot, Psidot and the profiles' s', s'' are derivatives of Theta, Psi, s.

(RoboticEquation) takes Theta, Thetadot, Psi and Psidot from a parameter
trajectory (:mod:`inertiaproof.dynamics.trajectory`), and the bounds of
Section 4 take sup |s'| and sup |s''| of its profiles. Nothing checks them
against each other elsewhere; a wrong s'' or a wrong rate bound would pass.
Here, on every profile shape (with a payload, a scaling and moving masses on
a line and round a circle) and on the built-in scenes' trajectories:

- s', s'', c', c'', Thetadot and Psidot against central differences of s, s', c, c',
  Theta and Psi, extrapolated twice (Richardson), with the difference of the
  two extrapolations as error estimate;
- Profile.rate_bound() and bounds.time.profile_acceleration_bound() are
  upper bounds of |s'| and |s''| on a fine grid and attained there (they are
  stated exact: a bound below the grid's maximum, or more than ATTAINED
  above it, is wrong).

Times stay a few steps away from the ends of a ramp, where s' or s'' jump.
"""

from __future__ import annotations

import numpy as np

from inertiaproof.bounds.time import profile_acceleration_bound
from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Path, Payload, Profile, Scaling
from inertiaproof.model import solids
from inertiaproof.model.inertia import inertia_com
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.scene import robots
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "ATTAINED", "PEAK_GRID", "profiles", "rate_residuals", "rates_result", "replay_rates", "RESOLUTION", "STEP", "time_derivative",
    "trajectories",
]

STEP = 1e-3  # central-difference step, relative to a ramp's duration (halved twice for Richardson)
RESOLUTION = 1e-6  # relative floor of a derivative's resolution
PEAK_GRID = 200_001  # points over a ramp for the attained maxima
ATTAINED = 1e-3  # relative: a bound this close above the grid's maximum is attained (a ramp's ends are open)


def time_derivative(fn, t, step):
    """(d fn / dt at times t, absolute error estimate per time): central differences at step, step/2, step/4,
    Richardson-extrapolated twice."""
    def central(h):
        return (fn(t + h) - fn(t - h)) / (2 * h)

    d1, d2, d4 = central(step), central(step / 2), central(step / 4)
    coarse, fine = (4 * d2 - d1) / 3, (4 * d4 - d2) / 3
    return fine, _largest(fine - coarse) + 64 * np.finfo(float).eps * _largest(fn(t)) / (step / 4)


def _largest(a):
    """max |a| per time (over every axis but the first)."""
    return np.abs(a).reshape(len(a), -1).max(axis=1)


def profiles():
    """One profile of every shape (exp growing and decaying), ramps over [1, 3]."""
    out = {shape: Profile(shape, 1.0, 2.0) for shape in Profile.SHAPES if shape != "exp"}
    out["exp decaying"] = Profile("exp", 1.0, rate=-0.7)
    out["exp growing"] = Profile("exp", 1.0, rate=0.4)
    return out


def trajectories():
    """Trajectories that exercise every load kind, and the built-in scenes' own."""
    box = solids.solid("box", 2.0, (0.2, 0.1, 0.3), position=(0.1, -0.2, 0.3))
    base = np.stack([box, box])
    rider = inertia_com(solids.solid("box", 1.5, (0.1, 0.1, 0.2)))
    loads = (Payload(0, box * 0.5, Profile("smoothstep", 1.0, 2.0)), Scaling(1, Profile("cosine", 1.2, 1.5)),
             MovingMass(1, 1.5, rider, Path("line", Profile("smoothstep", 1.1, 1.7), start=(0.3, 0, 0.1),
                                            end=(-0.4, 0.2, 0.0))),
             MovingMass(0, 0.7, rider, Path("circle", Profile("linear", 1.3, 1.4), center=(0.2, 0.1, 0),
                                            radius=0.3, normal=(1, 1, 1))))
    out = {"every load kind": ParameterTrajectory(base, loads, (0.0, 4.0))}
    for scene in (robots.planar_2r(payload=2.0), robots.panda(payload=2.0), robots.translating_sphere(),
                  robots.trolley_2r(), robots.trolley_2r(loop=True), robots.passenger_platform()):
        out[scene.name] = scene.trajectory
    return out


def _inside(starts, ends, t, margin):
    """Times at least ``margin`` away from every kink (a ramp's start and end)."""
    kinks = np.array([x for pair in zip(starts, ends) for x in pair])
    return t[np.all(np.abs(t[:, None] - kinks[None]) > margin, axis=1)]


def _ramps(trajectory):
    profiles_ = [load.profile if not isinstance(load, MovingMass) else load.path.profile for load in trajectory.loads]
    ramps = [p for p in profiles_ if p.shape not in ("constant", "exp")]
    return [p.start for p in ramps], [p.start + p.duration for p in ramps]


def rate_residuals(profile=None, trajectory=None, rng=None):
    """{property: (worst residual / resolution, at time)} of a profile or a trajectory: above 1 is a violation."""
    rng = np.random.default_rng(0) if rng is None else rng
    out = {}

    def compare(label, rate, fn, t, step):
        got, error = time_derivative(fn, t, step)
        ratio = _largest(rate - got) / (10 * error + RESOLUTION * _largest(got) + 1e-300)
        i = int(np.argmax(ratio))
        out[label] = (float(ratio[i]), float(t[i]))

    if profile is not None:
        ramp = profile.shape not in ("constant", "exp")
        span = (profile.start, profile.start + (profile.duration if ramp else 4.0))
        width = span[1] - span[0]
        step = STEP * width
        t = _inside([span[0]], [span[1]], rng.uniform(span[0] - 0.2 * width, span[1] + 0.2 * width, 64), 8 * step)
        compare("s' = ds/dt", profile.derivatives(t)[1], lambda x: profile.derivatives(x)[0], t, step)
        compare("s'' = ds'/dt", profile.derivatives(t)[2], lambda x: profile.derivatives(x)[1], t, step)
        grid = np.linspace(*span, PEAK_GRID)
        _, ds, dds = profile.derivatives(grid)
        for label, bound, values in (("rate bound = sup |s'|", profile.rate_bound(), np.abs(ds)),
                                     ("acceleration bound = sup |s''|", profile_acceleration_bound(profile),
                                      np.abs(dds))):
            if np.isfinite(bound):
                peak = values.max()
                below = bound < peak * (1 - 1e-12)
                out[label] = (1e300 if below else abs(bound - peak) / max(peak, 1e-300) / ATTAINED,
                              float(grid[np.argmax(values)]))
    if trajectory is not None:
        starts, ends = _ramps(trajectory)
        t0, t1 = trajectory.span
        t1 = t0 + 6.0 if not np.isfinite(t1) else t1
        step = STEP * min([e - s for s, e in zip(starts, ends)] + [1.0])
        t = _inside(starts, ends, rng.uniform(t0 + 4 * step, t1 - 4 * step, 48), 8 * step)
        compare("Thetadot = dTheta/dt", trajectory.theta(t)[1], lambda x: trajectory.theta(x)[0], t, step)
        compare("Psidot = dPsi/dt", trajectory.psi(t)[1], lambda x: trajectory.psi(x)[0], t, step)
        for k, load in enumerate(trajectory.loads):
            if isinstance(load, MovingMass):
                path = load.path
                compare(f"load {k}: c' = dc/dt", path.derivatives(t)[1], lambda x: path.derivatives(x)[0], t, step)
                compare(f"load {k}: c'' = dc'/dt", path.derivatives(t)[2], lambda x: path.derivatives(x)[1], t, step)
    return out


def rates_result(ctx, profile_set=None, trajectory_set=None):
    """Every profile and trajectory: derivatives against differences, bounds against the grid's maxima."""
    profile_set = profiles() if profile_set is None else profile_set
    trajectory_set = trajectories() if trajectory_set is None else trajectory_set
    rows, worst, counterexample = {}, (0.0, None), None
    cases = [("profile", name, {"profile": p}) for name, p in profile_set.items()] + \
        [("trajectory", name, {"trajectory": tr}) for name, tr in trajectory_set.items()]
    for kind, name, kw in cases:
        residuals = rate_residuals(rng=ctx.rng(f"GRE-physics:rates:{name}"), **kw)
        rows[f"{kind} {name}"] = {k: quantity(v[0], "ratio", f"worst residual / resolution (at t = {v[1]:.6g})")
                                  for k, v in residuals.items()}
        for prop, (ratio, t) in residuals.items():
            if ratio > worst[0]:
                worst = (ratio, f"{kind} {name}: {prop}")
            if ratio > 1 and counterexample is None:
                counterexample = {"kind": "trajectory-rates", "data": {
                    "case": kind, "name": name, "property": prop, "t": t, "ratio": ratio}}
    evidence = {"method": "central differences at steps h, h/2, h/4 (h = 1e-3 of the shortest ramp), Richardson "
                          "twice, error estimate |R1 - R2| + rounding; bounds against the maxima over "
                          f"{PEAK_GRID} grid points of a ramp",
                "cases": rows, "resolution": quantity(RESOLUTION, "tolerance", "relative floor of every resolution"),
                "worst": {"ratio": quantity(worst[0], "ratio", "residual / resolution; > 1 is a violation"),
                          "where": worst[1]}}
    if counterexample is not None:
        data = counterexample["data"]
        return Result("GRE-physics", Verdict.VIOLATED, f"{data['name']} ({data['case']}): {data['property']} fails by "
                      f"{data['ratio']:.3g} x its resolution at t = {data['t']:.6g}", evidence,
                      counterexample=counterexample)
    return Result("GRE-physics", Verdict.HOLDS, f"Thetadot, Psidot, s', s'', c', c'' are the derivatives of Theta, "
                  f"Psi, s, c on {len(profile_set)} profiles and {len(trajectory_set)} trajectories, and the rate and "
                  f"acceleration bounds are attained (worst {worst[0]:.2g} of the resolution: {worst[1]})", evidence)


@check("GRE-physics", variant="rates")
def trajectory_rates(ctx):
    return rates_result(ctx)


@replayer("trajectory-rates")
def replay_rates(data, ctx):
    cases = profiles() if data["case"] == "profile" else trajectories()
    if data["name"] not in cases:
        return Result("GRE-physics", Verdict.INCONCLUSIVE, f"no built-in {data['case']} named {data['name']!r}")
    return rates_result(ctx, {data["name"]: cases[data["name"]]} if data["case"] == "profile" else {},
                        {data["name"]: cases[data["name"]]} if data["case"] == "trajectory" else {})
