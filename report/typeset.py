"""report.tex to report.pdf with latexmk, in a scratch folder so DIR keeps no auxiliary files."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

__all__ = ["available", "pdf", "SOURCE_DATE_EPOCH", "TIMEOUT_S", "TypesetError"]

SOURCE_DATE_EPOCH = "1700000000"
TIMEOUT_S = 300


class TypesetError(RuntimeError):
    """latexmk ran but made no PDF; the message names the log and its first error."""


def available():
    return shutil.which("latexmk") is not None and shutil.which("pdflatex") is not None


def pdf(tex_path, extra_files=()):
    """Compile tex_path (with extra_files beside it) to a PDF next to it; returns the PDF's path."""
    tex_path = Path(tex_path)
    target = tex_path.with_suffix(".pdf")
    env = {**os.environ, "SOURCE_DATE_EPOCH": SOURCE_DATE_EPOCH, "FORCE_SOURCE_DATE": "1"}
    with tempfile.TemporaryDirectory(prefix="inertiaproof-tex-") as scratch:
        for path in (tex_path, *map(Path, extra_files)):
            shutil.copy(path, Path(scratch) / path.name)
        command = ["latexmk", "-pdf", "-interaction=nonstopmode", "-halt-on-error", "-file-line-error", "-quiet",
                   tex_path.name]
        try:
            done = subprocess.run(command, cwd=scratch, env=env, stdin=subprocess.DEVNULL, capture_output=True,
                                  text=True, timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            raise TypesetError(f"latexmk on {tex_path} took more than {TIMEOUT_S} s") from None
        made = Path(scratch) / target.name
        log = Path(scratch) / tex_path.with_suffix(".log").name
        if done.returncode != 0 or not made.is_file():
            kept = tex_path.with_suffix(".log")
            if log.is_file():
                shutil.copy(log, kept)
            raise TypesetError(f"latexmk could not compile {tex_path}: {_first_error(log)} (log: {kept})")
        shutil.copy(made, target)
    return target


def _first_error(log):
    try:
        lines = log.read_text(errors="replace").splitlines()
    except OSError:
        return "no log written"
    for line in lines:
        if line.startswith("!") or re.match(r"\S+\.tex:\d+: ", line):
            return line.strip()
    return "see the log"
