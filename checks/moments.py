"""EQ-moments: the closed-form moments of densities against integration (MassDistributionToInertialParam).

Three independent comparisons:

- symbolic: SymPy integrates each primitive solid in its canonical pose with
  symbolic dimensions, and the 1-D Bernstein moments, exactly; the closed
  forms evaluated on the same symbols must be identical;
- quadrature: solids and Bernstein boxes in random poses, and their unions
  and mixtures, by mapped tensor Gauss-Legendre rules (exact for these
  polynomial integrands up to rounding); the residual of each entry must lie
  below the rounding bound (N + 32) eps sum |terms| of an N-term sum;
- Monte Carlo: the pointwise density of a union and of an overlapping mixture,
  sampled uniformly; every entry within 6 standard errors.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from inertiaproof.checks.identities import all_of
from inertiaproof.symbolic import moments as symbolic_moments

from inertiaproof.model import density, quadrature, solids
from inertiaproof.result import Result, Verdict, quantity
from inertiaproof.suite.registry import check, replayer

__all__ = [
    "EPS", "eq_moments", "monte_carlo_part", "P_TWO_SIDED_6", "quadrature_part", "random_components",
    "replay_moments", "symbolic_part", "union_and_mixture", "Z_LIMIT",
]

EPS = np.finfo(float).eps
Z_LIMIT = 6.0
P_TWO_SIDED_6 = 1.973e-9  # P(|Z| > 6) for a standard normal Z


def symbolic_part(closed_form=solids.moments, max_degree=3):
    """Exact canonical moments (SymPy) against the closed forms on the same symbols."""
    mismatches, compared = [], 0
    for shape in solids.SHAPES:
        dims, mass, m, h, sigma = symbolic_moments.canonical_moments(shape)
        mc, hc, sc = closed_form(shape, mass, np.array(dims, dtype=object))
        for name, a, b in zip(["m", "h1", "h2", "h3"] + [f"Sigma{i}{j}" for i in range(1, 4) for j in range(1, 4)],
                              [m, *h, *sigma], [mc, *hc, *np.ravel(sc)]):
            compared += 1
            if sp.expand(a - b) != 0:
                mismatches.append({"shape": shape, "entry": name, "integrated": str(a), "closed_form": str(b)})
    for degree in range(max_degree + 1):
        side, integrated = symbolic_moments.bernstein_moments(degree)
        closed = density.bernstein_axis_moments(side, degree, sp.Integer(1))
        for j in range(3):
            for k in range(degree + 1):
                compared += 1
                if sp.expand(integrated[j][k] - closed[j][k]) != 0:
                    mismatches.append({"shape": f"bernstein degree {degree}", "entry": f"y^{j} B_{k}",
                                       "integrated": str(integrated[j][k]), "closed_form": str(closed[j][k])})
    evidence = {
        "method": "SymPy: exact iterated integration of rho [1, x, x x^T] over each canonical solid with symbolic "
                  "dimensions (tetrahedron: 12 symbolic vertex coordinates); 1-D Bernstein moments for degrees "
                  f"0..{max_degree}",
        "entries": quantity(compared, "count", "entries compared"),
        "mismatches": quantity(len(mismatches), "exact", "entries where integral and closed form differ"),
    }
    if mismatches:
        bad = mismatches[0]
        return Result("EQ-moments", Verdict.VIOLATED, f"{bad['shape']} {bad['entry']}: integral {bad['integrated']} "
                      f"!= closed form {bad['closed_form']}", evidence,
                      counterexample={"kind": "identity", "data": {"id": "EQ-moments", **bad}})
    return Result("EQ-moments", Verdict.HOLDS, f"closed forms equal the exact integrals ({compared} entries)", evidence)


def random_components(rng, per_shape=3):
    """Uniform solids of every shape and Bernstein boxes, in random poses away from the origin."""
    out = []
    for shape in solids.SHAPES:
        for _ in range(per_shape):
            scale = 10.0 ** rng.uniform(-2, 1)
            if shape == "tetrahedron":
                dims = scale * rng.normal(size=12)
            else:
                dims = scale * 10.0 ** rng.uniform(-1, 0, size=solids.DIMS[shape])
            out.append({"type": "solid", "shape": shape, "mass": 10.0 ** rng.uniform(-2, 2), "dims": dims.tolist(),
                        "quaternion": rng.normal(size=4).tolist(), "position": (3 * scale * rng.normal(size=3)).tolist()})
    for _ in range(2 * per_shape):
        scale = 10.0 ** rng.uniform(-2, 1)
        shape = tuple(rng.integers(1, 5, size=3))
        coef = rng.random(shape) * (rng.random(shape) < 0.7)
        coef.flat[0] += 0.1
        out.append({"type": "bernstein_box", "sides": (scale * 10.0 ** rng.uniform(-1, 0, size=3)).tolist(),
                    "coefficients": coef.tolist(), "quaternion": rng.normal(size=4).tolist(),
                    "position": (3 * scale * rng.normal(size=3)).tolist()})
    return out


def union_and_mixture():
    """A union of disjoint solids (a cone standing on a box) and an overlapping mixture."""
    union = {"components": [
        {"type": "solid", "shape": "box", "mass": 2.0, "dims": [0.4, 0.3, 0.2], "quaternion": [0.9, 0.1, -0.3, 0.2],
         "position": [0.5, -0.2, 0.1]},
        {"type": "solid", "shape": "cone", "mass": 0.7, "dims": [0.12, 0.5], "quaternion": [0.9, 0.1, -0.3, 0.2],
         "position": (np.array([0.5, -0.2, 0.1]) + density.rotation(np.array([0.9, 0.1, -0.3, 0.2])) @ [0, 0, 0.1]).tolist()},
    ]}
    mixture = {"components": [
        {"type": "solid", "shape": "ellipsoid", "mass": 1.5, "dims": [0.3, 0.2, 0.1], "quaternion": [1.0, 0.5, 0.2, 0.0],
         "position": [0.1, 0.2, 0.3]},
        {"type": "bernstein_box", "sides": [0.3, 0.4, 0.25], "coefficients": [[[0.0, 8.0], [3.0, 1.0]], [[5.0, 0.0], [2.0, 9.0]]],
         "quaternion": [0.3, -0.2, 0.8, 0.1], "position": [0.15, 0.1, 0.25]},
        {"type": "solid", "shape": "tetrahedron", "mass": 0.4, "dims": [0, 0, 0, 0.3, 0, 0, 0, 0.3, 0, 0, 0, 0.3],
         "quaternion": [1, 0, 0, 0], "position": [0.0, 0.1, 0.2]},
    ]}
    return {"union": union, "mixture": mixture}


def _flat(moments):
    m, h, sigma = moments
    return np.concatenate([[m], np.ravel(h), np.ravel(sigma)])


def quadrature_part(densities, closed_form=density.moments):
    """Closed forms against mapped Gauss-Legendre quadrature; residuals relative to the sums of |terms|."""
    worst, worst_name, rows = 0.0, None, {}
    for name, spec in densities.items():
        closed = _flat(closed_form(spec))
        value, size, nodes = quadrature.moments(spec)
        relative = np.abs(closed - _flat(value)) / np.maximum(_flat(size), np.finfo(float).tiny)
        bound = (nodes + 32) * EPS
        f_residual = (np.linalg.norm(closed - _flat(value)) / np.linalg.norm(closed))
        rows[name] = (float(relative.max() / bound), float(f_residual))
        if relative.max() / bound > worst:
            worst, worst_name = float(relative.max() / bound), name
    evidence = {
        "densities": quantity(len(densities), "count", "solids of every shape and Bernstein boxes in random poses, "
                                                       "a union and a mixture"),
        "worst_ratio": quantity(worst, "ratio", f"max over entries of |closed - quadrature| / ((N + 32) eps sum|terms|) "
                                               f"({worst_name}); <= 1 required"),
        "largest_relative_residual": quantity(max(r[1] for r in rows.values()), "residual",
                                              "max ||closed - quadrature|| / ||closed|| over (m, h, Sigma)"),
        "per_density": {k: {"ratio_to_bound": v[0], "relative_residual": v[1]} for k, v in rows.items()},
    }
    if worst > 1.0:
        spec = densities[worst_name]
        return Result("EQ-moments", Verdict.VIOLATED, f"{worst_name}: closed form and quadrature differ by {worst:.3g} "
                      "times the rounding bound", evidence,
                      counterexample={"kind": "moments", "data": {"density": spec, "name": worst_name}})
    return Result("EQ-moments", Verdict.HOLDS, f"{len(densities)} densities agree with quadrature to rounding "
                  f"(worst {worst:.2g} of the bound)", evidence)


def monte_carlo_part(densities, rng, samples, closed_form=density.moments):
    """Closed forms against Monte Carlo integration of the pointwise density (union, overlapping mixture)."""
    worst, worst_name, entries, detectable = 0.0, None, 0, 0.0
    for name, spec in densities.items():
        estimate, error = quadrature.monte_carlo(spec, samples, rng)
        closed = _flat(closed_form(spec))
        diff = np.abs(closed - _flat(estimate))
        se = _flat(error)
        detectable = max(detectable, float(np.max(Z_LIMIT * se / np.maximum(np.abs(closed), np.finfo(float).tiny))))
        z = np.where(se > 0, diff / np.where(se > 0, se, 1.0), np.where(diff > 0, np.inf, 0.0))
        entries += z.size
        if z.max() > worst:
            worst, worst_name = float(z.max()), name
    evidence = {
        "samples": quantity(samples, "count", "uniform points per density in a box around its carrier (fixed seed)"),
        "largest_z": quantity(worst, "estimate", f"max |closed - Monte Carlo| / standard error ({worst_name})"),
        "z_limit": quantity(Z_LIMIT, "tolerance", "a z-score above it is a violation"),
        "detectable_error": quantity(detectable, "tolerance", "relative error of an entry this comparison is sure to "
                                                              "catch: 6 standard errors over |entry| (the largest)"),
        "false_alarm": quantity(entries * P_TWO_SIDED_6, "error_probability",
                                "probability that a correct closed form exceeds the limit (normal approximation, union bound)"),
    }
    if worst > Z_LIMIT:
        return Result("EQ-moments", Verdict.VIOLATED, f"{worst_name}: closed form {worst:.1f} standard errors from "
                      "Monte Carlo", evidence,
                      counterexample={"kind": "moments", "data": {"density": densities[worst_name], "name": worst_name}})
    return Result("EQ-moments", Verdict.HOLDS, f"union and mixture within {worst:.1f} standard errors of Monte Carlo",
                  evidence)


@check("EQ-moments")
def eq_moments(ctx, closed_form=density.moments, closed_solid=solids.moments):
    rng = ctx.rng("EQ-moments")
    pieces = {f"{c.get('shape', c['type'])}#{i}": density.parse({"components": [c]})
              for i, c in enumerate(random_components(rng, max(3, ctx.profile.examples // 20)))}
    pieces.update({k: density.parse(v) for k, v in union_and_mixture().items()})
    ctx.progress("symbolic integration of the canonical solids")
    symbolic = symbolic_part(closed_solid, ctx.profile.bernstein_degree)
    ctx.progress(f"quadrature of {len(pieces)} densities")
    quad = quadrature_part(pieces, closed_form)
    table = quad.evidence.pop("per_density")
    written = ctx.outputs.write_data("eq-moments-quadrature.json", {"columns": ["density", "ratio_to_bound", "relative_residual"],
                                                            "rows": [[k, v["ratio_to_bound"], v["relative_residual"]]
                                                                     for k, v in table.items()]})
    if written:
        quad.evidence["per_density_table"] = written
    mc = monte_carlo_part({k: pieces[k] for k in ("union", "mixture")}, rng, ctx.profile.moment_samples, closed_form)
    return all_of("EQ-moments", [("symbolic", symbolic), ("quadrature", quad), ("monte carlo", mc)],
                  "m, h, I of uniform solids, Bernstein boxes, unions and mixtures in any pose")


@replayer("moments")
def replay_moments(data, ctx):
    """Closed form against quadrature for the saved density, with the current code."""
    spec = density.parse(data["density"], "counterexample density")
    return quadrature_part({data.get("name", "density"): spec})
