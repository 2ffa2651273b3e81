"""Reading a built report back as a person would: the PDF's text (poppler) and the HTML in headless Chromium."""

import re
import shutil
import subprocess

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--no-first-run", "--hide-scrollbars")
A4_WIDTH_PT = 595.28
MARGIN_PT = 56.69


def chromium(page, tmp_path, *args):
    done = subprocess.run([CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", *args, page.as_uri()],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout


def run(*command):
    return subprocess.run(command, capture_output=True, text=True, check=True, timeout=60).stdout


def pages(path, mode="-layout"):
    """The text of each page: -layout as it looks, -raw in the order it was typeset (table cells whole)."""
    return run("pdftotext", mode, str(path), "-").split("\f")[:-1]


def squeeze(text):
    return re.sub(r"\s+", "", text)


def past_the_margins(path):
    """Words of the PDF outside the text block's width (A4, 2 cm margins); also how many words there are."""
    boxes = run("pdftotext", "-bbox", str(path), "-")
    words = re.findall(r'<word xMin="([\d.]+)" yMin="[\d.]+" xMax="([\d.]+)" yMax="[\d.]+">(.*?)</word>', boxes)
    outside = [(w, float(a), float(b)) for a, b, w in words
               if float(a) < MARGIN_PT - 1 or float(b) > A4_WIDTH_PT - MARGIN_PT + 1]
    return outside, len(words)
