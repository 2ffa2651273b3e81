"""Data files next to results.json (Result.artifacts) as report blocks.

``work_precision*.json`` rows (scene, method, rtol, seconds, error; optional status,
note, work, predicted, implicit) become an error-against-run-time plot (implicit
methods dashed; per scene the cheapest method reaching each error, and the methods
with no finished run and why), a summary table and a "use" line per scene; ``stability*.json`` rows
(scene, method, status, seconds, steps, note) a table and a plot; any other
list of rows (objects, or {"columns": [...], "rows": [[...], ...]}) a plain table.
"""

from __future__ import annotations

import math
from pathlib import PurePosixPath

from inertiaproof.report import evidence
from inertiaproof.report import numbers as fmt
from inertiaproof.report.model import Column, Paragraph, Text, cell, code

__all__ = ["blocks", "cheapest", "IMPLICIT", "is_ok", "OK_STATUS", "stability", "USE_AT", "why_none",
           "work_precision", "work_precision_data"]

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


IMPLICIT = ("Radau", "BDF", "LSODA")  # solve_ivp's implicit methods (LSODA switches to BDF when stiff)
USE_AT = (1e-3, 1e-6, 1e-10)  # errors at which a scene's "use" line names the cheapest method


def work_precision(rows, figs, result_name):
    """Error against run time per scene and method (one line per method, implicit methods marked), a table of each
    method's fastest and most accurate run (or why it has none: not run, predicted beyond its budget, or how it
    ended), and per scene a "use" line: the cheapest method reaching each error of USE_AT."""
    data = work_precision_data(rows)
    scenes, missing, use = data["scenes"], data["not_run"], data["use"]
    table = []
    for scene in dict.fromkeys([*scenes, *missing]):
        methods = scenes.get(scene, {})
        for method, points in methods.items():
            best = min(points, key=lambda p: p[1])
            fastest = min(points, key=lambda p: p[0])
            table.append((cell(code(scene)), cell(_kind(method, data["implicit"])), cell(code(str(len(points)))),
                          cell(code(f"{fmt.number(fastest[1])} in {fmt.seconds(fastest[0])}")),
                          cell(code(f"{fmt.number(best[1])} in {fmt.seconds(best[0])}"))))
        for method, why in missing.get(scene, {}).items():
            table.append((cell(code(scene)), cell(_kind(method, data["implicit"])), cell(code("0")), cell(why),
                          cell("-")))
    out = [evidence.table((Column("scene", 0.22), Column("method", 0.2), Column("runs", 0.08, "r"),
                            Column("fastest run: error", 0.25, "r"), Column("most accurate run: error", 0.25, "r")),
                           table, "Integrators: work against precision")]
    for scene, line in use.items():
        out.append(Paragraph((Text("Use on "), code(scene), Text(": " + line))))
    if scenes:
        out.append(figs.new("work_precision", data,
                            f"{result_name}: error against run time for each integrator "
                            "(tighter tolerances to the right; dashed: implicit methods); "
                            "lower and further left is better. Each panel names the cheapest method reaching "
                            "each error, and the methods that have no finished run there."))
    return out


def work_precision_data(rows):
    """The work-precision figure's data from rows (scene, method, rtol, seconds, error; optional status, note,
    predicted, work, implicit): {"scenes": {scene: {method: [[seconds, error, rtol, work], ...]}}, "implicit":
    [methods], "not_run": {scene: {method: why}} for methods with no point, "use": {scene: text}}."""
    scenes, reasons, implicit = {}, {}, set()
    for row in rows:
        scene, method = str(row.get("scene", "")), str(row.get("method", "?"))
        if row.get("implicit") or (row.get("implicit") is None and method in IMPLICIT):
            implicit.add(method)
        s, e = fmt.to_float(row.get("seconds")), fmt.to_float(row.get("error"))
        if s is None or e is None:
            reasons.setdefault(scene, {}).setdefault(method, []).append(row)
            continue
        scenes.setdefault(scene, {}).setdefault(method, []).append(
            [s, e, fmt.to_float(row.get("rtol")), fmt.to_float(row.get("work"))])
    not_run = {}
    for scene, by_method in reasons.items():
        for method, failed in by_method.items():
            if method not in scenes.get(scene, {}):
                not_run.setdefault(scene, {})[method] = why_none(failed)
    use = {}
    for scene in dict.fromkeys([*scenes, *not_run]):
        parts = []
        for target in USE_AT:
            found = cheapest(scenes.get(scene, {}), target)
            if found:
                method, seconds, work = found
                spent = fmt.seconds(seconds) + ("" if work is None else f", work {work:.0f}")
                parts.append(f"error <= {_decade(target)}: {method} ({spent})")
        if not parts:
            parts.append(f"no method reached error {_decade(USE_AT[0])}")
        use[scene] = "; ".join(parts)
    return {"scenes": scenes, "implicit": sorted(implicit), "not_run": not_run, "use": use}


def cheapest(methods, error):
    """(method, seconds, work or None) of the method reaching ``error`` in the least run time, from {method: [[seconds,
    error, rtol, work], ...]}; between two runs of one method seconds and work are interpolated log-log at ``error``.
    None if no method reaches it."""
    best = None
    for method, points in methods.items():
        at = _at(sorted((p for p in points if p[1] > 0), key=lambda p: p[1]), error)  # 0: the reference itself
        if at is not None and (best is None or at[0] < best[1]):
            best = (method, *at)
    return best


def _at(points, error):
    """(seconds, work) along points sorted by error where the error first reaches ``error``; None if never."""
    reached = [p for p in points if p[1] <= error]
    if not reached:
        return None
    lo = max(reached, key=lambda p: p[1])
    above = [p for p in points if p[1] > error]
    if not above or lo[1] <= 0:
        return lo[0], lo[3]
    hi = min(above, key=lambda p: p[1])
    w = math.log(error / lo[1]) / math.log(hi[1] / lo[1])

    def between(a, b):
        if a is None or b is None or a <= 0 or b <= 0:
            return a
        return math.exp((1 - w) * math.log(a) + w * math.log(b))

    return between(lo[0], hi[0]), between(lo[3], hi[3])


def why_none(rows):
    """Why a method has no finished run in a scene, from its rows: predicted beyond its budget, or how they ended."""
    predicted = [fmt.to_float(r.get("predicted")) for r in rows]
    predicted = [p for p in predicted if p is not None]
    if predicted:
        return f"not run: predicted {min(predicted):.2g} right-hand sides (stiff)"
    statuses = list(dict.fromkeys(str(r.get("status") or "no error") for r in rows))
    return "no finished run: " + ", ".join(statuses)


def _decade(x):
    """1e-06 as 1e-6."""
    return f"1e{round(math.log10(x))}" if x > 0 and math.log10(x) == round(math.log10(x)) else f"{x:g}"


def _kind(method, implicit):
    return f"{method} (implicit)" if method in implicit else method


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
