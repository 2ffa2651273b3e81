"""The audit's report (``audit --report DIR``, ``report DIR``): real robots read back from the PDF and from headless
Chromium, byte-identical rebuilds, hostile names, and one-line errors on a broken audit.json.

The PDF, the HTML and a screenshot of the three robots are kept in artifacts/report/.
"""

import io
import json
import re
import shutil
from contextlib import redirect_stderr, redirect_stdout
from html.parser import HTMLParser
from xml.sax.saxutils import quoteattr

import pytest
import report_fixture
from inertiaproof.report import load, typeset
from readback import CHROMIUM, chromium, pages, past_the_margins, run, squeeze
from urdf_samples import inertial, joint, link, robot, robots_folder, two_link_arm, write

from inertiaproof import cli

ROBOTS = robots_folder()
THREE = ("panda_description/urdf/panda.urdf", "ur_description/urdf/ur5_robot.urdf",
         "allegro_hand_description/urdf/allegro_right_hand.urdf")
ALLEGRO_BAD = ("link_3.0", "link_7.0", "link_11.0", "link_15.0")
PDF = typeset.available() and shutil.which("pdftotext") is not None
needs_robots = pytest.mark.skipif(ROBOTS is None, reason="example-robot-data is not installed (test extra)")
needs_pdf = pytest.mark.skipif(not PDF, reason="latexmk/pdflatex or pdftotext not installed (CI installs them)")
needs_browser = pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (CI installs Debian's chromium)")
HOSTILE = "$\\end{document}$ a_b#1 $x^2$ 100% & {br} ~t ^c <script>alert(\"x\")</script> 'q' λ`--`"
LONG = "on_and_on_without_any_break_at_all_" + "1234567890" * 4


def audit(*argv):
    """(exit status, stdout, stderr) of ``inertiaproof audit ...``."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = cli.main(["audit", *map(str, argv)])
    return code, out.getvalue(), err.getvalue()


def report(folder, *flags):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = cli.main(["report", str(folder), *flags])
    return code, out.getvalue(), err.getvalue()


class Sections(HTMLParser):
    """The page's text per file section (data-id = the file's path), its tags and its figures."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.text, self.tags, self.figures, self.open = {}, [], [], [None]

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append(tag)
        if tag == "section":
            self.open.append(attrs.get("data-id", self.open[-1]))
        if tag == "figure":
            self.figures.append(0)
        if tag == "svg" and self.figures:
            self.figures[-1] += 1

    def handle_endtag(self, tag):
        if tag == "section":
            self.open.pop()

    def handle_data(self, data):
        self.text.setdefault(self.open[-1], []).append(data)

    def of(self, key):
        return "".join(self.text.get(key, []))


def parse(page):
    p = Sections()
    p.feed(page)
    return p


@pytest.fixture(scope="module")
def three(tmp_path_factory):
    """Panda, UR5 and the right Allegro hand audited with --report (with audit.pdf when latexmk is installed)."""
    if ROBOTS is None:
        pytest.skip("example-robot-data is not installed (test extra)")
    out = tmp_path_factory.mktemp("audit-three")
    code, printed, _ = audit(*(ROBOTS / f for f in THREE), "--report", out)
    assert code == 1  # the Allegro fingertips
    kept = report_fixture.artifacts_dir()
    for name in ("audit.html", "audit.pdf"):
        if (out / name).is_file():
            shutil.copy(out / name, kept / name)
    return out, printed


@needs_robots
def test_report_writes_json_html_tex_and_pdf(three):
    out, printed = three
    names = ["audit.json", "audit.html", "audit.tex", "audit-figures.pdf"] + (["audit.pdf"] if typeset.available() else [])
    assert [line for line in printed.splitlines() if line.startswith("report: ")] == [f"report: {out / n}" for n in names]
    doc = load.audit(out / "audit.json")
    assert [p.rsplit("/", 1)[-1] for p in doc["files"]] == [f.rsplit("/", 1)[-1] for f in THREE]


@needs_robots
@needs_pdf
def test_pdf_shows_the_robots_the_inconsistent_links_and_the_repairs(three):
    pdf = three[0] / "audit.pdf"
    text = pages(pdf)
    assert 5 <= len(text) <= 16, len(text)
    whole, flat = "\n".join(text), squeeze("\n".join(pages(pdf, "-raw")))
    assert "Not consistent: 1 file" in text[0]
    for path in THREE:
        assert squeeze(path.split("/", 1)[1]) in flat
    for name in ("robot’panda’", "robot’ur5’", "robot’allegro_hand_right’"):
        assert name in flat, name
    assert squeeze("allegro_right_hand.urdf: " + ", ".join(ALLEGRO_BAD)) in flat
    assert flat.count(squeeze('<inertia ixx="')) == len(ALLEGRO_BAD)
    assert "Repairs: the nearest consistent inertia about the CoM" in whole
    assert flat.count("Signs:oneentryoffbyapoweroften?") == len(ALLEGRO_BAD)
    assert flat.count("consistentwithixy,iyz,ixznegated:productsofinertiaintheoppositesignconvention") == len(ALLEGRO_BAD)
    assert re.findall(r"Figure (\d+)\.", whole) == ["1", "2"]  # the Panda's and the UR5's bounds
    assert "sharpest certified" in whole and "paper’s constant lies in" in whole
    outside, words = past_the_margins(pdf)
    assert words > 1000 and not outside, outside[:10]
    assert "Type 3" not in run("pdffonts", str(pdf))


@needs_robots
@needs_browser
def test_browser_dom_has_every_file_and_link(three, tmp_path):
    out, _ = three
    doc = json.loads((out / "audit.json").read_text())
    page = parse(chromium(out / "audit.html", tmp_path, "--dump-dom"))
    assert "script" not in page.tags
    for path, f in doc["files"].items():
        text = page.of(path)
        assert f["robot"] in text
        missing = [name for name in f["links"] if name not in text]
        assert not missing, (path, missing)
    assert page.figures == [1, 1]
    assert "Not consistent: 1 file" in page.of(None)


@needs_robots
@needs_browser
def test_screenshot_is_a_page_with_the_failure_on_top(three, tmp_path):
    from PIL import Image

    shot = report_fixture.artifacts_dir() / "audit-screenshot.png"
    shot.unlink(missing_ok=True)
    chromium(three[0] / "audit.html", tmp_path, f"--screenshot={shot}", "--window-size=1280,3000")
    image = Image.open(shot).convert("RGB")
    red = sum(n for n, (r, g, b) in image.crop((0, 0, 1280, 600)).getcolors(1 << 20) if r > 150 and g < 80 and b < 70)
    white = sum(n for n, pixel in image.getcolors(1 << 20) if min(pixel) > 245)
    assert red > 300, "no red 'Not consistent' box near the top"
    assert white < 0.95 * 1280 * 3000, "the page is (almost) blank"


@needs_robots
def test_rebuilding_from_audit_json_gives_identical_files(three, tmp_path):
    out, _ = three
    shutil.copy(out / "audit.json", tmp_path / "audit.json")
    code, printed, _ = report(tmp_path)
    assert code == 0 and "report.html" not in printed
    names = ["audit.html", "audit.tex", "audit-figures.pdf"] + (["audit.pdf"] if typeset.available() else [])
    for name in names:
        assert (tmp_path / name).read_bytes() == (out / name).read_bytes(), name


def _hostile_robot():
    def q(text):
        return quoteattr(text)[1:-1]

    first, second = q(f"first {HOSTILE}"), q(f"{HOSTILE} {LONG}")
    return robot(link("base"), link(first, inertial(1.0, "0.1 0 0.05", "0.3 0.2 0.1")),
                 link(second, inertial(0.05, "0.1 0 0", "0 0 0", 0.001, 0.001, 0.01)),
                 joint(q(f"j1 {HOSTILE}"), "base", first), joint("j2", first, second, xyz="0.3 0 0.05", axis="0 1 0"),
                 name=q(f"robot {HOSTILE}"))


def test_hostile_names_render_safely(tmp_path):
    path = write(tmp_path, _hostile_robot(), "hostile #1 $&%~{}.urdf")
    code, _, err = audit(path, "--report", tmp_path / "out")
    no_latexmk = "report: no audit.pdf: latexmk is not installed (Debian: texlive-latex-recommended latexmk)\n"
    assert code == 1 and err == ("" if typeset.available() else no_latexmk)
    names = [f"first {HOSTILE}", f"{HOSTILE} {LONG}"]
    page = parse((tmp_path / "out" / "audit.html").read_text())
    assert not {"script", "img", "iframe", "object", "link"} & set(page.tags)
    text = page.of(str(path))
    assert all(name in text for name in names) and f"robot {HOSTILE}" in text
    assert "\u03b11 ($\\end{document}$ a_b#1 $x^2$" in text  # the figure's labels print as written, not as mathtext
    if not PDF:
        pytest.skip("the PDF half needs latexmk/pdflatex and pdftotext (CI installs them); the HTML half passed")
    pdf = tmp_path / "out" / "audit.pdf"
    flat = squeeze("\n".join(pages(pdf, "-raw")))
    for name in names:
        assert squeeze(name) in flat, name  # the link column prints names in typewriter, every character as itself
    assert squeeze(str(path)) in flat
    outside, _ = past_the_margins(pdf)
    assert not outside, outside[:10]


def test_report_renders_an_audit_beside_results(tmp_path):
    report_fixture.write(tmp_path)
    code, out, _ = audit(write(tmp_path, two_link_arm()), "--json")
    (tmp_path / "audit.json").write_text(out)
    code, printed, err = report(tmp_path, "--no-pdf")
    assert code == 0 and err == ""
    written = [line.removeprefix("report: ") for line in printed.splitlines()]
    assert [w.rsplit("/", 1)[-1] for w in written if w.endswith(".html")] == ["report.html", "audit.html"]
    assert 'data-id="Thm4"' in (tmp_path / "report.html").read_text()
    assert "robot &#x27;test&#x27;" in (tmp_path / "audit.html").read_text()


def test_an_unreadable_file_and_a_robot_without_chains(tmp_path):
    write(tmp_path, robot(link("a"), joint("j", "a", "ghost")), "bad.urdf")
    write(tmp_path, robot(link("a"), link("b"), joint("j", "a", "b", kind="fixed")), "fixed.urdf")
    code, out, _ = audit(tmp_path, "--json")
    assert code == 2
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "audit.json").write_text(out)
    assert report(tmp_path / "out", "--no-pdf")[0] == 0
    page = parse((tmp_path / "out" / "audit.html").read_text())
    assert "joint 'j': <child link='ghost'> names no link" in page.of(str(tmp_path / "bad.urdf"))
    assert "No chains: no movable joint." in page.of(str(tmp_path / "fixed.urdf"))
    assert "Unreadable: 1 file" in page.of(None)


def _broken(doc, key):
    path = next(iter(doc["files"]))
    f = doc["files"][path]
    if key == "verdict":
        del f["links"]["l2"]["verdict"]
    elif key == "singular":
        f["chains"]["l2"]["singular"] = "never"
    elif key == "status":
        f["status"] = "maybe"
    elif key == "summary":
        doc["summary"]["files"] = "3"
    elif key == "signs":
        f["links"]["l2"]["signs"] = [{"sign": "x"}]
    return json.dumps(doc)


@pytest.mark.parametrize("key, message", [
    ("json", "audit.json: not JSON"),
    ("schema", "audit.json: not an inertiaproof audit file (schema inertiaproof.audit/1)"),
    ("verdict", "audit.json: files[{path!r}].links['l2']: no 'verdict'"),
    ("singular", "audit.json: files[{path!r}].chains['l2'].singular: must be an object"),
    ("status", "audit.json: files[{path!r}].status: must be 'ok' or 'error'"),
    ("summary", "audit.json: summary.files: must be an integer"),
    ("signs", "audit.json: files[{path!r}].links['l2'].signs[0]: no 'text'"),
])
def test_a_broken_audit_json_is_one_line_naming_the_file_and_the_place(tmp_path, key, message):
    path = write(tmp_path, two_link_arm())
    doc = json.loads(audit(path, "--json")[1])
    text = {"json": "{", "schema": json.dumps({**doc, "schema": "inertiaproof.results/1"})}.get(key) or _broken(doc, key)
    (tmp_path / "audit.json").write_text(text)
    code, _, err = report(tmp_path, "--no-pdf")
    assert code == 2 and err.count("\n") == 1, err
    assert f"{tmp_path}/{message.format(path=str(path))}" in err, err
