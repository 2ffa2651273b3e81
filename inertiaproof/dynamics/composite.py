"""M(q, Theta) by composite rigid bodies: (MassMatrix) regrouped along the chain.

Columns k <= j of body l's block are those of body j carried rigidly into
frame l, QJ_l[:, :j+1] = X_{l<-j} QJ_j[:, :j+1]. Hence, for k <= j,

    M_kj = sum_{l >= j} QJ_l[:, k]^T Z(Phi_l) QJ_l[:, j] = QJ_j[:, k]^T Z(Phi^c_j) QJ_j[:, j],

with Phi^c_j the bodies j..N lumped in frame j: X^T Z(Phi) X for a change
of frame is Z of the parameters carried along, and parameters move
linearly, f(Phi) -> t f(Phi) t^T for a frame change t
(MassDistributionToInertialParam). The force F_j = Z(Phi^c_j) QJ_j[:, j]
is carried back to frame k by X^T, where QJ_k[:, k] picks M_kj. Two passes
over the joints, no Python loop over configurations, generic in dtype (a
complex step passes through).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from inertiaproof.model.inertia import pseudo_inertia, pseudo_inertia_inverse, spatial_inertia

from .twists import Arena, chunks, fixed_map, flat_view, plane_turn, real_product, turn_wrenches

__all__ = [
    "force_of_unit_twist", "frame_change", "FROM_TURNING", "mass_matrix", "mass_matrix_partials",
    "turn_parameters", "TURNING",
]

# Phi in coordinates on which a turn about z acts as plane turns: (h1, I13, h2, I23, (I11 - I22)/2, I12,
# I11 + I22, m, h3, I33); (h1, h2) and (I13, I23) turn by the joint angle, ((I11 - I22)/2, I12) by twice it.
TURNING = np.zeros((10, 10))
for _row, _col, _value in ((0, 1, 1), (1, 9, 1), (2, 2, 1), (3, 8, 1), (4, 4, 0.5), (4, 5, -0.5), (5, 7, 1),
                           (6, 4, 1), (6, 5, 1), (7, 0, 1), (8, 3, 1), (9, 6, 1)):
    TURNING[_row, _col] = _value
FROM_TURNING = np.linalg.inv(TURNING)  # column i: the Phi whose i-th turning coordinate is 1


def frame_change(t):
    """10 x 10 map of Phi given in the frame F t to Phi in F, f -> t f t^T (t a fixed 4 x 4 transform),
    in turning coordinates; None for the identity."""
    if np.array_equal(t, np.eye(4)):
        return None
    return TURNING @ pseudo_inertia_inverse(t @ pseudo_inertia(FROM_TURNING.T) @ t.T).T


def force_of_unit_twist(s):
    """6 x 10 map Phi (turning coordinates) -> Z(Phi) s for a fixed twist s (Z is linear in Phi)."""
    return (spatial_inertia(FROM_TURNING.T) @ s).T


@lru_cache(maxsize=1024)
def _maps(joint):
    """A ZJoint's frame-change maps (before, after) and the force of its unit twist."""
    return frame_change(joint.before), frame_change(joint.after), force_of_unit_twist(joint.unit_twist)


def turn_parameters(phi, motion, scratch=None):
    """In place: Phi (10, K) in turning coordinates of a body in the frame after a joint's turn about z by x
    (slide along z), moved into the frame before it.

    Turn: h -> Rz h, I -> Rz I Rz^T, i.e. (h1, h2) and (I13, I23) turn by x, ((I11 - I22)/2, I12) by 2x.
    Slide by x e_z: h3 += m x, I += (2 x h3 + m x^2) diag(1, 1, 0) - x (e_z h^T + h e_z^T).
    """
    if motion.revolute:
        plane_turn(phi[0:2], phi[2:4], motion.cos, motion.sin, scratch=scratch)
        plane_turn(phi[4], phi[5], *motion.double_angle(), scratch=scratch)
    else:
        value = motion.value
        h1, h2, m, h3 = phi[0], phi[2], phi[7], phi[8]
        phi[6] += 2 * value * (2 * h3 + m * value)
        phi[1] -= value * h1
        phi[3] -= value * h2
        phi[8] += m * value


def _flat_parameters(theta, batch, count):
    """Theta (..., N, 10) as (N, 10, K) in turning coordinates, or (N, 10, 1) for one set for all configurations."""
    if theta.ndim == 2:
        return (theta @ TURNING.T)[:, :, None]
    theta = np.broadcast_to(theta, batch + theta.shape[-2:]).reshape(count, *theta.shape[-2:])
    return np.ascontiguousarray(np.transpose(theta @ TURNING.T, (1, 2, 0)))


def _fill(chain, x, phi, m, arena):
    """Into m (n, n, K): M at coordinate rows x (n, K) for parameters phi (N, 10, K or 1) in turning coordinates.

    The force stack holds F_j for j = n-1 down to l (columns reversed), expressed in frame l; two
    buffers of each kind take turns as source and target of the fixed maps.
    """
    n, count = chain.n, x.shape[1]
    joints, motions = chain.z_joints, chain.motions(x)
    force_buffers = (arena.take(6, n, count), arena.take(6, n, count))
    lumped_buffers = (arena.take(10, count), arena.take(10, count))
    scratch = arena.take(4 * n * count)
    held, side = 0, 0  # which lumped buffer and which force buffer hold the current values
    lumped = lumped_buffers[held]
    lumped[:] = phi[n - 1]
    for l in range(n - 1, -1, -1):
        size = n - 1 - l  # forces carried from frame l + 1
        if size:
            child, motion = joints[l + 1], motions[l + 1]
            before, after, _ = _maps(child)
            if after is not None:
                held = 1 - held
                lumped = real_product(after, lumped, out=lumped_buffers[held])
            turn_parameters(lumped, motion, scratch)
            if before is not None:
                held = 1 - held
                lumped = real_product(before, lumped, out=lumped_buffers[held])
            lumped += phi[l]
            forces = force_buffers[side][:, :size]
            if child.after_twist is not None:
                side = 1 - side
                forces = fixed_map(child.after_twist.T, forces, out=force_buffers[side][:, :size])
            turn_wrenches(forces, motion, scratch)
            if child.before_twist is not None:
                side = 1 - side
                fixed_map(child.before_twist.T, forces, out=force_buffers[side][:, :size])
        stack = force_buffers[side][:, :size + 1]
        real_product(_maps(joints[l])[2], lumped, out=stack[:, size])
        axis = joints[l].unit_axis
        if axis is None:
            m[l, l:] = real_product(joints[l].unit_twist[None], flat_view(stack, 6)).reshape(size + 1, -1)[::-1]
        else:
            m[l, l:] = stack[axis, ::-1]
        if motions[l].rate is not None:
            stack[:, size] *= motions[l].rate
            m[l, l:] *= motions[l].rate
            m[l, l] *= motions[l].rate
    upper = np.triu_indices(n, 1)
    m[upper[::-1]] = m[upper]


def mass_matrix(chain, q, theta):
    """M(q, Theta) (..., n, n) for configurations q (..., n) and parameters theta (N, 10) or (..., N, 10).

    Linear in theta, so M(q, Thetadot) is mass_matrix(chain, q, theta_dot). Agrees with
    dynamics.mass_matrix(chain.body_jacobian(q), theta) to round-off; the result is a view whose
    storage keeps the batch last.
    """
    q, theta = np.asarray(q), np.asarray(theta)
    batch = np.broadcast_shapes(q.shape[:-1], theta.shape[:-2])
    x, _ = chain.flat_coordinates(np.broadcast_to(q, batch + q.shape[-1:]))
    count, n = x.shape[1], chain.n
    phi = _flat_parameters(theta, batch, count)
    dtype = np.result_type(x.dtype, phi.dtype)
    m = np.empty((n, n, count), dtype)
    parts = chunks(count)
    size = (2 * 6 * n + 2 * 10 + 4 * n) * (parts[0].stop - parts[0].start)
    for part in parts:
        arena = Arena("composite", size, dtype)
        _fill(chain, x[:, part], phi if phi.shape[-1] == 1 else phi[..., part], m[..., part], arena)
    return np.moveaxis(m, -1, 0).reshape(batch + (n, n))


def mass_matrix_partials(chain, q, theta):
    """dM/dq (..., n, n, n), entry [k, j, i] = d M_kj / d q_i (as dynamics.mass_matrix_partials), by a complex
    step in each coordinate through :func:`mass_matrix` (exact to round-off)."""
    from .chain import COMPLEX_STEP

    q, theta = np.asarray(q, dtype=float), np.asarray(theta)
    steps = q[..., None, :] + 1j * COMPLEX_STEP * np.eye(chain.n)  # (..., n_i, n)
    m = mass_matrix(chain, steps, theta[..., None, :, :] if theta.ndim > 2 else theta)
    return np.moveaxis(m.imag / COMPLEX_STEP, -3, -1)
