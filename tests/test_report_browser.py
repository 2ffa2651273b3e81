"""The HTML report opened in headless Chromium: the DOM it builds (no scripts in it) and a screenshot.

The screenshot (and the HTML) are kept in artifacts/report/ ($INERTIAPROOF_ARTIFACTS/report/).
"""

import shutil
from html.parser import HTMLParser

import pytest
import report_fixture
from inertiaproof.report import content, load
from readback import CHROMIUM, chromium

from inertiaproof.suite import catalog

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (CI installs Debian's chromium)")]
VIOLATED_RGB = (0xB0, 0x2A, 0x1E)
PLOT_BLUE_RGB = (0x1F, 0x77, 0xB4)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out, _ = report_fixture.built(tmp_path_factory)
    shutil.copy(out / "report.html", report_fixture.artifacts_dir() / "report.html")
    return out


class Tree(HTMLParser):
    """What the DOM holds: sections by catalog ID, verdict badges, plots with their SVGs, text, script elements."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.sections, self.badges, self.plots, self.scripts, self.text = {}, [], [], 0, []
        self.open_plot = None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "section" and "data-id" in attrs:
            self.sections[attrs["data-id"]] = attrs.get("data-verdict")
        if tag == "span" and "verdict" in (attrs.get("class") or "").split():
            self.badges.append(attrs["class"].split()[-1].removeprefix("tone-"))
        if tag == "figure" and attrs.get("class") == "plot":
            self.open_plot = {"id": attrs.get("id"), "kind": attrs.get("data-plot"), "svg": 0, "paths": 0}
            self.plots.append(self.open_plot)
        if self.open_plot is not None and tag == "svg":
            self.open_plot["svg"] += 1
        if self.open_plot is not None and tag in ("path", "use"):
            self.open_plot["paths"] += 1
        self.scripts += tag == "script"

    def handle_endtag(self, tag):
        if tag == "figure":
            self.open_plot = None

    def handle_data(self, data):
        self.text.append(data)


def test_the_browser_dom_has_every_result_verdict_and_plot(report, tmp_path):
    tree = Tree()
    tree.feed(chromium(report / "report.html", tmp_path, "--dump-dom"))
    assert set(tree.sections) == {e.id for e in catalog.ENTRIES} | {"gate"}
    assert tree.sections["Thm4"] == "VIOLATED" and tree.sections["Cor2"] == "INCONCLUSIVE"
    assert {"HOLDS", "VIOLATED", "INCONCLUSIVE"} <= set(tree.badges)
    doc = load.results(report)
    figures = content.build(doc, load.data_files(report, doc)).figures()
    assert [(p["id"], p["kind"]) for p in tree.plots] == [(f.key, f.kind) for f in figures]
    assert all(p["svg"] == 1 and p["paths"] > 5 for p in tree.plots), tree.plots
    assert tree.scripts == 0
    text = "".join(tree.text)
    assert report_fixture.HOSTILE in text
    assert "What failed: 1 check found a counterexample" in text


def test_screenshot_shows_the_failure_first_and_the_plots(report, tmp_path):
    from PIL import Image

    shot = report_fixture.artifacts_dir() / "report-screenshot.png"
    shot.unlink(missing_ok=True)
    chromium(report / "report.html", tmp_path, f"--screenshot={shot}", "--window-size=1280,4000")
    print(f"screenshot: {shot}")
    image = Image.open(shot).convert("RGB")
    assert image.size == (1280, 4000)

    def near(rgb, box):
        region = image.crop(box)
        return sum(count for count, pixel in region.getcolors(1 << 20)
                   if max(abs(a - b) for a, b in zip(pixel, rgb)) < 24)

    assert near(VIOLATED_RGB, (0, 0, 1280, 700)) > 300, "no red 'What failed' box near the top"
    assert near(PLOT_BLUE_RGB, (0, 0, 1280, 4000)) > 100, "no plot drawn in the first 4000 pixels"
    white = near((255, 255, 255), (0, 0, 1280, 4000))
    assert white < 0.97 * 1280 * 4000, "the page is (almost) blank"
