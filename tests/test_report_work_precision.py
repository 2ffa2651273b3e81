"""The report's work-precision figure on stiff scenes: implicit methods beside the explicit ones, the explicit
ones not run said so, and per scene the cheapest method reaching each error."""

import warnings

import matplotlib
import pytest
from inertiaproof.report import datafiles, evidence, plots
from inertiaproof.report.model import Paragraph, Table


def _row(scene, method, rtol, seconds, error, work=None, status="ok", predicted=None, implicit=None):
    row = {"scene": scene, "method": method, "rtol": rtol, "seconds": seconds, "error": error, "status": status,
           "work": work, "predicted": predicted, "note": "not run: ..." if predicted else ""}
    if implicit is not None:
        row["implicit"] = implicit
    return row


def _rows():
    stiff = "stiff-thin-rod"
    rows = [_row(stiff, m, rtol, 0.0, None, 0, "budget", 4e9, False) for m in ("RK45", "DOP853") for rtol in (1e-4,)]
    rows += [_row(stiff, m, 1e-6, 0.0, None, 0, "not run", None, False) for m in ("RK45", "DOP853")]
    rows += [_row(stiff, "Radau", 1e-4, 0.06, 2e-5, 137, implicit=True),
             _row(stiff, "Radau", 1e-6, 0.18, 1e-7, 358, implicit=True),
             _row(stiff, "BDF", 1e-4, 0.09, 1e-4, 112, implicit=True),
             _row(stiff, "BDF", 1e-6, 0.14, 1e-6, 223, implicit=True),
             _row(stiff, "LSODA", 1e-4, 0.10, None, 200, "step collapse", implicit=True)]
    smooth = "many-links-24"  # rows of an older run: no implicit, work or predicted keys
    rows += [{"scene": smooth, "method": m, "rtol": rtol, "seconds": s, "error": e, "status": "ok"}
             for m, rtol, s, e in (("RK45", 1e-4, 0.06, 5e-5), ("RK45", 1e-6, 0.11, 4e-7),
                                   ("Radau", 1e-4, 0.75, 2e-5), ("Radau", 1e-6, 0.96, 3e-7))]
    return rows


def test_stiff_scenes_show_implicit_methods_and_say_why_explicit_ones_have_no_point():
    data = datafiles.work_precision_data(_rows())
    assert set(data["scenes"]["stiff-thin-rod"]) == {"Radau", "BDF"}
    assert data["implicit"] == ["BDF", "LSODA", "Radau"]  # by the rows' flag, or by name for older rows
    assert data["not_run"]["stiff-thin-rod"] == {
        "RK45": "not run: predicted 4e+09 right-hand sides (stiff)",
        "DOP853": "not run: predicted 4e+09 right-hand sides (stiff)",
        "LSODA": "no finished run: step collapse"}
    # Radau reaches 1e-6 between its two runs, interpolated log-log, before BDF's run at 1e-6 (0.14 s)
    method, seconds, work = datafiles.cheapest(data["scenes"]["stiff-thin-rod"], 1e-6)
    assert method == "Radau" and 0.06 < seconds < 0.14 and 137 < work < 358
    assert data["use"]["stiff-thin-rod"].startswith("error <= 1e-3: Radau (0.06 s, work 137); error <= 1e-6: Radau")
    assert data["use"]["many-links-24"] == "error <= 1e-3: RK45 (0.06 s); error <= 1e-6: RK45 (0.10 s)"  # interpolated
    assert datafiles.cheapest(data["scenes"]["stiff-thin-rod"], 1e-10) is None
    only_zero = {"A": [[1.0, 0.0, 1e-12, None]]}  # an error of 0: the reference itself, not a method reaching it
    assert datafiles.cheapest(only_zero, 1e-6) is None


def test_the_report_blocks_and_figure_name_the_method_to_use():
    figs = evidence.Figures()
    blocks = datafiles.work_precision(_rows(), figs, "run")
    table = next(b for b in blocks if isinstance(b, Table))
    cells = [" ".join(t.text for t in c) for row in table.rows for c in row]
    assert "RK45" in cells and "Radau (implicit)" in cells
    assert "not run: predicted 4e+09 right-hand sides (stiff)" in cells
    uses = [" ".join(t.text for t in b.inlines) for b in blocks if isinstance(b, Paragraph)]
    assert uses[0].startswith("Use on  stiff-thin-rod : error <= 1e-3: Radau")
    (figure,) = figs.made
    assert figure.kind == "work_precision" and "dashed: implicit" in figure.caption
    matplotlib.use("Agg")
    with warnings.catch_warnings(), matplotlib.rc_context(plots.STYLE):
        warnings.simplefilter("error", UserWarning)
        fig = plots.draw(figure)
    stiff_axes = next(ax for ax in fig.axes if ax.get_title() == "stiff-thin-rod")
    styles = {line.get_label(): line.get_linestyle() for line in stiff_axes.get_lines()}
    assert styles == {"Radau (implicit)": "--", "BDF (implicit)": "--"}
    notes = "\n".join(t.get_text() for t in stiff_axes.texts)
    assert "use: <= 1e-6: Radau" in notes and "RK45: not run: predicted 4e+09" in notes
    low = min(p[1] for points in figure.data["scenes"]["stiff-thin-rod"].values() for p in points)
    assert stiff_axes.get_ylim()[0] < low / 10  # room under the lowest point for the notes
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == ["Radau (implicit)", "BDF (implicit)", "RK45 (explicit)"]


@pytest.mark.parametrize("points", [[], [[0.0, 0.0, None, None]], [[1.0, 1e-3, None, None]]])
def test_degenerate_points_still_draw(points):
    data = {"scenes": {"s": {"m": points}}, "implicit": [], "not_run": {}, "use": {"s": "no method reached error 1e-3"}}
    matplotlib.use("Agg")
    with matplotlib.rc_context(plots.STYLE):
        plots.draw(type("F", (), {"kind": "work_precision", "data": data})())
