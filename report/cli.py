"""``inertiaproof report DIR`` and the ``build`` that ``inertiaproof run --report`` calls.

Writes DIR/report.html (self-contained), DIR/report.tex with the figures in
DIR/report-figures.pdf, and DIR/report.pdf when latexmk is installed.
"""

from __future__ import annotations

import sys
from pathlib import Path


def configure(parser):
    parser.add_argument("dir", metavar="DIR", help="a run's output folder (holds results.json)")
    parser.add_argument("--no-pdf", action="store_true", help="write report.html and report.tex only; skip latexmk")


def main(args):
    written, problem = _build(Path(args.dir), pdf=not args.no_pdf)
    for path in written:
        print(f"report: {path}")
    if problem:
        print(f"inertiaproof: error: {problem}", file=sys.stderr)
        return 1
    return 0


def build(out_dir, pdf=True):
    """Write the report of out_dir; returns the written paths (a failed PDF is reported on stderr, not raised)."""
    written, problem = _build(Path(out_dir), pdf=pdf)
    if problem:
        print(f"inertiaproof: warning: {problem}", file=sys.stderr)
    return written


def _build(out, pdf):
    from . import content, html, latex, load, plots, typeset

    doc = load.results(out)
    document = content.build(doc, load.data_files(out, doc))
    figures = document.figures()
    (out / latex.FIGURES).unlink(missing_ok=True)
    svgs = plots.render(figures, out / latex.FIGURES) if figures else {}
    written = [_write(out / "report.html", html.render(document, svgs)),
               _write(out / "report.tex", latex.render(document))]
    if figures:
        written.append(out / latex.FIGURES)
    if not pdf:
        return written, None
    if not typeset.available():
        print("report: no report.pdf: latexmk is not installed (Debian: texlive-latex-recommended latexmk)",
              file=sys.stderr)
        return written, None
    try:
        written.append(typeset.pdf(out / "report.tex", [out / latex.FIGURES] if figures else []))
    except typeset.TypesetError as exc:
        return written, str(exc)
    return written, None


def _write(path, text):
    path.write_text(text, encoding="utf-8")
    return path
