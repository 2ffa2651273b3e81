"""The report's content, HTML escaping, determinism, errors on bad input, and `run --report` on real runs."""

import copy
import json
import re
import subprocess
import sys
import warnings
from html.parser import HTMLParser

import pytest
import report_fixture
from hypothesis import given, settings
from hypothesis import strategies as st
from inertiaproof.report.paper_names import printed
from inertiaproof.report import content, evidence, html, latex, load
from inertiaproof.report.cli import build
from inertiaproof.report.model import Notice

from inertiaproof import cli
from inertiaproof.result import KINDS, Result, Verdict
from inertiaproof.suite import catalog, registry
from inertiaproof.suite.discovery import load_checks
from inertiaproof.suite.registry import CheckSpec


@pytest.fixture(scope="module")
def full(tmp_path_factory):
    out, _ = report_fixture.built(tmp_path_factory)
    return out


@pytest.fixture(scope="module")
def document(full):
    doc = load.results(full)
    return content.build(doc, load.data_files(full, doc))


class Elements(HTMLParser):
    """Start tags with their attributes, and the page's text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tags, self.text = [], []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))

    def handle_data(self, data):
        self.text.append(data)


def parse(page):
    p = Elements()
    p.feed(page)
    return p


def test_fixture_covers_every_id_verdict_and_convention():
    doc = report_fixture.document()
    assert {e.id for e in catalog.ENTRIES} <= {r["id"] for r in doc["checks"]}
    assert {r["verdict"] for r in doc["checks"]} == {"HOLDS", "VIOLATED", "INCONCLUSIVE"}
    found = {name: 0 for name in evidence.CONVENTIONS}
    for r in doc["checks"]:
        conventions, *_ = evidence.split(r["evidence"])
        for name, items in conventions.items():
            found[name] += len(items)
    assert all(found.values()), found


def test_sections_follow_the_paper_with_its_labels(document):
    results = [s for s in document.walk() if s.result_id is not None]
    ids = [s.result_id for s in results]
    assert ids[: len(catalog.ENTRIES)] == [e.id for e in catalog.ENTRIES]
    assert ids[len(catalog.ENTRIES):] == ["gate"]
    for section, entry in zip(results, catalog.ENTRIES):
        assert printed(entry.label) in "".join(getattr(x, "text", "") for x in section.title)  # as the paper prints it
    verdicts = {s.result_id: s.verdict for s in results}
    assert verdicts["Thm4"] == "VIOLATED" and verdicts["EQ-triangle"] == "INCONCLUSIVE" and verdicts["GRE"] == "HOLDS"


def test_a_failed_run_leads_with_what_failed(document):
    first = document.sections[0].blocks[0]
    assert isinstance(first, Notice) and first.tone == "VIOLATED"
    text = "".join(x.text for item in first.blocks[0].items for x in item if hasattr(x, "text"))
    assert "Thm4" in text and f"inertiaproof replay {report_fixture.VIOLATED_FILE}" in text


def test_every_plot_kind_is_made(document):
    kinds = [f.kind for f in document.figures()]
    assert set(kinds) == {"bracket", "constants", "hunt", "series", "work_precision", "stability"}
    assert [f.number for f in document.figures()] == list(range(1, len(kinds) + 1))


def test_html_is_self_contained_and_escaped(full, document):
    page = (full / "report.html").read_text()
    p = parse(page)
    tags = [t for t, _ in p.tags]
    assert "script" not in tags and "link" not in tags and "img" not in tags and "iframe" not in tags
    assert not [a for _, attrs in p.tags for k, a in attrs.items() if k in ("src", "href") and not a.startswith("#")]
    assert "@import" not in page and not re.search(r"url\((?!#)", page)
    assert report_fixture.HOSTILE in "".join(p.text)
    plots = [a for t, a in p.tags if t == "figure" and a.get("class") == "plot"]
    assert len(plots) == tags.count("svg") == len(document.figures())


def test_html_marks_every_result(full):
    p = parse((full / "report.html").read_text())
    sections = {a["data-id"]: a["data-verdict"] for t, a in p.tags if t == "section" and "data-id" in a}
    assert set(sections) == {e.id for e in catalog.ENTRIES} | {"gate"}
    assert sections["Thm4"] == "VIOLATED"
    anchors = {a["id"] for t, a in p.tags if "id" in a}
    links = {a["href"][1:] for t, a in p.tags if t == "a"}
    assert links <= anchors


def test_same_results_give_identical_files(full, tmp_path):
    again = report_fixture.write(tmp_path / "again")
    build(again, pdf=False)
    for name in ("report.html", "report.tex", latex.FIGURES):
        assert (full / name).read_bytes() == (again / name).read_bytes(), name


def test_latex_escapes_every_special_character():
    special = "\\ { } $ & # % _ ^ ~ < > | \" ' ` --"
    for code in (False, True):
        text = latex.escape(special, code=code)
        bare = re.sub(r"\\(char\d+|textbackslash|textless|textgreater|textbar|textquotesingle|textasciigrave"
                      r"|ttfamily|bk|allowbreak)\b|\\[{}$&#%]|[{}]", "", text)
        assert not re.search(r"[\\{}$&#%_^~]", bare), (code, text)
    expected = r"\ensuremath{\lambda} \ensuremath{\le} \'{e} \texttt{[U+1F600]}"
    assert latex.escape("\u03bb \u2264 \u00e9 \U0001f600") == expected


def test_long_tokens_may_break():
    token = "Asm3/Thm5:scene:ur5-with-a-sliding-trolley"
    assert latex.escape(token, code=True).count(r"\allowbreak") >= 5
    assert r"\bk" in latex.escape("340282366920938463463374607431768211457")
    assert r"\bk" not in latex.escape("short words stay whole")


def test_gate_says_which_derivations_changed():
    doc = report_fixture.document()
    gate = next(r for r in doc["checks"] if r["id"] == "gate")
    gate["verdict"] = "VIOLATED"
    gate["evidence"]["derivations"][1]["changed"] = True
    section = next(s for s in content.build(doc, {}).walk() if s.result_id == "gate")
    words = "".join(getattr(x, "text", "") for x in section.blocks[1].inlines)
    assert "6 derivations" in words and "Changed since the lockfile: 1 (mass_matrix_3R)" in words


def test_missing_data_file_and_unknown_id_still_make_a_report(tmp_path):
    doc = report_fixture.document()
    doc["checks"] = [copy.deepcopy(r) for r in doc["checks"] if r["id"] == "GRE-physics"]
    doc["checks"].append({"id": "stability", "check": "stability", "verdict": "HOLDS", "summary": "an extra",
                          "evidence": {"nested": {"deep": [1, {"x": [1, 2]}]}}})
    (tmp_path / "results.json").write_text(json.dumps(doc))
    written = build(tmp_path, pdf=False)
    page = (tmp_path / "report.html").read_text()
    assert "data/work_precision.json: missing (results.json lists it)" in page
    assert 'data-id="stability"' in page
    assert page.count('data-verdict="NOT RUN"') == len(catalog.ENTRIES) - 1
    assert [p.name for p in written] == ["report.html", "report.tex"]


@pytest.mark.parametrize("setup, message", [
    (lambda d: None, "results.json: not found"),
    (lambda d: (d / "results.json").write_text("{"), "results.json: not JSON"),
    (lambda d: (d / "results.json").write_text("[]"), "not an inertiaproof results file"),
    (lambda d: (d / "results.json").write_text(json.dumps(
        {"schema": "inertiaproof.results/1", "checks": [{"id": "Thm2", "verdict": "MAYBE"}]})),
     "checks[0] (Thm2): verdict 'MAYBE' is not one of HOLDS, VIOLATED, INCONCLUSIVE"),
    (lambda d: (d / "results.json").write_text(json.dumps(
        {"schema": "inertiaproof.results/1", "checks": [{"id": "Thm2", "verdict": "HOLDS", "evidence": [1]}]})),
     "checks[0] (Thm2): 'evidence' must be an object"),
])
def test_bad_input_is_one_line_naming_the_file(tmp_path, capsys, setup, message):
    setup(tmp_path)
    assert cli.main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and message in err and str(tmp_path) in err, err


def test_missing_folder_from_the_shell_has_no_traceback(tmp_path):
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "report", str(tmp_path / "nowhere")],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 2
    assert done.stderr.strip() == f"inertiaproof: error: {tmp_path / 'nowhere'}: no such folder " \
                                  f"(make one with 'inertiaproof run --out {tmp_path / 'nowhere'}')"


@pytest.fixture
def violating_check(monkeypatch):
    load_checks()

    def fn(ctx):
        return Result("Thm2", Verdict.VIOLATED, "alpha1 <exceeded> & \"quoted\"", {"margin": -1.0},
                      counterexample={"kind": "report-test", "data": {"q": [0.1, 0.2]}})

    monkeypatch.setitem(registry.CHECKS, "Thm2:report-test", CheckSpec("Thm2", "Thm2:report-test", fn, frozenset()))


def test_run_report_on_a_real_failing_run(tmp_path, capsys, violating_check):
    out = tmp_path / "out"
    code = cli.main(["run", "--only", "EQ-geom", "Def2", "Thm2", "Thm2:report-test", "--report", "--out", str(out),
                     "--quiet", "--counterexamples", str(tmp_path / "found")])
    assert code == 1
    printed = capsys.readouterr().out
    for name in ("report.html", "report.tex"):
        assert f"report: {out / name}" in printed
    page = (out / "report.html").read_text()
    first = page.index('class="notice tone-VIOLATED"')
    assert first < page.index("Every result at a glance")
    cx = next((tmp_path / "found").glob("Thm2-*.json"))
    assert f"inertiaproof replay {cx}" in page
    assert "alpha1 &lt;exceeded&gt; &amp; &quot;quoted&quot;" in page
    sections = dict(re.findall(r'data-id="([^"]+)" data-verdict="([^"]+)"', page))
    assert sections["EQ-geom"] == "HOLDS" and sections["Thm2"] == "VIOLATED" and sections["Thm4"] == "NOT RUN"
    plotted = set(re.findall(r'<figure class="plot" id="fig-\d+" data-plot="([a-z_]+)">\n<svg ', page))
    assert {"bracket", "constants"} <= plotted, plotted
    tex = (out / "report.tex").read_text()
    assert tex.index("What failed") < tex.index("Every result at a glance")


def quantity_of(value, kind="value"):
    return {"value": value, "kind": kind}


DEGENERATE = [
    {"id": "Rem2", "verdict": "HOLDS", "summary": "equal margins",
     "evidence": {"hunt": {"smallest_margin": quantity_of(1.0, "margin"), "margins": [1.0, 1.0, 1.0]}}},
    {"id": "EQ-schur", "check": "EQ-schur:a", "verdict": "VIOLATED", "summary": "negative and junk margins",
     "evidence": {"hunt": {"margins": [-1e-3, 0.5, 2, "nan", None]}}},
    {"id": "EQ-schur", "check": "EQ-schur:b", "verdict": "HOLDS", "summary": "no margins",
     "evidence": {"hunt": {"margins": []}}},
    {"id": "Def2", "verdict": "HOLDS", "summary": "bracket closes to zero",
     "evidence": {"bracket": {"lower": quantity_of(1.0), "convergence": [[0.1, 0.0, 2.0], [0.2, 1.0, 1.0], [1]]}}},
    {"id": "Thm3", "verdict": "HOLDS", "summary": "odd constants",
     "evidence": {"constants": {"paper": quantity_of("inf"), "certified": quantity_of(-2.0), "observed": 0}}},
    {"id": "CX-sphere", "verdict": "HOLDS", "summary": "series with junk on log axes",
     "evidence": {"series": {"x_log": True, "y_log": True, "lines": {"a": [[-1, 2], [0, 0], [1, 1]], "b": [],
                                                                    "c": [[1, "x"], [2]]}}}},
    {"id": "GRE-physics", "verdict": "HOLDS", "summary": "bad data files", "evidence": {},
     "artifacts": ["data/work_precision.json", "data/stability.json", "data/other.json", "data/broken.json"]},
]


def test_degenerate_plot_data_still_makes_a_report(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "work_precision.json").write_text(json.dumps(
        [{"scene": "s", "method": "m", "seconds": 0, "error": 0}, {"method": "m", "seconds": 1, "error": "nan"}]))
    (tmp_path / "data" / "stability.json").write_text(json.dumps({"rows": [{"scene": "a", "status": "failed"}]}))
    (tmp_path / "data" / "other.json").write_text(json.dumps({"nested": {"a": {"b": 1}, "c": {"b": 2}}}))
    (tmp_path / "data" / "broken.json").write_text("{nope")
    doc = {"schema": "inertiaproof.results/1", "checks": DEGENERATE}
    (tmp_path / "results.json").write_text(json.dumps(doc))
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        build(tmp_path, pdf=False)
    page = (tmp_path / "report.html").read_text()
    assert "data/broken.json: not JSON" in page
    assert page.count('<figure class="plot"') >= 6


text = st.text(st.characters(codec="utf-8", exclude_categories=("Cs",)), max_size=30)
json_values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | text
    | st.builds(quantity_of, st.floats(allow_nan=False) | text, st.sampled_from(sorted(KINDS))),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(text, inner, max_size=4), max_leaves=20)


@settings(max_examples=40, deadline=None)
@given(evidence=st.dictionaries(text, json_values, max_size=5), summary=text, note=text)
def test_any_evidence_renders_escaped(evidence, summary, note):
    doc = {"schema": "inertiaproof.results/1", "checks": [
        {"id": "Prop1", "check": "Prop1:" + note, "verdict": "INCONCLUSIVE", "summary": summary,
         "evidence": evidence, "counterexample": {"kind": note, "data": evidence, "file": note}}]}
    document = content.build(doc, {})
    svgs = {f.key: "<svg></svg>" for f in document.figures()}
    page = parse(html.render(document, svgs))
    assert "script" not in [t for t, _ in page.tags]
    assert " ".join(summary.split()) in " ".join("".join(page.text).split())
    tex = latex.render(document)
    body = re.sub(r"\\[{}]", "", tex[tex.index(r"\begin{document}"):])
    assert tex.count(r"\begin{") == tex.count(r"\end{") and body.count("{") == body.count("}")
    assert not re.search(r"[\x00-\x08\x0b-\x1f\x7f]", tex)


def test_a_headline_copied_from_one_case_is_shown_once():
    case = {"paper": quantity_of(2.0, "paper_constant"), "observed": quantity_of(1.0, "sampled")}
    other = {"paper": quantity_of(3.0, "paper_constant"), "observed": quantity_of(1.0, "sampled")}
    found, *_ = evidence.split({"constants": case, "scenes": {"a": {"constants": dict(case)},
                                                              "b": {"constants": other}}})
    assert [path for path, _ in found["constants"]] == [("scenes", "a"), ("scenes", "b")]
