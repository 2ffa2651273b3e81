"""The report's section for a control engineer (issue 12): per chain the paper's constant, the bracket of the true
extreme with its certified and attained sides named, the ratios; equations named as the paper prints them."""

import os
import re
from pathlib import Path

import pytest
from inertiaproof.report import engineer, plots
from inertiaproof.report.evidence import Figures
from inertiaproof.report.paper_names import PRINTED, printed, printed_names

from inertiaproof.suite import catalog

_SOURCE = Path("shared") / "paper" / "time_dependent_inertial_parameters.tex"  # ../shared beside the checkout
PAPER = next((p for p in [Path(os.environ.get("INERTIAPROOF_PAPER", "/nonexistent"))] +
              [up / _SOURCE for up in Path(__file__).resolve().parents[1:4]] if p.is_file()), Path("/nonexistent"))


def _q(value, kind):
    return {"value": value, "kind": kind, "note": ""}


def _doc():
    def scene(lower, upper, sense, paper=None):
        lo, hi = ("lower_bound", "sampled") if sense == "min" else ("sampled", "upper_bound")
        ev = {"bracket": {"quantity": "inf lambda_min(M)" if sense == "min" else "sup lambda_max(M)",
                          "lower": _q(lower, lo), "upper": _q(upper, hi), "convergence": [[0.01, lower / 2, upper],
                                                                                         [0.1, lower, upper]]}}
        if paper:
            ev["constants"] = {"paper": _q(paper[0], "lower_bound" if sense == "min" else "upper_bound"),
                               "paper_observed": _q(paper[1], "sampled")}
        return ev

    return {"checks": [
        {"id": "Thm2", "check": "Thm2", "verdict": "HOLDS", "evidence": {"scenes": {"arm": scene(0.1, 0.2, "min",
                                                                                                  (0.01, 0.02))}}},
        {"id": "Thm3", "check": "Thm3", "verdict": "HOLDS", "evidence": {"scenes": {"arm": scene(5.0, 6.0, "max",
                                                                                                  (60.0, 30.0))}}},
        {"id": "Def2", "check": "Def2", "verdict": "HOLDS", "evidence": {"chains": {"arm": scene(0.5, 0.5, "min")}}},
    ]}


def test_rows_name_sides_and_ratios():
    rows = {r["check"]: r for r in engineer.chain_rows(_doc())["arm"]}
    assert rows["Thm2"]["name"] == "Theorem 2, Eq. (60)" and rows["Thm3"]["name"] == "Theorem 3, Eq. (61)"
    assert (rows["Thm2"]["lower_kind"], rows["Thm2"]["upper_kind"]) == ("lower_bound", "sampled")
    assert (rows["Thm3"]["lower_kind"], rows["Thm3"]["upper_kind"]) == ("sampled", "upper_bound")
    width, span = engineer._ratios(rows["Thm3"])
    assert width == pytest.approx(1.2) and span == (pytest.approx(30 / 6), pytest.approx(60 / 5))
    width, span = engineer._ratios(rows["Thm2"])
    assert width == pytest.approx(2.0) and span == (pytest.approx(0.1 / 0.02), pytest.approx(0.2 / 0.01))
    assert rows["Def2"]["paper"] is None


def test_section_has_one_table_per_chain_and_a_narrowing_figure():
    figs = Figures()
    section = engineer.section(_doc(), figs, {"profile": "deep", "brackets": [
        {"scene_or_ingredient": "arm", "quantity": "q", "upper": 2.0, "width_against_seconds": [[0.1, 1.0],
                                                                                                [1.0, 0.01]]}]})
    assert section is not None and [f.kind for f in figs.made] == ["narrowing", "narrowing"]
    for f in figs.made:
        plots.draw(f)  # renders
    text = repr(section)
    assert "certified lower bound" in text and "attained at a witness" in text and "certified upper bound" in text


def test_no_latex_labels_in_the_paper_column():
    """Every catalog entry's paper reference, as the report prints it, carries no LaTeX label."""
    labels = [k for k in PRINTED if k not in ("Layout", "Kinematics")]
    for entry in catalog.ENTRIES:
        shown = printed(entry.label)
        words = set(re.findall(r"[A-Za-z][A-Za-z0-9_:]*", shown))
        assert not words & set(labels), (entry.id, shown)
    assert printed("Tjaja") == "Eq. (68)" and printed("Theorem 4 (BoundedEffectofVaryingParam)") == "Theorem 4, Eq. (62)"


def test_numbering_of_a_small_source():
    tex = r"""\section{A}\label{s:a}
\begin{align}x\label{one}\end{align}
\begin{align}a&=b\nonumber\\ c&=\begin{pmatrix}1\\2\end{pmatrix}\label{two}\\ d\label{three}\end{align}
\begin{align*}e\\f\end{align*}
\begin{theorem}\label{t:1} text \begin{align}g\label{four}\end{align}\end{theorem}
\subsection{B}\label{s:b}\begin{lemma}\label{l:1}\end{lemma}\begin{theorem}\end{theorem}\begin{theorem}\label{t:3}\end{theorem}
"""
    assert printed_names(tex) == {"s:a": "Section 1", "one": "Eq. (1)", "two": "Eq. (2)", "three": "Eq. (3)",
                                  "t:1": "Theorem 1", "four": "Eq. (4)", "s:b": "Section 1.1", "l:1": "Lemma 1",
                                  "t:3": "Theorem 3"}


@pytest.mark.skipif(not PAPER.is_file(), reason="the paper's source is not beside the checkout")
def test_printed_names_are_those_of_the_paper():
    assert printed_names(PAPER.read_text(encoding="utf-8")) == PRINTED
