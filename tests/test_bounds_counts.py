"""Counted budgets that scale with the chain (issue 49, item 6): the Fourier strategy declines a chain whose 5^m n^2
terms its rounds do not pay for, and the bracket it leaves stays valid; a pivot ladder's boxes times n^3 stay within
the work of LADDER_JOINTS joints; an audit with a cap of fully bounded chains gives the others the quick budget
and says so."""

from __future__ import annotations

import numpy as np

from inertiaproof.audit.document import audit_robot, read_robot
from inertiaproof.bounds.configuration import mass_sup
from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.perron import FOURIER_TERMS_PER_ROUND, fourier_fits, fourier_terms
from inertiaproof.bounds.pivot_search import LADDER_JOINTS, ladder_budget
from inertiaproof.bounds.strategies import Fourier, Walk
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.dynamics import composite
from inertiaproof.scene import robots


def test_fourier_declines_a_chain_beyond_its_count_and_the_bracket_stays_valid():
    panda = robots.panda(payload=2.0)
    chain, thetas = panda.chain, parameter_vertices(panda.trajectory)[0][:1]
    terms = fourier_terms(chain)
    assert terms == 5 ** 6 * 7 ** 2  # the first joint moves the chain rigidly: 6 free coordinates
    assert FOURIER_TERMS_PER_ROUND < terms <= FOURIER_TERMS_PER_ROUND * 20
    assert fourier_fits(chain, 20) and not fourier_fits(chain, 1)
    assert Fourier().applies(Walk(chain, thetas, 20, 200)) and not Fourier().applies(Walk(chain, thetas, 1, 200))
    bracket = mass_sup(chain, thetas, samples=200, rounds=1, rng=np.random.default_rng(0))
    paid = mass_sup(chain, thetas, samples=200, rounds=5, rng=np.random.default_rng(0))  # 5 rounds pay for 1e6 terms
    assert "exact Fourier coefficients" not in bracket.note and "exact Fourier coefficients" in paid.note
    assert paid.upper < bracket.upper  # the strategy declined is the one that tightens
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(5).random((4000, chain.n))
    sampled = np.linalg.eigvalsh(composite.mass_matrix(chain, q[:, None], thetas[None]))[..., -1].max()
    assert np.isfinite(bracket.upper) and bracket.upper >= sampled


def test_a_ladder_on_more_joints_gets_the_boxes_of_the_same_work():
    for rounds in (0, 20, 800):
        full = ladder_budget(rounds)[0]
        assert [ladder_budget(rounds, n)[0] for n in range(1, LADDER_JOINTS + 1)] == [full] * LADDER_JOINTS
        for n in (LADDER_JOINTS + 1, 12, 30):
            boxes = ladder_budget(rounds, n)[0]
            assert boxes * n**3 <= full * LADDER_JOINTS**3 < (boxes + 1) * n**3


LINK = ('<link name="{0}"><inertial><mass value="1"/><origin xyz="0.1 0 0"/>'
        '<inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>')
JOINT = ('<joint name="j{0}" type="revolute"><parent link="base"/><child link="b{0}"/><origin xyz="0 0 {0}"/>'
         '<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')


def test_an_audit_capped_at_one_full_chain_gives_the_others_the_quick_budget_and_says_so(tmp_path):
    path = tmp_path / "fork.urdf"
    path.write_text('<robot name="fork"><link name="base"/>' + "".join(LINK.format(f"b{k}") + JOINT.format(k)
                                                                       for k in (1, 2, 3)) + "</robot>")
    robot = read_robot(path)
    capped = audit_robot(robot, samples=64, rounds=4, bounds="all", full_chains=1, quick_rounds=0)
    assert [c["bounds_rounds"] for c in capped["chains"].values()] == [4, 0, 0]
    assert capped["bounds_cap"]["full_chains"] == 1 and "1 of the 3 chains" in capped["warnings"][-1]
    whole = audit_robot(robot, samples=64, rounds=4, bounds="all", full_chains=3, quick_rounds=0)
    assert "bounds_cap" not in whole and all("bounds_rounds" not in c for c in whole["chains"].values())
    for c, w in zip(capped["chains"].values(), whole["chains"].values()):  # every bracket holds the samples
        assert c["bounds"]["inf_lambda_min_certified"]["value"] <= w["bounds"]["inf_lambda_min_sampled"]["value"]
        assert c["bounds"]["sup_lambda_max_certified"]["value"] >= w["bounds"]["lambda_max"]["value"]


def test_the_profiles_cap_only_an_audit_with_bounds_all():
    from inertiaproof.suite.profiles import PROFILES

    ci = PROFILES["ci"]
    assert ci.audit_chains("all") == {"full_chains": ci.audit_full_chains, "quick_rounds": ci.audit_rounds}
    assert ci.audit_chains("arms") == {} and ci.audit_chains("none") == {}
