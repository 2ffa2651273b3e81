"""Mutation testing owned by the project: is every mutant of the core killed by ``inertiaproof run --profile ci``?

    python bench/mutation.py [--only ID ...] [--full] [--check] [--out FILE] [--keep DIR]

Each mutant is the kind of bug a real edit brings (a sign in Z, the 1/2 in Sigma,
a dropped M(q, Thetadot) qd, a swapped Christoffel index, a regressor column
order, a box's moments, a loosened classifier, ...), given as a literal
``pattern`` and its ``replacement`` in a named file of the repository, so that it
is easy to re-target when that file changes. The runner copies the package
into a temporary staging tree laid out as the installed package (the
``package-dir`` mapping of pyproject.toml) and, per mutant:

1. applies the mutant to the staged file (never to the working tree); a
   pattern that does not occur exactly once makes the mutant ``stale``;
2. runs ``inertiaproof gate --update`` there, so that the derivation lockfile
   cannot be what kills it;
3. runs ``inertiaproof run --profile ci`` there (or the mutant's own profile; ``--only``
   the checks of the mutant's reach, unless ``--full``): exit 1 (something VIOLATED, or a check
   crashed) kills the mutant, exit 3 (INCONCLUSIVE only) does not, exit 0 lets it
   survive;
4. restores the file and the lockfile.

A baseline run of the unmutated tree must exit 0 first. Prints one line per
mutant (killed / survived / inconclusive / stale, with the checks that killed
it) and writes ``bench/results/mutation.json``. A mutant that cannot change
behaviour is kept in the list with ``equivalent`` saying why. ``--check`` only
verifies that every pattern still matches. Timings are those of this machine.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from dataclasses import asdict, dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCHEMA = "inertiaproof.mutation/1"
TIMEOUT = 600  # seconds per command; a mutant that makes the run hang past it is killed ("timeout")


@dataclass(frozen=True)
class Mutant:
    id: str
    area: str  # model, dynamics, bounds, symbolic, classifier
    file: str  # path in the repository
    pattern: str  # literal text that occurs exactly once in the file
    replacement: str
    what: str  # the bug it stands for
    reach: tuple = ()  # catalog IDs or check names to run (--only); empty: the whole ci run
    equivalent: str = ""  # why it cannot change behaviour, if it cannot
    profile: str = "ci"  # the run's profile (the chain split runs in deep only)


SECTION2 = ("EQ-moments", "EQ-schur", "EQ-triangle", "Def1/Thm1-suff", "Thm1-nec", "Thm1-boundary", "Rem2")
EQUATION = ("GRE", "GRE-physics", "Prop1", "Prop2")
BOUNDS = ("Def2", "CX-normal", "CX-sphere", "Def3", "Thm2", "Lem1", "Asm2/Lem2", "Thm3", "Cor1", "Cor2", "Thm4",
          "EQ-acc", "Asm3/Thm5")

MUTANTS = (
    # -- the physical model ------------------------------------------------------------------------------------
    Mutant("model-sigma-half", "model", "inertiaproof/model/inertia.py",
           "return 0.5 * _trace_identity(inertia) - inertia", "return _trace_identity(inertia) - inertia",
           "the 1/2 of Sigma = tr(I)/2 I3 - I dropped", SECTION2),
    Mutant("model-inverse-trace", "model", "inertiaproof/model/inertia.py",
           "return _trace_identity(sigma) - sigma", "return 0.5 * _trace_identity(sigma) - sigma",
           "I = tr(Sigma) I3 - Sigma with a stray 1/2", SECTION2),
    Mutant("model-z-sign", "model", "inertiaproof/model/inertia.py",
           "minus_s = -skew(phi[..., 1:4])", "minus_s = skew(phi[..., 1:4])", "the sign of S(h) in the numeric Z",
           EQUATION + ("Thm2", "Thm3")),
    Mutant("model-z-transpose", "model", "inertiaproof/model/inertia.py",
           "z[..., 3:, :3] = np.swapaxes(minus_s, -1, -2)", "z[..., 3:, :3] = minus_s",
           "Z's lower-left block -S(h) instead of -S(h)^T", EQUATION + ("Thm2",)),
    Mutant("model-com-inertia", "model", "inertiaproof/model/inertia.py",
           "return inertia - np.swapaxes(s, -1, -2) @ s / m[..., None, None]",
           "return inertia + np.swapaxes(s, -1, -2) @ s / m[..., None, None]",
           "I_CoM = I + S(h)^T S(h)/m (parallel axis theorem the wrong way)", SECTION2 + ("GRE-physics",)),
    Mutant("model-urdf-parallel-axis", "model", "inertiaproof/model/inertia.py",
           "inertia = ic + mass[..., None, None] * (np.swapaxes(s, -1, -2) @ s)",
           "inertia = ic - mass[..., None, None] * (np.swapaxes(s, -1, -2) @ s)",
           "URDF inertia moved to the link frame with the wrong sign", SECTION2 + EQUATION),
    Mutant("model-box-moments", "model", "inertiaproof/model/solids.py",
           "return mass * np.diag(dims**2) / 12, zero", "return mass * np.diag(dims**2) / 6, zero",
           "the box's second moments m a^2/6 instead of m a^2/12", ("EQ-moments", "Def1/Thm1-suff", "Thm1-nec")),
    Mutant("model-ellipsoid-moments", "model", "inertiaproof/model/solids.py",
           "if shape == \"ellipsoid\":\n        return mass * np.diag(dims**2) / 5, zero",
           "if shape == \"ellipsoid\":\n        return mass * np.diag(dims**2) / 3, zero",
           "the ellipsoid's second moments m a^2/3 instead of m a^2/5", ("EQ-moments", "Def1/Thm1-suff", "Thm1-nec")),
    Mutant("model-cylinder-moments", "model", "inertiaproof/model/solids.py",
           "return mass * np.diag([3 * r * r, 3 * r * r, h * h]) / 12, zero",
           "return mass * np.diag([3 * r * r, 3 * r * r, h * h]) / 6, zero",
           "the cylinder's second moments doubled", ("EQ-moments", "Def1/Thm1-suff")),
    Mutant("model-rod-moment", "model", "inertiaproof/model/degenerate.py",
           "np.outer(d, d) / 3)", "np.outer(d, d) / 4)", "a uniform rod's second moment with 1/4 for 1/3",
           ("Thm1-boundary", "EQ-moments")),
    Mutant("model-realise-box", "model", "inertiaproof/model/realise.py",
           'FACTOR = {"ellipsoid": 5.0, "box": 12.0}', 'FACTOR = {"ellipsoid": 5.0, "box": 6.0}',
           "the realising box's sides sqrt(6 sigma/m) for sqrt(12 sigma/m)", ("Thm1-nec",)),
    Mutant("model-moving-mass-psi", "model", "inertiaproof/dynamics/trajectory.py",
           "return (np.concatenate([m * cd, m * np.cross(c, cd)], -1),",
           "return (np.concatenate([m * cd, m * np.cross(cd, c)], -1),",
           "psi_l of a moving mass with x cross xdot reversed", EQUATION + ("EQ-acc", "Asm3/Thm5")),
    Mutant("model-smoothstep-acceleration", "model", "inertiaproof/dynamics/trajectory.py",
           "k * k * (6 - 12 * x) * inside", "k * k * (6 - 6 * x) * inside",
           "a smoothstep ramp's second derivative", ("GRE-physics", "Prop1", "EQ-acc", "Thm4")),
    Mutant("model-rate-bound", "model", "inertiaproof/dynamics/trajectory.py",
           '"smoothstep": 1.5, "smootherstep": 1.875', '"smoothstep": 1.5, "smootherstep": 1.5',
           "sup |s'| of a smootherstep ramp understated", BOUNDS + ("GRE-physics",)),
    # -- the dynamics ------------------------------------------------------------------------------------------
    Mutant("dyn-christoffel-sign", "dynamics", "inertiaproof/dynamics/terms.py",
           "np.moveaxis(d, -1, -3) - np.moveaxis(d, -3, -1))", "np.moveaxis(d, -1, -3) + np.moveaxis(d, -3, -1))",
           "the Christoffel symbol's third term with the wrong sign", EQUATION),
    Mutant("dyn-christoffel-index", "dynamics", "inertiaproof/dynamics/terms.py",
           "return 0.5 * (np.swapaxes(d, -2, -1) + np.moveaxis(d, -1, -3) - np.moveaxis(d, -3, -1))",
           "return 0.5 * (np.swapaxes(d, -2, -1) + np.moveaxis(d, -1, -3) - np.swapaxes(np.moveaxis(d, -3, -1), -2, -1))",
           "a swapped Christoffel index: the third term's last two axes exchanged", EQUATION),
    Mutant("dyn-coriolis-transpose", "dynamics", "inertiaproof/dynamics/terms.py",
           'return np.swapaxes(np.einsum("...ijk,...i->...jk", christoffel(dm), qd), -1, -2)',
           'return np.einsum("...ijk,...i->...jk", christoffel(dm), qd)', "C transposed", EQUATION),
    Mutant("dyn-gravity-sign", "dynamics", "inertiaproof/dynamics/terms.py",
           'return -np.einsum("...lri,...lr->...i", b,', 'return np.einsum("...lri,...lr->...i", b,',
           "G with the wrong sign of gravity", EQUATION),
    Mutant("dyn-drop-m-thetadot", "dynamics", "inertiaproof/dynamics/terms.py",
           "lhs_matrix = lhs_matrix + mass_matrix(qj, theta_dot)", "lhs_matrix = lhs_matrix + 0 * mass_matrix(qj, theta_dot)",
           "the M(q, Thetadot) qd term dropped from the equation", EQUATION + ("stability",)),
    Mutant("dyn-h-symmetric", "dynamics", "inertiaproof/dynamics/terms.py",
           "return a - np.swapaxes(a, -1, -2)", "return a + np.swapaxes(a, -1, -2)",
           "H = A + A^T instead of A - A^T", EQUATION + ("Asm3/Thm5",)),
    Mutant("dyn-psidot-half", "dynamics", "inertiaproof/dynamics/terms.py",
           'return np.einsum("...pk,...p->...k", qj, psi_dot)', 'return 0.5 * np.einsum("...pk,...p->...k", qj, psi_dot)',
           "J^T Q^T Psidot halved", EQUATION + ("EQ-acc",)),
    Mutant("dyn-mass-partials", "dynamics", "inertiaproof/dynamics/terms.py",
           "return half + np.swapaxes(half, -3, -2)", "return 2 * half",
           "dM/dq without its symmetrisation", EQUATION),
    Mutant("dyn-mdot-rates", "dynamics", "inertiaproof/dynamics/terms.py",
           'return np.einsum("...kji,...i->...kj", dm, q_dot) + mass_matrix(qj, theta_dot)',
           'return np.einsum("...kji,...i->...kj", dm, q_dot)', "Mdot without its Thetadot part", ("Prop1",)),
    Mutant("dyn-coriolis-force", "dynamics", "inertiaproof/dynamics/terms.py",
           'return np.einsum("...lrk,...lr->...k", bd - d, w)', 'return np.einsum("...lrk,...lr->...k", bd + d, w)',
           "C qd of generalized_forces (coriolis_force) with the gradient of qd^T M qd added, not subtracted",
           EQUATION),
    Mutant("dyn-regressor-columns", "dynamics", "inertiaproof/dynamics/regressors.py",
           "UNIT_Z = spatial_inertia(np.eye(10))", "UNIT_Z = spatial_inertia(np.eye(10)[[0, 1, 2, 3, 4, 5, 6, 8, 7, 9]])",
           "the regressor's columns of I12 and I23 swapped", ("Prop2",)),
    Mutant("dyn-coriolis-regressor", "dynamics", "inertiaproof/dynamics/regressors.py",
           "return 0.5 * (t1 + t2 - t3)", "return 0.5 * (t1 - t2 - t3)", "the Coriolis regressor's second term sign",
           ("Prop2",)),
    Mutant("dyn-cubic-rate", "dynamics", "inertiaproof/dynamics/chain.py",
           '"cubic": (lambda q: q**3, lambda q: 3 * q**2)', '"cubic": (lambda q: q**3, lambda q: 2 * q**2)',
           "a wrong rate factor of the cubic coordinate map", ("Def2", "CX-normal", "Prop1")),
    Mutant("dyn-arctan-rate", "dynamics", "inertiaproof/dynamics/chain.py",
           '"arctan": (lambda q: np.arctan(q), lambda q: 1 / (1 + q**2))',
           '"arctan": (lambda q: np.arctan(q), lambda q: 1 / (1 + q**2) ** 2)',
           "a wrong rate factor of the arctan coordinate map", ("Def2", "CX-normal", "Prop1")),
    Mutant("dyn-twist-map", "dynamics", "inertiaproof/dynamics/twists.py",
           "x[:3, 3:] = -r.T @ skew(shift)", "x[:3, 3:] = r.T @ skew(shift)",
           "the twist map of a fixed transform with the lever arm's sign flipped", EQUATION + ("Def2",)),
    Mutant("dyn-slide-twist", "dynamics", "inertiaproof/dynamics/twists.py",
           "twists[0] += motion.value * twists[4]", "twists[0] -= motion.value * twists[4]",
           "a slide carries twists with the wrong lever", ("Def2", "Prop1", "Prop2", "Asm2/Lem2")),
    Mutant("dyn-complex-step", "dynamics", "inertiaproof/dynamics/chain.py",
           "out[..., part] = blocks / COMPLEX_STEP", "out[..., part] = blocks / (2 * COMPLEX_STEP)",
           "dQJ/dq off by a factor 2 (the complex step's scale)", EQUATION + ("Def2",)),
    Mutant("dyn-composite-rate", "dynamics", "inertiaproof/dynamics/composite.py",
           "            m[l, l] *= motions[l].rate\n", "",
           "the composite mass matrix's diagonal misses one rate factor", ("Def2", "CX-normal", "Lem1", "Cor1")),
    # -- the bounds ------------------------------------------------------------------------------------------
    Mutant("bounds-theorem3-factor", "bounds", "inertiaproof/bounds/formulas.py",
           "return KEY_STEP_UPPER * zeta * s**2", "return zeta * s**2",
           "Theorem 3's constant without its factor 2", BOUNDS),
    Mutant("bounds-theorem2-side", "bounds", "inertiaproof/bounds/constants.py",
           "formulas.alpha1_z(z_min, max(gamma.lower, 0.0))", "formulas.alpha1_z(z_min, gamma.upper)",
           "Theorem 2's certified constant from the observed side of inf sigma_min(QJ)^2", BOUNDS),
    Mutant("bounds-alpha1-tenfold", "bounds", "inertiaproof/bounds/formulas.py",
           "    return xi * gamma\n", "    return 10 * xi * gamma\n", "Theorem 2's alpha1 overstated tenfold", BOUNDS),
    Mutant("bounds-alpha1-z-tenfold", "bounds", "inertiaproof/bounds/formulas.py",
           "    return z_min * gamma\n", "    return 10 * z_min * gamma\n",
           "Theorem 2's certified constant (at the level of Z) overstated tenfold", BOUNDS),
    Mutant("bounds-alpha2-z-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "    return z_max * s**2\n", "    return z_max * s**2 / 10\n",
           "Theorem 3's certified constant (at the level of Z) a tenth", BOUNDS),
    Mutant("bounds-chi-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "return np.sqrt(69.0 * bodies) * mu * s**2", "return np.sqrt(69.0 * bodies) * mu * s**2 / 10",
           "Theorem 4's chi a tenth", BOUNDS),
    Mutant("bounds-chi-sharp-factor", "bounds", "inertiaproof/bounds/formulas.py",
           "return KEY_STEP_UPPER * mu * s**2", "return mu * s**2",
           "Theorem 4's certified constant without the key step's factor 2", BOUNDS),
    Mutant("bounds-chi-z-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "    return zdot * s**2\n", "    return zdot * s**2 / 10\n",
           "Theorem 4's certified constant (at the level of Z) a tenth", BOUNDS),
    Mutant("bounds-acceleration-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "    return dpsi * s\n", "    return dpsi * s / 10\n", "(LumpedAccelerationBounding)'s constant a tenth",
           BOUNDS),
    Mutant("bounds-theorem5-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "return np.sqrt(rows) * psi * y", "return np.sqrt(rows) * psi * y / 10", "Theorem 5's constant a tenth",
           BOUNDS),
    Mutant("bounds-theorem5-sharp-tenth", "bounds", "inertiaproof/bounds/formulas.py",
           "    return psi * y_rss\n", "    return psi * y_rss / 10\n",
           "Theorem 5's certified constant (Cauchy-Schwarz before the max) a tenth", BOUNDS),
    Mutant("bounds-remainder", "bounds", "inertiaproof/bounds/branch.py",
           "rem = 0.5 * rho**2", "rem = 0.05 * rho**2", "the Taylor remainder of a box understated tenfold", BOUNDS,
           "not in principle, but on every family the suite brackets: bracket_extreme clips the certified side by the "
           "best value found (certified <= best for an inf, >= best for a sup), and sampling plus local search finds "
           "the extremes of these degree-1 and degree-2 trigonometric polynomials, so a box bound short of its "
           "remainder never decides; with one sample, budgets of 0.8-12 rounds and three seeds on the 2R, 3R and UR5 chains "
           "the mutated brackets never undercut 50000 independent samples. Killing it needs the box bound itself, "
           "which is a closure inside the vertex bracket (bounds/branch.py, issue 12)"),
    Mutant("bounds-vertex-allowance", "bounds", "inertiaproof/bounds/families.py",
           "return (vals.max(1) + allowance).max(1)", "return (vals.max(1) - allowance).max(1)",
           "the rounding allowance of a convex vertex bound applied inwards", BOUNDS),
    Mutant("bounds-normality-floor", "bounds", "inertiaproof/bounds/apriori.py",
           "diag[l] = size * (1 - 8 * EPS)", "diag[l] = 2 * size",
           "the block-triangular normality floor from a doubled diagonal", BOUNDS),
    Mutant("bounds-spectral", "bounds", "inertiaproof/bounds/spectral.py",
           'return s[..., 0] if self is Spectral.SMAX else s[..., -1]',
           'return s[..., -1] if self is Spectral.SMAX else s[..., 0]',
           "sigma_max and sigma_min swapped", BOUNDS),
    Mutant("bounds-acceleration-peak", "bounds", "inertiaproof/bounds/time.py",
           '"smoothstep": 6.0,', '"smoothstep": 3.0,', "sup |s''| of a smoothstep ramp halved",
           BOUNDS + ("GRE-physics",)),
    Mutant("bounds-profile-range", "bounds", "inertiaproof/bounds/time.py",
           "return min(s0, s1), max(s0, s1)", "return s0, s0", "a ramp's range taken as its start value", BOUNDS),
    Mutant("bounds-key-step-factor", "bounds", "inertiaproof/bounds/time.py",
           "factor = 2.0 if build is spatial_inertia else 1.0", "factor = 1.0",
           "||Z(F)|| <= ||F|| for a moving mass (the key step's factor 2 dropped)", BOUNDS),
    # the three prover bugs of issue 25: the prover then claims more than it proved; the independent checker refutes
    # the certificate or cannot re-prove it
    Mutant("bounds-pivot-turn-loss", "bounds", "inertiaproof/bounds/pivots.py",
           "lower = before.T @ (centre - loss) @ before", "lower = before.T @ (centre + loss) @ before",
           "a joint's turn loss added to the pivot bound instead of subtracted", ("Def2", "Thm2", "Lem1")),
    Mutant("bounds-partition-gap", "bounds", "inertiaproof/bounds/pivot_search.py",
           "pending.append((np.concatenate([c - shift, c + shift])",
           "pending.append((np.concatenate([c - 1.5 * shift, c + 1.5 * shift])",
           "a box's halves moved apart: the middle of the box is covered by neither", ("Def2", "Thm2", "Lem1")),
    Mutant("bounds-split-sign", "bounds", "inertiaproof/bounds/interface.py",
           "armature = (lambda c: np.full((len(c), stack), -gamma))",
           "armature = (lambda c: np.full((len(c), stack), gamma))",
           "the chain split proves M + gamma I > 0 instead of M - gamma I > 0", ("Def2",), profile="deep"),
    # -- the symbolic derivations ------------------------------------------------------------------------------
    Mutant("sym-z-sign", "symbolic", "symbolic/lagrangian.py",
           "+ [-s[i][j] for j in range(3)] for i in range(3)]", "+ [s[i][j] for j in range(3)] for i in range(3)]",
           "the sign of S(h) in the symbolic Z (both routes through Z share it)", ("GRE", "GRE-F", "Prop1", "Prop2")),
    Mutant("sym-twist-sign", "symbolic", "symbolic/kinematics.py",
           "ang = vee(matmul(rt, dr))", "ang = [-x for x in vee(matmul(rt, dr))]",
           "the symbolic body angular velocity with the wrong sign", ("GRE", "GRE-F", "Prop1", "Prop2")),
    Mutant("sym-vee", "symbolic", "symbolic/kinematics.py",
           "return [w[2][1], w[0][2], w[1][0]]", "return [w[2][1], w[2][0], w[1][0]]",
           "vee reads a wrong entry of a skew matrix", ("GRE", "Prop1")),
    Mutant("sym-cubic-rate", "symbolic", "symbolic/jets.py",
           '"cubic": ((0, 0, 0, 1), (0, 0, 3)),', '"cubic": ((0, 0, 0, 1), (0, 0, 2)),',
           "a wrong rate factor of the symbolic cubic coordinate map", ("GRE", "Prop1")),
    Mutant("sym-sine-derivative", "symbolic", "symbolic/jets.py",
           "images.setdefault(c, []).append((-coeff, {s: 1, **extra, **qd}))",
           "images.setdefault(c, []).append((coeff, {s: 1, **extra, **qd}))",
           "d/dq cos q = +sin q in the jet calculus", ("GRE", "Prop1")),
    Mutant("sym-potential-sign", "symbolic", "symbolic/lagrangian.py",
           "total -= sum((gi * x for gi, x in zip(g, moment)), jets.zero)",
           "total += sum((gi * x for gi, x in zip(g, moment)), jets.zero)",
           "the symbolic potential with the wrong sign of gravity", ("GRE", "Prop2")),
    Mutant("sym-christoffel", "symbolic", "symbolic/robotics_equation.py",
           "(d[i][k][j] + d[j][k][i] - d[k][i][j]) / 2", "(d[i][k][j] + d[j][k][i] + d[k][i][j]) / 2",
           "the symbolic Christoffel symbol's third term with the wrong sign", ("GRE", "Prop1", "Prop2")),
    Mutant("sym-christoffel-transposed-partial", "symbolic", "symbolic/robotics_equation.py",
           "(d[i][k][j] + d[j][k][i] - d[k][i][j]) / 2", "(d[i][k][j] + d[j][k][i] - d[k][j][i]) / 2",
           "the symbolic Christoffel symbol reads dM_ji/dq_k for dM_ij/dq_k", ("GRE", "Prop1", "Prop2"),
           "mass_matrix_partials returns d[k] as a symmetric matrix (one entry per upper-triangle pair, mirrored), so "
           "d[k][j][i] is the same polynomial as d[k][i][j]: no number changes"),
    Mutant("sym-h-symmetric", "symbolic", "symbolic/robotics_equation.py",
           "return tuple(tuple(a[k][j] - a[j][k] for j in range(n)) for k in range(n))",
           "return tuple(tuple(a[k][j] + a[j][k] for j in range(n)) for k in range(n))",
           "the symbolic H = A + A^T", ("GRE", "Prop1")),
    Mutant("sym-drop-rates", "symbolic", "symbolic/robotics_equation.py",
           "M_rates=mass_matrix_at_rates(calc, m),", "M_rates=tuple(tuple(0 * x for x in row) for row in m),",
           "M(q, Thetadot) dropped from the symbolic paper form", ("GRE", "GRE-F")),
    # -- the classifier ------------------------------------------------------------------------------------------
    Mutant("classifier-loose", "classifier", "inertiaproof/model/consistency.py",
           "verdict = np.where(positive & (eig[:, 0] > 0), CONSISTENT, INCONSISTENT)",
           "verdict = np.where(positive & (eig[:, 0] > -1e-6 * scale), CONSISTENT, INCONSISTENT)",
           "rows inconsistent by 1e-6 relative accepted as consistent", SECTION2),
    Mutant("classifier-no-fallback", "classifier", "inertiaproof/model/consistency.py",
           "RESOLUTION = 64.0", "RESOLUTION = 0.0", "no exact decision below the float resolution", SECTION2),
    Mutant("classifier-boundary", "classifier", "inertiaproof/model/consistency.py",
           "    if kind == \"psd\":\n        return DEGENERATE, rank", "    if kind == \"psd\":\n        return CONSISTENT, -1",
           "a singular f >= 0 (point, line, plane) called consistent", SECTION2),
    Mutant("classifier-zero-mass", "classifier", "inertiaproof/model/consistency.py",
           "positive = (mass > 0) & ~invalid", "positive = (mass >= 0) & ~invalid", "a massless row allowed through",
           SECTION2,
           "with m = 0 the Schur complement divides by zero: h h^T / m is inf or nan, so Sigma_CoM's eigenvalues "
           "are nan, the row counts as unresolved and is decided exactly, where m <= 0 is inconsistent with the "
           "reason 'mass <= 0'"),
    Mutant("classifier-second-eigenvalue", "classifier", "inertiaproof/model/consistency.py",
           "verdict = np.where(positive & (eig[:, 0] > 0), CONSISTENT, INCONSISTENT)",
           "verdict = np.where(positive & (eig[:, 1] > 0), CONSISTENT, INCONSISTENT)",
           "the sign of the middle eigenvalue of Sigma_CoM decides", SECTION2),
    Mutant("classifier-narrow-band", "classifier", "inertiaproof/model/consistency.py",
           "~(np.abs(eig[:, 0]) > RESOLUTION * EPS * scale)", "~(np.abs(eig[:, 0]) > EPS * EPS * scale)",
           "the exact fallback only within eps^2 of the boundary", SECTION2),
    Mutant("classifier-schur", "classifier", "inertiaproof/model/consistency.py",
           "s11, s22, s33 = half_tr - i11 - h1 * h1 * inv_m,", "s11, s22, s33 = half_tr - i11 - h1 * h1 * inv_m / 2,",
           "a wrong Schur complement entry (h1^2/(2m))", SECTION2),
    Mutant("classifier-sylvester", "classifier", "inertiaproof/model/exact.py",
           "if all(minors[tuple(range(k))] > 0 for k in range(1, n + 1)):",
           "if all(minors[tuple(range(k))] >= 0 for k in range(1, n + 1)):",
           "exact definiteness: positive definite on nonnegative leading minors", SECTION2),
)


# -- staging ---------------------------------------------------------------------------------------------------

def package_dirs(root):
    """{package name: source folder} from pyproject.toml's package-dir mapping (the package itself first)."""
    mapping = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]["package-dir"]
    return dict(sorted(mapping.items(), key=lambda item: item[0].count(".")))


def stage(root, staging):
    """Copy the package into staging as it is installed; returns {repository folder: staged folder}."""
    folders = {}
    for package, source in package_dirs(root).items():
        target = staging.joinpath(*package.split("."))
        shutil.copytree(root / source, target, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        folders[source] = target
    return folders


def staged_path(folders, file):
    """The staged copy of a repository file (the longest matching package folder)."""
    source = max((s for s in folders if file.startswith(s.rstrip("/") + "/")), key=len)
    return folders[source] / file[len(source.rstrip("/")) + 1:]


def matches(root, mutant):
    path = root / mutant.file
    return path.read_text().count(mutant.pattern) if path.is_file() else 0


# -- running -----------------------------------------------------------------------------------------------------

def inertiaproof(args, staging, cache, work):
    """(exit status, seconds, stderr tail) of ``python -m inertiaproof ARGS`` on the staged package."""
    env = dict(os.environ, PYTHONPATH=str(staging), INERTIAPROOF_CACHE=str(cache), PYTHONDONTWRITEBYTECODE="1")
    start = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "inertiaproof", *args], cwd=work, env=env, capture_output=True,
                              text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - start, f"timed out after {TIMEOUT} s"
    return done.returncode, time.perf_counter() - start, done.stderr.strip()[-400:]


def run_suite(staging, cache, work, only, profile="ci"):
    """The run (``profile``) on the staged package: (exit status, seconds, {verdict: [check names]}, stderr tail)."""
    out = work / "out"
    shutil.rmtree(out, ignore_errors=True)
    args = ["run", "--profile", profile, "--quiet", "--out", str(out), "--counterexamples", str(work / "found")]
    code, seconds, err = inertiaproof(args + (["--only", *only] if only else []), staging, cache, work)
    verdicts = {}
    results = out / "results.json"
    if results.is_file():
        for r in json.loads(results.read_text())["checks"]:
            key = "CRASHED" if r["evidence"].get("crashed") else r["verdict"]
            verdicts.setdefault(key, []).append(r["check"])
    return code, seconds, verdicts, err


def judge(mutant, staging, folders, cache, work, full):
    """Apply, update the lockfile, run, restore: the mutant's row of the kill table."""
    row = {**asdict(mutant), "reach": list(mutant.reach)}
    path = staged_path(folders, mutant.file)
    original = path.read_text() if path.is_file() else ""
    count = original.count(mutant.pattern)
    if count != 1:
        return {**row, "status": "stale", "why": f"the pattern occurs {count} times in {mutant.file}, not once"}
    lock = staged_path(folders, "symbolic/derivations.lock.json")
    locked = lock.read_text()
    try:
        path.write_text(original.replace(mutant.pattern, mutant.replacement))
        gate_code, gate_s, gate_err = inertiaproof(["gate", "--update", "--quiet"], staging, cache, work)
        code, seconds, verdicts, err = run_suite(staging, cache, work, () if full else mutant.reach, mutant.profile)
    finally:
        path.write_text(original)
        lock.write_text(locked)
    killers = verdicts.get("VIOLATED", []) + [f"{name} (crashed)" for name in verdicts.get("CRASHED", [])]
    if code is None:
        status, killers = "killed", ["timeout"]
    elif code == 1:
        status = "killed"
        killers = killers or [f"the run failed without results: {err}"]
    elif code == 3:
        status = "inconclusive"
    elif code == 0:
        status = "survived"
    else:
        status, killers = "killed", [f"exit {code}: {err}"]
    return {**row, "status": status, "killed_by": killers, "inconclusive": verdicts.get("INCONCLUSIVE", []),
            "exit": code, "seconds": round(seconds, 1), "gate_update": {"exit": gate_code, "seconds": round(gate_s, 1)},
            "only": [] if full else list(mutant.reach)}


def summary(rows):
    out = {"mutants": len(rows)}
    for status in ("killed", "survived", "inconclusive", "stale"):
        out[status] = sum(r["status"] == status for r in rows)
    out["equivalent"] = sum(bool(r["equivalent"]) for r in rows)
    out["equivalent_survived"] = sum(bool(r["equivalent"]) and r["status"] != "killed" for r in rows)
    out["non_equivalent_not_killed"] = [r["id"] for r in rows if r["status"] != "killed" and not r["equivalent"]]
    return out


def line(r):
    who = ", ".join(r.get("killed_by") or r.get("inconclusive") or []) or r.get("why", "")
    note = f"  [equivalent: {r['equivalent']}]" if r["equivalent"] else ""
    return f"{r['id']:<30} {r['area']:<10} {r['status']:<12} {r.get('seconds', 0):>6}  {who}{note}"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--only", nargs="+", metavar="ID", help="mutant IDs to run")
    p.add_argument("--full", action="store_true", help="run every check for every mutant (ignore the reach)")
    p.add_argument("--check", action="store_true", help="only verify that every pattern matches once")
    p.add_argument("--out", default=str(ROOT / "bench" / "results" / "mutation.json"))
    p.add_argument("--keep", metavar="DIR", help="stage into DIR and keep it (default: a temporary folder)")
    args = p.parse_args(argv)
    chosen = [m for m in MUTANTS if not args.only or m.id in args.only]
    unknown = set(args.only or ()) - {m.id for m in MUTANTS}
    if unknown:
        p.error(f"unknown mutant(s): {', '.join(sorted(unknown))}")
    if args.check:
        bad = [(m.id, matches(ROOT, m)) for m in chosen if matches(ROOT, m) != 1]
        for mid, count in bad:
            print(f"stale: {mid}: its pattern occurs {count} times")
        print(f"{len(chosen) - len(bad)}/{len(chosen)} patterns match once")
        return 1 if bad else 0
    base = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="inertiaproof-mutation-"))
    staging, cache, work = base / "site", base / "cache", base / "work"
    for folder in (cache, work):
        folder.mkdir(parents=True, exist_ok=True)
    try:
        folders = stage(ROOT, staging)
        print(f"staged into {staging}; baseline ci run ...", flush=True)
        code, seconds, verdicts, err = run_suite(staging, cache, work, ())
        baseline = {"exit": code, "seconds": round(seconds, 1), "verdicts": {k: len(v) for k, v in verdicts.items()}}
        print(f"baseline: exit {code} in {seconds:.1f} s", flush=True)
        if code != 0:
            print(f"the unmutated suite does not pass (exit {code}): {verdicts} {err}", file=sys.stderr)
            return 2
        rows = []
        for mutant in chosen:
            rows.append(judge(mutant, staging, folders, cache, work, args.full))
            print(line(rows[-1]), flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(base, ignore_errors=True)
    doc = {"schema": SCHEMA, "command": " ".join(["python bench/mutation.py", *(argv or sys.argv[1:])]),
           "note": "killed: inertiaproof run --profile ci exits 1 after 'inertiaproof gate --update' on the mutated "
                   "tree; times are wall seconds on the machine that ran it",
           "baseline": baseline, "summary": summary(rows), "mutants": rows}
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(doc, indent=1) + "\n")
    s = doc["summary"]
    print(f"{s['killed']} killed, {s['survived']} survived, {s['inconclusive']} inconclusive, {s['stale']} stale of "
          f"{s['mutants']}; not killed and not equivalent: {', '.join(s['non_equivalent_not_killed']) or 'none'}")
    print(f"written: {args.out}")
    return 0 if not s["non_equivalent_not_killed"] else 1


if __name__ == "__main__":
    sys.exit(main())
