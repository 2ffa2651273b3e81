"""Where an element of an XML file stands in its text: line, column and the span of its markup.

lxml keeps the line of every element (``sourceline``: the line on which its
start tag ends), but no column and no span. A small tokenizer walks the
markup of the text in document order (skipping comments, CDATA, processing
instructions and the document type declaration) and pairs its k-th start tag
with lxml's k-th element. The pairing is accepted only when every tag name
agrees and every start tag ends on the line lxml reports; otherwise the
elements keep lxml's line alone. Lines and columns count from 1; columns
count Unicode code points; ``end_column`` is the column just after the
element's last character (SARIF's convention).
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass

from lxml import etree

__all__ = ["decode", "element_spans", "Source", "Span", "urdf_sources"]

TOKEN = re.compile(
    r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>|<!DOCTYPE(?:[^\[>]|\[.*?\])*>"
    r"|<(/?)([A-Za-z_:][\w:.\-]*)((?:\s+[^\s=/>]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>",
    re.S,
)


@dataclass(frozen=True)
class Span:
    line: int
    column: int | None  # None: lxml's line only
    end_line: int | None = None
    end_column: int | None = None
    start: int | None = None  # character offsets of the element's markup in the text
    end: int | None = None

    def region(self):
        """The SARIF region of the element."""
        out = {"startLine": self.line}
        if self.column is not None:
            out.update(startColumn=self.column, endLine=self.end_line, endColumn=self.end_column)
        return out


@dataclass(frozen=True)
class Source:
    """Where a link's inertia comes from, and the element a repair of it replaces.

    ``kind``: ``urdf`` (an ``<inertia>`` element), ``inertial`` (a URDF ``<inertial>`` without one, whose
    problem :mod:`.urdf` reports; no repair replaces it), ``diaginertia`` or
    ``fullinertia`` (an MJCF ``<inertial>`` element), ``sdf`` (an SDFormat ``<inertia>``), ``sdf_inertial`` (an
    SDFormat ``<inertial>`` without one, or the ``<link>`` without an ``<inertial>``), ``geoms`` (MuJoCo
    computed it from the body's geoms; ``span`` is then the ``<body>``), or
    ``joint_frame`` (a frame between two joints of one MJCF body, not a body).
    """

    path: str  # the file that holds the element (an MJCF include may differ from the model's file)
    span: Span | None
    kind: str
    attributes: tuple = ()  # MJCF <inertial>: (name, value) in file order
    expanded: str | None = None  # "xacro": the span is in the text xacro made of the file, not in the file


def decode(data):
    """(text, encoding) of an XML file's bytes, decoded as its declaration says (UTF-8 without one); bytes that do
    not decode survive a round trip (surrogateescape)."""
    declared = re.match(rb"<\?xml[^>]*?encoding\s*=\s*[\"']([A-Za-z0-9._-]+)[\"']", data.lstrip(b"\xef\xbb\xbf"))
    encoding = declared.group(1).decode("ascii") if declared else "utf-8"
    try:
        return data.decode(encoding, errors="surrogateescape"), encoding
    except LookupError:
        return data.decode("utf-8", errors="surrogateescape"), "utf-8"


def urdf_sources(data, root, path, spans=None):
    """{link name: Source} of every ``<link>`` with an ``<inertial>`` in a parsed URDF: its ``<inertia>``, or the
    ``<inertial>`` itself when it has none. ``spans``: :func:`element_spans` of the file, when computed already."""
    spans = element_spans(decode(data)[0], root) if spans is None else spans
    out = {}
    for link in root.findall("link"):
        inertial = link.find("inertial")
        inertia = None if inertial is None else inertial.find("inertia")
        if inertia is not None:
            out[link.get("name")] = Source(str(path), spans.get(inertia), "urdf")
        elif inertial is not None:
            out[link.get("name")] = Source(str(path), spans.get(inertial), "inertial")
    return out


def _line_starts(text):
    return [0] + [m.end() for m in re.finditer("\n", text)]


def _position(starts, offset):
    """1-based (line, column) of a character offset."""
    line = bisect.bisect_right(starts, offset)
    return line, offset - starts[line - 1] + 1


def element_spans(text, root):
    """{element: Span} for every element under ``root`` (lxml, parsed from ``text``)."""
    elements = [e for e in root.iter() if isinstance(e.tag, str)]
    starts = _line_starts(text)
    opened, stack, spans = [], [], {}
    for m in TOKEN.finditer(text):
        if m.group(2) is None:
            continue
        if m.group(1):  # end tag
            if not stack or stack[-1][1] != m.group(2):
                return _lines_only(elements)
            k, _, begin = stack.pop()
            spans[k] = (begin, m.end())
            continue
        k = len(opened)
        opened.append(m)
        if m.group(4):
            spans[k] = (m.start(), m.end())
        else:
            stack.append((k, m.group(2), m.start()))
    if stack or len(opened) != len(elements):
        return _lines_only(elements)
    out = {}
    for k, (element, m) in enumerate(zip(elements, opened)):
        if etree.QName(element).localname != m.group(2).rpartition(":")[2] or \
                _position(starts, m.end() - 1)[0] != element.sourceline:
            return _lines_only(elements)
        begin, end = spans[k]
        line, column = _position(starts, begin)
        end_line, last = _position(starts, end - 1)
        out[element] = Span(line, column, end_line, last + 1, begin, end)
    return out


def _lines_only(elements):
    return {e: Span(e.sourceline, None) for e in elements}
