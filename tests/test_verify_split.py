"""The chain split's certificate (SplitProof: body k, interface inertias L, the tail's and the head's trees) is
re-proved by the independent checker once the prover has completed its trees (inertiaproof.bounds.completion);
tampered, it is not re-proved or rejected with a one-line reason (issue 25)."""

from __future__ import annotations

import copy
from fractions import Fraction

import numpy as np
import pytest

from inertiaproof.bounds import interface
from inertiaproof.bounds.certificate import spectrum_certificate
from inertiaproof.bounds.completion import complete
from inertiaproof.bounds.configuration import mass_spectra
from inertiaproof.bounds.domain import search_box
from inertiaproof.bounds.time import parameter_vertices
from inertiaproof.scene import robots
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.verify.cli import check

BOXES = PROFILES["ci"].tree_boxes  # boxes the prover may test beyond a tree to complete it


@pytest.fixture(scope="module")
def split():
    """UR5's inf lambda_min(M) >= its sampled inf / 1.95, proved by the split at body 3 (about 500 boxes, 2 s)."""
    scene = robots.ur5()
    chain, thetas = scene.chain, parameter_vertices(scene.trajectory)[0]
    lo, hi = search_box(chain)
    q = lo + (hi - lo) * np.random.default_rng(0).random((4000, chain.n))
    values = mass_spectra(chain, thetas, q, "lmin").min(1)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(interface, "RUNGS", (1.95,))
        gamma, note, proof = interface.split_ladder(chain, thetas, float(values.min()), 20)
    assert proof is not None, note
    cert = spectrum_certificate(chain, thetas, "lambda_min", gamma, proof=proof, witness=q[np.argmin(values)])
    assert cert["split"]["body"] == 2 and cert["split"]["tail"] and cert["split"]["head"]
    return complete(cert, boxes=BOXES)


def test_the_split_is_reproved(split):
    assert split["method"] == "tree" and split["split"]["body"] == 2
    out = check(split)
    assert out["status"] == "re-proved" and "every leaf proved" in out["why"], out


def test_an_interface_inertia_raised_is_not_reproved(split):
    """L + 0.05 on its (4, 4) entry (the turn about x) lies above the tail's articulated inertia at sampled
    configurations (by 0.046 in its smallest eigenvalue): the split proves nothing, though the claim is true (no
    witness refutes it), and the checker names the tail's leaf where A_k - L is not definite, even on the tree the
    prover grows for it."""
    raised = copy.deepcopy(split)
    rows = raised["split"]["interfaces"][0]
    rows[3][3] = str(Fraction(rows[3][3]) + Fraction(1, 20))
    for cert in (raised, complete(raised, boxes=BOXES)):
        out = check(cert)
        assert out["status"] == "not re-proved", out
        assert "\n" not in out["why"] and "tail" in out["why"] and "A_k - L" in out["why"], out


def test_an_unparsable_interface_number_is_a_bad_certificate(split):
    broken = copy.deepcopy(split)
    broken["split"]["interfaces"][0][3][3] = "1/20 + " + broken["split"]["interfaces"][0][3][3]
    out = check(broken)
    assert out["status"] == "bad certificate", out
    assert out["why"].startswith("split.interfaces[0][3][3]") and "\n" not in out["why"], out
