"""The key step's certificate (kind ``key-step``): the Choi matrix of L(F) = Z(f^-1(F)) and the sharp constants of
L(I4), re-proved exactly by the independent checker. A tampered Choi matrix is a proof step that fails (not
re-proved); constants beyond L(I4) are refuted at F = I4."""

import copy
from fractions import Fraction

import pytest

from inertiaproof.checks.bound_verdicts import key_step_evidence
from inertiaproof.verify.cli import check


@pytest.fixture(scope="module")
def cert():
    return key_step_evidence()["certificate"].certificate


def test_the_key_step_is_reproved(cert):
    out = check(cert)
    assert out["status"] == "re-proved", out
    assert (cert["claim"]["lower"], cert["claim"]["upper"]) == ("1", "2")


def _entry(c, i, j, value):
    c["choi"][i][j] = str(value)
    return c


@pytest.mark.parametrize("tamper, status, why", [
    (lambda c: _entry(c, 0, 1, Fraction(c["choi"][0][1]) + 1), "not re-proved", "not symmetric positive semidefinite"),
    (lambda c: _entry(c, 0, 0, -1), "not re-proved", "not symmetric positive semidefinite"),
    (lambda c: _entry(c, 0, 0, Fraction(c["choi"][0][0]) + 1), "not re-proved", "differs from L"),
    (lambda c: c["claim"].update(upper="199/100"), "refuted", "upper I6 - L(I4)"),
    (lambda c: c["claim"].update(lower="101/100"), "refuted", "L(I4) - lower I6"),
])
def test_a_tampered_key_step_is_not_reproved(cert, tamper, status, why):
    bad = copy.deepcopy(cert)
    tamper(bad)
    out = check(bad)
    assert out["status"] == status and why in out["why"], out
    if status == "refuted":
        assert out["where"]["witness"] == {"F": "I4"}, out


def test_a_malformed_choi_matrix_is_a_bad_certificate(cert):
    bad = copy.deepcopy(cert)
    bad["choi"][3][4] = "one"
    out = check(bad)
    assert out["status"] == "bad certificate" and "choi[3][4]" in out["why"], out
