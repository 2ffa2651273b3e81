"""An adapt document (``inertiaproof.adapt/1``, DIR/adapt.json of ``inertiaproof adapt``) as a report
:class:`~report.model.Document`: the run and its summary, then one plot per time series (tracking error, parameter
error, lambda_min of each f(Phi_hat_l), the spectrum of M(q, Theta_hat) along the run and over sampled q)."""

from __future__ import annotations

from pathlib import Path

from inertiaproof.errors import InputError
from inertiaproof.report import numbers as fmt
from inertiaproof.report.evidence import Figures, table
from inertiaproof.report.load import read_json
from inertiaproof.report.model import Column, Document, Paragraph, Section, Text, cell, code

__all__ = ["ADAPT", "build", "load", "SCHEMA"]

ADAPT = "adapt.json"
SCHEMA = "inertiaproof.adapt/1"
SERIES = ("t", "tracking_error", "parameter_error", "lambda_min_f_hat", "lambda_min_M_hat", "lambda_max_M_hat")


def load(path):
    """The adapt document at path, checked well enough that the report cannot trip over it."""
    path = Path(path)
    doc = read_json(path)
    if not isinstance(doc, dict) or doc.get("schema") != SCHEMA:
        raise InputError(f"{path}: not an inertiaproof adapt file (schema {SCHEMA})")
    series = doc.get("series")
    missing = [k for k in SERIES if not isinstance(series, dict) or not isinstance(series.get(k), list)]
    if missing:
        raise InputError(f"{path}: series: missing {', '.join(missing)}")
    return doc


def _lines(t, columns, names):
    """{name: [[t, y], ...]} of one series or of the columns of a (T, k) series."""
    rows = [c if isinstance(c, list) else [c] for c in columns]
    return {name: [[x, r[k]] for x, r in zip(t, rows)] for k, name in enumerate(names)}


def build(doc):
    figs, s, x = Figures(), doc.get("summary", {}), doc["series"]
    t = x["t"]
    what = f"{doc.get('law')} (gain {fmt.value(doc.get('gain'))}) on the {doc.get('plant')} plant"
    bodies = len(x["lambda_min_f_hat"][0]) if x["lambda_min_f_hat"] and isinstance(x["lambda_min_f_hat"][0], list) \
        else 1
    low = {"at q(t)": x["lambda_min_M_hat"], "sampled inf over q": x.get("inf_lambda_min_M_hat")}
    high = {"at q(t)": x["lambda_max_M_hat"], "sampled sup over q": x.get("sup_lambda_max_M_hat")}
    plots = (
        ("tracking error |q - q_d|", "rad", _lines(t, x["tracking_error"], ["|e|"])),
        ("parameter error sum_l |f(Phi_hat_l - Phi_l)|_F / sum_l |f(Phi_l)|_F", "relative",
         _lines(t, x["parameter_error"], ["parameter error"])),
        ("lambda_min(f(Phi_hat_l)): below 0 the estimate is not physically consistent", "lambda_min",
         _lines(t, x["lambda_min_f_hat"], [f"body {k + 1}" for k in range(bodies)])),
        ("lambda_min(M(q, Theta_hat)): below 0 the estimated mass matrix is indefinite", "lambda_min",
         {name: [[a, b] for a, b in zip(t, v)] for name, v in low.items() if isinstance(v, list)}),
        ("lambda_max(M(q, Theta_hat))", "lambda_max",
         {name: [[a, b] for a, b in zip(t, v)] for name, v in high.items() if isinstance(v, list)}),
    )
    figures = tuple(figs.new("series", {"title": title, "x_label": "t (s)", "y_label": unit, "lines": lines},
                             f"{what}: {title}.") for title, unit, lines in plots)
    rows = [(cell(code(k)), cell(code(fmt.value(v)))) for k, v in s.items()]
    rows += [(cell(code(k)), cell(code(fmt.value(doc.get(k))))) for k in ("status", "note", "balance_error",
                                                                          "evaluations", "seconds")]
    scene = doc.get("scene", {})
    run = Section("run", (Text("The run"),), (
        Paragraph((Text(f"{scene.get('description') or scene.get('name')}: "), Text(what, "strong"),
                   Text(f"; scene file {scene.get('source')}."))),
        table((Column("quantity", 0.45), Column("value", 0.55)), rows, "Summary of the run"),
    ))
    return Document("inertiaproof adapt", "Adaptive tracking under time-varying inertial parameters",
                    (run, Section("series", (Text("Time series"),), figures)))
