"""Reading nfrc's output directories from the plotting scripts."""
import json
import os
import sys


def load_branch(directory, program):
    """DIR/branch.json as a dict; exits with a message naming `program` and the file if it
    cannot be read or parsed."""
    path = os.path.join(directory, "branch.json")
    try:
        with open(path) as handle:
            return json.load(handle)
    except OSError as error:
        sys.exit(f"{program}: cannot read {path}: {error.strerror}")
    except json.JSONDecodeError as error:
        sys.exit(f"{program}: {path} is not valid JSON: {error}")


# Stability as branch.json records it: "stable" per point is true, false or null (not
# analysed); "bifurcations" lists where it changes, by type.
BIFURCATION_STYLES = {
    # type: (marker, label); a fold keeps the open circle that marked the engine's folds.
    "fold": ("o", "fold"),
    "branch_point": ("s", "branch point"),
    "period_doubling": ("^", "period doubling"),
    "neimark_sacker": ("D", "Neimark–Sacker"),
}


def stability_runs(omega, values, stable):
    """Splits a curve into runs of (omega, values, unstable): a segment between two points is
    unstable when either end is (stable is False), so that every unstable point shows; null
    (not analysed) counts as stable, drawn as before stability existed. Consecutive runs
    share their end point so the curve stays connected."""
    flags = [s is False for s in stable]
    runs = []
    start = 0
    for i in range(1, len(omega)):
        segment_unstable = flags[i - 1] or flags[i]
        if i > 1 and segment_unstable != (flags[i - 2] or flags[i - 1]):
            runs.append((omega[start:i], values[start:i], not segment_unstable))
            start = i - 1
    if omega:
        last = len(omega) > 1 and (flags[-2] or flags[-1])
        runs.append((omega[start:], values[start:], last))
    return runs


def draw_branch(axes, omega, values, stable, label=None, **style):
    """Draws a branch solid where stable (or not analysed) and dashed where unstable; returns
    the colour used. `style` goes to every run (color, lw, ...); `label` to the first run."""
    colour = style.pop("color", None)
    for run_omega, run_values, unstable in stability_runs(omega, values, stable):
        (line,) = axes.plot(run_omega, run_values, "--" if unstable else "-", color=colour,
                            label=label, **style)
        colour, label = line.get_color(), None
    return colour


def any_unstable(points):
    return any(p.get("stable") is False for p in points)


def mark_bifurcations(axes, bifurcations, value, colour, labelled):
    """One marker per bifurcation at (omega, value(entry)); a type's legend entry is given
    once (types already in `labelled`, a set updated here, get none) and only if present."""
    for kind, (marker, text) in BIFURCATION_STYLES.items():
        found = [b for b in bifurcations if b.get("type") == kind]
        xy = [(b.get("omega"), value(b)) for b in found]
        xy = [(w, y) for w, y in xy if w is not None and y is not None]
        if not xy:
            continue
        axes.plot([w for w, _ in xy], [y for _, y in xy], marker, mfc="none", color=colour,
                  ms=7, label=None if kind in labelled else text)
        labelled.add(kind)
