"""A report Document as one self-contained HTML page: inline CSS and SVG, no scripts, no fetches."""

from __future__ import annotations

import re
from html import escape
from importlib import resources

from inertiaproof.report.model import Badge, Bullets, Code, Figure, Link, Notice, Paragraph, Table, Text

__all__ = ["render", "TAGS"]

TAGS = {"code": "code", "strong": "strong", "em": "em"}


def render(document, svgs):
    """The page; ``svgs`` maps each figure's key to its <svg> element."""
    css = resources.files(__package__).joinpath("style.css").read_text(encoding="utf-8")
    toc = "".join(f'<li><a href="#{s.key}">{_inlines(s.title)}</a></li>' for s in document.sections)
    body = "\n".join(_section(s, 2, svgs) for s in document.sections)
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f"<title>{escape(document.title)}</title>\n<style>\n{css}</style>\n</head>\n<body>\n"
        f'<header>\n<h1>{escape(document.title)}</h1>\n<p class="subtitle">{escape(document.subtitle)}</p>\n'
        f'<nav><ul class="toc">{toc}</ul></nav>\n</header>\n<main>\n{body}\n</main>\n</body>\n</html>\n'
    )


def _section(section, level, svgs):
    attrs = f' id="{escape(section.key)}"'
    if section.result_id is not None:
        attrs += f' class="result" data-id="{escape(section.result_id)}"'
    if section.verdict is not None:
        attrs += f' data-verdict="{escape(section.verdict)}"'
    h = min(level, 6)
    parts = [f"<section{attrs}>", f"<h{h}>{_inlines(section.title)}</h{h}>"]
    parts += [_block(b, svgs) for b in section.blocks]
    parts += [_section(c, level + 1, svgs) for c in section.children]
    parts.append("</section>")
    return "\n".join(parts)


def _block(block, svgs):
    if isinstance(block, Paragraph):
        return f"<p>{_inlines(block.inlines)}</p>"
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Bullets):
        return "<ul>" + "".join(f"<li>{_inlines(item)}</li>" for item in block.items) + "</ul>"
    if isinstance(block, Code):
        caption = f'<div class="code-caption">{escape(block.caption)}</div>' if block.caption else ""
        return f'<div class="code">{caption}<pre>{escape(block.text)}</pre></div>'
    if isinstance(block, Figure):
        return (f'<figure class="plot" id="{escape(block.key)}" data-plot="{escape(block.kind)}">\n'
                f"{_inline_svg(svgs[block.key], block.caption)}\n"
                f"<figcaption><strong>Figure {block.number}.</strong> {escape(block.caption)}</figcaption>\n</figure>")
    if isinstance(block, Notice):
        inner = "\n".join(_block(b, svgs) for b in block.blocks)
        return (f'<div class="notice tone-{_css(block.tone)}">\n<p class="notice-title">{escape(block.title)}</p>\n'
                f"{inner}\n</div>")
    raise TypeError(f"no HTML for {type(block).__name__}")


def _inline_svg(svg, caption):
    """An SVG document as an element of the page: no XML prolog or metadata, labelled for screen readers."""
    svg = svg[svg.index("<svg"):]
    svg = re.sub(r"\s*<metadata>.*?</metadata>", "", svg, flags=re.S)
    return svg.replace("<svg ", f'<svg role="img" aria-label="{escape(caption)}" ', 1).strip()


def _table(table):
    cols = "".join(f'<col style="width:{c.width * 100:.1f}%">' for c in table.columns)
    head = "".join(f'<th class="{_align(c)}">{escape(c.title)}</th>' for c in table.columns)
    rows = []
    for row in table.rows:
        if len(row) == 1:
            rows.append(f'<tr class="span"><td colspan="{len(table.columns)}">{_inlines(row[0])}</td></tr>')
            continue
        cells = "".join(f'<td class="{_align(c)}">{_inlines(v)}</td>' for c, v in zip(table.columns, row))
        rows.append(f"<tr>{cells}</tr>")
    caption = f"<caption>{escape(table.caption)}</caption>" if table.caption else ""
    head = f"<thead><tr>{head}</tr></thead>\n" if any(c.title for c in table.columns) else ""
    return (f"<table>{caption}<colgroup>{cols}</colgroup>\n{head}<tbody>\n"
            + "\n".join(rows) + "\n</tbody></table>")


def _inlines(inlines):
    return "".join(_inline(x) for x in inlines)


def _inline(x):
    if isinstance(x, Text):
        tag = TAGS.get(x.style)
        return f"<{tag}>{escape(x.text)}</{tag}>" if tag else escape(x.text)
    if isinstance(x, Link):
        text = f"<code>{escape(x.text)}</code>" if x.style == "code" else escape(x.text)
        return f'<a href="#{escape(x.target)}">{text}</a>'
    if isinstance(x, Badge):
        return f'<span class="verdict tone-{_css(x.colour)}">{escape(x.verdict)}</span>'
    raise TypeError(f"no HTML for {type(x).__name__}")


def _align(column):
    return "num" if column.align == "r" else "txt"


def _css(verdict):
    return verdict.replace(" ", "-")
