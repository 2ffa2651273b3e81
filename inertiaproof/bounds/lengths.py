"""What a chain's lengths bound for every q, and the bodies of the Jacobian-only quantities.

- :func:`lever_bounds`, :func:`column_bounds`: certified bounds of the columns of QJ from the lengths of the
  fixed transforms and the slides alone (the a-priori bounds of :mod:`inertiaproof.bounds.configuration` and the
  entrywise bounds of M in :mod:`inertiaproof.bounds.taylor` rest on them);
- :func:`block_rows`, :func:`unit_bodies`: parameter rows of the bodies diag(mu I3, nu I3), and of unit bodies
  (Z = I), whose mass matrix is (QJ)^T QJ (Definition 2).

Below :mod:`inertiaproof.bounds.configuration`, :mod:`inertiaproof.bounds.taylor` and
:mod:`inertiaproof.bounds.interface`, which import it (issue 25: no circles of imports).
"""

from __future__ import annotations

import numpy as np

from .spectral import EPS

__all__ = ["block_rows", "column_bounds", "lever_bounds", "unit_bodies"]


def lever_bounds(chain):
    """Certified |u_k x (z_l - p_k)| <= |z_l - p_k| (l >= k) for all q: the sum of the translations of the fixed
    transforms and of the slides from joint k's axis to body l's origin (rotations keep lengths), the first offset
    of a turning joint counted by its part across the axis (:func:`_axis_distance`). Lower triangle of an n x n array; a slide
    without limits counts as 0 only as the first joint (it moves the joint points too): see certification_obstacle."""
    lengths = []
    for joint in chain.joints:
        slide = 0.0 if joint.revolute or joint.limits is None else max(abs(joint.limits[0]), abs(joint.limits[1]))
        lengths.append((np.linalg.norm(joint.before[:3, 3]), np.linalg.norm(joint.after[:3, 3]), slide))
    out = np.zeros((chain.n, chain.n))
    for l in range(chain.n):
        for k in range(l + 1):
            out[l, k] = sum(lengths[m][1] + lengths[m][2] for m in range(k, l + 1)) + sum(
                lengths[m][0] for m in range(k + 1, l + 1))
            if chain.joints[k].revolute:  # only the distance from joint k's axis counts: |u_k x (z_l - p_k)|
                out[l, k] = min(out[l, k], _axis_distance(chain, k, l, lengths))
    return out * (1 + 4 * chain.n * EPS)


def _axis_distance(chain, k, l, lengths):
    """A bound of the distance of body l's origin from joint k's axis for every q: the offset fixed to joint k's
    turn (its after transform and joint k+1's before transform, in joint k's frame with the axis on z) counts by
    its part across the axis; the later translations and slides by their lengths."""
    z = chain.z_joints[k]
    offset = z.after[:3, 3].copy()
    if l > k:
        offset = offset + z.after[:3, :3] @ chain.z_joints[k + 1].before[:3, 3]
    rest = sum(lengths[m][1] + lengths[m][2] for m in range(k + 1, l + 1)) + sum(
        lengths[m][0] for m in range(k + 2, l + 1))
    return float(np.hypot(offset[0], offset[1])) + rest


def column_bounds(chain):
    """Certified bounds (n x n, lower triangle) of the linear and angular parts of column k of body l's block:
    revolute R_l^T (u_k x (z_l - p_k), u_k) gives (|z_l - p_k|, 1), prismatic (R_l^T u_k, 0) gives (1, 0)."""
    revolute = np.array([j.revolute for j in chain.joints])
    mask = np.tril(np.ones((chain.n, chain.n), bool))
    linear = np.where(mask, np.where(revolute[None, :], lever_bounds(chain), 1.0), 0.0)
    angular = np.where(mask, np.where(revolute[None, :], 1.0, 0.0), 0.0)
    return linear, angular


def block_rows(linear, angular):
    """Parameter rows (N, 10) of the spatial inertias diag(linear_l I3, angular_l I3) (mass, no first moment,
    isotropic rotational inertia): invariant under every rotation of the body frame."""
    rows = np.zeros((len(linear), 10))
    rows[:, 0] = linear
    rows[:, 4:7] = np.asarray(angular)[:, None]
    return rows


def unit_bodies(chain):
    """Parameter rows (1, N, 10) of unit bodies (Z = I): their mass matrix is (QJ)^T QJ."""
    return block_rows(np.ones(chain.bodies), np.ones(chain.bodies))[None]
