"""The audit document (:mod:`inertiaproof.audit`) as one self-contained HTML page."""

from __future__ import annotations

from html import escape

STYLE = """
body{font-family:system-ui,sans-serif;margin:2em;max-width:80em}
table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{border:1px solid #ccc;padding:.2em .5em;text-align:left;vertical-align:top}
.consistent{color:#176117}.degenerate{color:#8a5a00}.inconsistent,.invalid,.error{color:#a11212;font-weight:bold}
.frame{color:#888}code{font-size:90%}
"""


def _cell(text, cls=""):
    return f"<td{f' class={cls!r}' if cls else ''}>{escape(str(text))}</td>"


def _links(f):
    rows = []
    for name, link in f["links"].items():
        role = link["role"] if link["role"] != "merged" else f"merged into {link['group']}"
        cls = "frame" if link["massless_frame"] else link["verdict"]
        signs = "; ".join(s["text"] for s in link["signs"])
        repair = link["repair"] or {}
        fix = (f"{repair['change_frobenius_rel']['value']:.3g} relative change: "
               + " ".join(f"{k}={v:.4g}" for k, v in repair["inertia"].items())) if repair.get("inertia") else repair.get("note", "")
        rows.append("<tr>" + _cell(name) + _cell(role) + _cell(link["verdict"], cls) + _cell(link["reason"])
                    + _cell(signs) + _cell(fix) + "</tr>")
    head = "<tr><th>link</th><th>role</th><th>verdict</th><th>reason</th><th>signs</th><th>repair</th></tr>"
    return f"<table>{head}{''.join(rows)}</table>"


def _chains(f):
    rows = []
    for c in f["chains"].values():
        numbers = "; ".join(f"{k} = {q['value']:.6g} [{q['kind']}]" for k, q in (c["bounds"] or {}).items()
                            if isinstance(q, dict) and "kind" in q and isinstance(q["value"], (int, float)))
        rows.append("<tr>" + _cell(c["name"]) + _cell(c["kinds"]) + _cell("yes" if c["bodies_consistent"] else "no")
                    + _cell(f"{c['singular']['verdict']}: {c['singular']['argument']}") + _cell(numbers) + "</tr>")
    head = "<tr><th>chain</th><th>joints</th><th>bodies consistent</th><th>M(q) singular</th><th>eigenvalues of M(q)</th></tr>"
    return f"<table>{head}{''.join(rows)}</table>" if rows else "<p>No chains (no movable joints).</p>"


def render(doc):
    s = doc["summary"]
    parts = [f"<h1>Robot audit</h1><p>{s['files']} files, {s['files_consistent']} consistent, "
             f"{s['files_not_consistent']} not consistent, {s['unreadable']} unreadable; profile {escape(doc['profile'])}, "
             f"{doc['runtime_s']:.2f} s. Verdicts by Theorem 1: f(Phi) &gt; 0 on the inertia as written.</p>"]
    for path, f in doc["files"].items():
        if f["status"] == "error":
            parts.append(f"<h2>{escape(path)}</h2><p class='error'>{escape(f['error'])}</p>")
            continue
        state = "consistent" if f["consistent"] else "not consistent: " + ", ".join(f["not_consistent"])
        parts.append(f"<h2>{escape(path)}</h2><p>robot <code>{escape(f['robot'])}</code>: {escape(state)}</p>"
                     + _links(f) + _chains(f))
    return f"<!doctype html><html><head><meta charset='utf-8'><title>inertiaproof audit</title><style>{STYLE}</style></head><body>{''.join(parts)}</body></html>\n"
