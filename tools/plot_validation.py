#!/usr/bin/python3
"""Draws the results of `nfrc validate` (DIR/validation.json): HBM against transient simulation.

usage: plot_validation.py DIR

Writes
  DIR/signals_K.png       for each DIR/signals_K.csv: the HBM solution (solid black) and the
                          transient's last period (dashed red) against t, one row per output
                          DOF for x and for v, and one per friction/contact force; the title
                          gives omega, the matched branch and the relative h1/energy differences.
  DIR/validation.png/.svg the frequency response curve of DIR/hbm/branch.json with the HBM
                          solutions at the validation frequencies (open circles; the branch
                          dashed where unstable, bifurcations marked by type), the transients
                          (periodic: red crosses, not periodic: orange triangles) and the chirp
                          sweeps (DIR/chirp_up.csv blue, DIR/chirp_down.csv green) if present.
The measure is the mean energy over a period (log axis) when the branch energies span more than
two decades, else max|x| of the first output DOF.
"""
import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from nfrc_output import any_unstable, draw_branch, load_branch, mark_bifurcations  # noqa: E402

PROGRAM = "plot_validation"


def fail(message):
    sys.exit(f"{PROGRAM}: {message}")


def number(value):
    """value as a finite float, or None (missing, null, not a number, inf/nan)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    value = float(value)
    return value if math.isfinite(value) else None


def entry_of(value, index):
    """value[index] as a number if value is a long enough list, else None."""
    if isinstance(value, list) and 0 <= index < len(value):
        return number(value[index])
    return None


def listed(value):
    """value if it is a list, else [] (fields may be missing when a run failed)."""
    return value if isinstance(value, list) else []


def load_validation(directory):
    path = os.path.join(directory, "validation.json")
    try:
        with open(path) as handle:
            document = json.load(handle)
    except OSError as error:
        fail(f"cannot read {path}: {error.strerror}")
    except json.JSONDecodeError as error:
        fail(f"{path} is not valid JSON: {error}")
    if not isinstance(document, dict):
        fail(f"{path}: expected a JSON object at the top level")
    points = document.get("points")
    if not isinstance(points, list) or not all(isinstance(p, dict) for p in points):
        fail(f"{path}: \"points\" must be a list of objects")
    return document


def read_csv(path):
    """{column: [float]} of a CSV file with a header row; exits naming the file on errors."""
    try:
        with open(path, newline="") as handle:
            rows = list(csv.reader(handle))
    except OSError as error:
        fail(f"cannot read {path}: {error.strerror}")
    if not rows:
        fail(f"{path} is empty")
    header = [name.strip() for name in rows[0]]
    columns = {name: [] for name in header}
    for line, row in enumerate(rows[1:], start=2):
        if not row:
            continue
        if len(row) != len(header):
            fail(f"{path}:{line}: {len(row)} fields, the header has {len(header)}")
        for name, text in zip(header, row):
            try:
                columns[name].append(float(text))
            except ValueError:
                fail(f"{path}:{line}: {text!r} in column {name} is not a number")
    return header, columns


# ----------------------------------------------------------------------------- signals_K.png

def find_transient(document, file_name):
    """(point, transient) of validation.json whose "signals" is file_name, or (None, None)."""
    for point in document["points"]:
        for transient in listed(point.get("transients")):
            if isinstance(transient, dict) and transient.get("signals") == file_name:
                return point, transient
    return None, None


def format_differences(values):
    return ", ".join("-" if v is None else f"{v:.2g}" for v in values)


def signals_title(file_name, point, transient):
    if transient is None:
        return f"{file_name} (no entry in validation.json)"
    omega = number(point.get("omega"))
    parts = [f"$\\omega$ = {omega:.6g}" if omega is not None else "$\\omega$ = ?"]
    label = transient.get("matches")
    start = transient.get("start")
    text = f"branch {label}" if label else "no matching HBM solution"
    if start:
        text += f" (start: {start})"
    parts.append(text)
    differences = transient.get("differences") or {}
    line2 = []
    h1 = differences.get("h1")
    if isinstance(h1, list) and h1:
        line2.append(r"rel. diff. $h_1$: " + format_differences([number(v) for v in h1]))
    energy = number(differences.get("energy"))
    if energy is not None:
        line2.append(f"energy: {energy:.2g}")
    title = ", ".join(parts)
    if line2:
        title += "\n" + "; ".join(line2)
    return title


def force_columns(header, side):
    """The "<side>_law<I>_force" columns in file order."""
    pattern = re.compile(rf"^{side}_law(\d+)_force$")
    return [name for name in header if pattern.match(name)]


def closed(values, first):
    """One period closed by repeating the first sample at t = T (signals are periodic)."""
    return values + [first] if values else values


def plot_signals(directory, document, file_name, output_names):
    path = os.path.join(directory, file_name)
    header, columns = read_csv(path)
    if "t" not in columns or not columns["t"]:
        fail(f"{path}: no column t or no rows")
    t = columns["t"]
    if "theta" in columns and len(t) > 1 and columns["theta"][1] > columns["theta"][0]:
        period = 2 * math.pi * (t[1] - t[0]) / (columns["theta"][1] - columns["theta"][0])
    elif len(t) > 1:
        period = t[-1] + (t[1] - t[0])
    else:
        period = t[0]
    t_closed = t + [t[0] + period]

    names = list(output_names) or sorted(
        {m.group(1) for name in header for m in [re.match(r"^hbm_x_(.+)$", name)] if m})
    rows = []  # (ylabel, hbm column or None, transient column or None)
    for quantity in ("x", "v"):
        for name in names:
            rows.append((f"${quantity}$ ({name})", f"hbm_{quantity}_{name}",
                         f"transient_{quantity}_{name}"))
    hbm_forces = force_columns(header, "hbm")
    transient_forces = force_columns(header, "transient")
    for k in range(max(len(hbm_forces), len(transient_forces))):
        hbm = hbm_forces[k] if k < len(hbm_forces) else None
        transient = transient_forces[k] if k < len(transient_forces) else None
        law = (hbm or transient).split("_")[1]
        rows.append((f"force ({law})", hbm, transient))
    rows = [row for row in rows if row[1] in columns or row[2] in columns]
    if not rows:
        fail(f"{path}: no hbm_/transient_ signal columns")

    figure, axes = plt.subplots(len(rows), 1, sharex=True, squeeze=False,
                                figsize=(7, 1.0 + 1.6 * len(rows)))
    for (ylabel, hbm, transient), ax in zip(rows, axes[:, 0]):
        if hbm in columns:
            ax.plot(t_closed, closed(columns[hbm], columns[hbm][0]), "-", color="black", lw=1.4,
                    label="HBM")
        if transient in columns:
            ax.plot(t_closed, closed(columns[transient], columns[transient][0]), "--",
                    color="tab:red", lw=1.2, label="transient")
        ax.set_ylabel(ylabel, fontsize=8)
        ax.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel("$t$ (one period)")
    axes[-1, 0].set_xlim(t_closed[0], t_closed[-1])
    point, transient = find_transient(document, file_name)
    axes[0, 0].set_title(signals_title(file_name, point, transient), fontsize=9)
    figure.tight_layout()
    output = os.path.join(directory, os.path.splitext(file_name)[0] + ".png")
    figure.savefig(output, dpi=150)
    plt.close(figure)
    return output


# ----------------------------------------------------------------------------- validation.png

def choose_measure(branch_points):
    energies = [e for e in (number(p.get("energy")) for p in branch_points) if e is not None]
    if energies and min(energies) > 0 and max(energies) / min(energies) > 100:
        return "energy"
    return "max_abs"


def measure_of(entry, measure):
    if not isinstance(entry, dict):
        return None
    return number(entry.get("energy")) if measure == "energy" else entry_of(entry.get("max_abs"), 0)


def plot_validation(directory, document, branch, written):
    branch_points = [p for p in listed(branch.get("points")) if isinstance(p, dict)]
    measure = choose_measure(branch_points)
    output_names = document.get("output_dofs") or branch.get("output_dofs") or []
    first = output_names[0] if output_names else "0"

    figure, axes = plt.subplots(figsize=(7, 4.5))
    line = [(number(p.get("omega")), measure_of(p, measure), p.get("stable"))
            for p in branch_points]
    line = [(w, y, s) for w, y, s in line if w is not None and y is not None]
    draw_branch(axes, [w for w, _, _ in line], [y for _, y, _ in line], [s for _, _, s in line],
                label="HBM branch", color="black", lw=1.4)
    if any_unstable(branch_points):
        axes.plot([], [], "--", color="black", lw=1.4, label="HBM branch, unstable")
    bifurcations = [b for b in listed(branch.get("bifurcations")) if isinstance(b, dict)]
    # Folds once: the stability analysis's when it reports them, else the engine's.
    folds = [] if any(b.get("type") == "fold" for b in bifurcations) else [
        (number(f.get("omega")), measure_of(f, measure))
        for f in listed(branch.get("folds")) if isinstance(f, dict)]
    folds = [(w, y) for w, y in folds if w is not None and y is not None]
    if folds:
        axes.plot([w for w, _ in folds], [y for _, y in folds], "D", mfc="none", color="grey",
                  ms=5, label="folds")
    mark_bifurcations(axes, bifurcations, lambda b: measure_of(b, measure), "grey", set())

    # Chirp sweeps first, so that the markers are drawn on top of them.
    chirp = document.get("chirp") if isinstance(document.get("chirp"), dict) else {}
    column = "energy" if measure == "energy" else f"max_abs_{first}"
    for name, colour in (("up", "tab:blue"), ("down", "tab:green")):
        info = chirp.get(name) if isinstance(chirp.get(name), dict) else {}
        file_name = info.get("file") or f"chirp_{name}.csv"
        path = os.path.join(directory, file_name)
        if not os.path.isfile(path):
            continue
        _, columns = read_csv(path)
        if "omega" not in columns or column not in columns:
            fail(f"{path}: needs columns omega and {column}")
        w0, w1 = number(info.get("omega_start")), number(info.get("omega_end"))
        label = f"chirp {name}"
        if w0 is not None and w1 is not None:
            label += f" ({w0:.4g} $\\to$ {w1:.4g})"
        axes.plot(columns["omega"], columns[column], "-", color=colour, lw=0.7, alpha=0.9,
                  label=label)

    hbm, periodic, other = [], [], []
    failed = 0
    for point in document["points"]:
        omega = number(point.get("omega"))
        if omega is None:
            continue
        for solution in listed(point.get("hbm_solutions")):
            value = measure_of(solution, measure)
            if value is not None:
                hbm.append((omega, value))
        for transient in listed(point.get("transients")):
            value = measure_of(transient, measure)
            if value is None:
                failed += 1
            elif transient.get("periodic") is True or transient.get("status") == "periodic":
                periodic.append((omega, value))
            else:
                other.append((omega, value))
    if hbm:
        axes.plot([w for w, _ in hbm], [y for _, y in hbm], "o", mfc="none", color="black",
                  ms=8, label="HBM solutions")
    if periodic:
        axes.plot([w for w, _ in periodic], [y for _, y in periodic], "x", color="tab:red",
                  ms=8, mew=1.6, label="transient (periodic)")
    if other:
        axes.plot([w for w, _ in other], [y for _, y in other], "^", color="tab:orange",
                  ms=7, label="transient (not periodic)")
    if failed:
        axes.text(0.01, 0.01, f"{failed} transient(s) without a recorded period",
                  transform=axes.transAxes, fontsize=8, color="red")

    axes.set_xlabel(r"excitation frequency $\omega$")
    if measure == "energy":
        axes.set_ylabel("mean total energy over a period")
        axes.set_yscale("log")
    else:
        axes.set_ylabel(rf"max$_t\,|x(t)|$ of {first}")
    case = document.get("case")
    title = "validation"
    if isinstance(case, str) and case:
        title += ": " + os.path.basename(case)
    axes.set_title(title, fontsize=9)
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    base = os.path.join(directory, "validation")
    figure.savefig(base + ".png", dpi=150)
    figure.savefig(base + ".svg")
    plt.close(figure)
    written += [base + ".png", base + ".svg"]


def main():
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        sys.exit(__doc__.split("\n\n")[1])
    directory = sys.argv[1]
    document = load_validation(directory)
    branch = load_branch(os.path.join(directory, "hbm"), PROGRAM)
    if not isinstance(branch, dict):
        fail(f"{os.path.join(directory, 'hbm', 'branch.json')}: expected a JSON object")
    output_names = document.get("output_dofs") or branch.get("output_dofs") or []

    written = []
    signal_files = sorted((f for f in os.listdir(directory) if re.match(r"^signals_\d+\.csv$", f)),
                          key=lambda f: int(f[len("signals_"):-len(".csv")]))
    for file_name in signal_files:
        written.append(plot_signals(directory, document, file_name, output_names))
    plot_validation(directory, document, branch, written)
    print(f"{PROGRAM}: wrote " + ", ".join(written))


if __name__ == "__main__":
    main()
