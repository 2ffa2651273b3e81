"""The consistent fit and its certificates (issue 50): on torques of the spatial 3R arm (regressors of Property 2)
with Gaussian noise, the fit recovers the truth within the noise, every body is certified consistent, the certified
lower bound on the residual of every consistent Theta lies below the fit's residual and the truth's and within a
few percent of the fit's; data from an inconsistent truth (a body of negative mass) are certified inconsistent; the
independent checker (``python -m inertiaproof.verify``) re-proves every certificate, and no altered one."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
from fractions import Fraction
from importlib import resources

import jsonschema
import numpy as np
import pytest
from scipy import stats

from inertiaproof.dynamics import motion, regressors
from inertiaproof.identify.consistent import consistent_fit
from inertiaproof.identify.problem import NormalEquations
from inertiaproof.model.inertia import pseudo_inertia
from inertiaproof.scene import robots
from inertiaproof.verify.cli import check
from inertiaproof.verify.exact import BadCertificate, read_json

SCHEMA = jsonschema.Draft202012Validator(json.loads(
    resources.files("inertiaproof.verify").joinpath("certificate-2.schema.json").read_text()))
NOISE = 0.05  # N m, the torques' standard deviation
FRICTION = np.tile([0.3, 0.5], 3)  # viscous, Coulomb per joint


def samples(chain, count, seed):
    """Regressor rows (count * n, 10 N + 2 n) at random states: bodies' R_l (RoboticRegressor), then per joint its
    viscous (qd) and Coulomb (sign qd) columns."""
    rng = np.random.default_rng(seed)
    n = chain.n
    q, qd, qdd = rng.uniform(-np.pi, np.pi, (count, n)), rng.normal(0, 1.5, (count, n)), rng.normal(0, 3, (count, n))
    kin = motion.kinematics(chain, q)
    r = regressors.regressor(kin.qj, kin.dqj, kin.rotations, chain.gravity, qd, qd, qdd)  # (S, N, n, 10)
    friction = np.zeros((count, n, 2 * n))
    for k in range(n):
        friction[:, k, 2 * k], friction[:, k, 2 * k + 1] = qd[:, k], np.sign(qd[:, k])
    return np.hstack([np.moveaxis(r, 2, 1).reshape(count * n, -1), friction.reshape(count * n, -1)]), rng


def problem(truth_bodies, count=300, seed=0):
    scene = robots.spatial_3r()
    a, rng = samples(scene.chain, count, seed)
    truth = np.concatenate([np.asarray(truth_bodies, float).ravel(), FRICTION])
    b = a @ truth + rng.normal(0, NOISE, a.shape[0])
    extra = tuple(f"joint {k}.{w}" for k in (1, 2, 3) for w in ("viscous", "coulomb"))
    return NormalEquations.of_rows(a, b, ("link1", "link2", "link3"), extra, {"path": "synthetic"}), truth


BASE = np.asarray(robots.spatial_3r().trajectory.base, float)
TRACES = [10 * float(np.max(np.trace(pseudo_inertia(BASE), axis1=1, axis2=2)))] * 3  # stated: 10x the largest


@pytest.fixture(scope="module")
def consistent():
    ne, truth = problem(BASE)
    return ne, truth, consistent_fit(ne, trace_bounds=TRACES)


@pytest.fixture(scope="module")
def inconsistent():
    bodies = BASE.copy()
    bodies[2, 0] = -1.0  # body 3 of negative mass, its first moment and inertia kept: f(Phi_3) indefinite
    ne, truth = problem(bodies)
    return ne, truth, consistent_fit(ne, trace_bounds=TRACES)


def _written(certs, folder):
    paths = []
    for i, cert in enumerate(certs):
        paths.append(folder / f"cert{i}.json")
        paths[-1].write_text(json.dumps(cert))
    return paths


def _checker(paths):
    return subprocess.run([sys.executable, "-m", "inertiaproof.verify", *map(str, paths)], capture_output=True,
                          text=True, timeout=300, check=False)


def test_the_fit_recovers_the_truth_within_the_noise(consistent):
    ne, truth, fit = consistent
    error = fit.theta - truth
    rank = fit.details["rank"]
    # |theta_LS - truth|_H^2 / sigma^2 is chi-square(rank); the fit is the H-projection onto a convex set holding
    # the truth, no farther from it
    assert error @ ne.H @ error / NOISE**2 <= stats.chi2.ppf(0.999, rank)
    assert np.allclose(fit.theta[30:], FRICTION, atol=0.05)
    assert np.all(np.linalg.eigvalsh(pseudo_inertia(fit.theta[:30].reshape(3, 10)))[:, 0] > 0)


def test_every_body_certified_and_the_lower_bound_within_a_few_percent(consistent, tmp_path):
    ne, truth, fit = consistent
    assert fit.status == "certified", fit.reason
    assert "no physically consistent parameters fit these data better than" in fit.reason
    kinds = [c["claim"]["kind"] for c in fit.certificates]
    assert kinds.count("body-spectrum") == 3 and kinds.count("residual-bound") == 1
    assert fit.lower_bound <= fit.residual and fit.lower_bound <= ne.residual(truth)
    assert (fit.residual - fit.lower_bound) / fit.residual < 0.02
    done = _checker(_written(fit.certificates, tmp_path))
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.count("re-proved") == 4
    assert not [e for c in fit.certificates for e in SCHEMA.iter_errors(c)]


def test_no_consistent_parameters_of_the_set_fall_below_the_bound(consistent):
    """The claim attacked directly: random consistent Theta near the fit (f(Phi_l) = A A^T, inside the trace bounds)
    all have r >= L."""
    ne, _, fit = consistent
    rng = np.random.default_rng(3)
    f = pseudo_inertia(fit.theta[:30].reshape(3, 10))
    root = np.linalg.cholesky(f)
    for _ in range(200):
        a = root + rng.normal(0, 0.02, (3, 4, 4)) * np.abs(root).max()
        bodies = [np.linalg.solve(*_f_system(a[l] @ a[l].T)) for l in range(3)]
        theta = np.concatenate([np.ravel(bodies), fit.theta[30:] + rng.normal(0, 0.01, 6)])
        assert ne.residual(theta) >= fit.lower_bound


def _f_system(f):
    """(M, vec) with M Phi = vec for f(Phi) = f (f is linear and one to one)."""
    m = pseudo_inertia(np.eye(10)).reshape(10, 16).T
    return m.T @ m, m.T @ f.ravel()


def test_an_inconsistent_truth_is_certified_inconsistent(inconsistent, tmp_path):
    _, _, fit = inconsistent
    assert fit.status == "inconsistent data", fit.reason
    assert "the data demand an inconsistent inertia beyond the noise" in fit.reason
    excess = [c for c in fit.certificates if c["claim"].get("quantity") == "excess"]
    assert len(excess) == 1
    assert check(excess[0])["status"] == "re-proved"
    assert fit.lower_bound > (1 + fit.details["kappa"]) * fit.details["least_squares_residual"]
    done = _checker(_written(fit.certificates, tmp_path))
    assert done.returncode == 0, done.stdout + done.stderr


def test_the_prior_and_an_ellipsoid_keep_the_fit_consistent(consistent):
    ne, truth, _ = consistent
    prior = truth + np.concatenate([np.zeros(30), np.full(6, 0.1)])
    centre, radius = np.zeros(3), 2.0  # a ball of radius 2 about each frame's origin holds each rod
    q = np.block([[-np.eye(3) / radius**2, (centre / radius**2)[:, None]],
                  [(centre / radius**2)[None, :], np.array([[1.0 - centre @ centre / radius**2]])]])
    fit = consistent_fit(ne, prior=prior, prior_weight=1e-3, ellipsoids={"link3": q}, trace_bounds=TRACES)
    assert fit.status == "certified", fit.reason
    assert np.trace(q @ pseudo_inertia(fit.theta[20:30])) >= -1e-9
    assert fit.lower_bound <= fit.residual


def test_a_payload_outside_the_links_ellipsoid_is_certified_inconsistent():
    """A 2 kg point mass beyond the end of link 3 (the model omits it): consistent as a heavier link 3, so the fit
    without geometry is certified; with link 3's bounding ball (centre mid-rod, radius 0.35 m) as the condition
    tr(Q f(Phi)) >= 0, the data are certified inconsistent with every consistent link inside its geometry."""
    bodies = BASE.copy()
    c, mass = np.array([0.3, 0.0, 0.0]), 2.0
    bodies[2] += mass * np.concatenate([[1.0], c, [c @ c - x * x for x in c], [-c[0] * c[1], -c[1] * c[2], -c[0] * c[2]]])
    ne, _ = problem(bodies)
    centre, radius = np.array([-0.25, 0.0, 0.0]), 0.35
    q = np.block([[-np.eye(3) / radius**2, (centre / radius**2)[:, None]],
                  [(centre / radius**2)[None, :], np.array([[1.0 - centre @ centre / radius**2]])]])
    assert consistent_fit(ne, trace_bounds=TRACES).status == "certified"
    fit = consistent_fit(ne, ellipsoids={"link3": q}, trace_bounds=TRACES)
    assert fit.status == "inconsistent data", fit.reason
    excess = next(c for c in fit.certificates if c["claim"].get("quantity") == "excess")
    out = check(excess)
    assert out["status"] == "re-proved" and "bounding ellipsoids" in out["claim"], out
    assert not list(SCHEMA.iter_errors(excess))
    dropped = copy.deepcopy(excess)
    dropped["dual"]["nu"] = ["0"] * 3  # the ellipsoid's multiplier dropped: the bound no longer reaches
    assert check(dropped)["status"] in ("not re-proved", "refuted")


def _lower(fit):
    return next(c for c in fit.certificates if c["claim"]["kind"] == "residual-bound")


def _altered(cert, change):
    out = copy.deepcopy(cert)
    change(out)
    return check(out)["status"]


def test_altered_certificates_are_not_reproved(consistent, inconsistent):
    _, _, fit = consistent
    cert = _lower(fit)
    assert check(cert)["status"] == "re-proved"
    bound = Fraction(cert["claim"]["bound"])
    r_star = Fraction(fit.residual)
    unproved = {"not re-proved", "refuted"}

    def raise_bound(c):
        c["claim"]["bound"] = str(r_star * Fraction(101, 100))

    def lower_h(c):
        c["data"]["H"] = [[str(Fraction(x) * Fraction(9, 10)) for x in row] for row in c["data"]["H"]]

    def skew_h(c):
        c["data"]["H"][0][1] = str(Fraction(c["data"]["H"][0][1]) + 1)

    def drop_body(c):
        c["dual"]["Z"].pop()

    def zero_dual(c):
        c["dual"]["Z"] = [[["0"] * 4 for _ in range(4)] for _ in c["dual"]["Z"]]

    def indefinite(c):
        c["dual"]["Z"][1] = [["1", "0", "0", "0"], ["0", "-1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]]

    def nan(c):
        c["data"]["g"][0] = "NaN"

    def no_sigma(c):
        c["dual"]["sigma"] = "0"

    def negative_sigma(c):
        c["dual"]["sigma"] = "-1"

    def smaller_trace(c):
        c["bounds"]["trace"] = ["-1"] * 3

    def statement(c):
        c["claim"]["statement"] = "no physically consistent parameters fit better"

    assert _altered(cert, raise_bound) in unproved
    assert _altered(cert, lower_h) in unproved
    assert _altered(cert, zero_dual) in unproved
    assert _altered(cert, indefinite) == "not re-proved"
    for change in (skew_h, drop_body, nan, negative_sigma, smaller_trace, statement):
        assert _altered(cert, change) == "bad certificate", change.__name__
    if np.linalg.eigvalsh(np.array([[float(Fraction(x)) for x in row] for row in cert["data"]["H"]]))[0] < 0:
        assert _altered(cert, no_sigma) == "not re-proved"  # H as written is not semidefinite: sigma is needed
    assert bound <= r_star
    excess = next(c for c in inconsistent[2].certificates if c["claim"].get("quantity") == "excess")

    def raise_kappa(c):
        c["claim"]["bound"] = str(Fraction(c["claim"]["bound"]) * 10**6)

    assert _altered(excess, raise_kappa) in unproved
    with pytest.raises(BadCertificate):
        read_json(json.dumps(cert).replace('"0"', "NaN", 1))


def test_a_false_lower_bound_is_refuted_at_its_own_point(consistent):
    """Where dual.theta lies in the set, a bound above its residual is refuted there (both sides exact)."""
    _, _, fit = consistent
    cert = copy.deepcopy(_lower(fit))
    theta = [Fraction(x) for x in cert["dual"]["theta"]]
    cert["dual"]["theta"] = [str(Fraction(x)) for x in fit.theta]  # the fit itself: consistent, inside the bounds
    cert["claim"]["bound"] = str(Fraction(fit.residual) * 2)
    out = check(cert)
    assert out["status"] == "refuted" and out["where"]["witness"], out
    assert theta  # the certificate's own point was another
