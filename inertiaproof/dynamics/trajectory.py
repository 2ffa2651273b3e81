"""Time-dependent inertial parameters Theta(t) and lumped velocities Psi(t).

A :class:`ParameterTrajectory` is the chain's constant bodies plus loads:

- :class:`Payload`: a rigid body whose density grows from nothing in place
  (loading, mass arriving at rest in the body frame): Theta_l += s(t) Phi_p,
  no internal motion, Psi = 0.
- :class:`Scaling`: the body's whole density scales by s(t) (the paper's
  sphere counterexample, CX-sphere).
- :class:`MovingMass`: a rigid body translating inside body l along a path
  c(t) (a trolley, a passenger): Phi_l gains Phi_p(c(t)) and, by
  (DefMatrixZ ff.), psi_l = int sigma rho [I3; S(x)] v dx = [m_p cdot; m_p c x cdot].

Everything is batched over the leading axes of ``t``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from inertiaproof.model.inertia import from_urdf, skew

__all__ = ["MovingMass", "ParameterTrajectory", "Path", "Payload", "Profile", "Scaling", "SineMotion"]


# -- scalar time profiles s(t) with s', s'' ------------------------------------

@dataclass(frozen=True)
class Profile:
    """s(t): 'constant', 'linear', 'smoothstep' (C1), 'smootherstep' (C2), 'cosine' ramps from 0 to 1
    over [start, start + duration]; 'exp' is exp(rate (t - start))."""

    shape: str = "smootherstep"
    start: float = 0.0
    duration: float = 1.0
    rate: float = 0.0

    SHAPES = ("constant", "linear", "smoothstep", "smootherstep", "cosine", "exp")

    def __post_init__(self):
        if self.shape not in self.SHAPES:
            raise ValueError(f"profile shape must be one of {self.SHAPES}, not {self.shape!r}")
        if self.shape not in ("constant", "exp") and not self.duration > 0:
            raise ValueError(f"profile duration must be > 0, got {self.duration}")

    def derivatives(self, t):
        """(s, s', s'') at times t."""
        t = np.asarray(t, dtype=float)
        if self.shape == "constant":
            one = np.ones_like(t)
            return one, 0 * one, 0 * one
        if self.shape == "exp":
            e = np.exp(self.rate * (t - self.start))
            return e, self.rate * e, self.rate**2 * e
        x = np.clip((t - self.start) / self.duration, 0.0, 1.0)
        inside = ((t > self.start) & (t < self.start + self.duration)).astype(float)
        k = 1.0 / self.duration
        if self.shape == "linear":
            return x, k * inside, 0 * x
        if self.shape == "smoothstep":
            return x * x * (3 - 2 * x), k * 6 * x * (1 - x) * inside, k * k * (6 - 12 * x) * inside
        if self.shape == "smootherstep":
            s = x**3 * (10 + x * (-15 + 6 * x))
            return s, k * 30 * x * x * (1 - x) ** 2 * inside, k * k * 60 * x * (1 - x) * (1 - 2 * x) * inside
        # cosine
        return 0.5 * (1 - np.cos(np.pi * x)), k * 0.5 * np.pi * np.sin(np.pi * x) * inside, \
            k * k * 0.5 * np.pi**2 * np.cos(np.pi * x) * inside

    def rate_bound(self):
        """sup |s'(t)| over t >= start (exact; infinite for a growing exponential on an unbounded span)."""
        peak = {"constant": 0.0, "linear": 1.0, "smoothstep": 1.5, "smootherstep": 1.875, "cosine": np.pi / 2}
        if self.shape == "exp":
            return abs(self.rate) if self.rate <= 0 else np.inf
        return peak[self.shape] / (self.duration if self.shape != "constant" else 1.0)


# -- loads ---------------------------------------------------------------------

@dataclass(frozen=True)
class Payload:
    body: int  # 0-based index of the carrying body
    phi: np.ndarray  # the payload's Phi in the body frame when fully loaded
    profile: Profile

    def theta(self, t):
        s, ds, _ = self.profile.derivatives(t)
        return s[..., None] * self.phi, ds[..., None] * self.phi

    def psi(self, t):
        return None


@dataclass(frozen=True)
class Scaling:
    body: int
    profile: Profile

    def factor(self, t):
        return self.profile.derivatives(t)


@dataclass(frozen=True)
class Path:
    """c(t) = start + s(t) (end - start) for 'line', or a circle of ``radius`` about ``center`` in the plane
    normal to ``normal`` at angle 2 pi s(t) for 'circle'."""

    shape: str
    profile: Profile
    start: tuple = (0.0, 0.0, 0.0)
    end: tuple = (0.0, 0.0, 0.0)
    center: tuple = (0.0, 0.0, 0.0)
    radius: float = 0.0
    normal: tuple = (0.0, 0.0, 1.0)

    def derivatives(self, t):
        """(c, cdot, cddot) with shapes (..., 3)."""
        s, ds, dds = (x[..., None] for x in self.profile.derivatives(t))
        if self.shape == "line":
            a, b = np.asarray(self.start, float), np.asarray(self.end, float)
            return a + s * (b - a), ds * (b - a), dds * (b - a)
        n = np.asarray(self.normal, float)
        n = n / np.linalg.norm(n)
        e1 = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n, e1)
        ang = 2 * np.pi * s
        r = self.radius
        c = np.asarray(self.center, float) + r * (np.cos(ang) * e1 + np.sin(ang) * e2)
        dang, ddang = 2 * np.pi * ds, 2 * np.pi * dds
        tangent = -np.sin(ang) * e1 + np.cos(ang) * e2
        inward = -(np.cos(ang) * e1 + np.sin(ang) * e2)
        return c, r * dang * tangent, r * (ddang * tangent + dang**2 * inward)


@dataclass(frozen=True)
class MovingMass:
    body: int
    mass: float
    inertia_com: np.ndarray  # 3x3 about its own CoM, in the body's axes (it translates, does not turn)
    path: Path

    def theta(self, t):
        c, cd, _ = self.path.derivatives(t)
        m = self.mass
        phi = from_urdf(np.full(c.shape[:-1], m), c, np.broadcast_to(self.inertia_com, c.shape[:-1] + (3, 3)))
        sc, scd = skew(c), skew(cd)
        d_inertia = m * (np.swapaxes(scd, -1, -2) @ sc + np.swapaxes(sc, -1, -2) @ scd)
        phi_dot = np.concatenate([
            np.zeros(c.shape[:-1] + (1,)),
            m * cd,
            np.stack([d_inertia[..., 0, 0], d_inertia[..., 1, 1], d_inertia[..., 2, 2],
                      d_inertia[..., 0, 1], d_inertia[..., 1, 2], d_inertia[..., 0, 2]], -1),
        ], -1)
        return phi, phi_dot

    def psi(self, t):
        """(psi_l, psidot_l), each (..., 6): [m cdot; m c x cdot] and its derivative [m cddot; m c x cddot]."""
        c, cd, cdd = self.path.derivatives(t)
        m = self.mass
        return (np.concatenate([m * cd, m * np.cross(c, cd)], -1),
                np.concatenate([m * cdd, m * np.cross(c, cdd)], -1))


# -- the trajectory ------------------------------------------------------------

@dataclass(frozen=True)
class ParameterTrajectory:
    base: np.ndarray  # (N, 10) constant parameters of the bodies
    loads: tuple = ()
    span: tuple = (0.0, 1.0)  # [t0, t1]; t1 may be inf

    @property
    def bodies(self):
        return self.base.shape[0]

    @property
    def time_varying(self):
        return bool(self.loads)

    @property
    def internal_motion(self):
        return any(isinstance(load, MovingMass) for load in self.loads)

    @property
    def mass_change(self):
        """Whether mass is added or removed (a payload or a scaling), not only moved around."""
        return any(isinstance(load, (Payload, Scaling)) for load in self.loads)

    def theta(self, t, mass_time=None):
        """(Theta, Thetadot) at times t: shapes (..., N, 10).

        With ``mass_time``, payloads and scalings are frozen at those times (their rate is 0): the
        parameters of a body that gains or loses mass in discrete pieces (inertiaproof.sim.capture).
        """
        t = np.asarray(t, dtype=float)
        frozen = mass_time is not None
        tm = np.broadcast_to(np.asarray(mass_time, dtype=float), t.shape) if frozen else t
        theta = np.broadcast_to(self.base, t.shape + self.base.shape).copy()
        theta_dot = np.zeros_like(theta)
        for load in self.loads:
            if isinstance(load, Scaling):
                s, ds, _ = load.factor(tm)
                ds = 0 * ds if frozen else ds
                theta[..., load.body, :], theta_dot[..., load.body, :] = (
                    s[..., None] * theta[..., load.body, :],
                    ds[..., None] * theta[..., load.body, :] + s[..., None] * theta_dot[..., load.body, :],
                )
        for load in self.loads:
            if isinstance(load, Payload):
                phi, phi_dot = load.theta(tm)
                theta[..., load.body, :] += phi
                theta_dot[..., load.body, :] += 0 * phi_dot if frozen else phi_dot
            elif isinstance(load, MovingMass):
                phi, phi_dot = load.theta(t)
                theta[..., load.body, :] += phi
                theta_dot[..., load.body, :] += phi_dot
        return theta, theta_dot

    def psi(self, t):
        """(Psi, Psidot) at times t: shapes (..., 6N)."""
        t = np.asarray(t, dtype=float)
        psi = np.zeros(t.shape + (self.bodies, 6))
        psi_dot = np.zeros_like(psi)
        for load in self.loads:
            if isinstance(load, MovingMass):
                p, pd = load.psi(t)
                psi[..., load.body, :] += p
                psi_dot[..., load.body, :] += pd
        return psi.reshape(t.shape + (-1,)), psi_dot.reshape(t.shape + (-1,))

    def times(self, count, horizon=None):
        """``count`` sample times over the span; an infinite span is cut at ``horizon`` (default t0 + 50)."""
        t0, t1 = self.span
        if not np.isfinite(t1):
            t1 = t0 + (50.0 if horizon is None else horizon)
        return np.linspace(t0, t1, count)


@dataclass(frozen=True)
class SineMotion:
    """x(t) = center + amplitude sin(rate t + phase), entrywise over arrays of one shape (joint coordinates,
    Theta (N, 10), Psi (6N,)): analytic in t, so a complex step in t passes through."""

    center: np.ndarray
    amplitude: np.ndarray
    rate: np.ndarray
    phase: np.ndarray

    def at(self, t):
        """(x, xdot) at times t: shapes t.shape + center.shape."""
        t = np.asarray(t)[(...,) + (None,) * np.ndim(self.center)]
        angle = self.rate * t + self.phase
        return self.center + self.amplitude * np.sin(angle), self.amplitude * self.rate * np.cos(angle)
