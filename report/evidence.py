"""A result's evidence as report blocks: the plotted conventions of inertiaproof.result, everything else generically.

Conventions (any depth): ``bracket``, ``constants``, ``hunt``, ``series``.
Everything else becomes a table of what / value / kind / note, sub-tables for
lists of records, and code blocks for long text.
"""

from __future__ import annotations

import json

from inertiaproof.report import numbers as fmt
from inertiaproof.report.model import Code, Column, Figure, Table, Text, cell, code

__all__ = [
    "bracket_figure", "bracket_table", "constants_points", "constants_table", "CONVENTIONS", "Figures",
    "generic_blocks", "hunt_blocks", "json_text", "LONG_TEXT", "MAX_ROWS", "MAX_TEXT_LINES", "RECORD_TEXT",
    "records_table", "series_figures", "split", "table",
]

CONVENTIONS = ("bracket", "constants", "hunt", "series")
MAX_ROWS = 40
LONG_TEXT = 160
MAX_TEXT_LINES = 80


class Figures:
    """Hands out figure numbers and keys in reading order."""

    def __init__(self):
        self.made = []

    def new(self, kind, data, caption):
        figure = Figure(f"fig-{len(self.made) + 1}", len(self.made) + 1, kind, data, caption)
        self.made.append(figure)
        return figure


def split(evidence):
    """(conventions {name: [(path, value)]}, rows, tables, texts) of an evidence dict."""
    found = {name: [] for name in CONVENTIONS}
    rows, tables, texts = [], [], []

    def walk(x, path):
        key = path[-1] if path else None
        if key in CONVENTIONS and isinstance(x, dict) and _valid(key, x):
            found[key].append((path[:-1], x))
        elif fmt.is_quantity(x):
            note = "; ".join(filter(None, (str(x.get("note") or ""), checked(x))))
            rows.append((path, fmt.quantity(x), x["kind"], note))
        elif isinstance(x, str) and (len(x) > LONG_TEXT or "\n" in x):
            texts.append((path, x))
        elif _records(x):
            tables.append((path, x))
        elif isinstance(x, dict) and x:
            for k, v in x.items():
                walk(v, path + (str(k),))
        elif isinstance(x, list) and any(isinstance(v, (dict, list)) for v in x) and not _numeric(x):
            for i, v in enumerate(x):
                walk(v, path[:-1] + (f"{path[-1] if path else ''}[{i}]",))
        else:
            rows.append((path, fmt.value(x), "", ""))

    walk(evidence or {}, ())
    return {name: _distinct(items) for name, items in found.items()}, rows, tables, texts


def _distinct(items):
    """Items without repeats: of equal values (a headline copied from one of several cases) the longest path stays."""
    best = {}
    for i, (path, value) in enumerate(items):
        key = json.dumps(value, sort_keys=True, default=str)
        if key not in best or len(path) > len(items[best[key]][0]):
            best[key] = i
    return [items[i] for i in sorted(best.values())]


def generic_blocks(rows, tables, texts):
    blocks = []
    if rows:
        blocks.append(table((Column("what", 0.27), Column("value", 0.3), Column("kind", 0.14), Column("note", 0.29)),
                            _grouped(rows), "Evidence"))
    for path, records in tables:
        blocks.append(records_table(records, _label(path)))
    for path, text in texts:
        blocks.append(Code(_clip(text), _label(path)))
    return blocks


def _grouped(rows):
    """Table rows with the rows of one parent path together under a heading row naming it."""
    parents = {}
    for path, *rest in rows:
        parents.setdefault(path[:-1], []).append((path[-1] if path else "", *rest))
    out = []
    for parent, children in parents.items():
        if parent:
            out.append((cell(Text(_label(parent), "strong")),))
        out += [(cell(code(key)), cell(_value_inline(v)), cell(k), cell(n)) for key, v, k, n in children]
    return out


def _clip(text):
    lines = text.splitlines()
    if len(lines) <= MAX_TEXT_LINES and len(text) <= 100 * MAX_TEXT_LINES:
        return text
    kept = "\n".join(lines[:MAX_TEXT_LINES])[: 100 * MAX_TEXT_LINES]
    return f"{kept}\n... ({len(text) - len(kept)} more characters in results.json)"


RECORD_TEXT = 48  # characters: a longer text in a record goes under it, spanning the table


def records_table(records, caption):
    """A list of flat dicts, or a dict of flat dicts (named rows), as a table.

    Columns are as wide as their content (within limits); a text longer than
    RECORD_TEXT characters goes into a row spanning the table under its record.
    """
    if isinstance(records, dict):
        records = [{"name": name, **row} for name, row in records.items()]
    keys = []
    for row in records:
        keys.extend(k for k in row if k not in keys)
    keys = keys[:8]
    long_keys = [k for k in keys if any(isinstance(r.get(k), str) and len(r[k]) > RECORD_TEXT for r in records)]
    short = [k for k in keys if k not in long_keys] or keys[:1]
    long_keys = [k for k in long_keys if k not in short]
    weights = [max(len(k), min(24, max((len(fmt.value(r[k])) for r in records if k in r), default=1))) for k in short]
    columns = tuple(Column(k, w / sum(weights), "r" if _numeric_column(records, k) else "l")
                    for k, w in zip(short, weights))
    rows = []
    for row in records:
        rows.append(tuple(cell(_value_inline(fmt.value(row[k])) if k in row else "") for k in short))
        texts = [inline for k in long_keys if k in row for inline in (Text(f"{k}: ", "em"), Text(f"{row[k]} "))]
        if texts:
            rows.append((cell(*texts),))
    return table(columns, rows, caption)


def bracket_table(brackets):
    rows = []
    for path, b in brackets:
        lower, upper = b.get("lower"), b.get("upper")
        width = _difference(upper, lower)
        where = (code(_label(path)), Text(" ")) if path else ()
        rows.append((cell(*where, str(b.get("quantity") or "extreme")), _side(lower), _side(upper),
                     cell(code(width)), cell(code(str(len(b.get("convergence") or []))))))
    return table((Column("extreme", 0.28), Column("lower", 0.2, "r"), Column("upper", 0.2, "r"),
                   Column("width", 0.18, "r"), Column("points", 0.14, "r")), rows,
                  "Brackets: the true extreme lies between lower and upper")


def bracket_figure(brackets, figs, result_name):
    lines = []
    unit = None
    for path, b in brackets:
        points = []
        for point in b.get("convergence") or []:
            if isinstance(point, list) and len(point) == 3:
                s, lo, up = (fmt.to_float(v) for v in point)
                if None not in (s, lo, up):
                    points.append([s, up - lo])
        if points:
            lines.append({"label": _label(path) or str(b.get("quantity") or "extreme"), "points": points})
            unit = unit or _unit(b.get("lower")) or _unit(b.get("upper"))
    if not lines:
        return None
    quantities = ", ".join(dict.fromkeys(str(b.get("quantity")) for _, b in brackets if b.get("quantity")))
    of = f" on {quantities}" if quantities else ""
    return figs.new("bracket", {"lines": lines, "unit": unit},
                    f"{result_name}: width of the bracket{of} (upper minus lower) against the run time spent "
                    "narrowing it.")


def constants_table(constants, name, figure=None):
    rows = []
    for path, c in constants:
        observed = c.get("observed")
        rows.append((cell(code(_label(path) or name)), _side(c.get("paper"), "paper_constant"),
                     _side(c.get("certified"), "certified_constant"),
                     _side(observed), cell(code(fmt.ratio(c.get("paper"), observed))),
                     cell(code(fmt.ratio(c.get("certified"), observed)))))
    caption = "Constants of the bound; a ratio near 1 means a tight constant"
    if figure is not None:
        caption += f" (all bounds: Figure {figure.number})"
    return table((Column("bound", 0.16), Column("paper", 0.18, "r"), Column("certified", 0.18, "r"),
                   Column("observed", 0.18, "r"), Column("paper / observed", 0.15, "r"),
                   Column("certified / observed", 0.15, "r")), rows, caption)


def constants_points(constants, name, violated=False):
    """Rows of the constants figure: label, paper, certified, observed (floats or None), violated."""
    out = []
    for path, c in constants:
        label = name if not path else f"{name} {_label(path)}"
        out.append({"label": label, **{k: fmt.to_float(c.get(k)) for k in ("paper", "certified", "observed")},
                    "violated": violated})
    return out


def hunt_blocks(hunts, figs, result_name):
    rows, series, unit = [], [], None
    for path, h in hunts:
        margins = [m for m in (fmt.to_float(v) for v in h.get("margins") or []) if m is not None]
        negative = sum(m < 0 for m in margins)
        rows.append((cell(code(_label(path) or "hunt")), cell(code(fmt.value(h.get("examples", len(margins))))),
                     cell(code(fmt.value(h["smallest_margin"]) if "smallest_margin" in h else "n/a")),
                     cell(code(str(len(margins)))), cell(code(str(negative)))))
        if margins:
            series.append({"label": _label(path) or result_name, "margins": margins})
            unit = unit or _unit(h.get("smallest_margin"))
    blocks = [table((Column("hunt", 0.28), Column("examples", 0.16, "r"), Column("smallest margin", 0.24, "r"),
                      Column("margins", 0.16, "r"), Column("negative", 0.16, "r")), rows,
                     "Hypothesis hunts: margin = distance from the boundary of the statement (positive = holds)")]
    if series:
        blocks.append(figs.new("hunt", {"hunts": series, "unit": unit},
                               f"{result_name}: margins of the examples the hunt tried "
                               "(positive = the statement holds)."))
    return blocks


def series_figures(series, figs, result_name):
    out = []
    for path, s in series:
        title = str(s.get("title") or _label(path) or "series")
        out.append(figs.new("series", s, f"{result_name}: {title}."))
    return out


def json_text(data, max_lines=60):
    """Indented JSON with short lists of scalars kept on one line."""
    lines = _json_lines(data, 0)
    if len(lines) > max_lines:
        lines = lines[:max_lines] + [f"... ({len(lines) - max_lines} more lines in the file)"]
    return "\n".join(lines)


def _json_lines(x, depth):
    pad = " " * depth
    flat = json.dumps(x, ensure_ascii=False)
    if not isinstance(x, (dict, list)) or not x or len(flat) <= 72:
        return [pad + flat]
    if isinstance(x, list) and not any(isinstance(v, (dict, list)) for v in x):
        return [pad + "["] + _wrapped([json.dumps(v, ensure_ascii=False) for v in x], pad + " ") + [pad + "]"]
    opening, closing = ("{", "}") if isinstance(x, dict) else ("[", "]")
    items = list(x.items()) if isinstance(x, dict) else [(None, v) for v in x]
    lines = [pad + opening]
    for i, (key, value) in enumerate(items):
        inner = _json_lines(value, depth + 1)
        if key is not None:
            inner[0] = f"{pad} {json.dumps(key, ensure_ascii=False)}: {inner[0].lstrip()}"
        if i < len(items) - 1:
            inner[-1] += ","
        lines += inner
    return lines + [pad + closing]


def _wrapped(items, pad, width=72):
    lines, line = [], ""
    for i, item in enumerate(items):
        item += "," if i < len(items) - 1 else ""
        if line and len(pad) + len(line) + 1 + len(item) > width:
            lines.append(pad + line)
            line = item
        else:
            line = f"{line} {item}" if line else item
    return lines + [pad + line]


def table(columns, rows, caption, limit=MAX_ROWS):
    rows = list(rows)
    if limit is not None and len(rows) > limit:
        more = len(rows) - limit
        rows = rows[:limit] + [(cell(Text(f"... and {more} more rows, not shown", "em")),)]
    return Table(tuple(columns), tuple(rows), caption)


def _valid(key, x):
    if key == "series":
        lines = x.get("lines")
        return isinstance(lines, dict) and all(isinstance(v, list) for v in lines.values())
    if key == "hunt":
        return isinstance(x.get("margins", []), list)
    if key == "bracket":
        return "lower" in x or "upper" in x
    return any(k in x for k in ("paper", "certified", "observed"))


def _flat(row):
    return isinstance(row, dict) and not set(row) & set(CONVENTIONS) and all(
        fmt.is_quantity(v) or not isinstance(v, (dict, list)) or _numeric(v) for v in row.values())


def _records(x):
    if isinstance(x, list):
        return len(x) >= 1 and all(isinstance(r, dict) and r and _flat(r) for r in x) and not all(
            fmt.is_quantity(r) for r in x)
    if isinstance(x, dict) and len(x) >= 2 and not fmt.is_quantity(x) and not set(x) & set(CONVENTIONS):
        return all(isinstance(r, dict) and r and not fmt.is_quantity(r) and _flat(r) for r in x.values())
    return False


def _numeric(x):
    if isinstance(x, list):
        return all(_numeric(v) for v in x)
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _numeric_column(records, key):
    values = [r[key] for r in records if key in r]
    return bool(values) and all(fmt.to_float(v) is not None for v in values)


def _label(path):
    return " / ".join(path)


def _value_inline(text):
    return code(text) if text[:1].isdigit() or text[:1] in "-[" or text in fmt.NON_FINITE else Text(text)


def checked(q):
    """What the independent checker said of a certified number (its ``certificate`` entry), in words; "" for none."""
    entry = q.get("certificate")
    if not isinstance(entry, dict) or "status" not in entry:
        return ""
    if entry["status"] == "re-proved":
        return f"re-proved by the independent checker ({entry['file']}, {fmt.seconds(entry.get('seconds', 0))})"
    return f"{entry['status']} by the independent checker ({entry['file']}): {entry.get('why', '')}"


def _side(q, expected_kind=None):
    if q is None:
        return cell("n/a")
    if fmt.is_quantity(q):
        status = q.get("certificate", {}).get("status") if isinstance(q.get("certificate"), dict) else None
        mark = (Text(f" {status}", "em"),) if status else ()
        if q["kind"] == expected_kind:
            return cell(code(fmt.quantity(q)), *mark)
        return cell(code(fmt.quantity(q)), Text(f" {q['kind']}", "em"), *mark)
    return cell(code(fmt.value(q)))


def _unit(q):
    return q.get("unit") if fmt.is_quantity(q) else None


def _difference(upper, lower):
    u, l = fmt.to_float(upper), fmt.to_float(lower)
    return "n/a" if u is None or l is None else fmt.number(u - l)
