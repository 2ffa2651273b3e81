"""Section 4 for a control engineer: per chain, each bound's paper constant, the certified bracket of the true
extreme and how far apart they are; and how the brackets narrowed with run time.

The numbers come from the results of Def2, Thm2, Thm3, Thm4, EQ-acc and Asm3/Thm5 (their ``scenes`` or
``chains`` evidence). A bracket of the true extreme has a lower and an upper bound; which of them is certified
(branch and bound, rigorous) and which is attained at a witness configuration (a true value, so a bound from
the other side) depends on whether the extreme is an infimum or a supremum, and the table says so per row. The
paper's constant is known up to its own ingredients' brackets: [lower, upper] as evaluated with certified and
with observed ingredients. Bench data of ``bench/bracket_narrowing.py`` (deep profile), when present, give a
second narrowing figure.
"""

from __future__ import annotations

import math

from inertiaproof.report import evidence
from inertiaproof.report import numbers as fmt
from inertiaproof.report.model import Column, Paragraph, Section, Text, cell, code
from inertiaproof.report.paper_names import printed

__all__ = ["BOUNDS", "chain_rows", "narrowing_lines", "section"]

# check, how the paper names it (labels as in its source), the inequality, sense of the extreme
BOUNDS = (
    ("Def2", ("definition:NormalJacobian",), "inf_q sigma_min(QJ)^2 > 0 (QJ normal)", "min"),
    ("Thm2", ("theorem:LowerBoundedMassMatrix", "LowerBoundedness"), "M(q, Theta(t)) >= alpha1 I", "min"),
    ("Thm3", ("theorem:UpperBoundedMassMatrix", "UpperBoundedness"), "M(q, Theta(t)) <= alpha2 I", "max"),
    ("Thm4", ("theorem:BoundedRateOfChange", "BoundedEffectofVaryingParam"), "sigma_max(M(q, Thetadot)) <= chi",
     "max"),
    ("EQ-acc", ("LumpedAccelerationBounding",), "||J^T Q^T Psidot|| <= dPsi* sup sigma_max(QJ)", "max"),
    # Theorem 5 has no label of its own in the paper's source: its number is the fifth theorem environment
    ("Asm3/Thm5", ("Theorem 5", "BoundedEffectOfLumpedVel"), "sigma_max(H(q, Psi)) <= sqrt(6N) Psi* max_p Y_p",
     "max"),
)


def _value(q):
    return fmt.to_float(q.get("value")) if isinstance(q, dict) else None


def _per_scene(result):
    ev = result.get("evidence") or {}
    scenes = ev.get("scenes") if isinstance(ev.get("scenes"), dict) else ev.get("chains")
    return scenes if isinstance(scenes, dict) else {}


def chain_rows(doc):
    """{chain: [row]} with row = dict(check, name, inequality, sense, paper (lo, hi) or None, lower, upper,
    lower_kind, upper_kind, quantity)."""
    by_id = {}
    for r in doc.get("checks", []):
        if (r.get("check") or r["id"]) == r["id"]:
            by_id.setdefault(r["id"], r)
    out = {}
    for check, labels, inequality, sense in BOUNDS:
        result = by_id.get(check)
        if result is None:
            continue
        for chain, ev in _per_scene(result).items():
            b = ev.get("bracket") if isinstance(ev, dict) else None
            if not isinstance(b, dict):
                continue
            c = ev.get("constants") or {}
            paper = None
            if c:
                ends = sorted(v for v in (_value(c.get("paper")), _value(c.get("paper_observed"))) if v is not None)
                paper = (ends[0], ends[-1]) if ends else None
            out.setdefault(chain, []).append({
                "check": check, "name": ", ".join(printed(label) for label in labels), "inequality": inequality,
                "sense": sense, "paper": paper, "quantity": str(b.get("quantity", "")),
                "lower": _value(b.get("lower")), "upper": _value(b.get("upper")),
                "lower_kind": (b.get("lower") or {}).get("kind"), "upper_kind": (b.get("upper") or {}).get("kind"),
                "verdict": result.get("verdict")})
    return out


def _side(value, kind):
    what = {"lower_bound": "certified lower bound", "upper_bound": "certified upper bound",
            "sampled": "attained at a witness"}.get(kind, str(kind or ""))
    return (Text(fmt.number(value) if value is not None else "none"), Text(f" ({what})", "em"))


def _ratio(a, b):
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)) or a <= 0 or b <= 0:
        return None
    return a / b


def _ratios(row):
    """(bracket width ratio upper/lower, conservatism range of the paper's constant against the true extreme)."""
    width = _ratio(row["upper"], row["lower"])
    if row["paper"] is None:
        return width, None
    lo, hi = row["paper"]
    if row["sense"] == "max":  # paper constant / true sup, the sup in [lower, upper]
        span = (_ratio(lo, row["upper"]), _ratio(hi, row["lower"]))
    else:  # true inf / paper constant
        span = (_ratio(row["lower"], hi), _ratio(row["upper"], lo))
    return width, span


def _shown_ratio(x):
    if x is None:
        return "n/a"
    return f"{x:.7g}" if abs(x - 1) < 1e-3 else f"{x:.3g}"


def _table(chain, rows):
    body = []
    for row in rows:
        width, span = _ratios(row)
        paper = ("none (a definition: only the extreme)" if row["paper"] is None else
                 f"in [{fmt.number(row['paper'][0])}, {fmt.number(row['paper'][1])}]")
        conservative = ("n/a" if span is None else
                        f"{_shown_ratio(span[0])} to {_shown_ratio(span[1])}"
                        + (" (paper / sup)" if row["sense"] == "max" else " (inf / paper)"))
        body.append((cell(Text(row["name"], "strong"), Text(": " + row["inequality"])),
                     cell(Text(paper)),
                     cell(code(row["quantity"])),
                     cell(*_side(row["lower"], row["lower_kind"])),
                     cell(*_side(row["upper"], row["upper_kind"])),
                     cell(Text(_shown_ratio(width))),
                     cell(Text(conservative))))
    columns = (Column("bound, as the paper numbers it", 0.2), Column("paper's constant", 0.13),
               Column("true extreme", 0.15), Column("lower bound of the extreme", 0.13),
               Column("upper bound of the extreme", 0.13), Column("bracket ratio upper / lower", 0.09, "r"),
               Column("how conservative the paper is", 0.17))
    return evidence.table(columns, body, f"{chain}: the paper's constants against the true extremes", limit=None)


def narrowing_lines(doc, most=12):
    """Lines (label, [[seconds, relative width]]) of this run's brackets' convergence, at most ``most``."""
    lines = []
    for r in doc.get("checks", []):
        if (r.get("check") or r["id"]) != r["id"]:
            continue
        for chain, ev in _per_scene(r).items():
            b = ev.get("bracket") if isinstance(ev, dict) else None
            points = []
            for p in (b or {}).get("convergence") or []:
                if (isinstance(p, list) and len(p) == 3 and all(isinstance(x, (int, float)) for x in p)
                        and all(math.isfinite(x) for x in p) and p[2] != 0):
                    points.append([max(float(p[0]), 1e-6), abs(p[2] - p[1]) / abs(p[2])])
            if points:
                lines.append({"label": f"{chain}: {b.get('quantity', r['id'])}", "points": points})
    return lines[:most]


def bench_lines(bench, most=12):
    """Lines from bench/results/bracket_narrowing.json: width against seconds divided by the final upper end."""
    lines = []
    for b in (bench or {}).get("brackets") or []:
        upper = fmt.to_float(b.get("upper"))
        pts = b.get("width_against_seconds") or []
        if not upper or not pts:
            continue
        lines.append({"label": f"{b.get('scene_or_ingredient', '?')}: {b.get('quantity', '?')}",
                      "points": [[max(float(s), 1e-6), float(w) / abs(upper)] for s, w in pts
                                 if isinstance(w, (int, float)) and math.isfinite(w) and w > 0]})
    return [line for line in lines if line["points"]][:most]


def section(doc, figs, bench=None):
    """The Section, or None when the run has none of these bounds."""
    chains = chain_rows(doc)
    if not chains:
        return None
    lead = Paragraph((Text(
        "For each chain the suite ran, every Section 4 bound as the paper numbers it: the paper's constant (known "
        "up to its own ingredients: the interval between its value with certified and with observed ingredients), "
        "the true extreme it bounds, bracketed from both sides, and two ratios: the bracket's upper / lower end "
        "(1 = the extreme is known exactly) and how far the paper's constant is from the true extreme (paper / sup "
        "for an upper bound, inf / paper for a lower bound; 1 = the paper is sharp). Each side of a bracket says "
        "whether it is certified (rigorous, with its rounding bounded) or attained at a witness configuration (a "
        "true value of the quantity, so a bound of the extreme from the other side)."),))
    blocks = [lead] + [_table(chain, rows) for chain, rows in chains.items()]
    lines = narrowing_lines(doc)
    if lines:
        blocks.append(figs.new("narrowing", {"lines": lines},
                               "Relative width (upper - lower) / |upper| of this run's brackets against the run time "
                               "spent narrowing them."))
    more = bench_lines(bench)
    if more:
        blocks.append(figs.new("narrowing", {"lines": more},
                               f"Relative width of the brackets of bench/bracket_narrowing.py (profile "
                               f"{bench.get('profile', '?')}) against run time, divided by the final upper end."))
    return Section("engineer", (Text("Section 4 for a control engineer: paper constants against true extremes"),),
                   tuple(blocks))
