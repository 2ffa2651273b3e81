"""The one result type that every check returns and every consumer reads.

A :class:`Result` answers one catalog ID with a :class:`Verdict` and its
evidence. Numbers in evidence say what they are: build them with
:func:`quantity`, whose ``kind`` is one of :data:`KINDS`. A certified number
cites its certificate by hash (:mod:`inertiaproof.citation`); the Result
carries the certificates its evidence cites in ``certificates``, beside the
evidence, and the checker's answers join that list, not the evidence
(:func:`inertiaproof.suite.certificates.settle`).

Evidence keys the report plots (use them wherever the data fits):

- ``"bracket"``: an extreme estimated two-sidedly, ``{"quantity": "inf_q
  lambda_min(M)", "lower": quantity, "upper": quantity, "convergence":
  [[seconds, lower, upper], ...]}``; plotted as bracket width against run time.
- ``"constants"``: a bound's constants side by side, ``{"paper": quantity
  (paper_constant), "certified": quantity (certified_constant), "observed":
  quantity (sampled or a bracket side)}``; plotted as tightness per bound.
- ``"hunt"``: a Hypothesis hunt, ``{"examples": quantity, "smallest_margin":
  quantity, "margins": [floats]}``; plotted as a histogram of margins.
- ``"series"``: any other curve, ``{"title", "x_label", "y_label", "x_log",
  "y_log", "lines": {name: [[x, y], ...]}}``.
- data files in ``Result.artifacts`` (written with ``Context.write_data``)
  for tables too large for results.json, e.g. ``data/work_precision.json``
  (rows: scene, method, rtol, seconds, error) and ``data/stability.json``
  (rows: scene, method, status, seconds, steps, note).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from enum import Enum

import numpy as np

from inertiaproof.citation import Certificate, Citation, cite, cited_in, entry_of

__all__ = ["combine", "decide", "KINDS", "quantity", "Result", "Verdict"]


class Verdict(str, Enum):
    HOLDS = "HOLDS"
    VIOLATED = "VIOLATED"
    INCONCLUSIVE = "INCONCLUSIVE"

    def __str__(self):
        return self.value


KINDS = {
    "exact": "computed exactly (rational or symbolic arithmetic)",
    "value": "a computed value, accurate to round-off",
    "paper_constant": "the constant as the paper states it",
    "certified_constant": "the sharpest constant the suite certifies",
    "upper_bound": "a certified upper bound of the true value",
    "lower_bound": "a certified lower bound of the true value",
    "sampled": "the extreme over samples: a one-sided estimate of an inf or sup",
    "estimate": "an estimate without a guaranteed side",
    "residual": "the size of what should vanish",
    "margin": "distance from the boundary of the statement (positive = holds)",
    "tolerance": "the numerical resolution a margin is compared with",
    "error_probability": "probability that a randomised test passed although the statement is false",
    "ratio": "a ratio of two of the other numbers",
    "count": "a count",
    "seconds": "wall time in seconds",
}


def quantity(value, kind, note=None, unit=None, certificate=None):
    """A number in evidence that says what it is; a certified one cites its ``certificate`` (a
    :class:`~inertiaproof.citation.Certificate` or its content, schema ``inertiaproof.certificate/2``) by hash
    where it has one (:func:`inertiaproof.citation.cite`)."""
    if kind not in KINDS:
        raise ValueError(f"unknown quantity kind {kind!r}; one of {sorted(KINDS)}")
    q = {"value": _plain(value), "kind": kind}
    if note:
        q["note"] = note
    if unit:
        q["unit"] = unit
    if certificate:
        q["certificate"] = cite(certificate, q["value"])
    return q


def _plain(x, cited=None):
    """JSON-ready copies of numpy scalars and arrays; non-finite floats become strings. A citation
    (:class:`~inertiaproof.citation.Citation`) is written with ``cited``'s record of its certificate (hash to
    {file, claim, status, ...}) where it has one."""
    if isinstance(x, Citation):
        return {**(cited or {}).get(x["hash"], {}), **x}
    if isinstance(x, Certificate):
        return x.content
    if isinstance(x, dict):
        return {str(k): _plain(v, cited) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v, cited) for v in x]
    if isinstance(x, np.ndarray):
        return _plain(x.tolist())
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else ("inf" if x > 0 else "-inf" if x < 0 else "nan")
    if isinstance(x, Enum):
        return x.value
    return x


@dataclass
class Result:
    id: str  # catalog ID, e.g. "Thm2"
    verdict: Verdict
    summary: str  # one line a person reads first
    evidence: dict = field(default_factory=dict)
    counterexample: dict | None = None  # replayable; see inertiaproof.suite.replay
    runtime_s: float = 0.0
    seed: int | None = None
    profile: str | None = None
    scene: str | None = None
    artifacts: list = field(default_factory=list)  # data files written next to results.json
    check: str | None = None  # the registered check's name (id, or id:variant)
    certificates: list | None = None  # the certificates the evidence cites (inertiaproof.citation): Certificate,
    # Settled once written and re-proved, records once read back; None: those the evidence's citations hold

    def __post_init__(self):
        self.verdict = Verdict(self.verdict)
        if self.certificates is None:
            self.certificates = cited_in(self.evidence)

    def to_json(self):
        """The JSON of results.json: the certificates as records ({hash, file, claim, status, ...}), each citation in
        evidence with its certificate's record."""
        records = [entry_of(c) for c in self.certificates]
        cited = {r["hash"]: {k: v for k, v in r.items() if k != "hash"} for r in records if "hash" in r}
        return {f.name: _plain(records if f.name == "certificates" else getattr(self, f.name), cited)
                for f in fields(self)}

    @classmethod
    def from_json(cls, data):
        return cls(**{k: data[k] for k in cls.__dataclass_fields__ if k in data})


def decide(margin, tolerance):
    """HOLDS when margin > tolerance, VIOLATED when margin < -tolerance, else INCONCLUSIVE."""
    if margin > tolerance:
        return Verdict.HOLDS
    if margin < -tolerance:
        return Verdict.VIOLATED
    return Verdict.INCONCLUSIVE


def combine(verdicts):
    """VIOLATED if any is, else INCONCLUSIVE if any is, else HOLDS."""
    verdicts = [Verdict(v) for v in verdicts]
    if Verdict.VIOLATED in verdicts:
        return Verdict.VIOLATED
    if Verdict.INCONCLUSIVE in verdicts:
        return Verdict.INCONCLUSIVE
    return Verdict.HOLDS
