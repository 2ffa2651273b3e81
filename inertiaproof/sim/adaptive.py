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
implements its five methods and enters :data:`LAWS` (README: adaptive laws).
"""

from __future__ import annotations

import numpy as np

from inertiaproof.model.inertia import pseudo_inertia

__all__ = ["AdaptiveLaw", "LAWS", "NaturalAdaptation", "SlotineLi", "adjoint", "f_inverse", "f_map", "make_law"]

F_MATRIX = pseudo_inertia(np.eye(10)).reshape(10, 16).T  # vec(f(x)) = F x: f of Theorem 1 as a 16 x 10 matrix
ADJOINT_INVERSE = np.linalg.inv(F_MATRIX.T @ F_MATRIX)  # f^{-*}(g) = f((F^T F)^{-1} g)
F_PSEUDO_INVERSE = ADJOINT_INVERSE @ F_MATRIX.T  # x = F^+ vec(f(x))


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

    def __repr__(self):
        return f"{type(self).__name__}({self.gain:g})"


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


LAWS = {law.name: law for law in (SlotineLi, NaturalAdaptation)}


def make_law(name, gain):
    """The law called ``name`` with adaptation gain ``gain``."""
    if name not in LAWS:
        raise KeyError(f"adaptive law must be one of {sorted(LAWS)}, not {name!r}")
    return LAWS[name](gain)
