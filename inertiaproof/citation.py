"""Certificates as values, and the citations of them in evidence: the one channel by which a proof reaches results.json.

A :class:`Certificate` is a proof the prover returns (schema ``inertiaproof.certificate/2``,
:mod:`inertiaproof.bounds.certificate`): its content, its canonical text (sorted keys) and its content hash (the
first 16 hex digits of the text's SHA-256, the name of its file under ``OUT/certificates``), computed once when it is
made. It is the (read-only) dict of its content, so the prover composes certificates from certificates (a ``product``'s
ingredients, a ``sum``'s terms) as it composes their contents.

Evidence cites a certificate by hash: :func:`cite` makes a :class:`Citation` (``{"hash": ...}``, with ``"as":
"root"`` where the number is the square root of the claim's bound) that holds its certificate.
:class:`inertiaproof.result.Result` carries the certificates its evidence cites as a list beside the evidence; the
checker's answers join that list (:func:`inertiaproof.suite.certificates.settle`), never the evidence.
"""

from __future__ import annotations

import copy
import hashlib
import json
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["Certificate", "Citation", "cite", "cited_in", "content_of", "entry_of", "Settled"]


def content_of(node):
    """``node`` with every :class:`Certificate` inside it replaced by its content: plain JSON-ready data."""
    if isinstance(node, dict):
        return {k: content_of(v) for k, v in node.items()}
    if isinstance(node, (list, tuple)):
        return [content_of(v) for v in node]
    return node


class Certificate(dict):
    """A certificate's content (the dict itself, read-only) with its canonical text and hash, computed once. A deep
    copy is a plain dict of the content, to alter."""

    __slots__ = ("text", "hash")

    def __init__(self, content):
        content = content_of(dict(content))
        super().__init__(content)
        text = json.dumps(content, sort_keys=True)
        object.__setattr__(self, "text", text)
        object.__setattr__(self, "hash", hashlib.sha256(text.encode()).hexdigest()[:16])

    @classmethod
    def of(cls, content):
        """``content`` as a Certificate (itself if it is one); None for None."""
        if content is None or isinstance(content, Certificate):
            return content
        return cls(content)

    @property
    def content(self):
        """The content as a plain dict."""
        return dict(self)

    @property
    def name(self):
        """The name of its file: ``<hash>.json``."""
        return f"{self.hash}.json"

    def _read_only(self, *args, **kwargs):
        raise TypeError("a certificate is a value: copy it (copy.deepcopy gives its content) to alter it")

    __setitem__ = __delitem__ = __ior__ = update = pop = popitem = setdefault = clear = _read_only
    __setattr__ = __delattr__ = _read_only

    def __reduce__(self):
        return Certificate, (dict(self),)

    def __deepcopy__(self, memo):
        return copy.deepcopy(dict(self), memo)

    def __eq__(self, other):
        return dict.__eq__(self, other)

    def __hash__(self):
        return hash(self.hash)

    def __repr__(self):
        return f"Certificate({self.hash}: {self.get('claim', {}).get('kind')})"


class Citation(dict):
    """A number's citation of a certificate in evidence: ``{"hash": ...}`` (and ``"as": "root"``), holding the
    :class:`Certificate` it cites."""

    def __init__(self, certificate, root=False):
        super().__init__(hash=certificate.hash, **({"as": "root"} if root else {}))
        self.certificate = certificate

    def __reduce__(self):
        return Citation, (self.certificate, self.get("as") == "root")

    def __deepcopy__(self, memo):
        return self  # a citation is a value: copies of evidence cite the same certificate


def _root(value, certificate):
    """Whether ``value`` is the square root of the certificate's claimed bound (sup sigma_max(QJ) of a claim on
    (QJ)^T QJ), as the checker reads results.json."""
    bound = certificate.get("claim", {}).get("bound")
    if not isinstance(value, float) or bound is None:
        return False
    try:
        return Fraction(value) != Fraction(bound) and Fraction(value) ** 2 == Fraction(bound)
    except (ValueError, TypeError, OverflowError):  # a non-finite number cites nothing it is the root of
        return False


def cite(certificate, value=None):
    """The :class:`Citation` of ``certificate`` (a Certificate, its content, or another number's Citation of it) by
    the number ``value``; None for None."""
    if isinstance(certificate, Citation):  # another number's citation: the same certificate
        certificate = certificate.certificate
    certificate = Certificate.of(certificate)
    return None if certificate is None else Citation(certificate, _root(value, certificate))


def cited_in(node):
    """The certificates the citations in ``node`` (evidence) hold, each once, in the order first cited: what a
    :class:`~inertiaproof.result.Result` made from that evidence carries. It looks for :class:`Citation` values,
    the only form a citation takes, not for dictionaries of a certificate's shape."""
    found = {}
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, Citation):
            found.setdefault(item.certificate.hash, item.certificate)
        elif isinstance(item, dict):
            stack.extend(reversed(list(item.values())))
        elif isinstance(item, (list, tuple)):
            stack.extend(reversed(item))
    return list(found.values())


@dataclass(frozen=True)
class Settled:
    """A certificate once written and put to the independent checker: ``file`` (``certificates/<name>``, the
    completed certificate's where completion changed it: ``filed``) and the checker's answer."""

    certificate: Certificate  # as the evidence cites it
    file: str
    status: str
    why: str = ""
    claim: str | None = None  # None: the checker was not asked (nor are boxes and seconds)
    boxes: int | None = None
    seconds: float | None = None
    filed: Certificate | None = None  # the certificate written, where it is not the one cited
    completion_seconds: float | None = None  # the prover's seconds growing its tree for the checker (None: not needed)

    @property
    def hash(self):
        return self.certificate.hash

    @property
    def written(self):
        """The certificate in the file."""
        return self.filed or self.certificate

    def entry(self):
        """{file, claim, status, why, boxes, seconds, completion_seconds}: what results.json says of it."""
        answer = {"claim": self.claim, "status": self.status, "why": self.why, "boxes": self.boxes,
                  "seconds": self.seconds, "completion_seconds": self.completion_seconds}
        return {"file": self.file, **{k: v for k, v in answer.items() if v is not None}}


def entry_of(item):
    """results.json's record of an item of ``Result.certificates`` (a Certificate, Settled, or a record read back):
    {hash, file, claim, status, why, boxes, seconds}; an unsettled one says so."""
    if isinstance(item, Settled):
        return {"hash": item.hash, **item.entry()}
    if isinstance(item, Certificate):
        return {"hash": item.hash, "status": "not settled"}
    return dict(item)
