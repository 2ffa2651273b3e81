"""The LaTeX report compiled to PDF, read back as a person would: pages, text, fonts, nothing past the margins."""

import json
import re
import shutil

import pytest
import report_fixture
from inertiaproof.report import typeset
from inertiaproof.report.paper_names import printed
from readback import pages, past_the_margins, run, squeeze

from inertiaproof.suite import catalog

pytestmark = [
    pytest.mark.latex,
    pytest.mark.skipif(not typeset.available(), reason="latexmk/pdflatex not installed (CI installs texlive-latex-* "
                                                       "and latexmk)"),
    pytest.mark.skipif(shutil.which("pdftotext") is None, reason="pdftotext not installed (Debian: poppler-utils)"),
]


@pytest.fixture(scope="module")
def pdf(tmp_path_factory):
    out, _ = report_fixture.built(tmp_path_factory)
    path = out / "report.pdf"
    assert path.is_file(), "the report build made no report.pdf although latexmk is installed"
    shutil.copy(path, report_fixture.artifacts_dir() / "report.pdf")
    return path


def test_pages_and_reading_order(pdf):
    info = run("pdfinfo", str(pdf))
    count = int(re.search(r"Pages:\s+(\d+)", info).group(1))
    assert 10 <= count <= 24, count
    text = pages(pdf)
    assert len(text) == count
    first = text[0]
    assert "inertiaproof report" in first and "What failed: 1 check found a counterexample" in first
    assert first.index("What failed") < first.index("Every result at a glance")
    assert squeeze(f"inertiaproof replay {report_fixture.VIOLATED_FILE}") in squeeze(first)
    whole = "\n".join(text)
    order = ["Summary", "Bounds at a glance", "Section 2: Physical consistency", "Section 3: The generalized robotics",
             "Section 4: Structural properties", "Beyond the paper", "How to read the numbers"]
    order += ["Appendix: mutation testing"] if "Appendix: mutation testing" in whole else []  # bench/results/mutation.json
    positions = [whole.index(heading) for heading in order]
    assert positions == sorted(positions)
    assert order[-1] in "".join(text[-count // 2:])


def test_every_id_verdict_and_figure(pdf):
    whole = "\n".join(pages(pdf))
    flat = squeeze("\n".join(pages(pdf, "-raw")))
    for entry in catalog.ENTRIES:
        assert squeeze(f"{entry.id}: {printed(entry.label)}") in flat, entry.id  # as the paper prints it
    for verdict in ("HOLDS", "VIOLATED", "INCONCLUSIVE"):
        assert verdict in whole
    numbers = [int(n) for n in re.findall(r"Figure (\d+)\.", whole)]
    assert numbers == list(range(1, max(numbers) + 1)) and len(numbers) >= 12
    assert "run time spent narrowing [s]" in whole and "observed worst case" in whole


def test_hostile_strings_print_as_themselves(pdf):
    flat = squeeze("\n".join(pages(pdf, "-raw")))
    in_code = json.dumps(report_fixture.HOSTILE, ensure_ascii=False)
    assert squeeze(in_code) in flat
    in_prose = squeeze(report_fixture.HOSTILE).replace("'", "\u2019").replace("`", "\u2018")
    assert in_prose in flat
    assert squeeze(report_fixture.LONG_EXACT) in flat
    assert squeeze(json.dumps(report_fixture.ASCII)) in flat
    assert squeeze(report_fixture.ASCII).replace("'", "\u2019").replace("`", "\u2018") in flat


def test_fonts_are_vector_and_figures_truetype(pdf):
    fonts = run("pdffonts", str(pdf))
    assert "Type 3" not in fonts
    assert re.search(r"DejaVuSans\s+CID TrueType", fonts)


def test_nothing_runs_past_the_margins(pdf):
    outside, words = past_the_margins(pdf)
    assert words > 2000
    assert not outside, outside[:10]


def test_first_page_shows_the_failure_in_red(pdf):
    from PIL import Image

    if shutil.which("pdftoppm") is None:
        pytest.skip("pdftoppm not installed (Debian: poppler-utils)")
    stem = report_fixture.artifacts_dir() / "report-page"
    run("pdftoppm", "-r", "60", "-f", "1", "-l", "1", "-singlefile", "-png", str(pdf), str(stem))
    image = Image.open(f"{stem}.png").convert("RGB")
    width, height = image.size
    red = sum(count for count, (r, g, b) in image.crop((0, 0, width, height // 2)).getcolors(1 << 20)
              if r > 140 and g < 80 and b < 70)
    assert red > 200, "no red 'What failed' rule and title in the top half of page 1"


def test_a_latex_error_names_the_log_and_the_line(tmp_path):
    tex = tmp_path / "report.tex"
    tex.write_text("\\documentclass{article}\n\\begin{document}\n\\undefinedmacro\n\\end{document}\n")
    with pytest.raises(typeset.TypesetError) as caught:
        typeset.pdf(tex)
    message = str(caught.value)
    assert "report.tex:3: Undefined control sequence" in message and str(tmp_path / "report.log") in message
    assert not (tmp_path / "report.pdf").exists() and not (tmp_path / "report.aux").exists()
