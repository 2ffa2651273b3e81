"""An audit document (``inertiaproof.audit/1``, DIR/audit.json) as a report :class:`~report.model.Document`.

Reading order: what is not consistent, every file at a glance and the run;
then one section per file: its links (verdict, reason, signs of a mistake,
size of the repair), the suggested repairs, the bodies that are not
consistent, its chains (can M(q) become singular?) and their bounds (the
paper's alpha1 and alpha2 against the sharpest certified constants and the
eigenvalue bracket), in a table and a figure; last, how to read the verdicts.
"""

from __future__ import annotations

from collections import Counter
from pathlib import PurePath

from inertiaproof.report import numbers as fmt
from inertiaproof.report.evidence import Figures, table
from inertiaproof.report.model import (
    Badge,
    Bullets,
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

from inertiaproof.audit.text import headline, remarks, role, totals

__all__ = [
    "BOUNDS", "build", "LINK_MEANINGS", "LINK_TONES", "NOT_JUDGED", "short_names", "SINGULAR_MEANINGS",
    "SINGULAR_TONES", "SUBTITLE", "TITLE",
]

TITLE = "inertiaproof audit"
SUBTITLE = "Physical consistency of robot descriptions and the bounds of their mass matrices (Kaufmann & Reger)"
NOT_JUDGED = "NOT RUN"
LINK_TONES = {"consistent": "HOLDS", "degenerate": "INCONCLUSIVE", "inconsistent": "VIOLATED", "invalid": "VIOLATED"}
SINGULAR_TONES = {"never": "HOLDS", "not_excluded": "INCONCLUSIVE", "everywhere": "VIOLATED",
                  "indefinite": "VIOLATED", "singular": "VIOLATED"}
LINK_MEANINGS = {
    "consistent": "f(Phi) > 0: some nonnegative density with a 3-D carrier has these mass, CoM and inertia (Theorem 1)",
    "degenerate": "f(Phi) >= 0 and singular: only a point, line or planar mass has them",
    "inconsistent": "no nonnegative mass distribution has them (e.g. I_CoM breaks a triangle inequality)",
    "invalid": "a number is not finite",
}
SINGULAR_MEANINGS = {
    "never": "M(q) > 0 at every q within the limits: every body is consistent, or a certified lower bound is positive",
    "not_excluded": "some body is not consistent and no bound decides: M(q) may become singular",
    "everywhere": "the last bodies are massless: M(q) is singular at every q",
    "indefinite": "a sampled q gives a negative eigenvalue beyond rounding: negative kinetic energy",
    "singular": "a sampled q gives an eigenvalue zero to rounding",
}
# per constant: label, statement, keys of the paper's constant's ends, of the certified constant, of the true
# extreme's lower and upper side, and of its observed (sampled) side
BOUNDS = (
    ("\u03b11", "\u03b11 \u2264 inf \u03bbmin(M(q))", ("alpha1_paper_lower", "alpha1_paper_upper"),
     "alpha1_certified", ("inf_lambda_min_certified", "inf_lambda_min_sampled"), "inf_lambda_min_sampled"),
    ("\u03b12", "\u03b12 \u2265 sup \u03bbmax(M(q))", ("alpha2_paper_lower", "alpha2_paper_upper"),
     "alpha2_certified", ("lambda_max", "sup_lambda_max_certified"), "lambda_max"),
)


def build(doc):
    """The Document of an audit document (as :func:`report.load.audit` returns it)."""
    files = doc["files"]
    keys = {path: f"file-{i + 1}" for i, path in enumerate(files)}
    names = short_names(files)
    figs = Figures()
    robots = tuple(_file(path, f, keys[path], names[path], figs) for path, f in files.items())
    return Document(TITLE, SUBTITLE, (_summary(doc, keys, names),
                                      Section("robots", (Text("Robots"),), children=robots), _legend()))


def short_names(paths):
    """Each path relative to the folder all of them lie in (a lone file by its name)."""
    parts = {p: PurePath(p).parts for p in paths}
    folders = [v[:-1] for v in parts.values()]
    common = 0
    while folders and all(len(f) > common and f[common] == folders[0][common] for f in folders):
        common += 1
    return {p: PurePath(*v[common:]).as_posix() for p, v in parts.items()}


# -- the summary ---------------------------------------------------------------

def _summary(doc, keys, names):
    files, s = doc["files"], doc["summary"]
    failing = [p for p, f in files.items() if f["status"] == "ok" and not f["consistent"]]
    unreadable = [p for p, f in files.items() if f["status"] == "error"]
    blocks = []
    if failing:
        items = tuple((Link(names[p], keys[p], "code"), Text(": " + ", ".join(files[p]["not_consistent"])))
                      for p in failing)
        blocks.append(Notice("VIOLATED", f"Not consistent: {_count(len(failing), 'file')} with moving links or "
                                         "bodies that no solid body can have", (Bullets(items),)))
    if unreadable:
        items = tuple((Link(names[p], keys[p], "code"), Text(": " + files[p]["error"])) for p in unreadable)
        blocks.append(Notice("VIOLATED", f"Unreadable: {_count(len(unreadable), 'file')}", (Bullets(items),)))
    if not failing and not unreadable:
        blocks.append(Notice("HOLDS", "Every moving link and body is consistent",
                             (Paragraph((Text(f"{_count(len(files), 'file')} audited."),)),)))
    blocks.append(Paragraph((Text(f"{_count(s['files'], 'file')} audited in {fmt.seconds(doc.get('runtime_s'))}: "),
                             Text(totals(s) + "."))))
    blocks.append(_glance(files, keys, names))
    blocks.append(_run_table(doc))
    return Section("summary", (Text("Summary"),), tuple(blocks))


def _glance(files, keys, names):
    rows = []
    for path, f in files.items():
        where = cell(Link(names[path], keys[path], "code"))
        if f["status"] == "error":
            rows.append((where, cell("-"), cell("-"), cell("-"), cell(Badge("unreadable", "VIOLATED")), cell("-")))
            continue
        singular = Counter(c["singular"]["verdict"] for c in f["chains"].values())
        counted = str(len(f["links"]))
        if "counts" in f:  # how many of them are judged (joint frames, massless frames, fixed bases are not)
            counted += f" ({len(f['links']) - f['counts'].get('not_judged', 0)})"
        rows.append((where, cell(code(f["robot"])), cell(code(counted)),
                     cell(code(str(len(f["not_consistent"])))), cell(_file_badge(f)),
                     cell(", ".join(f"{v} ({n})" for v, n in singular.items()) or "no chains")))
    columns = (Column("file", 0.35), Column("robot", 0.18), Column("links (judged)", 0.1, "r"),
               Column("not consistent", 0.11, "r"), Column("verdict", 0.13), Column("M(q) singular", 0.13))
    return table(columns, rows, "Every file at a glance", limit=None)


def _run_table(doc):
    rows = [("profile", doc.get("profile")), ("seed", doc.get("seed")), ("M(q) bounds for", doc.get("bounds")),
            ("floating base", doc.get("floating_base")), ("repair slack", doc.get("repair_slack")),
            ("run time", fmt.seconds(doc.get("runtime_s")))]
    rows += [(f"version of {k}", v) for k, v in doc.get("versions", {}).items()]
    return table((Column("", 0.3), Column("", 0.7)), [(cell(k), cell(code(fmt.value(v)))) for k, v in rows],
                 "The audit", limit=None)


def _file_badge(f):
    return Badge("consistent", "HOLDS") if f["consistent"] else Badge("not consistent", "VIOLATED")


# -- one file ------------------------------------------------------------------------

def _file(path, f, key, name, figs):
    if f["status"] == "error":
        title = (code(name), Text(" "), Badge("unreadable", "VIOLATED"))
        blocks = (Paragraph((Text("File "), code(path), Text("."))),
                  Notice("VIOLATED", "This file could not be read", (Paragraph((code(f["error"]),)),)))
        return Section(key, title, blocks, result_id=path, verdict="VIOLATED")
    blocks = [Paragraph((Text("File "), code(path), Text(f": {headline(f)}.")))]
    if remarks(f):
        blocks.append(Bullets(tuple((Text(line),) for line in remarks(f))))
    blocks += _links(f["links"])
    blocks += _repairs(f["links"])
    blocks += _bodies(f["bodies"])
    blocks += _chains(f["chains"])
    blocks += _bounds(f["chains"], name, figs)
    return Section(key, (code(name), Text(" "), _file_badge(f)), tuple(blocks), result_id=path,
                   verdict="HOLDS" if f["consistent"] else "VIOLATED")


def _links(links):
    frames = [name for name, link in links.items() if link["massless_frame"] and link["role"] != "joint_frame"]
    joint_frames = [name for name, link in links.items() if link["role"] == "joint_frame"]
    rows = []
    for name, link in links.items():
        if link["massless_frame"]:
            continue
        tone = LINK_TONES.get(link["verdict"], "INCONCLUSIVE") if link["moving"] else NOT_JUDGED
        why = link["reason"] + ("" if link["moving"] else " (does not move: not judged)")
        signs = [Text(f" Sign{'s' * (len(link['signs']) > 1)}: ", "strong"),
                 Text("; ".join(s["text"] for s in link["signs"]))] if link["signs"] else []
        rows.append((cell(code(name), Text(f" {role(link)}", "em")), cell(Badge(link["verdict"], tone)),
                     cell(why, *signs), cell(code(_repair_size(link["repair"])))))
    columns = (Column("link and its role", 0.22), Column("verdict", 0.12),
               Column("reason; signs of a mistake", 0.56), Column("repair", 0.1, "r"))
    out = [table(columns, rows, f"Links with mass or inertia ({len(rows)} of {len(links)}); repair: relative change "
                                "of the inertia", limit=None)] if rows else []
    if frames:
        names = [x for i, name in enumerate(frames) for x in ([Text(", ")] if i else []) + [code(name)]]
        out.append(Paragraph((Text(f"Massless frames ({len(frames)}): ", "strong"), *names,
                              Text(". No mass and no inertia: frames, not bodies, so not judged."))))
    if joint_frames:
        names = [x for i, name in enumerate(joint_frames) for x in ([Text(", ")] if i else []) + [code(name)]]
        out.append(Paragraph((Text(f"Joint frames ({len(joint_frames)}): ", "strong"), *names,
                              Text(". Frames between two joints of one MuJoCo body: not bodies, so not judged."))))
    return out


def _repair_size(repair):
    if repair is None:
        return ""
    return "none" if repair["inertia"] is None else _number(repair.get("change_frobenius_rel"))


def _repairs(links):
    rows, notes = [], []
    for name, link in links.items():
        r = link["repair"]
        if r is None:
            continue
        if r["inertia"] is None:
            rows.append((cell(code(name)), cell("-"), cell("-"), cell(Text(r["note"], "em"))))
            continue
        notes.append(r["note"])
        change = f"{_number(r.get('change_frobenius_rel'))} relative; {_number(r.get('change_spectral'))}"
        moments = f"({_numbers(r.get('principal_moments_before'))}) -> ({_numbers(r.get('principal_moments_after'))})"
        six = " ".join(f'{k}="{v}"' for k, v in (r.get("written") or {}).items())  # digits consistent as written
        rows.append((cell(code(name)), cell(code(change)), cell(code(moments)), cell(code(f"<inertia {six}/>"))))
    if not rows:
        return []
    why = f" ({'; '.join(dict.fromkeys(notes))})" if notes else ""
    columns = (Column("link", 0.16), Column("change (Frobenius; spectral)", 0.18, "r"),
               Column("principal moments [kg m^2]", 0.26), Column("suggested <inertia> about the CoM", 0.4))
    return [table(columns, rows, f"Repairs: the nearest consistent inertia about the CoM{why}", limit=None)]


def _number(q, digits=3):
    """A number or quantity as short text with its unit; n/a when it is not a finite number."""
    value = fmt.to_float(q)
    if value is None:
        return "n/a"
    unit = q.get("unit") if fmt.is_quantity(q) else None
    return f"{value:.{digits}g}" + (f" {unit}" if unit else "")


def _numbers(q):
    values = q.get("value") if fmt.is_quantity(q) else q
    return ", ".join(_number(v, 4) for v in values) if isinstance(values, list) else "n/a"


def _bodies(bodies):
    rows = [(cell(code(name)), cell(code(b["joint"] or "-")), cell(code(", ".join(b["links"]))),
             cell(Badge(b["verdict"], LINK_TONES.get(b["verdict"], "INCONCLUSIVE"))), cell(b["reason"]))
            for name, b in bodies.items() if b["verdict"] != "consistent" and b.get("judged", True)]
    if not rows:
        return []
    columns = (Column("body", 0.16), Column("joint", 0.16), Column("links", 0.2), Column("verdict", 0.13),
               Column("reason", 0.35))
    return [table(columns, rows, "Bodies that are not consistent (a moving link with the links fixed to it)",
                  limit=None)]


def _chains(chains):
    if not chains:
        return [Paragraph((Text("No chains: no movable joint.", "em"),))]
    rows = []
    for c in chains.values():
        verdict = c["singular"]["verdict"]
        rows.append((cell(code(c["name"])), cell(code(f"{len(c['joints'])} {c['kinds']}")),
                     cell("all consistent" if c["bodies_consistent"] else "not all consistent"),
                     cell(Badge(verdict, SINGULAR_TONES.get(verdict, "INCONCLUSIVE")), Text(" " + c["singular"]["argument"]))))
    columns = (Column("chain", 0.24), Column("joints", 0.12), Column("bodies", 0.12),
               Column("can M(q) become singular?", 0.52))
    return [table(columns, rows, f"Chains ({len(chains)}): from the base to each leaf through movable joints",
                  limit=None)]


def _bounds(chains, name, figs):
    measured = {leaf: c["bounds"] for leaf, c in chains.items() if c["bounds"]}
    if not measured:
        return []
    rows, points = [], []
    for leaf, b in measured.items():
        rows.append((cell(Text("chain "), code(chains[leaf]["name"])),))
        for label, statement, paper, certified, extreme, observed in BOUNDS:
            rows.append((cell(statement), cell(code(_interval(b, paper))), cell(code(_number(b.get(certified)))),
                         cell(code(_interval(b, extreme)))))
            points.append({"label": f"{label} ({leaf})", "paper": [fmt.to_float(b.get(k)) for k in paper],
                           "certified": fmt.to_float(b.get(certified)),
                           "observed": fmt.to_float(b.get(observed))})
    columns = (Column("bound", 0.25), Column("paper's constant lies in", 0.27, "r"),
               Column("sharpest certified", 0.18, "r"), Column("the extreme lies in", 0.3, "r"))
    figure = figs.new("constants", {"bounds": points, "x_label": "eigenvalue of M(q) (units of M)"},
                      f"{name}: per chain, the paper's \u03b11 and \u03b12 (the range between their values from "
                      "certified and from observed ingredients), the sharpest certified constants and the observed "
                      "extremes of the eigenvalues of M(q) over the joint limits. \u03b11 lies left of the smallest "
                      "eigenvalue, \u03b12 right of the largest; the distance is the conservatism.")
    text = Paragraph((Text("The paper's constants lie between their values from certified ingredients (valid bounds) "
                           "and from observed ones (estimates); the true extreme of the eigenvalues lies between its "
                           "certified and its sampled side."),))
    caption = f"Bounds of M(q) over the joint limits (Theorems 2 and 3; Figure {figure.number})"
    return [text, table(columns, rows, caption, limit=None), figure]


def _interval(bounds, keys):
    return "[" + ", ".join(_number(bounds.get(k)) for k in keys) + "]"


# -- how to read ------------------------------------------------------------------------

def _legend():
    links = [(cell(Badge(v, LINK_TONES[v])), cell(m)) for v, m in LINK_MEANINGS.items()]
    links.append((cell("a verdict in grey"), cell("a massless frame, or a link that does not move (the "
                                                  "base and links fixed to it, unless --floating-base): not judged")))
    singular = [(cell(Badge(v, SINGULAR_TONES[v])), cell(m)) for v, m in SINGULAR_MEANINGS.items()]
    text = Paragraph((Text("A file is consistent when every moving link with mass and every body (a moving link "
                           "with the links fixed to it) is. Numbers: certified sides are guaranteed bounds; sampled "
                           "sides are extremes over random configurations, one-sided estimates of the inf or sup."),))
    return Section("reading", (Text("How to read the audit"),), (
        text, table((Column("verdict", 0.2), Column("meaning", 0.8)), links, "Verdicts of links and bodies"),
        table((Column("M(q) singular", 0.2), Column("meaning", 0.8)), singular, "Can M(q) become singular?")))


def _count(n, noun):
    return f"{n} {noun}{'' if n == 1 else 's'}"
