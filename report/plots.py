"""The report's figures: one drawing function per kind, rendered as inline SVG (HTML) and PDF pages (LaTeX).

Output is deterministic: no dates in the metadata, a hash salt per figure
(unique SVG ids when several figures share one HTML page), TrueType fonts in
PDF (pdf.fonttype 42) and text as text in SVG.
"""

from __future__ import annotations

import io
import math

__all__ = [
    "bracket", "CHAR", "constants", "DECADES", "DRAW", "draw", "hunt", "LEGEND", "LINE", "MAX_POINTS", "METADATA",
    "narrowing",
    "NOTE_LINE", "PAD", "RED", "render", "series", "stability", "STYLE", "SUPERSCRIPT", "thin", "TICK", "WIDTH",
    "work_precision",
]

WIDTH = 6.4
STYLE = {
    "font.family": "DejaVu Sans",
    "font.size": 8.5,
    "axes.titlesize": 9,
    "axes.labelsize": 8.5,
    "legend.fontsize": 7.5,
    "legend.frameon": False,
    "axes.grid": True,
    "axes.grid.which": "major",
    "grid.color": "#dddddd",
    "grid.linewidth": 0.6,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "lines.markersize": 4,
    "pdf.fonttype": 42,
    "svg.fonttype": "none",
    "path.simplify": False,
    "text.parse_math": False,  # names and notes print as written: a $ is a dollar sign, not mathtext
}
METADATA = {
    "svg": {"Date": None, "Creator": None, "Format": None, "Type": None},
    "pdf": {"CreationDate": None, "ModDate": None, "Creator": None, "Producer": None},
}
RED = "#c0392b"
CHAR = 0.075  # inches per character of a tick label
LINE = 0.17  # inches per line of label text
TICK = 0.09
PAD = 0.08
LEGEND = 0.3
MAX_POINTS = 500
DECADES = 20.0
SUPERSCRIPT = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079")


def render(figures, pdf_path):
    """{figure key: SVG document} for HTML, and the same figures as the pages of one PDF at pdf_path (LaTeX).

    One drawing per figure serves both formats; the PDF embeds its fonts once for all pages.
    """
    import matplotlib
    from matplotlib.backends.backend_pdf import PdfPages

    svgs = {}
    with matplotlib.rc_context(STYLE), PdfPages(pdf_path, metadata=METADATA["pdf"]) as pages:
        for figure in figures:
            fig = draw(figure)
            with matplotlib.rc_context({"svg.hashsalt": figure.key}):
                out = io.StringIO()
                fig.savefig(out, format="svg", metadata=METADATA["svg"])
            svgs[figure.key] = out.getvalue()
            pages.savefig(fig)
    return svgs


def thin(points, most=MAX_POINTS):
    """At most about ``most`` [x, y] points: the lowest and highest y of each run of neighbours (no extreme lost)."""
    if len(points) <= most:
        return points
    size = math.ceil(2 * len(points) / most)
    kept = []
    for start in range(0, len(points), size):
        bucket = points[start:start + size]
        low, high = min(bucket, key=lambda p: p[1]), max(bucket, key=lambda p: p[1])
        kept += sorted({id(low): low, id(high): high}.values(), key=lambda p: p[0])
    return kept


def draw(figure):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(WIDTH, 2.8))
    DRAW[figure.kind](fig, figure.data)
    return fig


def bracket(fig, data):
    ax = fig.add_subplot()
    for line in data["lines"]:
        points = thin(sorted(line["points"]))
        ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=_short(line["label"], 60))
    unit = f" [{data['unit']}]" if data.get("unit") else ""
    _scale(ax, "x", [p[0] for line in data["lines"] for p in line["points"]])
    _scale(ax, "y", [p[1] for line in data["lines"] for p in line["points"]])
    ax.set_xlabel("run time spent narrowing [s]")
    ax.set_ylabel(f"bracket width (upper - lower){unit}")
    _legend(ax, loc="best")
    _fit(fig)


def constants(fig, data):
    """One row per bound: its constants on one axis; a ``paper`` given as [lower, upper] is drawn as that range."""
    bounds = data["bounds"]
    fig.set_size_inches(WIDTH, 0.9 + 0.32 * len(bounds))
    ax = fig.add_subplot()
    marks = (("paper", "o", "#1f77b4", "paper's constant"), ("certified", "D", "#2ca02c", "sharpest certified"),
             ("observed", "x", RED, "observed worst case"))
    values = [v for b in bounds for k, *_ in marks for v in _ends(b[k])]
    log = _scale(ax, "x", [v for v in values if v > 0])

    def shown(value):
        return [v for v in _ends(value) if v > 0 or not log]

    for y, b in enumerate(bounds):
        present = [v for k, *_ in marks for v in shown(b[k])]
        if len(present) > 1:
            ax.plot([min(present), max(present)], [y, y], color="#bbbbbb", linewidth=1.5, zorder=1)
        if isinstance(b["paper"], list) and len(shown(b["paper"])) == 2:
            ax.plot(shown(b["paper"]), [y, y], color=marks[0][2], alpha=0.35, linewidth=5, solid_capstyle="butt",
                    zorder=2)
    for key, marker, color, label in marks:
        points = [(v, y) for y, b in enumerate(bounds) for v in shown(b[key])]
        ax.scatter([p[0] for p in points], [p[1] for p in points], marker=marker, color=color, label=label, zorder=3,
                   s=36 if marker == "x" else 22)
    ax.set_yticks(range(len(bounds)), [_short(b["label"], 34) + (" (VIOLATED)" if b.get("violated") else "")
                                       for b in bounds])
    for label, b in zip(ax.get_yticklabels(), bounds):
        if b.get("violated"):
            label.set_color(RED)
    ax.set_ylim(len(bounds) - 0.5, -0.5)
    ax.grid(False, axis="y")
    hidden = log and any(v <= 0 for v in values)
    ax.set_xlabel(data.get("x_label", "value of the constant (units of each bound)")
                  + ("; values \u2264 0 not shown" if hidden else ""))
    _legend_above(fig, ax)
    _fit(fig, legend_above=True)


def hunt(fig, data):
    import numpy as np

    ax = fig.add_subplot()
    everything = [m for h in data["hunts"] for m in h["margins"]]
    positive = min(everything) > 0
    log = positive and max(everything) / min(everything) >= DECADES
    bins = np.geomspace(min(everything), max(everything), 25) if log else np.linspace(
        min(everything + [0.0]), max(everything + [0.0]), 25) if everything else 10
    for h in data["hunts"]:
        ax.hist(h["margins"], bins=bins, histtype="stepfilled" if len(data["hunts"]) == 1 else "step",
                alpha=0.75, linewidth=1.2, label=_short(h["label"], 40))
    if log:
        _log(ax, "x", everything)
    if not positive:
        ax.axvline(0.0, color=RED, linestyle="--", linewidth=1, label="boundary (margin 0)")
    unit = f" [{data['unit']}]" if data.get("unit") else ""
    ax.set_xlabel(f"margin{unit}" + (" (log scale)" if log else ""))
    ax.set_ylabel("examples")
    _legend(ax, loc="best")
    _fit(fig)


def series(fig, data):
    ax = fig.add_subplot()
    logs = {"x": bool(data.get("x_log")), "y": bool(data.get("y_log"))}
    xs, ys = [], []
    for name, points in data["lines"].items():
        points = [p for p in points if isinstance(p, list) and len(p) == 2 and all(_finite(v) for v in p)]
        points = thin([p for p in points if (p[0] > 0 or not logs["x"]) and (p[1] > 0 or not logs["y"])])
        ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=_short(str(name), 50))
        xs += [p[0] for p in points]
        ys += [p[1] for p in points]
    for axis, values in (("x", xs), ("y", ys)):
        if logs[axis] and values:
            _log(ax, axis, values)
    ax.set_xlabel(str(data.get("x_label", "")))
    ax.set_ylabel(str(data.get("y_label", "")))
    _legend(ax, loc="best")
    _fit(fig)


def work_precision(fig, data):
    """Error against run time, log-log, one panel per scene and one line per method (explicit solid with circles,
    implicit dashed with squares: ``data["implicit"]``); under each panel's lines, its ``data["use"]`` line (the
    cheapest method per error) and the methods of ``data["not_run"]`` with why they have no point."""
    scenes = data["scenes"]
    implicit = set(data.get("implicit", ()))
    notes = {scene: _panel_notes(data, scene) for scene in scenes}
    drawn = list(dict.fromkeys(m for s in scenes.values() for m in s))
    colors = {m: f"C{i % 10}" for i, m in enumerate(drawn)}
    cols = min(2, len(scenes))
    rows = math.ceil(len(scenes) / cols)
    fig.set_size_inches(WIDTH, 0.6 + LEGEND * math.ceil(len(drawn) / 3) + 2.4 * rows)
    axes = fig.subplots(rows, cols, squeeze=False)
    handles = {}
    for ax, (scene, by_method) in zip(axes.flat, scenes.items()):
        everything = [p for points in by_method.values() for p in points]
        for method, points in by_method.items():
            points = sorted(points, key=lambda p: (-p[2] if len(p) > 2 and p[2] is not None else 0.0, p[0]))
            points = [p for p in points if p[0] > 0 and p[1] > 0]  # along the tolerance (noisy times may not be)
            kind = "implicit" if method in implicit else "explicit"
            (line,) = ax.plot([p[0] for p in points], [p[1] for p in points], color=colors[method],
                              label=f"{_short(method, 24)} ({kind})", marker="s" if kind == "implicit" else "o",
                              linestyle="--" if kind == "implicit" else "-")
            handles.setdefault(method, line)
        _log(ax, "x", [p[0] for p in everything if p[0] > 0])
        errors = [p[1] for p in everything if p[1] > 0]
        _log(ax, "y", errors)
        if notes[scene] and errors:  # room under the lowest point for the notes: they never hide a line
            low, high = math.log10(min(errors)), math.log10(max(errors))
            span = max(high - low, 1.0)
            share = min(0.6, (NOTE_LINE * len(notes[scene]) + PAD) / (2.4 - 0.7))
            ax.set_ylim(10 ** (low - 0.05 * span - share / (1 - share) * 1.1 * span), 10 ** (high + 0.05 * span))
        if notes[scene]:
            ax.text(0.02, 0.02, "\n".join(notes[scene]), transform=ax.transAxes, fontsize=6.5, va="bottom",
                    ha="left", linespacing=1.15)
        ax.set_title(_short(scene, 50))
        ax.set_xlabel("run time [s]")
        ax.set_ylabel("error")
    for ax in axes.flat[len(scenes):]:
        ax.set_visible(False)
    if handles:
        fig.legend(list(handles.values()), [h.get_label() for h in handles.values()], loc="upper center",
                   bbox_to_anchor=(0.5, 1.0), ncols=min(3, len(handles)))
    _fit(fig, legend_above=math.ceil(len(handles) / 3))


NOTE_LINE = 0.11  # inches per line of a panel's notes (6.5 pt)


def _panel_notes(data, scene):
    """The lines written into a work-precision panel: which method to use per error, and the methods with no
    point (why)."""
    lines = []
    use = data.get("use", {}).get(scene)
    if use:
        lines += ["use: " + part.replace("error ", "") for part in use.split("; ")]
    for method, why in data.get("not_run", {}).get(scene, {}).items():
        lines.append(_short(f"{method}: {why}", 70))
    return lines


def stability(fig, data):
    points = data["points"]
    scenes = list(dict.fromkeys(p["scene"] for p in points))
    methods = list(dict.fromkeys(p["method"] for p in points))
    fig.set_size_inches(WIDTH, 1.0 + 0.4 * len(scenes))
    ax = fig.add_subplot()
    step = 0.6 / max(1, len(methods))

    def y(p):
        return scenes.index(p["scene"]) + (methods.index(p["method"]) - (len(methods) - 1) / 2) * step

    for i, method in enumerate(methods):
        ok = [p for p in points if p["method"] == method and p["ok"]]
        ax.scatter([p["seconds"] for p in ok], [y(p) for p in ok], color=f"C{i % 10}", label=_short(method, 30),
                   zorder=3)
    failed = [p for p in points if not p["ok"]]
    if failed:
        ax.scatter([p["seconds"] for p in failed], [y(p) for p in failed], color=RED, marker="X", s=60, zorder=4,
                   label="failed")
        for p in failed:
            ax.annotate(_short(p["method"], 20), (p["seconds"], y(p)), xytext=(6, 0), textcoords="offset points",
                        fontsize=7, va="center", color=RED)
    _scale(ax, "x", [p["seconds"] for p in points])
    ax.set_yticks(range(len(scenes)), [_short(s, 28) for s in scenes])
    ax.set_ylim(len(scenes) - 0.5, -0.5)
    ax.grid(False, axis="y")
    ax.set_xlabel("run time [s]")
    _legend_above(fig, ax)
    _fit(fig, legend_above=True)


def narrowing(fig, data):
    """Relative bracket width against run time, one line per bracket, log-log where it spans decades."""
    ax = fig.add_subplot()
    for line in data["lines"]:
        points = thin(sorted(line["points"]))
        ax.plot([p[0] for p in points], [p[1] for p in points], marker="o", label=_short(line["label"], 60))
    _scale(ax, "x", [p[0] for line in data["lines"] for p in line["points"]])
    _scale(ax, "y", [p[1] for line in data["lines"] for p in line["points"]])
    ax.set_xlabel("run time spent narrowing [s]")
    ax.set_ylabel("(upper - lower) / |upper|")
    rows = math.ceil(len(data["lines"]) / 2)
    height = 2.6 + LINE * rows
    fig.set_size_inches(WIDTH, height)
    _fit(fig)
    handles, labels = ax.get_legend_handles_labels()
    if handles:  # below the axes, two columns: a dozen brackets do not fit inside
        legend = LINE * rows + PAD
        bottom = fig.subplotpars.bottom * height
        fig.subplots_adjust(bottom=(bottom + legend) / height)
        fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5, 0.0), ncols=2)


DRAW = {"bracket": bracket, "constants": constants, "hunt": hunt, "series": series,
        "work_precision": work_precision, "stability": stability, "narrowing": narrowing}


def _legend(ax, **kwargs):
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kwargs)


def _legend_above(fig, ax):
    """One row of legend entries centred over the whole figure (not over the axes, which long labels push right)."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        fig.legend(handles, labels, loc="upper center", bbox_to_anchor=(0.5, 1.0), ncols=min(4, len(handles)))


def _scale(ax, axis, values):
    """Log scale when the (positive) values span decades; returns whether it chose log."""
    values = [v for v in values if _finite(v)]
    if values and min(values) > 0 and max(values) / min(values) >= DECADES:
        _log(ax, axis, values)
        return True
    return False


def _log(ax, axis, values):
    from matplotlib import ticker

    positive = [v for v in values if v > 0]
    if not positive:
        return
    getattr(ax, f"set_{axis}scale")("log")
    target = getattr(ax, f"{axis}axis")
    decades = math.log10(max(positive) / min(positive))
    target.set_major_locator(ticker.LogLocator(base=10, numticks=12))
    target.set_major_formatter(ticker.FuncFormatter(_power))
    if decades < 1.5:
        target.set_minor_locator(ticker.LogLocator(base=10, subs=(2.0, 5.0), numticks=12))
        target.set_minor_formatter(ticker.FuncFormatter(_power))
    else:
        target.set_minor_locator(ticker.NullLocator())


def _fit(fig, legend_above=False):
    """Margins from the labels' lengths: as tight as a layout engine, without drawing everything twice."""
    from matplotlib import ticker

    axes = [ax for ax in fig.axes if ax.get_visible()]
    for ax in axes:
        for axis in (ax.xaxis, ax.yaxis):
            if type(axis.get_major_formatter()) is ticker.ScalarFormatter:
                axis.set_major_formatter(ticker.FuncFormatter(_plain))
    width, height = fig.get_size_inches()
    left = max(PAD + (LINE if ax.get_ylabel() else 0) + CHAR * _widest(ax.yaxis) + TICK for ax in axes)
    right = PAD + CHAR * max(_widest(ax.xaxis) for ax in axes) / 2
    bottom = PAD + TICK + LINE + (LINE if any(ax.get_xlabel() for ax in axes) else 0)
    title = LINE * 1.4 if any(ax.get_title() for ax in axes) else 0
    top = PAD + title + LEGEND * int(legend_above)  # legend_above: True, or the legend's rows
    rows, cols = axes[0].get_subplotspec().get_geometry()[:2]
    axis_width = (width - left - right - (cols - 1) * (left + PAD)) / cols
    axis_height = (height - top - bottom - (rows - 1) * (bottom + title)) / rows
    fig.subplots_adjust(left=left / width, right=1 - right / width, bottom=bottom / height, top=1 - top / height,
                        wspace=(left + PAD) / axis_width, hspace=(bottom + title) / axis_height)


def _widest(axis):
    lo, hi = sorted(axis.get_view_interval())
    ticks = [t for t in axis.get_major_locator()() if lo <= t <= hi]
    return max((len(label) for label in axis.get_major_formatter().format_ticks(ticks)), default=1)


def _plain(v, _pos=None):
    return "0" if v == 0 else f"{v:.6g}"


def _power(v, _pos=None):
    if v <= 0:
        return ""
    exponent = math.floor(math.log10(v) + 1e-9)
    mantissa = round(v / 10 ** exponent, 6)
    power = "10" + str(exponent).translate(SUPERSCRIPT)
    if exponent in (0, 1):
        return f"{v:g}"
    return power if mantissa == 1 else f"{mantissa:g}\u00b7{power}"


def _ends(value):
    """The plotted values of a constant: none, one, or both ends of a [lower, upper] range."""
    return [v for v in (value if isinstance(value, list) else [value]) if v is not None]


def _short(text, n):
    return text if len(text) <= n else text[: n - 1] + "\u2026"


def _finite(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
