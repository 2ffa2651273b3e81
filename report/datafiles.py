"""Data files next to results.json (Result.artifacts) as report blocks.

``work_precision*.json`` rows (scene, method, rtol, seconds, error) become an
error-against-run-time plot and a summary table; ``stability*.json`` rows
(scene, method, status, seconds, steps, note) a table and a plot; any other
list of rows (objects, or {"columns": [...], "rows": [[...], ...]}) a plain table.
"""

from __future__ import annotations

from pathlib import PurePosixPath

from inertiaproof.report import evidence
from inertiaproof.report import numbers as fmt
from inertiaproof.report.model import Column, Paragraph, Text, cell, code

__all__ = ["blocks", "is_ok", "OK_STATUS", "stability", "work_precision"]

OK_STATUS = {"ok", "success", "succeeded", "passed", "stable", "holds", "converged"}


def blocks(name, content, figs, result_name):
    if isinstance(content, str):
        return [Paragraph((Text("Data file problem: ", "strong"), code(content)))]
    stem = PurePosixPath(name).name
    intro = Paragraph((Text("Data file "), code(name), Text(".")))
    if isinstance(content, dict):
        _, rows, tables, texts = evidence.split(content)
        return [intro] + evidence.generic_blocks(rows, tables, texts)
    if stem.startswith("work_precision"):
        return [intro] + work_precision(content, figs, result_name)
    if stem.startswith("stability"):
        return [intro] + stability(content, figs, result_name)
    return [intro, evidence.records_table(content, name)] if content else [intro]


def is_ok(status):
    return str(status).strip().lower() in OK_STATUS


def work_precision(rows, figs, result_name):
    scenes = {}
    for row in rows:
        s, e = fmt.to_float(row.get("seconds")), fmt.to_float(row.get("error"))
        if s is None or e is None:
            continue
        method = scenes.setdefault(str(row.get("scene", "")), {}).setdefault(str(row.get("method", "?")), [])
        method.append([s, e, fmt.to_float(row.get("rtol"))])
    table = []
    for scene, methods in scenes.items():
        for method, points in methods.items():
            best = min(points, key=lambda p: p[1])
            fastest = min(points, key=lambda p: p[0])
            table.append((cell(code(scene)), cell(method), cell(code(str(len(points)))),
                          cell(code(f"{fmt.number(fastest[1])} in {fmt.seconds(fastest[0])}")),
                          cell(code(f"{fmt.number(best[1])} in {fmt.seconds(best[0])}"))))
    out = [evidence.table((Column("scene", 0.24), Column("method", 0.18), Column("runs", 0.1, "r"),
                            Column("fastest run: error", 0.24, "r"), Column("most accurate run: error", 0.24, "r")),
                           table, "Integrators: work against precision")]
    if scenes:
        out.append(figs.new("work_precision", {"scenes": scenes},
                            f"{result_name}: error against run time for each integrator "
                            "(tighter tolerances to the right); "
                            "lower and further left is better."))
    return out


def stability(rows, figs, result_name):
    keys = ("scene", "method", "status", "seconds", "steps", "note")
    widths = (0.2, 0.13, 0.2, 0.12, 0.12, 0.23)
    columns = tuple(Column(k, w, "r" if k in ("seconds", "steps") else "l") for k, w in zip(keys, widths))
    table = []
    points = []
    for row in rows:
        ok = is_ok(row.get("status"))
        status = Text(str(row.get("status", "")), "" if ok else "strong")
        table.append((cell(code(str(row.get("scene", "")))), cell(str(row.get("method", ""))), cell(status),
                      cell(code(fmt.value(row.get("seconds")))), cell(code(fmt.value(row.get("steps")))),
                      cell(str(row.get("note") or ""))))
        seconds = fmt.to_float(row.get("seconds"))
        if seconds is not None:
            points.append({"scene": str(row.get("scene", "")), "method": str(row.get("method", "")),
                           "seconds": seconds, "ok": ok})
    failed = sum(not is_ok(r.get("status")) for r in rows)
    out = [evidence.table(columns, table, f"Stability study: {failed} of {len(rows)} runs did not finish cleanly")]
    if points:
        out.append(figs.new("stability", {"points": points},
                            f"{result_name}: run time of each integrator on the stiff and extreme cases; "
                            "crosses mark runs that failed."))
    return out
