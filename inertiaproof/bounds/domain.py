"""The configuration domain of a chain: the box over which Section 4's extremes are taken, and where certification stops."""

from __future__ import annotations

import json

import numpy as np

__all__ = [
    "bernstein_domain", "certification_obstacle", "chain_key", "derivative_factors", "free_coordinates",
    "search_box",
]




def certification_obstacle(chain):
    """Why no certified configuration bracket exists for this chain (None if one does).

    The first joint may slide without limits: QJ does not depend on its coordinate."""
    for k, joint in enumerate(chain.joints):
        if joint.coordinate.name != "identity" and k > 0:
            return f"joint {k + 1} maps its coordinate by {joint.coordinate.name!r}: QJ is no trigonometric polynomial"
        if joint.coordinate.name != "identity" and k == 0:
            return "the first joint's coordinate map is not the identity"
        if not joint.revolute and joint.limits is None and k > 0:
            return f"joint {k + 1} slides without limits: the configuration domain is unbounded"
    return None


def search_box(chain):
    """The configuration box: joint limits, one period for unlimited revolute joints, and one period from the lower
    limit for a revolute joint whose limits span more (example-robot-data's UR5: +-2 pi; every quantity bracketed is a function of
    cos q_j and sin q_j, so the box holds every value the limits allow, and it is half as wide)."""
    lo, hi = chain.coordinate_box()
    periodic = np.array([j.revolute and j.coordinate.name == "identity" for j in chain.joints], bool)
    return lo, np.where(periodic, np.minimum(hi, lo + 2 * np.pi), hi)


def bernstein_domain(chain):
    """Box over which the derivative inequalities hold: a full period for every revolute coordinate."""
    lo, hi = search_box(chain)
    revolute = np.array([j.revolute for j in chain.joints])
    return np.where(revolute, -np.pi, lo), np.where(revolute, np.pi, hi)


def free_coordinates(chain):
    """Coordinates QJ depends on: not the first joint's (it moves the whole chain rigidly; body twists are invariant)."""
    free = np.ones(chain.n, bool)
    if chain.joints[0].coordinate.name == "identity":
        free[0] = False
    return free


def derivative_factors(chain, lo, hi, degree):
    """c_j with sup|dp/dq_j| <= c_j sup|p|: Bernstein (degree) on a period, Markov (2 degree^2 / width) on an interval."""
    revolute = np.array([j.revolute for j in chain.joints])
    return np.where(revolute, float(degree), 2.0 * degree**2 / np.maximum(hi - lo, 1e-300))




def chain_key(chain):
    """The chain's content as a key: every joint's kind, axis, fixed transforms, coordinate map and limits."""
    return json.dumps(chain.to_data(), sort_keys=True)

