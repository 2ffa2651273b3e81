"""Internal DTD entities in robot files, expanded safely or refused with one line naming the file.

A URDF or MJCF file may declare entities in its document type declaration
(``<!DOCTYPE robot [<!ENTITY nm "base">]>``) and use them in attribute
values (``<parent link="&nm;"/>``, ``<mass value="&m;"/>``). Such a file is
read as XML defines it, with every internal entity expanded, after checks
made before anything is expanded:

- no external entity (``SYSTEM``/``PUBLIC``, general or parameter) may be
  declared: they are never read, neither from disk nor from the network;
- every entity the file uses must be declared in the file itself (an
  external DTD is not read, and an unknown entity would read as "");
- an entity may not stand for markup (``<``): its elements would have no
  place in the file, and the audit reports where each element stands;
- entities may nest at most :data:`MAX_DEPTH` deep, must not refer to
  themselves, and all uses together may add at most :data:`GROWTH` times
  the file's size plus :data:`SLACK` characters (a "billion laughs" file
  declares a few hundred bytes that expand to gigabytes).

The lengths are computed from the declarations, without expanding them.
lxml then expands internal entities only (``resolve_entities="internal"``,
no DTD loading, no network, no huge trees). Entities stand for values
(attribute values, text), never for elements, so every element keeps its
line, and the positions of :mod:`.locate`, taken from the file's own text,
stay right.

:func:`expanded_text` gives the file's text with its entities replaced in
place, for MuJoCo (whose parser does not expand entities): the document
type declaration becomes as many blank lines as it took, so MuJoCo's line
numbers are the file's.
"""

from __future__ import annotations

import codecs
import re

from inertiaproof.errors import InputError

__all__ = ["doctype_span", "expanded_text", "GROWTH", "MAX_DEPTH", "parse", "SLACK"]

MAX_DEPTH = 8  # entities within entities
GROWTH = 10  # the expansion may add at most GROWTH times the file's size ...
SLACK = 1 << 16  # ... plus this many characters
PREDEFINED = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}
_REFERENCE = re.compile(r"&([A-Za-z_:][\w.:\-]*);")
_SKIPPED = re.compile(r"<!--.*?-->|<!\[CDATA\[.*?\]\]>|<\?.*?\?>", re.S)


def _text(data):
    """The file's text (a byte-order mark says UTF-8, -16 or -32; else as :func:`.locate.decode`), without the
    mark."""
    from .locate import decode

    for bom, encoding in ((codecs.BOM_UTF32_LE, "utf-32"), (codecs.BOM_UTF32_BE, "utf-32"),
                          (codecs.BOM_UTF8, "utf-8-sig"), (codecs.BOM_UTF16_LE, "utf-16"),
                          (codecs.BOM_UTF16_BE, "utf-16")):
        if data.startswith(bom):
            return data.decode(encoding, errors="surrogateescape")
    return decode(data)[0]


def _plain_parser(remove_comments=True):
    from lxml import etree

    return etree.XMLParser(remove_comments=remove_comments, resolve_entities=False, no_network=True, load_dtd=False,
                           huge_tree=False)


def _expanding_parser(remove_comments=True):
    """Internal entities only (lxml >= 5); our own checks have refused external ones before, whatever lxml does."""
    from lxml import etree

    try:
        return etree.XMLParser(remove_comments=remove_comments, resolve_entities="internal", no_network=True,
                               load_dtd=False, huge_tree=False)
    except (TypeError, ValueError):  # lxml < 5 knows only True and False
        return etree.XMLParser(remove_comments=remove_comments, resolve_entities=True, no_network=True,
                               load_dtd=False, huge_tree=False)


def _references(text):
    """The names of the general entities the text refers to, outside comments, CDATA and processing instructions,
    each as often as it occurs (the predefined five left out)."""
    return [m.group(1) for m in _REFERENCE.finditer(_SKIPPED.sub("", text)) if m.group(1) not in PREDEFINED]


def _declarations(text, path):
    """{name: (replacement text, or None when external; system URL)} of the general entities the document type
    declaration of the text declares, read from the declaration alone (so that nothing of the document is expanded
    yet); None without a document type declaration. Parameter entities are refused."""
    from lxml import etree

    span = doctype_span(text)
    if span is None:
        return None
    dtd = text[span[0]:span[1]]
    parameter = re.search(r"<!ENTITY\s+%\s*([^\s\"']*)", _SKIPPED.sub("", dtd))
    if parameter:
        raise InputError(f"{path}: the document type declares the parameter entity '%{parameter.group(1)}': "
                         "parameter entities are not read")
    try:
        root = etree.fromstring((dtd + "<x/>").encode("utf-8"), _plain_parser())
    except (etree.XMLSyntaxError, ValueError):
        return None  # the parse of the whole file names what is wrong
    found = root.getroottree().docinfo.internalDTD
    return {} if found is None else {e.name: (e.content, e.system_url) for e in found.iterentities()}


def _check(text, declared, path, size):
    """Refuse what cannot be expanded safely; returns the names of the entities the text uses (sorted)."""
    for name, (content, system) in declared.items():
        if system is not None or content is None:
            where = f' (SYSTEM "{system}")' if system else ""
            raise InputError(f"{path}: the document type declares the external entity '{name}'{where}: external "
                             "entities are not read; write its value into the file")
    used = _references(text)
    missing = sorted({name for name in used if name not in declared})
    if missing:
        raise InputError(f"{path}: entity '&{missing[0]};' is not declared in the file (an external DTD is not "
                         "read)")
    lengths, depths, markup = {}, {}, set()

    def too_deep(chain):
        return InputError(f"{path}: entities nest more than {MAX_DEPTH} deep ({' -> '.join(chain)}): refused")

    def length(name, chain):
        """The length of the entity's full expansion; its depth (1 without references) goes to ``depths``."""
        if name in chain:
            raise InputError(f"{path}: entity '{name}' refers to itself ({' -> '.join([*chain, name])})")
        if name in lengths:
            if len(chain) + depths[name] > MAX_DEPTH:
                raise too_deep([*chain, name])
            return lengths[name]
        if len(chain) >= MAX_DEPTH:
            raise too_deep([*chain, name])
        content = declared[name][0]
        inner = _references(content)
        for other in inner:
            if other not in declared:
                raise InputError(f"{path}: entity '{name}' refers to '&{other};', which is not declared in the file")
        total = len(_REFERENCE.sub("", content)) + sum(length(other, [*chain, name]) for other in inner)
        depths[name] = 1 + max((depths[other] for other in inner), default=0)
        if "<" in content or any(other in markup for other in inner):
            markup.add(name)
        lengths[name] = total
        return total

    limit = GROWTH * size + SLACK
    added = 0
    for name in used:
        added += length(name, [])
        if added > limit:
            raise InputError(f"{path}: its entities expand to more than {limit} characters ({GROWTH} times the "
                             f"file's {size} bytes plus {SLACK}): refused (an entity expansion bomb?)")
    for name in used:
        if name in markup:
            raise InputError(f"{path}: entity '{name}' stands for markup ('<'): only entities for values (names, "
                             "numbers) are expanded")
    return sorted(set(used))


def parse(data, path, *, remove_comments=True):
    """The root element of an XML file's bytes, internal entities expanded after the checks above.

    Raises InputError (one line naming ``path``) for what is refused, and lxml's XMLSyntaxError (or ValueError)
    for text that is not XML, as a plain ``etree.fromstring`` would."""
    from lxml import etree

    text = _text(data)
    if "<!DOCTYPE" in text:
        declared = _declarations(text, path)
        if declared is not None and _check(text, declared, path, len(data)):
            return etree.fromstring(data, _expanding_parser(remove_comments))
        if declared is None:
            root = etree.fromstring(data, _plain_parser(remove_comments))
            dtd = root.getroottree().docinfo.internalDTD
            if dtd is not None and any(True for _ in dtd.iterentities()):
                raise InputError(f"{path}: its document type declaration declares entities but cannot be read "
                                 "apart from the document: refused")
            return root
    return etree.fromstring(data, _plain_parser(remove_comments))  # no DOCTYPE: libxml2 refuses undeclared entities


def doctype_span(text):
    """(start, end) of the document type declaration in the text, or None; quoted literals, comments and processing
    instructions inside it may hold ']' and '>'."""
    m = re.search(r"<!DOCTYPE\b", text)
    if m is None:
        return None
    i, subset = m.end(), False
    while i < len(text):
        skipped = next(((opening, closing) for opening, closing in (('"', '"'), ("'", "'"), ("<!--", "-->"),
                                                                    ("<?", "?>")) if text.startswith(opening, i)),
                       None)
        if skipped is not None:
            j = text.find(skipped[1], i + len(skipped[0]))
            if j < 0:
                return None
            i = j + len(skipped[1])
            continue
        c = text[i]
        if c == "[":
            subset = True
        elif c == "]":
            subset = False
        elif c == ">" and not subset:
            return m.start(), i + 1
        i += 1
    return None


def expanded_text(data, path):
    """The file's text with every entity it uses replaced in place (escaped: values only, as checked), and its
    document type declaration as blank lines; None when it uses no entity. Raises InputError as :func:`parse`."""
    from xml.sax.saxutils import escape

    text = _text(data)
    if "<!DOCTYPE" not in text:
        return None
    declared = _declarations(text, path)
    if declared is None or not _check(text, declared, path, len(data)):
        return None
    span = doctype_span(text)
    cache = {}

    def value(name):
        if name not in cache:
            cache[name] = _REFERENCE.sub(lambda m: PREDEFINED.get(m.group(1)) or value(m.group(1)),
                                         declared[name][0])
        return cache[name]

    def substitute(part):
        return _REFERENCE.sub(lambda m: m.group(0) if m.group(1) in PREDEFINED
                              else escape(value(m.group(1)), {'"': "&quot;", "'": "&apos;", "\n": "&#10;"}),
                              part)  # a value's line breaks as references: the lines after it stay the file's

    body, out, at = text[span[1]:], [], 0
    for m in _SKIPPED.finditer(body):  # comments, CDATA and processing instructions stay as written
        out += [substitute(body[at:m.start()]), m.group(0)]
        at = m.end()
    out.append(substitute(body[at:]))
    blank = "\n" * text.count("\n", span[0], span[1])
    return text[:span[0]] + blank + "".join(out)
