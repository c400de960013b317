#!/usr/bin/env python3
"""Draws the reports' figures with matplotlib (common/util/figure.h).

    /usr/bin/python3 scripts/uwplot.py SPEC.json
    /usr/bin/python3 scripts/uwplot.py --self-test

The programs embed this script and run it once per batch of figures (the
import of matplotlib costs about half a second). SPEC.json holds
{"figures": [FIGURE, ...]}; each FIGURE is

    {"png": path, "svg": path, "title": str, "x_label": str, "y_label": str,
     "width_in": 10, "height_in": 5, "dpi": 100,
     "log_x": false, "log_y": false, "equal_aspect": false,
     "x_categories": [names] (optional: x = 0, 1, ... are these items),
     "series": [SERIES, ...]}

and each SERIES {"kind": k, "colour": matplotlib colour, "label": str, ...}
with, by kind: line/points x, y; errorbars x, low, high; bars x, y, width;
histogram values, bins; hline y; vline x. Labels say units; a label ""
stays out of the legend.

Ticks are multiples of 1, 2 or 5 x 10^k, as uw::NiceTicks places them, and
never carry an offset or a power of ten apart from their labels: a reader
copies a value off the axis without arithmetic. Item axes name their items
(image names), thinned to at most 60 labels and turned to be read. The SVG
keeps its text as text (svg.fonttype none), without a date, so that the
same figure gives the same bytes and its labels can be checked.
"""
import json
import math
import os
import re
import sys
import tempfile

MAX_CATEGORY_LABELS = 60


def configure(matplotlib):
    matplotlib.use("Agg")
    matplotlib.rcParams.update({
        "svg.fonttype": "none",
        "svg.hashsalt": "uwmetric",
        "axes.formatter.useoffset": False,
        # Image names are text, never mathtext between two '$'.
        "text.parse_math": False,
        "axes.grid": True,
        "grid.alpha": 0.35,
        "font.size": 10,
        "legend.fontsize": 9,
        "legend.framealpha": 0.85,
    })


def plain_number(value):
    """A log axis's tick as a plain number, as small or large as it is."""
    import numpy
    return numpy.format_float_positional(value, trim="-")


def nice_ticks(axis, limits, ticker, is_log):
    low, high = sorted(limits)
    if is_log and low > 0 and high / low >= 10:
        # Decades written as plain numbers (0.001, 10, 1000), not 10^k in
        # mathtext, and unlabelled minor ticks; 1, 2 and 5 in each decade
        # when there are fewer than 3.
        subs = (1.0, 2.0, 5.0) if high / low < 1000 else (1.0,)
        axis.set_major_locator(
            ticker.LogLocator(base=10.0, subs=subs, numticks=12))
        axis.set_major_formatter(
            ticker.FuncFormatter(lambda value, _: plain_number(value)))
    else:
        # 1-2-5 steps (on a log axis within a decade too, which has no power
        # of ten to label), each label the value itself: no offset and no
        # "1e6" apart from the numbers.
        axis.set_major_locator(
            ticker.MaxNLocator(nbins=8, steps=[1, 2, 5, 10], min_n_ticks=3))
        formatter = ticker.ScalarFormatter(useOffset=False)
        formatter.set_scientific(False)
        axis.set_major_formatter(formatter)
    if is_log:
        axis.set_minor_formatter(ticker.NullFormatter())


def finite(value):
    """NaN and infinities reach here as null (JSON has no such numbers)."""
    return value is not None and math.isfinite(value)


def finite_columns(*columns):
    """The rows of equally long columns whose every value is finite."""
    keep = [i for i in range(min(len(c) for c in columns))
            if all(finite(c[i]) for c in columns)]
    return [[c[i] for i in keep] for c in columns]


def draw_series(axes, series):
    kind = series["kind"]
    colour = series.get("colour", "C0")
    label = series.get("label", "") or None
    if kind == "line":
        x, y = finite_columns(series["x"], series["y"])
        axes.plot(x, y, color=colour, label=label, linewidth=1.5)
    elif kind == "points":
        x, y = finite_columns(series["x"], series["y"])
        axes.plot(x, y, linestyle="none", marker="o",
                  markersize=series.get("marker_size", 4), color=colour,
                  label=label)
    elif kind == "errorbars":
        x, low, high = finite_columns(series["x"], series["low"],
                                      series["high"])
        axes.vlines(x, low, high, colors=colour, label=label, linewidth=1.5)
    elif kind == "bars":
        x, y = finite_columns(series["x"], series["y"])
        axes.bar(x, y, width=series.get("width", 0.8), color=colour,
                 label=label)
    elif kind == "histogram":
        values = [v for v in series["values"] if finite(v)]
        axes.hist(values, bins=series.get("bins", 40), color=colour,
                  label=label)
    elif kind == "hline" and finite(series["y"]):
        axes.axhline(series["y"], color=colour, label=label, linewidth=1.2,
                     linestyle="--")
    elif kind == "vline" and finite(series["x"]):
        axes.axvline(series["x"], color=colour, label=label, linewidth=1.2,
                     linestyle="--")
    elif kind not in ("hline", "vline"):
        raise ValueError("unknown series kind '%s'" % kind)


def draw(figure_spec, pyplot, ticker):
    figure = pyplot.figure(figsize=(figure_spec.get("width_in", 10),
                                    figure_spec.get("height_in", 5)))
    axes = figure.add_subplot(1, 1, 1)
    for series in figure_spec["series"]:
        draw_series(axes, series)
    log_x = figure_spec.get("log_x", False)
    log_y = figure_spec.get("log_y", False)
    if log_x:
        axes.set_xscale("log")
    if log_y:
        axes.set_yscale("log")
    if figure_spec.get("equal_aspect", False):
        axes.set_aspect("equal", adjustable="datalim")
    nice_ticks(axes.yaxis, axes.get_ylim(), ticker, log_y)
    categories = figure_spec.get("x_categories")
    if categories:
        step = max(1, math.ceil(len(categories) / MAX_CATEGORY_LABELS))
        shown = list(range(0, len(categories), step))
        axes.set_xticks(shown)
        axes.set_xticklabels([categories[i] for i in shown], rotation=90,
                             fontsize=7 if len(shown) > 20 else 9)
        axes.set_xlim(-0.7, len(categories) - 0.3)
        axes.grid(False, axis="x")
    else:
        nice_ticks(axes.xaxis, axes.get_xlim(), ticker, log_x)
    axes.set_title(figure_spec.get("title", ""))
    axes.set_xlabel(figure_spec.get("x_label", ""))
    axes.set_ylabel(figure_spec.get("y_label", ""))
    if any(series.get("label") for series in figure_spec["series"]):
        axes.legend(loc="best")
    figure.tight_layout()
    metadata = {"Date": None, "Creator": "uwmetric"}
    figure.savefig(figure_spec["svg"], format="svg", metadata=metadata)
    figure.savefig(figure_spec["png"], format="png",
                   dpi=figure_spec.get("dpi", 100),
                   metadata={"Software": "uwmetric"})
    pyplot.close(figure)


def run(spec_path):
    import matplotlib
    configure(matplotlib)
    from matplotlib import pyplot, ticker
    with open(spec_path, encoding="utf-8") as spec_file:
        spec = json.load(spec_file)
    for figure_spec in spec["figures"]:
        try:
            draw(figure_spec, pyplot, ticker)
        except Exception as error:
            raise RuntimeError("figure '%s': %s" % (
                figure_spec.get("png", "?"), error)) from error


def tick_labels(svg_text, axis):
    """The tick labels of one axis ('x' or 'y') in a figure's SVG, in order
    (matplotlib groups each tick as <g id="xtick_N">)."""
    from xml.etree import ElementTree
    namespace = "{http://www.w3.org/2000/svg}"
    labels = []
    for group in ElementTree.fromstring(svg_text).iter(namespace + "g"):
        if re.fullmatch(axis + r"tick_\d+", group.get("id", "")):
            for text in group.iter(namespace + "text"):
                labels.append((text.text or "").replace("\u2212", "-"))
    return labels


def self_test():
    with tempfile.TemporaryDirectory() as folder:
        spec = {"figures": [{
            "png": os.path.join(folder, "a.png"),
            "svg": os.path.join(folder, "a.svg"),
            "title": "t", "x_label": "x (m)", "y_label": "y (m)",
            "series": [
                {"kind": "line", "x": [0.0371842, 0.0385], "y": [2.28375, -0.5075],
                 "colour": "C0", "label": "line"},
                # NaN from the C++ side arrives as null and is left out.
                {"kind": "points", "x": [0.038, None, 0.0375],
                 "y": [None, 1.0, 0.5], "colour": "C2", "label": "points"},
                {"kind": "hline", "y": 1.0, "colour": "C1", "label": ""},
                {"kind": "vline", "x": None, "colour": "C1", "label": ""}]}, {
            "png": os.path.join(folder, "b.png"),
            "svg": os.path.join(folder, "b.svg"),
            "x_categories": ["img_%03d.png" % i for i in range(130)],
            "series": [{"kind": "bars", "x": list(range(130)),
                        "y": [i * 0.01 for i in range(130)], "width": 0.7}]}]}
        spec_path = os.path.join(folder, "spec.json")
        with open(spec_path, "w") as spec_file:
            json.dump(spec, spec_file)
        run(spec_path)
        failures = []
        with open(os.path.join(folder, "a.svg")) as svg_file:
            svg = svg_file.read()
        for axis in "xy":
            labels = tick_labels(svg, axis)
            values = [float(label) for label in labels]
            steps = {round(b - a, 12) for a, b in zip(values, values[1:])}
            if len(values) < 3 or len(steps) != 1:
                failures.append("%s ticks %s are not evenly spaced" %
                                (axis, labels))
                continue
            step = steps.pop()
            mantissa = step / 10 ** math.floor(math.log10(step))
            if min(abs(mantissa - m) for m in (1, 2, 5)) > 1e-9:
                failures.append("%s tick step %g is not 1, 2 or 5 x 10^k" %
                                (axis, step))
        with open(os.path.join(folder, "b.svg")) as svg_file:
            labels = tick_labels(svg_file.read(), "x")
        if len(labels) > MAX_CATEGORY_LABELS or labels[:2] != [
                "img_000.png", "img_003.png"]:
            failures.append("category labels %s" % labels[:4])
        for name in ("a.png", "b.png"):
            with open(os.path.join(folder, name), "rb") as png:
                if png.read(8) != b"\x89PNG\r\n\x1a\n":
                    failures.append(name + " is not a PNG")
    for failure in failures:
        print("FAIL:", failure)
    print("uwplot self-test:", "failed" if failures else "passed")
    return 1 if failures else 0


def main(argv):
    if len(argv) == 2 and argv[1] == "--self-test":
        return self_test()
    if len(argv) != 2 or argv[1].startswith("-"):
        print(__doc__, file=sys.stderr)
        return 2
    try:
        run(argv[1])
    except ImportError as error:
        print("uwplot: %s (Debian: apt-get install python3-matplotlib)" %
              error, file=sys.stderr)
        return 3
    except Exception as error:
        print("uwplot: %s" % error, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
