"""The report's content, independent of its output format.

The HTML and LaTeX writers both render a :class:`Document`; everything a
reader sees is decided here, once, as sections of blocks (paragraphs, tables,
figures, code, notices) made of inline pieces (text, code, links, verdicts).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = [
    "Badge", "Bullets", "cell", "Code", "code", "Column", "Document", "Figure", "Link", "Notice", "Paragraph",
    "Section", "Table", "Text",
]


@dataclass(frozen=True)
class Text:
    text: str
    style: str = ""  # "", "code", "strong" or "em"


@dataclass(frozen=True)
class Link:
    text: str
    target: str  # the key of a Section or Figure
    style: str = ""


@dataclass(frozen=True)
class Badge:
    verdict: str  # the text; HOLDS, VIOLATED, INCONCLUSIVE or NOT RUN unless a tone is given
    tone: str = ""  # one of those four: the colour, when the text is another word

    @property
    def colour(self):
        return self.tone or self.verdict


@dataclass(frozen=True)
class Paragraph:
    inlines: tuple


@dataclass(frozen=True)
class Column:
    title: str
    width: float  # fraction of the text width
    align: str = "l"  # "l" or "r"


@dataclass(frozen=True)
class Table:
    columns: tuple
    rows: tuple  # of tuples of cells (a cell is a tuple of inlines); a row of one cell spans the table
    caption: str = ""


@dataclass(frozen=True)
class Bullets:
    items: tuple  # of tuples of inlines


@dataclass(frozen=True)
class Code:
    text: str
    caption: str = ""


@dataclass(frozen=True)
class Figure:
    key: str
    number: int
    kind: str  # a drawing function of report.plots
    data: dict
    caption: str


@dataclass(frozen=True)
class Notice:
    tone: str  # a verdict: the colour of the box
    title: str
    blocks: tuple


@dataclass(frozen=True)
class Section:
    key: str
    title: tuple  # inlines
    blocks: tuple = ()
    children: tuple = ()
    result_id: str | None = None
    verdict: str | None = None


@dataclass(frozen=True)
class Document:
    title: str
    subtitle: str
    sections: tuple = field(default_factory=tuple)

    def figures(self):
        """Every figure, in reading order."""
        return [b for s in self.walk() for b in _blocks(s.blocks) if isinstance(b, Figure)]

    def walk(self):
        stack = list(reversed(self.sections))
        while stack:
            section = stack.pop()
            yield section
            stack.extend(reversed(section.children))


def _blocks(blocks):
    for b in blocks:
        yield b
        if isinstance(b, Notice):
            yield from _blocks(b.blocks)


def cell(*inlines):
    """A table cell from inlines or plain strings."""
    return tuple(Text(x) if isinstance(x, str) else x for x in inlines)


def code(text):
    return Text(text, "code")
