"""``inertiaproof report DIR`` and the ``build`` that ``inertiaproof run --report`` and ``audit --report`` call.

From DIR/results.json: DIR/report.html (self-contained), DIR/report.tex with
the figures in DIR/report-figures.pdf, and DIR/report.pdf when latexmk is
installed. From DIR/audit.json the same as DIR/audit.*, from DIR/adapt.json as DIR/adapt.*. Any of them.
"""

from __future__ import annotations

import sys
from pathlib import Path

__all__ = ["build", "configure", "main", "STEMS"]

STEMS = ("report", "audit", "adapt")


def configure(parser):
    parser.add_argument("dir", metavar="DIR", help="a run's output folder (holds results.json, audit.json, adapt.json)")
    parser.add_argument("--no-pdf", action="store_true", help="write the .html and .tex files only; skip latexmk")


def main(args):
    written, problems = _build(Path(args.dir), not args.no_pdf, STEMS)
    for path in written:
        print(f"report: {path}")
    for problem in problems:
        print(f"inertiaproof: error: {problem}", file=sys.stderr)
    return 1 if problems else 0


def build(out_dir, pdf=True, only=STEMS):
    """Write the reports of out_dir (``only`` of "report", "audit"); returns the written paths.

    A failed PDF is reported on stderr, not raised.
    """
    written, problems = _build(Path(out_dir), pdf, only)
    for problem in problems:
        print(f"inertiaproof: warning: {problem}", file=sys.stderr)
    return written


def _build(out, pdf, only):
    written, problems = [], []
    for stem, document in _documents(out, only):
        paths, problem = _render(out, stem, document, pdf)
        written += paths
        problems += [problem] if problem else []
    return written, problems


def _documents(out, only):
    """(stem, Document) of each source in out: results.json as "report", audit.json as "audit", adapt.json as
    "adapt"."""
    from inertiaproof.report import adapt, audit, content, load

    has_audit = "audit" in only and (out / load.AUDIT).is_file()
    has_adapt = "adapt" in only and (out / adapt.ADAPT).is_file()
    if "report" in only and (not (has_audit or has_adapt) or (out / "results.json").is_file()):
        doc = load.results(out)  # names what is missing when out holds none
        yield "report", content.build(doc, load.data_files(out, doc), load.mutation(out), load.bracket_narrowing(out))
    if has_audit:
        yield "audit", audit.build(load.audit(out / load.AUDIT))
    if has_adapt:
        yield "adapt", adapt.build(adapt.load(out / adapt.ADAPT))


def _render(out, stem, document, pdf):
    """Write out/stem.html, .tex, -figures.pdf (and .pdf); returns (written paths, a problem or None)."""
    from inertiaproof.report import html, latex, plots, typeset

    figures = document.figures()
    figure_file = out / f"{stem}-figures.pdf"
    figure_file.unlink(missing_ok=True)
    svgs = plots.render(figures, figure_file) if figures else {}
    tex = out / f"{stem}.tex"
    written = [_write(out / f"{stem}.html", html.render(document, svgs)),
               _write(tex, latex.render(document, figure_file.name))]
    if figures:
        written.append(figure_file)
    if not pdf:
        return written, None
    if not typeset.available():
        print(f"report: no {stem}.pdf: latexmk is not installed (Debian: texlive-latex-recommended latexmk)",
              file=sys.stderr)
        return written, None
    try:
        written.append(typeset.pdf(tex, [figure_file] if figures else []))
    except typeset.TypesetError as exc:
        return written, str(exc)
    return written, None


def _write(path, text):
    path.write_text(text, encoding="utf-8")
    return path
