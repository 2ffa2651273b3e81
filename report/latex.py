"""A report Document as a LaTeX file for Debian's texlive-latex-base and -recommended (pdflatex, OT1 fonts).

Every string is escaped so that any character prints as itself; the
typewriter font prints ASCII through \\char codes (pdftotext reads them back),
and long tokens (IDs, hashes, numbers) may break anywhere, so nothing
overflows a table column. Figures are pages of one PDF file.
"""

from __future__ import annotations

import re
import unicodedata
from importlib import resources

from inertiaproof.report.model import Badge, Bullets, Code, Figure, Link, Notice, Paragraph, Table, Text

__all__ = [
    "ACCENTS", "BREAK_AFTER", "escape", "FIGURES", "GREEK", "LETTERS", "LONG_TOKEN", "render", "ROMAN", "SECTIONS",
    "SYMBOLS", "TEXT", "TYPEWRITER",
]

FIGURES = "report-figures.pdf"
LONG_TOKEN = {False: 14, True: 8}
BREAK_AFTER = set("/_-.,:;=")
SECTIONS = ("section", "subsection", "subsubsection", "paragraph")

ROMAN = {"\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"{\ttfamily\char36}", "&": r"\&", "#": r"\#",
         "%": r"\%",
         "_": r"{\ttfamily\char95}", "^": r"{\ttfamily\char94}", "~": r"{\ttfamily\char126}", "<": r"\textless{}",
         ">": r"\textgreater{}", "|": r"\textbar{}", '"': r"{\ttfamily\char34}", "'": "'{}", "`": "`{}", "-": "-{}",
         "!": "!{}", "?": "?{}"}
TYPEWRITER = {c: rf"\char{ord(c)}{{}}" for c in "\\{}$&#%_^~<>|\""}
TYPEWRITER.update({"'": r"\char13{}", "`": r"\char18{}", "-": "-{}", "!": "!{}", "?": "?{}"})
SYMBOLS = {"\u2264": r"\le", "\u2265": r"\ge", "\u2260": r"\ne", "\u2248": r"\approx", "\u00d7": r"\times",
           "\u00b7": r"\cdot", "\u2212": "-", "\u2192": r"\to", "\u221e": r"\infty", "\u221a": r"\surd",
           "\u00b1": r"\pm", "\u2016": r"\|", "\u2208": r"\in", "\u2211": r"\sum", "\u2202": r"\partial",
           "\u2207": r"\nabla", "\u227b": r"\succ", "\u227a": r"\prec", "\u2ab0": r"\succeq", "\u2aaf": r"\preceq",
           "\u2200": r"\forall", "\u2203": r"\exists", "\u21d2": r"\Rightarrow", "\u21d4": r"\Leftrightarrow"}
TEXT = {"\u2014": ("---", "--"), "\u2013": ("--", "-"), "\u2026": (r"\ldots{}", "..."), "\u2018": ("`", "'"),
        "\u2019": ("'", "'"), "\u201c": ("``", '"'), "\u201d": ("''", '"'), "\u00a0": ("~", " ")}
GREEK = dict(zip(
    [chr(c) for c in (*range(0x3B1, 0x3C2), 0x3C2, *range(0x3C3, 0x3CA))],
    "alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi o pi rho varsigma sigma tau upsilon phi "
    "chi psi omega".split()))
GREEK.update(zip("\u0393\u0394\u0398\u039b\u039e\u03a0\u03a3\u03a5\u03a6\u03a8\u03a9",
                 "Gamma Delta Theta Lambda Xi Pi Sigma Upsilon Phi Psi Omega".split()))
LETTERS = {"\u00df": r"\ss{}", "\u00e6": r"\ae{}", "\u00c6": r"\AE{}", "\u00f8": r"\o{}", "\u00d8": r"\O{}",
           "\u0153": r"\oe{}", "\u0152": r"\OE{}", "\u0131": r"\i{}", "\u0142": r"\l{}", "\u0141": r"\L{}"}
ACCENTS = {"\u0300": "`", "\u0301": "'", "\u0302": "^", "\u0303": "~", "\u0308": '"', "\u030a": "r",
           "\u0327": "c", "\u030c": "v", "\u0304": "=", "\u0306": "u", "\u0307": ".", "\u030b": "H"}


def render(document, figures=FIGURES):
    """The LaTeX source; its figures are the pages of the PDF file named ``figures``, beside it."""
    preamble = resources.files(__package__).joinpath("preamble.tex").read_text(encoding="utf-8")
    out = [preamble, f"\\hypersetup{{pdftitle={{{_pdf_string(document.title)}}}}}", r"\begin{document}",
           r"\raggedright",
           r"\begin{center}", rf"{{\LARGE\bfseries {escape(document.title)}\par}}\smallskip",
           rf"{{\itshape {escape(document.subtitle)}\par}}", r"\end{center}"]
    for section in document.sections:
        out.append(_section(section, 0, figures))
    out.append(r"\end{document}")
    return "\n".join(out) + "\n"


def escape(text, code=False):
    """Text for LaTeX: every character prints as itself; long tokens may break anywhere."""
    table = TYPEWRITER if code else ROMAN
    pieces = []
    for token in re.split(r"(\s+)", text):
        if not token:
            continue
        if token.isspace():
            pieces.append(" ")
            continue
        if len(token) > LONG_TOKEN[code]:
            pieces.append("".join(_char(c, table, code) + (r"\allowbreak{}" if c in BREAK_AFTER else r"\bk{}")
                                  for c in token[:-1]) + _char(token[-1], table, code))
        else:
            pieces.append("".join(_char(c, table, code) for c in token))
    return "".join(pieces)


def _char(c, table, code):
    if c in table:
        return table[c]
    if c.isascii():
        return c if c.isprintable() else " "
    if c in SYMBOLS:
        return rf"\ensuremath{{{SYMBOLS[c]}}}"
    if c in TEXT:
        return TEXT[c][1 if code else 0]
    if c in GREEK:
        return GREEK[c] if GREEK[c] == "o" else rf"\ensuremath{{\{GREEK[c]}}}"
    if c in LETTERS:
        return LETTERS[c]
    base, *marks = unicodedata.normalize("NFD", c)
    if base.isascii() and base.isalpha() and len(marks) == 1 and marks[0] in ACCENTS:
        return rf"\{ACCENTS[marks[0]]}{{{base}}}"
    return rf"\texttt{{[U+{ord(c):04X}]}}"


def _section(section, depth, figures):
    command = SECTIONS[min(depth, len(SECTIONS) - 1)]
    title = _inlines(section.title)
    bookmark = _pdf_string("".join(_plain(x) for x in section.title))
    parts = [rf"\hypertarget{{{section.key}}}{{}}%", rf"\{command}{{\texorpdfstring{{{title}}}{{{bookmark}}}}}"]
    parts += [_block(b, figures) for b in section.blocks]
    parts += [_section(c, depth + 1, figures) for c in section.children]
    return "\n".join(parts)


def _block(block, figures):
    if isinstance(block, Paragraph):
        return _inlines(block.inlines) + "\n"
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Bullets):
        items = "\n".join(rf"\item {_inlines(item)}" for item in block.items)
        return f"\\begin{{itemize}}\n{items}\n\\end{{itemize}}"
    if isinstance(block, Code):
        return _code(block)
    if isinstance(block, Figure):
        return (rf"\par\medskip\noindent\begin{{minipage}}{{\linewidth}}\hypertarget{{{block.key}}}{{}}\centering"
                "\n" rf"\includegraphics[width=\linewidth,height=0.8\textheight,keepaspectratio,page={block.number}]"
                rf"{{{figures}}}\par\smallskip" "\n"
                rf"\figurecaption{{{block.number}}}{{{escape(block.caption)}}}" "\n" r"\end{minipage}\par\medskip")
    if isinstance(block, Notice):
        inner = "\n".join(_block(b, figures) for b in block.blocks)
        return f"\\begin{{notice}}{{{_color(block.tone)}}}{{{escape(block.title)}}}\n{inner}\n\\end{{notice}}"
    raise TypeError(f"no LaTeX for {type(block).__name__}")


def _table(table):
    n = len(table.columns)
    spec = "".join(
        rf">{{\{'raggedleft' if c.align == 'r' else 'raggedright'}\arraybackslash}}"
        rf"p{{\dimexpr {c.width:.3f}\linewidth-2\tabcolsep\relax}}" for c in table.columns)
    head = " & ".join(rf"\textbf{{{escape(c.title)}}}" for c in table.columns) + r" \\"
    lines = [rf"\begin{{longtable}}{{@{{}}{spec}@{{}}}}"]
    if table.caption:
        lines.append(_span(n, rf"\textbf{{{escape(table.caption)}}}"))
    if any(c.title for c in table.columns):
        lines += [r"\toprule", head, r"\midrule", r"\endfirsthead", r"\toprule", head, r"\midrule", r"\endhead"]
    else:
        # an empty row of the columns in the first head fixes their widths in the first pass (one pdflatex run less)
        lines += [r"\toprule", "&" * (n - 1) + r"\\[-\normalbaselineskip]", r"\endfirsthead", r"\toprule", r"\endhead"]
    lines += [r"\bottomrule", r"\endlastfoot"]
    for row in table.rows:
        lines.append(_span(n, _inlines(row[0])) if len(row) == 1 else " & ".join(_inlines(c) for c in row) + r" \\")
    lines.append(r"\end{longtable}")
    return "\n".join(lines)


def _span(columns, content):
    return (rf"\multicolumn{{{columns}}}{{@{{}}>{{\raggedright\arraybackslash}}p{{\dimexpr\linewidth-2\tabcolsep\relax}}@{{}}}}"
            rf"{{{content}}} \\")


def _code(block):
    lines = block.text.splitlines() or [""]
    body = "\\\\\n".join(r"\mbox{}" + _code_line(line) for line in lines)
    caption = rf"{{\small\itshape {escape(block.caption)}}}\par\nopagebreak" "\n" if block.caption else ""
    return f"{caption}\\begin{{codeblock}}\n{body}\n\\end{{codeblock}}"


def _code_line(line):
    indent = len(line) - len(line.lstrip(" "))
    return r"\ " * indent + escape(line[indent:], code=True).replace(" ", r"\ ")


def _inlines(inlines):
    return "".join(_inline(x) for x in inlines)


def _inline(x):
    if isinstance(x, Text):
        if x.style == "code":
            return rf"\texttt{{{escape(x.text, code=True)}}}"
        text = escape(x.text)
        return {"strong": rf"\textbf{{{text}}}", "em": rf"\emph{{{text}}}"}.get(x.style, text)
    if isinstance(x, Link):
        text = rf"\texttt{{{escape(x.text, code=True)}}}" if x.style == "code" else escape(x.text)
        return rf"\hyperlink{{{x.target}}}{{{text}}}"
    if isinstance(x, Badge):
        return rf"\verdict{{{_color(x.colour)}}}{{{escape(x.verdict)}}}"
    raise TypeError(f"no LaTeX for {type(x).__name__}")


def _plain(x):
    return x.verdict if isinstance(x, Badge) else x.text


def _pdf_string(text):
    return re.sub(r"[^A-Za-z0-9 .,:;/()=+-]", " ", text).strip()


def _color(verdict):
    return verdict.replace(" ", "")
