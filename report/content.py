"""The results document (results.json plus data files) as a report :class:`~report.model.Document`.

Reading order: what failed, the summary and a table of every result, the
bounds at a glance, then one section per catalog ID in the paper's order
(statement, verdict, counterexample, evidence, plots), the gate, and how to
read the numbers.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass

from inertiaproof.report import datafiles, engineer, evidence, paper_names
from inertiaproof.report import numbers as fmt
from inertiaproof.report.model import (
    Badge,
    Bullets,
    Code,
    Column,
    Document,
    Link,
    Notice,
    Paragraph,
    Section,
    Text,
    cell,
    code,
)

from inertiaproof.result import KINDS, combine
from inertiaproof.suite import catalog
from inertiaproof.suite.certificates import certificate_tally

__all__ = ["build", "MUTATION_TONES", "NOT_RUN", "PAPER", "TITLE"]

NOT_RUN = "NOT RUN"
TITLE = "inertiaproof report"
PAPER = ("Kaufmann & Reger, On robotic manipulators with time-dependent inertial parameters: "
         "from physical consistency to boundedness of the mass matrix")


@dataclass
class _Run:
    doc: dict  # the results document
    data: dict  # {artifact: rows or a one-line problem}
    keys: dict  # {id(result): anchor}
    figs: evidence.Figures
    bounds_figure: object = None  # the constants overview, when there is one


def build(doc, data=None, mutation=None, narrowing=None):
    """The Document of a results document and its data files ({artifact: rows or problem}); ``mutation`` is
    (path, table or problem) of bench/mutation.py, shown as an appendix; ``narrowing`` bench/bracket_narrowing.py's
    data, plotted in the section for a control engineer."""
    run = _Run(doc, data or {}, _keys(doc["checks"]), evidence.Figures())
    grouped = {}
    for r in doc["checks"]:
        grouped.setdefault(r["id"], []).append(r)
    extras = [e for e in catalog.APPLICATIONS + catalog.EXTRAS if e.id in grouped]
    unknown = [i for i in grouped if i not in catalog.BY_ID]
    verdicts = {i: combine(r["verdict"] for r in rs).value for i, rs in grouped.items()}

    sections = [_summary(run, grouped, verdicts, [e.id for e in extras] + unknown)]
    overview = _constants_overview(run)
    if overview:
        sections.append(overview)
    engineering = engineer.section(doc, run.figs, narrowing)
    if engineering:
        sections.append(engineering)
    for number, name in catalog.SECTIONS.items():
        children = tuple(_result_section(run, e.id, e, grouped.get(e.id, []))
                         for e in catalog.ENTRIES if e.section == number)
        sections.append(Section(f"sec-{number}", (Text(f"Section {number}: {name}"),), children=children))
    beyond = [_result_section(run, e.id, e, grouped[e.id]) for e in extras]
    beyond += [_result_section(run, i, None, grouped[i]) for i in unknown]
    if beyond:
        sections.append(Section("sec-beyond", (Text("Beyond the paper"),), children=tuple(beyond)))
    sections.append(_legend())
    if mutation:
        sections.append(_mutation_appendix(*mutation))
    return Document(TITLE, PAPER, tuple(sections))


MUTATION_TONES = {"killed": "HOLDS", "survived": "VIOLATED", "inconclusive": "INCONCLUSIVE", "stale": "NOT RUN"}


def _mutation_appendix(path, table):
    """Appendix: bench/mutation.py's kill table (which checks killed each mutant of the core)."""
    if isinstance(table, str):
        return Section("mutation", (Text("Appendix: mutation testing"),), (Paragraph((Text(table, "em"),)),))
    s, base = table.get("summary") or {}, table.get("baseline") or {}
    lead = Paragraph((
        Text("Each mutant is a small wrong edit of the core (a sign, a factor, a dropped term, a loosened tolerance) "
             "applied to a temporary copy of the package; "), code("inertiaproof gate --update"),
        Text(" runs first, so the lockfile cannot be what kills it, then "), code("inertiaproof run --profile ci"),
        Text(". A mutant is killed when the run exits 1 (something VIOLATED or a check crashed). "),
        Text(f"{s.get('killed', '?')} of {s.get('mutants', '?')} killed, {s.get('survived', '?')} survived, "
             f"{s.get('inconclusive', '?')} only inconclusive, {s.get('stale', '?')} stale (pattern no longer in the "
             f"code); {s.get('equivalent', 0)} declared equivalent.", "strong"),
        Text(f" Baseline run: exit {base.get('exit', '?')} in {fmt.seconds(base.get('seconds'))}. From "),
        code(str(path)), Text(", written by "), code(str(table.get("command", "python bench/mutation.py"))), Text("."),
    ))
    rows = []
    for m in table["mutants"]:
        status = str(m.get("status", "?"))
        who = ", ".join(map(str, m.get("killed_by") or m.get("inconclusive") or [])) or str(m.get("why", ""))
        if m.get("equivalent"):
            who = (who + "; " if who else "") + f"equivalent: {m['equivalent']}"
        rows.append((cell(code(str(m.get("id", "?")))), cell(str(m.get("area", ""))), cell(str(m.get("what", ""))),
                     cell(Badge(status, MUTATION_TONES.get(status, "NOT RUN"))), cell(who)))
    columns = (Column("mutant", 0.2), Column("area", 0.09), Column("the bug", 0.3), Column("status", 0.11),
               Column("killed by (or why not)", 0.3))
    return Section("mutation", (Text("Appendix: mutation testing"),),
                   (lead, evidence.table(columns, rows, "Mutants of the core and the checks that kill them",
                                         limit=None)))


def _summary(run, grouped, verdicts, beyond):
    doc, keys = run.doc, run.keys
    checks = doc["checks"]
    blocks = []
    violated = [r for r in checks if r["verdict"] == "VIOLATED"]
    inconclusive = [r for r in checks if r["verdict"] == "INCONCLUSIVE"]
    paper = [verdicts.get(e.id, NOT_RUN) for e in catalog.ENTRIES]
    counts = {v: paper.count(v) for v in ("HOLDS", "VIOLATED", "INCONCLUSIVE", NOT_RUN)}
    if violated:
        blocks.append(Notice("VIOLATED", f"What failed: {_count(len(violated), 'check')} found a counterexample",
                             (Bullets(tuple(_failure(r, keys) for r in violated)),)))
    if inconclusive:
        blocks.append(Notice("INCONCLUSIVE", f"Inconclusive: {_count(len(inconclusive), 'check')} could not decide",
                             (Bullets(tuple(_brief(r, keys) for r in inconclusive)),)))
    if not violated and not inconclusive:
        ran = "No check ran." if not checks else (
            "The one check that ran holds." if len(checks) == 1 else f"All {len(checks)} checks that ran hold.")
        if counts[NOT_RUN]:
            ran += f" {counts[NOT_RUN]} of the {len(paper)} results of the paper were not run."
        blocks.append(Notice("HOLDS", "Nothing failed", (Paragraph((Text(ran),)),)))
    by_check = {v: sum(r["verdict"] == v for r in checks) for v in ("HOLDS", "VIOLATED", "INCONCLUSIVE")}
    blocks.append(Paragraph((
        Text(f"Of the {len(paper)} results of the paper, "),
        Text(f"{counts['HOLDS']} hold, {counts['VIOLATED']} violated, {counts['INCONCLUSIVE']} inconclusive, "
             f"{counts[NOT_RUN]} not run", "strong"),
        Text(f". {_count(len(checks), 'check')} ran ({by_check['HOLDS']} HOLDS, {by_check['VIOLATED']} VIOLATED, "
             f"{by_check['INCONCLUSIVE']} INCONCLUSIVE) in {fmt.seconds(doc.get('runtime_s'))}; "
             f"{len(doc.get('skipped') or [])} left out."),
    )))
    certificates, tally = certificate_tally(checks)
    if certificates:
        blocks.append(Paragraph((Text("Certificates back the certified numbers of this run: "), Text(tally, "strong"),
                                 Text(" by the independent checker, which inertiaproof verify OUT runs again from "
                                      "the files alone."))))
    blocks.append(_glance(grouped, verdicts, beyond))
    blocks.append(_run_table(doc))
    if doc.get("skipped"):
        blocks.append(evidence.table((Column("check", 0.3), Column("why it was left out", 0.7)),
                                     [(cell(code(str(s.get("check", "?")))), cell(str(s.get("reason", ""))))
                                      for s in doc["skipped"]], "Left out of this run"))
    return Section("summary", (Text("Summary"),), tuple(blocks))


def _count(n, noun):
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _glance(grouped, verdicts, beyond):
    rows = []
    for i in [e.id for e in catalog.ENTRIES] + beyond:
        entry = catalog.BY_ID.get(i)
        results = grouped.get(i, [])
        time = sum(fmt.to_float(r.get("runtime_s")) or 0.0 for r in results)
        rows.append((cell(Link(i, _section_key(i), "code")), cell(_printed(entry.label) if entry else "not in the catalog"),
                     cell(Badge(verdicts.get(i, NOT_RUN))), cell(code(str(len(results)))),
                     cell(code(fmt.seconds(time) if results else "-"))))
    columns = (Column("ID", 0.19), Column("paper", 0.43), Column("verdict", 0.16), Column("checks", 0.1, "r"),
               Column("time", 0.12, "r"))
    return evidence.table(columns, rows, "Every result at a glance", limit=None)


def _run_table(doc):
    scene = doc.get("scene")
    rows = [("profile", str(doc.get("profile"))), ("seed", str(doc.get("seed"))),
            ("scene", str(scene) if scene else "none: the built-in robots"),
            ("total run time", fmt.seconds(doc.get("runtime_s")))]
    rows += [(f"version of {k}", str(v)) for k, v in (doc.get("versions") or {}).items()]
    return evidence.table((Column("", 0.3), Column("", 0.7)), [(cell(k), cell(code(v))) for k, v in rows],
                          "The run")


def _failure(r, keys):
    parts = [Link(r.get("check") or r["id"], keys[id(r)], "code"), Text(": " + str(r.get("summary", "")))]
    cx = r.get("counterexample") or {}
    if cx.get("file"):
        parts += [Text(". Counterexample "), code(str(cx["file"])), Text("; replay: "), code(_replay(cx["file"]))]
    elif cx:
        parts.append(Text(". Counterexample in the section (not saved to a file)."))
    return tuple(parts)


def _brief(r, keys):
    return (Link(r.get("check") or r["id"], keys[id(r)], "code"), Text(": " + str(r.get("summary", ""))))


def _replay(path):
    return f"inertiaproof replay {shlex.quote(str(path))}"


def _printed(label):
    """A catalog entry's paper reference as the paper prints it ("Eq. (68)", "Theorem 2"), not its LaTeX label."""
    return paper_names.printed(label)


def _constants_overview(run):
    points = []
    for r in run.doc["checks"]:
        found, _, _, _ = evidence.split(r.get("evidence"))
        points += evidence.constants_points(found["constants"], r.get("check") or r["id"],
                                            r["verdict"] == "VIOLATED")
    if not points:
        return None
    figure = run.bounds_figure = run.figs.new("constants", {"bounds": points},
                      "Each bound's constants on one axis: the paper's constant, the sharpest constant the suite "
                      "certifies, and the observed worst case. For an upper bound the paper's constant should lie "
                      "to the right of the observed worst case, for a lower bound to the left; the gap is the "
                      "conservatism. Bounds of VIOLATED results are labelled in red.")
    text = Paragraph((Text("How conservative the paper's constants are, bound by bound. The tables in each "
                           "section give the numbers and the ratios."),))
    return Section("bounds", (Text("Bounds at a glance"),), (text, figure))


def _result_section(run, result_id, entry, results):
    verdict = combine(r["verdict"] for r in results).value if results else NOT_RUN
    label = _printed(entry.label) if entry else "not in the catalog"
    title = (Text(result_id, "code"), Text(f": {label} "), Badge(verdict))
    statement = entry.statement if entry else "a result this version of the report does not know."
    blocks = [Paragraph((Text("Statement: ", "strong"), Text(statement)))]
    if result_id == "gate" and results:
        blocks.append(_gate_paragraph(results))
    children = []
    if not results:
        blocks.append(Paragraph((Text("Not run in this run.", "em"),)))
        for s in run.doc.get("skipped") or []:
            if str(s.get("check", "")).split(":")[0] == result_id:
                blocks.append(Paragraph((Text("Left out: "), code(str(s.get("check"))),
                                         Text(": " + str(s.get("reason", ""))))))
    elif len(results) == 1 and run.keys[id(results[0])] == _section_key(result_id):
        blocks += _result_blocks(run, results[0])
    else:
        for r in results:
            title_r = (Text(r.get("check") or r["id"], "code"), Text(" "), Badge(r["verdict"]))
            children.append(Section(run.keys[id(r)], title_r, tuple(_result_blocks(run, r)), verdict=r["verdict"]))
    return Section(_section_key(result_id), title, tuple(blocks), tuple(children), result_id=result_id,
                   verdict=verdict)


def _result_blocks(run, r):
    name = r.get("check") or r["id"]
    scene = f", scene {r['scene']}" if r.get("scene") else ""
    facts = f": {fmt.seconds(r.get('runtime_s'))}, seed {r.get('seed')}, profile {r.get('profile')}{scene}."
    blocks = [Paragraph((Text("Finding: ", "strong"), Text(str(r.get("summary", ""))))),
              Paragraph((Text("Check "), code(name), Text(facts)))]
    if r.get("counterexample"):
        blocks += _counterexample(r["counterexample"])
    found, rows, tables, texts = evidence.split(r.get("evidence"))
    if found["bracket"]:
        blocks.append(evidence.bracket_table(found["bracket"]))
        figure = evidence.bracket_figure(found["bracket"], run.figs, name)
        if figure:
            blocks.append(figure)
    if found["constants"]:
        blocks.append(evidence.constants_table(found["constants"], name, run.bounds_figure))
    if found["hunt"]:
        blocks += evidence.hunt_blocks(found["hunt"], run.figs, name)
    blocks += evidence.series_figures(found["series"], run.figs, name)
    blocks += evidence.generic_blocks(rows, tables, texts)
    for artifact in r.get("artifacts") or []:
        if isinstance(artifact, str):
            blocks += datafiles.blocks(artifact, run.data.get(artifact, f"{artifact}: not read"), run.figs, name)
    return blocks


def _counterexample(cx):
    kind = str(cx.get("kind", "?"))
    if cx.get("file"):
        lead = Paragraph((Text("Counterexample", "strong"), Text(f" (kind {kind}), saved to "), code(str(cx["file"])),
                          Text(". Replay it with:")))
        out = [lead, Code(_replay(cx["file"]))]
    else:
        out = [Paragraph((Text("Counterexample", "strong"), Text(f" (kind {kind}); not saved to a file, so it "
                                                                   "cannot be replayed."),))]
    return out + [Code(evidence.json_text(cx.get("data")), "its data")]


def _gate_paragraph(results):
    names, changed = [], []
    for r in results:
        for record in _records(r.get("evidence")):
            name = str(record.get("name") or record.get("derivation") or "?")
            names.append(name)
            status = str(record.get("status", "")).lower()
            if record.get("changed") is True or status in ("changed", "new", "missing", "stale"):
                changed.append(name)
    if not names:
        return Paragraph((Text("The gate's evidence names no derivations.", "em"),))
    inlines = [Text("Fingerprinted: ", "strong"), Text(f"{len(names)} derivations ("), *_names(names), Text("). ")]
    if changed:
        inlines += [Text(f"Changed since the lockfile: {len(changed)} (", "strong"), *_names(changed),
                    Text(").", "strong")]
    else:
        inlines.append(Text("None changed since the lockfile.", "strong"))
    return Paragraph(tuple(inlines))


def _records(x):
    if isinstance(x, list):
        if x and all(isinstance(v, dict) and ("name" in v or "derivation" in v) for v in x):
            yield from x
            return
        for v in x:
            yield from _records(v)
    elif isinstance(x, dict):
        for v in x.values():
            yield from _records(v)


def _names(names):
    out = []
    for i, n in enumerate(names):
        out += ([Text(", ")] if i else []) + [code(n)]
    return out


def _legend():
    rows = [(cell(code(k)), cell(v)) for k, v in KINDS.items()]
    rows.append((cell(code(NOT_RUN)), cell("the catalog ID had no check in this run")))
    text = Paragraph((Text("Every number in the evidence says what kind of number it is. A margin is positive when "
                           "the statement holds; a sampled extreme is only a one-sided estimate of an inf or sup, "
                           "a bracket (lower and upper) encloses it."),))
    return Section("kinds", (Text("How to read the numbers"),),
                   (text, evidence.table((Column("kind", 0.25), Column("meaning", 0.75)), rows, "Kinds of numbers")))


def _section_key(result_id):
    return "r-" + _slug(result_id)


def _keys(checks):
    """{id(result): anchor}: the ID's section for a lone result named like its ID, else a key per check."""
    counts = {}
    for r in checks:
        counts[r["id"]] = counts.get(r["id"], 0) + 1
    keys, used = {}, set()
    for r in checks:
        name = r.get("check") or r["id"]
        if counts[r["id"]] == 1 and name == r["id"]:
            key = _section_key(r["id"])
        else:
            key = "c-" + _slug(name)
            base, n = key, 2
            while key in used:
                key, n = f"{base}-{n}", n + 1
        used.add(key)
        keys[id(r)] = key
    return keys


def _slug(text):
    return re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-") or "x"
