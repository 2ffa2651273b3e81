"""Extremes over time of the parameter trajectory's ingredients (Definition 3; Theorems 2-5).

Theta(t) of payloads and scalings lies on segments Theta_base + s Phi_load with s in the profile's range;
spectral extremes that are concave or convex in Theta are then attained at the segment's ends (exact for one
load per body). Moving masses are bounded by positivity (Z(Phi_load) >= 0) and by the profile's rate and
acceleration bounds, the rest of Theta(t) beside them (payloads, scalings) over its segments' hull.
"""

from __future__ import annotations

import itertools

import numpy as np

from inertiaproof.dynamics.trajectory import MovingMass, ParameterTrajectory, Payload, Scaling
from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse, sigma_from_inertia, spatial_inertia

from .certificate import body_spectrum_certificate, exact, moving_mass_certificate
from .spectral import EPS, ROUNDING, spectral

__all__ = [
    "ACCELERATION_PEAK", "affine_loads", "BODY_FUNCTIONS", "fixed_part_vertices", "lumped_velocity_bounds",
    "moving_mass_hull", "parameter_vertices", "profile_acceleration_bound", "profile_range", "time_extreme",
    "vertex_extreme",
]



ACCELERATION_PEAK = {"constant": 0.0, "linear": 0.0, "smoothstep": 6.0, "smootherstep": 10.0 / np.sqrt(3.0),
                     "cosine": np.pi**2 / 2}


def profile_range(profile, span):
    """[min, max] of s(t) over the span (the ramps are monotone; exp is monotone)."""
    t0, t1 = span
    if profile.shape == "exp":
        a = np.exp(profile.rate * (t0 - profile.start))
        b = np.exp(profile.rate * (t1 - profile.start)) if np.isfinite(t1) else (np.inf if profile.rate > 0 else 0.0)
        return min(a, b), max(a, b)
    s0 = float(profile.derivatives(t0)[0])
    s1 = float(profile.derivatives(t1 if np.isfinite(t1) else profile.start + profile.duration + 1)[0])
    return min(s0, s1), max(s0, s1)


def profile_acceleration_bound(profile):
    """sup_t |s''(t)| (inf for 'linear', whose rate jumps)."""
    if profile.shape == "exp":
        return profile.rate**2 if profile.rate <= 0 else np.inf
    if profile.shape == "linear":
        return np.inf
    return ACCELERATION_PEAK[profile.shape] / (profile.duration**2 if profile.shape != "constant" else 1.0)


def affine_loads(trajectory):
    """True when every load is a payload or a scaling: Theta(t) is affine in the profiles' values s_i(t)."""
    return all(isinstance(load, (Payload, Scaling)) for load in trajectory.loads)


def parameter_vertices(trajectory):
    """Stacks (V, N, 10) of Theta and of Thetadot whose convex hulls hold Theta(t) and Thetadot(t) for all t.

    None when a moving mass makes Theta(t) non-affine. With one load the hull of
    Theta is the segment the trajectory sweeps: extremes over it are exact.
    """
    if not affine_loads(trajectory):
        return None
    loads = trajectory.loads
    ranges = [profile_range(load.profile, trajectory.span) for load in loads]
    rates = [load.profile.rate_bound() for load in loads]
    values, rate_values = [], []
    for corner in itertools.product(*[(a, b) for a, b in ranges]) if loads else [()]:
        values.append(_theta_at(trajectory, corner, None))
    for corner in itertools.product(*[(-r, r) for r in rates]) if loads else [()]:
        for s in itertools.product(*[(a, b) for a, b in ranges]) if loads else [()]:
            rate_values.append(_theta_at(trajectory, s, corner))
    return np.array(values), np.array(rate_values)


def formation(trajectory, rate=False):
    """How :func:`parameter_vertices` forms the vertices of Theta(t) (``rate``: of Thetadot(t)), for a certificate
    (the checker forms them again): the base rows and each load with its kind, body (from 1), Phi (a payload's), the
    range of its profile over the span and its rate bound. None where a load is not affine or a range is unbounded."""
    if not affine_loads(trajectory):
        return None
    loads = []
    for load in trajectory.loads:
        (a, b), r = profile_range(load.profile, trajectory.span), load.profile.rate_bound()
        if not np.all(np.isfinite([a, b, r])):
            return None
        loads.append({"kind": "payload" if isinstance(load, Payload) else "scaling", "body": load.body + 1,
                      **({"phi": [exact(x) for x in load.phi]} if isinstance(load, Payload) else {}),
                      "range": [exact(a), exact(b)], "rate": exact(r)})
    return {"of": "rate" if rate else "theta", "base": [[exact(x) for x in row] for row in trajectory.base],
            "loads": loads}


def _theta_at(trajectory, s, ds):
    """Theta (ds None) or Thetadot for profile values s and rates ds, in the order ParameterTrajectory.theta uses."""
    theta = trajectory.base.astype(float).copy()
    dot = np.zeros_like(theta)
    for load, si, k in zip(trajectory.loads, s, range(len(s))):
        if isinstance(load, Scaling):  # an unbounded s leaves non-finite entries, which callers leave out
            dsi = 0.0 if ds is None else ds[k]
            with np.errstate(invalid="ignore"):
                theta[load.body], dot[load.body] = si * theta[load.body], dsi * theta[load.body] + si * dot[load.body]
    for load, si, k in zip(trajectory.loads, s, range(len(s))):
        if isinstance(load, Payload):
            theta[load.body] += si * load.phi
            dot[load.body] += (0.0 if ds is None else ds[k]) * load.phi
    return theta if ds is None else dot


def _path_geometry(path):
    """(max |c|, max |dc/ds|, max |d2c/ds2|) of a load's path over s in [0, 1]."""
    if path.shape == "line":
        a, b = np.asarray(path.start, float), np.asarray(path.end, float)
        return max(np.linalg.norm(a), np.linalg.norm(b)), np.linalg.norm(b - a), 0.0
    r = path.radius
    return np.linalg.norm(path.center) + r, 2 * np.pi * r, (2 * np.pi) ** 2 * r


def _moving_mass_terms(load):
    """Certified bounds of one moving mass: sup ||f(Phi_p)||, sup sigma(f(Phidot_p)), Psi*, dPsi*."""
    cmax, d1, d2 = _path_geometry(load.path)
    m = load.mass
    rate, acc = load.path.profile.rate_bound(), profile_acceleration_bound(load.path.profile)
    sigma_c = sigma_from_inertia(load.inertia_com)
    lever = np.sqrt(1 + cmax**2)
    return {
        "f_norm": m * (1 + cmax**2) + np.linalg.eigvalsh(sigma_c)[-1],
        "f_rate": m * rate * d1 * (2 * cmax + 1),
        "psi": m * rate * d1 * lever,
        "psi_dot": m * (acc * d1 + rate**2 * d2) * lever if np.isfinite(acc) else np.inf,
    }


BODY_FUNCTIONS = {  # name: (matrix of Phi, spectral kind, uses Thetadot)
    "lmin_f": (pseudo_inertia, "lmin", False),
    "lmax_f": (pseudo_inertia, "lmax", False),
    "lmin_Z": (spatial_inertia, "lmin", False),
    "lmax_Z": (spatial_inertia, "lmax", False),
    "smax_fdot": (pseudo_inertia, "absmax", True),
    "smax_Zdot": (spatial_inertia, "absmax", True),
}


def time_extreme(trajectory, name, *, samples=2001, horizon=None):
    """min over bodies of inf_t (lmin_*) or max over bodies of sup_t (the others) of a body function, bracketed.

    Returns dict(observed, certified, witness_time, body, how, sense), and ``certificate`` (kind ``body-spectrum``,
    :func:`.certificate.body_spectrum_certificate`) when the certified side comes from the vertices and is finite.
    The observed side is a true value on a time grid; the certified side comes from the segment ends (payloads,
    scalings) or from positivity and rate bounds (moving masses). Eigenvalues computed in floating point are moved
    outwards by the rounding allowance ROUNDING eps |lambda|_max of their matrix (lower sides down, upper sides up).
    """
    build, kind, rate = BODY_FUNCTIONS[name]
    t = trajectory.times(samples, horizon)
    theta, theta_dot = trajectory.theta(t)
    vals = spectral(build(theta_dot if rate else theta), kind)  # (T, N)
    sense = "min" if kind == "lmin" else "max"
    flat = np.argmin(vals) if sense == "min" else np.argmax(vals)
    ti, body = np.unravel_index(flat, vals.shape)
    observed = float(vals[ti, body])
    verts, certificate = parameter_vertices(trajectory), None
    if verts is not None:
        stack = verts[1] if rate else verts[0]
        finite = np.all(np.isfinite(stack), axis=(-2, -1))
        cvals = _rounded(build(stack[finite]), kind)
        rounding = (f"; each vertex's eigenvalue {'lowered' if sense == 'min' else 'raised'} by the rounding "
                    f"allowance {ROUNDING:g} eps |lambda|_max of its matrix")
        if finite.all():
            how = ("exact: the extreme over t is at an end of the segment Theta_base + s Phi_load (one load per body)"
                   if len(trajectory.loads) <= 1 else "the hull of the loads' segments (an outer bound)") + rounding
            certified, certificate = vertex_extreme(stack, name, how, formation(trajectory, rate))
        elif sense == "min":
            certified = float(cvals.min())
            how = ("a scaling grows without bound on the span; growth of a consistent body only raises lambda_min"
                   + rounding)
            directions = _growth_directions(trajectory)
            if directions is not None:
                certificate = body_spectrum_certificate(stack[finite], name, certified, how, directions)
        else:
            certified, how = np.inf, "a profile grows without bound on the span: the supremum is infinite"
    else:
        certified, how = _moving_mass_bound(trajectory, name), "positivity of the loads and their rate bounds"
        certificate = _moving_certificate(trajectory, name, certified, how)
    found = {"observed": observed, "certified": certified, "witness_time": float(t[ti]), "body": int(body), "how": how,
             "sense": sense}
    if certificate is not None:
        found["certificate"] = certificate
    return found


def _growth_directions(trajectory):
    """(N, 10): the row each body grows along without bound (its base row under a scaling, the payload's Phi),
    zero for bounded bodies; None where a body has two unbounded loads (a cone, not a ray)."""
    directions, seen = np.zeros_like(trajectory.base, dtype=float), set()
    for load in trajectory.loads:
        if np.isfinite(profile_range(load.profile, trajectory.span)[1]):
            continue
        if load.body in seen:
            return None
        seen.add(load.body)
        directions[load.body] = trajectory.base[load.body] if isinstance(load, Scaling) else load.phi
    return directions


def vertex_extreme(stack, name, how="", formed=None):
    """(certified, certificate): the min over bodies and rows of ``stack`` (V, N, 10) of the body function ``name``
    (a lmin_* of :data:`BODY_FUNCTIONS`; the max for the others), moved outward by its rounding allowance, so a bound
    over the convex hull of each body's rows; and its ``body-spectrum`` certificate (``how``: its provenance;
    ``formed``: how the rows were formed, :func:`formation`)."""
    build, kind, _ = BODY_FUNCTIONS[name]
    values = _rounded(build(np.asarray(stack, float)), kind)
    certified = float(values.min() if kind == "lmin" else values.max())
    return certified, body_spectrum_certificate(stack, name, certified, how, formation=formed)


def _rounded(matrices, kind):
    """Spectral function ``kind`` of a batch of symmetric matrices, moved outwards by its rounding allowance:
    ROUNDING eps |lambda|_max (down for lambda_min, up for lambda_max and |lambda|_max)."""
    allowance = ROUNDING * EPS * spectral(matrices, "absmax")
    return spectral(matrices, kind) + (-allowance if kind == "lmin" else allowance)


def fixed_part_vertices(trajectory, rate=False):
    """(V, N, 10): vertices of Theta(t) (``rate``: of Thetadot(t)) less its moving masses, the hull of the payloads'
    and scalings' segments; None where a profile grows without bound."""
    fixed = ParameterTrajectory(trajectory.base, tuple(load for load in trajectory.loads
                                                       if not isinstance(load, MovingMass)), trajectory.span)
    stack = parameter_vertices(fixed)[1 if rate else 0]
    return stack if np.all(np.isfinite(stack)) else None


def moving_mass_hull(trajectory, kind):
    """(V, N, 10) whose hull bounds Theta(t) of moving masses in the semidefinite order of each body's f: for "lmin"
    the rest's vertices (:func:`fixed_part_vertices`; a moving body adds f(Phi_p) >= 0), for "lmax" those plus, on
    each moving body, the row of diag(Sigma_c, 0) + m (1 + C^2) I4 >= f(Phi_p(c)) (|c| <= C), its diagonal raised by
    ROUNDING eps of its size for the float steps. M(q, Theta) is monotone in each f(Phi_l) (Z = L(f), L a positive map:
    the key step), so lambda_min and lambda_max of M over t are bounded by their extremes over the hull. None where a
    profile grows without bound."""
    stack = fixed_part_vertices(trajectory)
    if stack is None or kind == "lmin":
        return stack
    stack = stack.copy()
    for load in trajectory.loads:
        if isinstance(load, MovingMass):
            f = np.zeros((4, 4))
            f[:3, :3] = sigma_from_inertia(load.inertia_com)
            lift = load.mass * (1 + _path_geometry(load.path)[0] ** 2)
            f += (lift + ROUNDING * EPS * (lift + np.abs(f).sum())) * np.eye(4)
            stack[:, load.body] += pseudo_inertia_inverse(f)
    return stack


def _moving_mass_bound(trajectory, name):
    """Theta(t) = Theta_fixed(t) + sum_p Phi_p(t), Theta_fixed in the hull of :func:`fixed_part_vertices` (and so
    its rate): a moving body adds a PSD f(Phi_p) (and Z(Phi_p)) of norm at most its ``f_norm``, and a rate of norm at
    most its ``f_rate``."""
    build, kind, rate = BODY_FUNCTIONS[name]
    stack = fixed_part_vertices(trajectory, rate)
    if stack is None:
        return -np.inf if kind == "lmin" else np.inf
    extra = np.zeros(trajectory.bodies)
    for load in trajectory.loads:
        if isinstance(load, MovingMass):
            terms = _moving_mass_terms(load)
            factor = 2.0 if build is spatial_inertia else 1.0  # ||Z(F)|| <= 2 ||F|| for F >= 0 or |F| bounded
            extra[load.body] += factor * (terms["f_rate"] if rate else terms["f_norm"])
    base = _rounded(build(stack), kind)  # (V, N)
    if kind == "lmin":
        return float(base.min())  # adding a consistent body only adds a PSD term
    return _up((base + extra).max())


def lumped_velocity_bounds(trajectory, *, samples=2001):
    """Psi* = sup_t ||Psi||, dPsi* = sup_t ||Psidot||: observed on a time grid, certified from the paths and profiles."""
    t = trajectory.times(samples)
    psi, psi_dot = trajectory.psi(t)
    n_psi, n_dot = np.linalg.norm(psi, axis=-1), np.linalg.norm(psi_dot, axis=-1)
    found, terms = {}, [_moving_mass_terms(load) for load in trajectory.loads if isinstance(load, MovingMass)]
    for name, norms in (("psi", n_psi), ("psi_dot", n_dot)):
        certified = _up(sum(term[name] for term in terms))
        found[name] = {"observed": float(norms.max()), "certified": certified,
                       "witness_time": float(t[np.argmax(norms)])}
        certificate = _moving_certificate(trajectory, name, certified, "mass, path length and the profile's peaks")
        if certificate is not None:
            found[name]["certificate"] = certificate
    return found


def _up(x):
    """x moved up by the rounding allowance ROUNDING eps |x| of its few float steps."""
    return float(x + ROUNDING * EPS * abs(x))


def _moving_certificate(trajectory, name, bound, how):
    """The ``moving-mass`` certificate of a bound over time where a load moves, the rest of Theta(t) (or of its rate)
    over the hull of its vertices; for Psi, which only the moving loads have, over the base. None otherwise."""
    if not any(isinstance(load, MovingMass) for load in trajectory.loads):
        return None
    rest = fixed_part_vertices(trajectory, BODY_FUNCTIONS[name][2]) if name in BODY_FUNCTIONS else trajectory.base[None]
    return None if rest is None else moving_mass_certificate(trajectory, name, bound, how, rest)
