"""Adaptive laws for the inertial parameters: one interface, two laws.

A law keeps its own state z (..., N, 10) per body, reads the estimate
Theta_hat = estimate(z) off it and moves z with

    zdot = rate(z, g),    g_l = R_l(q, qd, qd_r, qdd_r)^T s    (RoboticRegressor)

where s = qd - qd_r is the sliding variable of Slotine and Li. Every law has a
divergence D(z, Theta) >= 0, zero iff Theta_hat = Theta, with

    d/dt D(z(t), Theta) = -g . (Theta_hat - Theta)    for constant Theta,

which cancels the parameter term of V = 1/2 s^T M s + D in the Lyapunov argument
(inertiaproof.sim.tracking). ``divergence_gradient`` is dD/dTheta: what a
time-varying Theta adds to Ddot. A new law subclasses :class:`AdaptiveLaw`,
implements its five methods and enters :data:`LAWS` (README: adaptive laws); ``linearization`` (for implicit
integration) has a default by finite differences.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from inertiaproof.model.inertia import pseudo_inertia

__all__ = ["AdaptiveLaw", "LAWS", "NaturalAdaptation", "SlotineLi", "adjoint", "f_inverse", "f_map", "make_law",
           "per_body_jacobian"]

F_MATRIX = pseudo_inertia(np.eye(10)).reshape(10, 16).T  # vec(f(x)) = F x: f of Theorem 1 as a 16 x 10 matrix
ADJOINT_INVERSE = np.linalg.inv(F_MATRIX.T @ F_MATRIX)  # f^{-*}(g) = f((F^T F)^{-1} g)
F_PSEUDO_INVERSE = ADJOINT_INVERSE @ F_MATRIX.T  # x = F^+ vec(f(x))
SQRT_EPS = np.sqrt(np.finfo(float).eps)
MARGIN_ROOT_SLACK = 1e-9  # NaturalAdaptation.margin_floor's roots, rounded outwards (bisection stops within 2e-12)


def f_map(x):
    """f(x) (..., 4, 4) (DefTrafoInertialParameters) as one product with F."""
    return (x @ F_MATRIX.T).reshape(x.shape[:-1] + (4, 4))


def f_inverse(a):
    """f^{-1}(A) (..., 10) of symmetric A (..., 4, 4) (Theorem 1, second part); the symmetric part of any A."""
    return a.reshape(a.shape[:-2] + (16,)) @ F_PSEUDO_INVERSE.T


def adjoint(a):
    """f^*(A) (..., 10) with f^*(A) . x = tr(A f(x)) for symmetric A (..., 4, 4)."""
    return a.reshape(a.shape[:-2] + (16,)) @ F_MATRIX


class AdaptiveLaw:
    """The interface of an adaptive law, with its gain ``gain``. Methods are batched over leading axes."""

    name = "law"

    def __init__(self, gain):
        self.gain = float(gain)

    def initial(self, theta_hat):
        """z at the start, from an initial estimate (..., N, 10)."""
        raise NotImplementedError

    def estimate(self, z):
        """Theta_hat (..., N, 10)."""
        raise NotImplementedError

    def rate(self, z, g):
        """zdot for the drive g_l = R_l^T s (..., N, 10)."""
        raise NotImplementedError

    def divergence(self, z, theta):
        """D(z, Theta) (...): the parameter part of the Lyapunov function."""
        raise NotImplementedError

    def divergence_gradient(self, z, theta):
        """dD/dTheta (..., N, 10)."""
        raise NotImplementedError

    def outside(self, z):
        """Where (..., N) the state has left the law's domain, across a barrier D is infinite on: a law whose
        solution cannot get there (D <= V stays finite), so an integrator that did stepped over it (default: none)."""
        return np.zeros(np.shape(z)[:-1], bool)

    def barrier_margin(self, z):
        """How far (..., N) the state is from the law's barrier, relative to its own size (default: inf, none)."""
        return np.full(np.shape(z)[:-1], np.inf)

    def margin_floor(self, bound, theta):
        """A lower bound (..., N) on :meth:`barrier_margin` of every state whose divergence from ``theta`` (..., N, 10)
        is at most ``bound`` (...) (default: 0, none known)."""
        return np.zeros(np.shape(theta)[:-1])

    def linearization(self, z, g):
        """(d estimate/dz, d rate/dz, d rate/dg) at (z, g), per body (..., N, 10, 10) with [..., i, k] = d out_i /
        d in_k, for the Newton matrix of an implicit integrator (inertiaproof.sim.tracking), where an approximation
        suffices. By default forward differences of the law's own methods (a law acts on each body separately);
        the two laws here give closed forms."""
        g_probe = g[..., None, :, :]
        return (per_body_jacobian(self.estimate, z),
                per_body_jacobian(lambda x: self.rate(x, g_probe), z),
                per_body_jacobian(lambda x: self.rate(z[..., None, :, :], x), g))

    def __repr__(self):
        return f"{type(self).__name__}({self.gain:g})"


def per_body_jacobian(fun, x):
    """d fun / dx (..., N, 10, 10) of a map fun acting on each body's 10 components of x (..., N, 10), by forward
    differences: fun takes (..., K, N, 10) with a probe axis K (1 at x, 10 at the probes); steps sqrt(eps) x the
    body's largest |x_k| (sqrt(eps) where the body's x is zero)."""
    size = np.broadcast_to(np.abs(x).max(-1, keepdims=True), x.shape)
    h = SQRT_EPS * np.where(size > 0, size, 1.0)  # (..., N, 10)
    probes = x[..., None, :, :] + np.moveaxis(h[..., None] * np.eye(x.shape[-1]), -2, -3)  # (..., 10 k, N, 10)
    change = fun(probes) - fun(x[..., None, :, :])  # (..., 10 k, N, 10 i)
    return np.moveaxis(change / np.moveaxis(h, -1, -2)[..., None], -3, -1)


class SlotineLi(AdaptiveLaw):
    """The Euclidean gradient of Slotine and Li (1987): Theta_hat' = -gamma sum_l R_l^T s, z = Theta_hat,
    D = |Theta_hat - Theta|^2 / (2 gamma). Nothing keeps f(Phi_hat_l) positive definite."""

    name = "slotine-li"

    def initial(self, theta_hat):
        return np.array(theta_hat, dtype=float)

    def estimate(self, z):
        return z

    def rate(self, z, g):
        return -self.gain * g

    def divergence(self, z, theta):
        return 0.5 * np.sum((z - theta) ** 2, axis=(-2, -1)) / self.gain

    def divergence_gradient(self, z, theta):
        return (theta - z) / self.gain

    def linearization(self, z, g):
        eye = np.broadcast_to(np.eye(10), z.shape + (10,))
        return eye, np.zeros_like(eye), -self.gain * eye


class NaturalAdaptation(AdaptiveLaw):
    """Natural adaptation on the pseudo-inertias (Lee, Kwon and Park 2018): the gradient of s^T Y Theta_hat in the
    Riemannian metric of the log-det Bregman divergence,

        f(Phi_hat_l)' = -gamma f(Phi_hat_l) f^{-*}(R_l^T s) f(Phi_hat_l),
        D = (1/gamma) sum_l [tr(f(Phi_l) U_l) - log det(f(Phi_l) U_l) - 4],   U_l = f(Phi_hat_l)^{-1}.

    The state is the mirror variable U_l = f(z_l), which moves linearly: U_l' = gamma f^{-*}(R_l^T s) (the update
    is integrated exactly on the cone of positive definite matrices). f(Phi_hat_l) = U_l^{-1} is positive definite
    exactly while U_l is; U_l turning singular means f(Phi_hat_l) blew up.
    """

    name = "natural"

    def initial(self, theta_hat):
        return f_inverse(np.linalg.inv(f_map(np.asarray(theta_hat, dtype=float))))

    def mirror(self, z):
        """U_l = f(z_l) (..., N, 4, 4)."""
        return f_map(z)

    def estimate(self, z):
        return f_inverse(np.linalg.inv(self.mirror(z)))

    def rate(self, z, g):
        return self.gain * g @ ADJOINT_INVERSE

    def divergence(self, z, theta):
        product = self.mirror(z) @ f_map(theta)
        _, logdet = np.linalg.slogdet(product)
        return np.sum(np.trace(product, axis1=-2, axis2=-1) - logdet - 4.0, axis=-1) / self.gain

    def divergence_gradient(self, z, theta):
        return adjoint(self.mirror(z) - np.linalg.inv(f_map(theta))) / self.gain

    def outside(self, z):
        """Where (..., N) U_l is not positive definite: f(Phi_hat_l) = U_l^-1 passed through infinity, where D is."""
        return np.linalg.eigvalsh(self.mirror(z))[..., 0] <= 0

    def barrier_margin(self, z):
        """lambda_min(U_l) / lambda_max(U_l) (..., N): where it reaches rounding, f(Phi_hat_l) = U_l^-1 is beyond what
        float64 resolves."""
        eigenvalues = np.linalg.eigvalsh(self.mirror(z))
        return eigenvalues[..., 0] / np.abs(eigenvalues).max(-1)

    def margin_floor(self, bound, theta):
        """mu_lo / mu_hi / cond(f(Phi_l)) (..., N) for D <= ``bound``: body l's term of gamma D, a sum of
        mu - log mu - 1 over the eigenvalues mu of f(Phi_l) U_l, each >= 0, keeps each mu within the two roots of
        mu - log mu - 1 = gamma D; and lambda_min(U_l) >= mu_lo / lambda_max(f(Phi_l)), lambda_max(U_l) <= mu_hi /
        lambda_min(f(Phi_l)). The roots by bisection, each rounded outwards by MARGIN_ROOT_SLACK."""
        g = self.gain * np.maximum(np.asarray(bound, float), 0.0)  # D >= 0: a negative bound is rounding
        minus_log_lo = np.vectorize(lambda x: brentq(lambda u: np.expm1(-u) + u - x, 0.0, x + 2.0))  # mu = e^-u
        hi = np.vectorize(lambda x: brentq(lambda m: m - np.log(m) - 1.0 - x, 1.0, 2.0 * x + 3.0))
        log_ratio = -minus_log_lo(g) - MARGIN_ROOT_SLACK - np.log(hi(g) + MARGIN_ROOT_SLACK)
        eigenvalues = np.linalg.eigvalsh(f_map(np.asarray(theta, float)))
        return np.exp(log_ratio)[..., None] * eigenvalues[..., 0] / eigenvalues[..., -1]

    def linearization(self, z, g):
        """Closed forms: d f^-1(U^-1) = -f^-1(U^-1 f(dz) U^-1) (finite differences lose it when U is as
        ill-conditioned as a thin rod's), and the rate is linear in g and free of z."""
        u_inv = np.linalg.inv(self.mirror(z))[..., None, :, :]
        d_estimate = np.swapaxes(-f_inverse(u_inv @ f_map(np.eye(10)) @ u_inv), -1, -2)
        rate = np.broadcast_to(self.gain * ADJOINT_INVERSE.T, d_estimate.shape)
        return d_estimate, np.zeros_like(d_estimate), rate


LAWS = {law.name: law for law in (SlotineLi, NaturalAdaptation)}


def make_law(name, gain):
    """The law called ``name`` with adaptation gain ``gain``."""
    if name not in LAWS:
        raise KeyError(f"adaptive law must be one of {sorted(LAWS)}, not {name!r}")
    return LAWS[name](gain)
