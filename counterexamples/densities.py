"""Random mass densities with a 3-D carrier, as JSON-able specs of :mod:`inertiaproof.model.density`.

``nonnegative_densities`` draws what Definition 1 admits: uniform primitive
solids in random poses, Bernstein-polynomial densities on boxes (with zero
coefficients, so rho vanishes on parts of the box), and mixtures of them,
from ordinary bodies to thin plates, needles and flat tetrahedra whose
thickness goes down to 10^-thinness of their size (near the boundary of
Theorem 1). ``signed_densities`` draws mixtures with a negative component
for the negative tests.
"""

from __future__ import annotations

import numpy as np
from hypothesis import assume
from hypothesis import strategies as st
from inertiaproof.counterexamples.inertias import log_uniform

from inertiaproof.model import solids

__all__ = [
    "bernstein_components", "components", "density_families", "nonnegative_densities", "quaternions",
    "signed_densities", "solid_components", "UNIT",
]

UNIT = st.floats(-1, 1, allow_nan=False)


@st.composite
def quaternions(draw):
    """A quaternion (w, x, y, z), not normalised; R(q) = M(q) / |q|^2 is a rotation."""
    q = [draw(UNIT) for _ in range(4)]
    return q if sum(x * x for x in q) > 1e-2 else [1.0, 0.0, 0.0, 0.0]


def _aspects(draw, count, thinness):
    """Per-axis factors in (10^-thinness, 1]: mostly ordinary, sometimes extreme."""
    extreme = log_uniform(10.0**-thinness, 1.0)
    return np.array([draw(st.one_of(st.floats(0.2, 1.0), extreme)) for _ in range(count)])


def _flat_tetrahedron(draw, scale, thinness):
    """Four vertices, the fourth moved toward the plane of the others by a factor down to 10^-thinness."""
    v = scale * np.array([[draw(UNIT) for _ in range(3)] for _ in range(4)])
    normal = np.cross(v[1] - v[0], v[2] - v[0])
    assume(np.linalg.norm(normal) > 1e-3 * scale * scale)
    normal /= np.linalg.norm(normal)
    height = (v[3] - v[0]) @ normal
    assume(abs(height) > 1e-2 * scale)
    t = draw(st.one_of(st.just(1.0), log_uniform(10.0**-thinness, 1.0)))
    v[3] -= (1.0 - t) * height * normal
    return v.ravel().tolist()


@st.composite
def solid_components(draw, thinness=8, mass=(1e-3, 1e3), size=(1e-3, 10.0), sign=1.0, shapes=solids.SHAPES):
    shape = draw(st.sampled_from(shapes))
    scale = draw(log_uniform(*size))
    if shape == "tetrahedron":
        dims = _flat_tetrahedron(draw, scale, thinness)
        try:
            solids.validate(shape, dims)
        except ValueError:
            assume(False)
    else:
        dims = (scale * _aspects(draw, solids.DIMS[shape], thinness)).tolist()
    return {
        "type": "solid", "shape": shape, "mass": sign * draw(log_uniform(*mass)), "dims": dims,
        "quaternion": draw(quaternions()), "position": [scale * draw(st.floats(-3, 3)) for _ in range(3)],
    }


@st.composite
def bernstein_components(draw, thinness=8, mass=(1e-3, 1e3), size=(1e-3, 10.0), max_degree=3, sign=1.0):
    """A Bernstein-polynomial density on a box; a drawn fraction of the coefficients is exactly 0.

    The coefficients come from a NumPy generator seeded by a drawn integer
    (cheap to draw; Hypothesis still varies and shrinks the seed).
    """
    scale = draw(log_uniform(*size))
    sides = scale * _aspects(draw, 3, thinness)
    shape = tuple(draw(st.integers(0, max_degree)) + 1 for _ in range(3))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    coef = rng.random(shape) * (rng.random(shape) >= draw(st.sampled_from([0.0, 0.3, 0.7])))
    if not coef.any():
        coef.flat[rng.integers(coef.size)] = 1.0
    total = draw(log_uniform(*mass))
    coef *= total * np.prod(shape) / (np.prod(sides) * coef.sum())
    return {
        "type": "bernstein_box", "sides": sides.tolist(), "coefficients": (sign * coef).tolist(),
        "quaternion": draw(quaternions()), "position": [scale * draw(st.floats(-3, 3)) for _ in range(3)],
    }


def components(thinness=8, sign=1.0):
    return st.one_of(solid_components(thinness=thinness, sign=sign), bernstein_components(thinness=thinness, sign=sign))


def nonnegative_densities(thinness=8, max_components=3):
    """Nonnegative Lebesgue densities with a 3-D carrier: one component or a mixture of up to ``max_components``."""
    return st.lists(components(thinness), min_size=1, max_size=max_components).map(lambda c: {"components": c})


def density_families(thinness=8):
    """The same densities split by family (each primitive, Bernstein boxes, mixtures), so a hunt can cover each."""
    single = lambda s: s.map(lambda c: {"components": [c]})  # noqa: E731
    families = {shape: single(solid_components(thinness=thinness, shapes=(shape,))) for shape in solids.SHAPES}
    families["bernstein_box"] = single(bernstein_components(thinness=thinness))
    families["mixture"] = st.lists(components(thinness), min_size=2, max_size=3).map(lambda c: {"components": c})
    return families


@st.composite
def signed_densities(draw, thinness=3):
    """A nonnegative density plus a component of negative mass: rho < 0 somewhere (not admitted by Definition 1)."""
    positive = draw(st.lists(components(thinness), min_size=1, max_size=2))
    return {"components": positive + [draw(components(thinness, sign=-1.0))]}
