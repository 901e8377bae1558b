#!/usr/bin/python3
"""Draws frequency response curves from nfrc output directories (branch.json).

usage: plot_frc.py DIR [DIR ...] [--measure max_abs|min|max|h1|energy] [--logy] [--output PATH_WITHOUT_EXT]
       [--labels A,B,...] [--title TEXT]

One directory: writes DIR/frc.png and DIR/frc.svg. Several: overlays them and writes to
--output (default: the first DIR's frc_overlay). Where stability was analysed, unstable
parts of a branch are dashed (stable or not analysed: solid); folds are marked with open
circles and the other bifurcations (branch points, period doublings, Neimark–Sacker) with
their own markers, listed in the legend only when present.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from nfrc_output import any_unstable, draw_branch, load_branch, mark_bifurcations  # noqa: E402


def load(directory):
    return load_branch(directory, "nfrc plot")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--measure", default="max_abs", choices=["max_abs", "min", "max", "h1", "energy"])
    parser.add_argument("--xlim", help="omega range to show, as MIN,MAX")
    parser.add_argument("--logy", action="store_true")
    parser.add_argument("--output")
    parser.add_argument("--labels")
    parser.add_argument("--title")
    args = parser.parse_args()

    labels = args.labels.split(",") if args.labels else None
    figure, axes = plt.subplots(figsize=(7, 4.5))
    labelled = set()  # bifurcation types already in the legend
    unstable_shown = False
    for i, directory in enumerate(args.dirs):
        document = load(directory)
        points = document.get("points", [])
        if not points:
            sys.exit(f"nfrc plot: {directory}/branch.json has no points")
        names = document.get("output_dofs", [])
        if args.measure == "energy":
            names = names[:1]
        omega = [p["omega"] for p in points]
        stable = [p.get("stable") for p in points]
        unstable_shown = unstable_shown or any_unstable(points)
        bifurcations = document.get("bifurcations") or []
        # The stability analysis reports folds among its bifurcations; the engine's folds
        # are drawn only when it did not, so that each fold is marked once.
        folds = [] if any(b.get("type") == "fold" for b in bifurcations) else \
            document.get("folds", [])

        def value(entry, d):
            return entry[args.measure] if args.measure == "energy" else entry[args.measure][d]

        for d, name in enumerate(names):
            values = [value(p, d) for p in points]
            label = labels[i] if labels and i < len(labels) else os.path.basename(
                os.path.normpath(directory))
            if len(names) > 1 and args.measure != "energy":
                label += f" (DOF {name})"
            colour = draw_branch(axes, omega, values, stable, label=label, lw=1.4)
            if folds:
                axes.plot([f["omega"] for f in folds], [value(f, d) for f in folds],
                          "o", mfc="none", color=colour, ms=7,
                          label=None if "fold" in labelled else "folds")
                labelled.add("fold")
            mark_bifurcations(axes, bifurcations, lambda b: value(b, d), colour, labelled)
    if unstable_shown:
        axes.plot([], [], "--", color="grey", lw=1.4, label="unstable")
    axes.set_xlabel(r"excitation frequency $\omega$")
    axes.set_ylabel({"max_abs": r"max$_t\,|x(t)|$", "h1": "first-harmonic amplitude",
                     "min": r"min$_t\,x(t)$", "max": r"max$_t\,x(t)$",
                     "energy": "mean total energy over a period"}[args.measure])
    if args.xlim:
        axes.set_xlim(*[float(v) for v in args.xlim.split(",")])
    if args.logy:
        axes.set_yscale("log")
    summary = load(args.dirs[0]).get("summary", {})
    title = args.title or load(args.dirs[0]).get("case", {}).get("title", "")
    if title:
        axes.set_title(title, fontsize=9)
    if summary.get("termination") not in (None, "reached_lambda_bound", "closed_curve"):
        axes.text(0.01, 0.01, f"run ended: {summary.get('termination')}",
                  transform=axes.transAxes, fontsize=8, color="red")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    base = args.output or (os.path.join(args.dirs[0], "frc") if len(args.dirs) == 1
                           else os.path.join(args.dirs[0], "frc_overlay"))
    figure.savefig(base + ".png", dpi=150)
    figure.savefig(base + ".svg")
    print(f"nfrc plot: wrote {base}.png and {base}.svg")


if __name__ == "__main__":
    main()
