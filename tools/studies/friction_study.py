#!/usr/bin/python3
"""Runs the friction study of Legrand & Pierre (2024), Section 5, with nfrc and writes its
figures and tables.

usage: friction_study.py [--nfrc PATH] [--out DIR] [--force] [--jobs N]
                         [--figures DIR] [--markdown PATH]

Runs every case of cases/friction/ with `nfrc run CASE --out OUT/NAME` (stderr to
OUT/NAME/nfrc.log), skipping a run whose OUT/NAME/branch.json already ended with
summary.termination == reached_lambda_bound unless --force. Then draws
docs/figures/friction/*.png and writes docs/friction_results.md (tables and figure
references, paths relative to the repository root, ready to paste into the README).
Defaults: --nfrc build/nfrc, --out out/friction, both relative to the repository root.
A case that does not reach the end of its range is named on stderr with its termination and
message, drawn as far as it got, and makes the exit status 1.
"""
import concurrent.futures
import math
import os
import sys
import time

sys.dont_write_bytecode = True  # keep tools/ free of __pycache__
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

import plot_signals  # noqa: E402
from study_common import (DPI, REPO, execute, load, parse_arguments, save, table,  # noqa: E402
                          termination, value_at)

CASES = "cases/friction"
# Run names whose case is a member of a manifest in CASES (FILE#NAME); the others are files.
MEMBERS = {
    "frc_n8": "fig7.json#n8",
    "frc_n9": "fig7.json#n9",
    "frc_n10_5": "fig7.json#n10_5",
    "frc_n11": "fig7.json#n11",
    "frc_n12": "fig7.json#n12",
    "frc_linear": "fig7.json#linear",
    "convergence_e_nphi10": "convergence_e.json#nphi10",
    "convergence_e_nphi20": "convergence_e.json#nphi20",
    "convergence_e_nphi40": "convergence_e.json#nphi40",
    "convergence_e_nphi80": "convergence_e.json#nphi80",
    "convergence_e_nphi160": "convergence_e.json#nphi160",
    "damper_mass_m2_0_5": "damper_mass.json#m2_0_5",
    "damper_mass_m2_0_25": "damper_mass.json#m2_0_25",
    "damper_mass_m2_0_125": "damper_mass.json#m2_0_125",
    "damper_mass_m2_0": "damper_mass.json#m2_0",
    "piecewise_linear_delta_2": "piecewise_linear.json#delta_2",
    "piecewise_linear_delta_1": "piecewise_linear.json#delta_1",
    "piecewise_linear_delta_0_5": "piecewise_linear.json#delta_0_5",
    "piecewise_linear_delta_0_25": "piecewise_linear.json#delta_0_25",
    "signals_a": "signals.json#a",
    "signals_b": "signals.json#b",
    "signals_c": "signals.json#c",
    "signals_d": "signals.json#d",
}

# (run name = case file stem, group)
FRC_LOADS = [("frc_n8", 8.0), ("frc_n9", 9.0), ("frc_n10", 10.0), ("frc_n10_5", 10.5),
             ("frc_n11", 11.0), ("frc_n12", 12.0)]
POINTS = [  # label, run, N, omega, published description, published stick phases
    ("A", "signals_a", 8.0, 0.618, "slip–slip, r jumps between ±7.2", 0),
    ("B", "signals_b", 8.0, 0.293, "two short stick phases", 2),
    ("C", "signals_c", 10.5, 0.299, "two stick phases, stick ≈ slip time (anti-resonance)", 2),
    ("D", "signals_d", 10.5, 0.308, "four stick and four slip phases", 4),
    ("E", "signals_e", 10.0, 0.308, "four stick phases, eight transitions", 4),
]
CONVERGENCE = [(10, "convergence_e_nphi10"), (20, "convergence_e_nphi20"),
               (40, "convergence_e_nphi40"), (80, "convergence_e_nphi80"),
               (160, "convergence_e_nphi160")]
DAMPER = [  # m2, run, published stick phases (count), published description
    (1.0, "damper_mass_m2_1", 0, "none (slip–slip)"),
    (0.5, "damper_mass_m2_0_5", 2, "two short"),
    (0.25, "damper_mass_m2_0_25", 4, "four"),
    (0.125, "damper_mass_m2_0_125", 4, "four"),
    (0.0, "damper_mass_m2_0", 2, "two smooth stick and slip phases"),
]
PIECEWISE = [(2.0, "piecewise_linear_delta_2"), (1.0, "piecewise_linear_delta_1"),
             (0.5, "piecewise_linear_delta_0_5"), (0.25, "piecewise_linear_delta_0_25")]
RUNS = ([name for name, _ in FRC_LOADS] + ["frc_linear"] + [p[1] for p in POINTS] +
        [name for _, name in CONVERGENCE] + [d[1] for d in DAMPER] +
        [name for _, name in PIECEWISE] + ["one_dof_coulomb", "point_e"])

# Published values (../shared/cases.md, case 1; the paper's Section 5.1).
PUBLISHED_SUPERHARMONICS = [0.54, 0.30, 0.21, 0.16, 0.13, 0.11]
PRIMARY = 0.618
NLVIB_PEAK = (0.990, 3.666)  # one-DOF Coulomb oscillator: omega, first-harmonic amplitude

# Extrema of log10(energy) less prominent than this (decades) are ripple, not resonances. The
# N_phi = 60 curves carry a truncation ripple up to ~0.0075 decades (N = 10 near 0.57, absent
# from the N_phi = 160 curve of point_e); the study measures and reports it.
PROMINENCE_DECADES = 0.008
MATCH_TOLERANCE = 0.015  # |omega_found - omega_published| accepted as "the same" extremum

LOAD_COLOURS = {8.0: "tab:blue", 9.0: "tab:orange", 10.0: "tab:green", 10.5: "tab:purple",
                11.0: "tab:brown", 12.0: "tab:gray"}


# ----------------------------------------------------------------------------- runs

def run_one(nfrc, out, name, force):
    """Runs one case unless it already reached the end of its range (and not force).
    Returns (status, seconds)."""
    if not force and termination(load(out, name)) == "reached_lambda_bound":
        return "skipped (already reached_lambda_bound)", 0.0
    code, seconds = execute([nfrc, "run", os.path.join(REPO, CASES, MEMBERS.get(name, name + ".json")), "--out",
                             os.path.join(out, name)], os.path.join(out, name))
    return f"exit {code} ({termination(load(out, name))})", seconds


def run_all(nfrc, out, force, jobs):
    """Runs RUNS; returns how many were skipped as already finished."""
    skipped = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_one, nfrc, out, name, force): name for name in RUNS}
        for future in concurrent.futures.as_completed(futures):
            status, seconds = future.result()
            skipped += status.startswith("skipped")
            print(f"friction_study: {futures[future]:40s} {status}  {seconds:7.1f} s", flush=True)
    return skipped


def incomplete(out):
    """[(name, termination, message)] of the runs that did not reach the end of their range."""
    found = []
    for name in RUNS:
        document = load(out, name)
        if termination(document) != "reached_lambda_bound":
            message = (document["summary"].get("message", "") if document else
                       f"no readable branch.json (see {os.path.join(out, name, 'nfrc.log')})")
            found.append((name, termination(document), message))
    return found


# ----------------------------------------------------------------------------- helpers

def curve(document):
    points = document["points"]
    return (np.array([p["omega"] for p in points]), np.array([p["energy"] for p in points]))


def parabola_vertex(x, y):
    """Vertex of the parabola through three points; None if degenerate."""
    (x0, x1, x2), (y0, y1, y2) = x, y
    denominator = (x0 - x1) * (x0 - x2) * (x1 - x2)
    if denominator == 0.0:
        return None
    a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denominator
    b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denominator
    c = (x1 * x2 * (x1 - x2) * y0 + x2 * x0 * (x2 - x0) * y1 +
         x0 * x1 * (x0 - x1) * y2) / denominator
    if a == 0.0:
        return None
    xv = -b / (2.0 * a)
    if not min(x) <= xv <= max(x):
        return None
    return xv, a * xv * xv + b * xv + c


def prominence(y, i):
    """Topographic prominence of the local maximum y[i] of a sequence."""
    left = y[i]
    j = i - 1
    while j >= 0 and y[j] <= y[i]:
        left = min(left, y[j])
        j -= 1
    right = y[i]
    j = i + 1
    while j < len(y) and y[j] <= y[i]:
        right = min(right, y[j])
        j += 1
    return y[i] - max(left, right)


def extrema(omega, energy, threshold=PROMINENCE_DECADES):
    """Interior local maxima and minima of log10(energy) along the branch with prominence
    >= threshold decades, refined by a parabola through the extremum and its neighbours.
    Returns [(kind, omega, energy, prominence)] sorted by omega."""
    y = np.log10(energy)
    found = []
    for i in range(1, len(y) - 1):
        for kind, sign in (("max", 1.0), ("min", -1.0)):
            if sign * y[i] > sign * y[i - 1] and sign * y[i] >= sign * y[i + 1]:
                p = prominence(sign * y, i)
                if p < threshold:
                    continue
                vertex = parabola_vertex(omega[i - 1:i + 2], y[i - 1:i + 2])
                w, v = vertex if vertex else (omega[i], y[i])
                found.append((kind, w, 10.0 ** v, p))
    return sorted(found, key=lambda e: e[1])


def nearest(found, kind, target):
    candidates = [e for e in found if e[0] == kind]
    if not candidates:
        return None
    return min(candidates, key=lambda e: abs(e[1] - target))


def signals(out, name, index=0):
    document = load(out, name)
    if document is None or not document.get("signals"):
        return None
    return plot_signals.Signals(os.path.join(out, name), index)


# ----------------------------------------------------------------------------- figures

def figure7(out, figures):
    figure, axes = plt.subplots(figsize=(8.4, 5.6))
    zoom = (0.278, 0.334)  # B-E lie here; drawn again in an inset
    inset = axes.inset_axes([0.345, 0.35, 0.255, 0.30])
    linear = load(out, "frc_linear")
    if linear:
        w, e = curve(linear)
        axes.plot(w, e, color="red", lw=1.4, label="linear, μ = 0")
        inset.plot(w, e, color="red", lw=1.2)
    documents = {}
    for name, load_n in FRC_LOADS:
        document = load(out, name)
        if not document:
            continue
        documents[load_n] = document
        w, e = curve(document)
        label = f"N = {load_n:g}"
        if termination(document) != "reached_lambda_bound":
            label += f" (incomplete: stopped at ω = {w[-1]:.3f})"
        axes.plot(w, e, color=LOAD_COLOURS[load_n], lw=1.1, label=label)
        inset.plot(w, e, color=LOAD_COLOURS[load_n], lw=1.1)
    offsets = {"A": (7, 4), "B": (-4, 7), "C": (-4, -15), "D": (5, -9), "E": (-12, 5)}
    inset_energies = []
    for label, _, load_n, omega, _, _ in POINTS:
        if load_n not in documents:
            continue
        w, e = curve(documents[load_n])
        energy = value_at(w, e, omega)
        style = dict(ms=5, mfc="white", mec="black", mew=1.2, zorder=5)
        axes.plot([omega], [energy], "o", **style)
        target = axes
        if zoom[0] <= omega <= zoom[1]:
            target = inset
            inset.plot([omega], [energy], "o", **style)
            inset_energies.append(energy)
        target.annotate(label, (omega, energy), textcoords="offset points",
                        xytext=offsets[label], fontsize=9, fontweight="bold", zorder=6)
    axes.set_yscale("log")
    axes.set_xlim(0.1, 0.8)
    inset.set_yscale("log")
    inset.set_xlim(*zoom)
    if inset_energies:
        inset.set_ylim(min(inset_energies) / 1.35, max(inset_energies) * 1.6)
    inset.tick_params(which="both", labelsize=7)
    plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
    inset.yaxis.set_major_formatter(plain)
    inset.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    inset.set_yticks([60, 80, 100, 150, 200, 300])
    inset.grid(True, which="both", alpha=0.25)
    inset.set_title("zoom on B–E", fontsize=8)
    axes.indicate_inset_zoom(inset, edgecolor="0.4")
    axes.set_xlabel("excitation frequency ω [rad/s]")
    axes.set_ylabel("mean total energy over a period")
    axes.set_title("Two-DOF oscillator with Coulomb friction, $N_\\phi$ = 60 "
                   "(cf. Legrand & Pierre 2024, Fig. 7)", fontsize=10)
    axes.grid(True, which="both", alpha=0.25)
    axes.legend(fontsize=7.5, loc="upper left")
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig7_frc.png"), "friction")


def figure_points(out, figures):
    paths = {}
    for label, name, _, _, published, _ in POINTS:
        s = signals(out, name)
        if s is None:
            continue
        title = f"Point {label}: {s.describe()}\npaper: {published}" + (
            "; shaded: sticking" if s.stick_runs else "")
        paths[label] = plot_signals.plot(
            [s], [label], ["x", "v", "r", "rv"], title=title,
            output=os.path.join(figures, f"fig8_11_point_{label.lower()}"), dpi=DPI,
            panel_size=(3.9, 2.7))
    return paths


def figure_convergence(out, figures, rows):
    runs = [(nphi, signals(out, name)) for nphi, name in CONVERGENCE]
    runs = [(nphi, s) for nphi, s in runs if s is not None]
    if not runs:
        return None
    figure = plt.figure(figsize=(11.5, 7.2))
    grid = figure.add_gridspec(2, 3)
    panels = [("x2", figure.add_subplot(grid[0, 0])), ("v2", figure.add_subplot(grid[0, 1])),
              ("r", figure.add_subplot(grid[0, 2])), ("rv", figure.add_subplot(grid[1, 0]))]
    colours = {10: "tab:orange", 20: "tab:green", 40: "tab:blue", 80: "tab:red", 160: "black"}
    # N_phi = 160 first and thick, the coarser ones on top of it
    for nphi, s in sorted(runs, key=lambda r: -r[0] if r[0] == 160 else 0):
        for panel, axes in panels:
            plot_signals.draw_panel(axes, panel, s, colours.get(nphi, "gray"),
                                    label=f"$N_\\phi$ = {nphi}",
                                    lw=2.4 if nphi == 160 else 0.9)
    for panel, axes in panels:
        plot_signals.finish_panel(axes, panel, [s for _, s in runs])
    handles, names = panels[0][1].get_legend_handles_labels()
    order = sorted(range(len(names)), key=lambda i: int(names[i].split("=")[1]))
    panels[0][1].legend([handles[i] for i in order], [names[i] for i in order], fontsize=7,
                        loc="lower left")
    axes = figure.add_subplot(grid[1, 1:])
    nphis = [r["nphi"] for r in rows if r["nphi"] != 160]
    for key, label, marker in (("energy", "mean energy", "o"), ("max_x2", "max$|x_2|$", "s"),
                               ("h1_x2", "first-harmonic amplitude of $x_2$", "^")):
        diffs = [abs(r[key + "_diff"]) / abs(rows[-1][key]) for r in rows if r["nphi"] != 160]
        axes.loglog(nphis, diffs, marker + "-", label=label)
    reference = np.array(nphis, dtype=float)
    start = abs(rows[0]["energy_diff"]) / abs(rows[-1]["energy"])
    axes.loglog(reference, start * (reference / reference[0]) ** -1.0, "k:", lw=0.8,
                label="slope $N_\\phi^{-1}$ (reference)")
    axes.set_xlabel("$N_\\phi$ (number of Fourier coefficients)")
    axes.set_ylabel("|value − value at $N_\\phi$ = 160|\n/ value at $N_\\phi$ = 160")
    axes.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    axes.set_xticks(nphis)
    axes.set_xticklabels([str(n) for n in nphis])
    axes.grid(True, which="both", alpha=0.25)
    axes.legend(fontsize=8)
    axes.set_title("difference to $N_\\phi$ = 160", fontsize=9)
    figure.suptitle("Convergence at point E (N = 10, ω = 0.308) in $N_\\phi$ "
                    "(cf. Legrand & Pierre 2024, Fig. 12)", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig12_convergence.png"), "friction")


def figure_damper(out, figures):
    runs = [(m2, signals(out, name)) for m2, name, _, _ in DAMPER]
    runs = [(m2, s) for m2, s in runs if s is not None]
    if not runs:
        return None
    labels = [f"$m_2$ = {m2:g}" + (", $d_2$ = 0" if m2 == 0 else "") for m2, _ in runs]
    return plot_signals.plot(
        [s for _, s in runs], labels, ["x", "r", "rx"], rows=True,
        title="Damper mass at N = 6.5, ω = 0.4, $N_\\phi$ = 160 (cf. Legrand & Pierre 2024, "
              "Fig. 14); $x_2$ solid, $x_1$ dashed, shaded: sticking",
        output=os.path.join(figures, "fig14_damper_mass"), dpi=DPI, panel_size=(3.6, 1.95))


def figure_piecewise(out, figures):
    runs, labels = [], []
    for delta, name in PIECEWISE:
        s = signals(out, name)
        if s is not None:
            runs.append(s)
            labels.append(f"δ = {delta:g}")
    exact = signals(out, "signals_e")
    if exact is not None:
        runs.append(exact)
        labels.append("exact (min–max)")
    if not runs:
        return None
    # exact law in black, drawn last; the approximations in colours
    order = list(range(len(runs)))
    figure, grid = plt.subplots(2, 3, figsize=(11.5, 6.6))
    colours = ["tab:orange", "tab:green", "tab:blue", "tab:red", "black"]
    for panel, axes in zip(["x1", "x2", "r", "v1", "v2", "rv"], grid.flat):
        for i in order:
            plot_signals.draw_panel(axes, panel, runs[i], colours[i], label=labels[i],
                                    lw=1.4 if i == len(runs) - 1 else 0.9)
        plot_signals.finish_panel(axes, panel, runs)
    grid[0][0].legend(fontsize=7, loc="lower left")
    figure.suptitle("Piecewise-linear law at point E (N = 10, ω = 0.308, $N_\\phi$ = 160) "
                    "vs the exact law (cf. Legrand & Pierre 2024, Fig. 15)", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig15_piecewise_linear.png"), "friction")


def figure_one_dof(out, figures):
    document = load(out, "one_dof_coulomb")
    if not document:
        return None, None
    points = document["points"]
    w = np.array([p["omega"] for p in points])
    a = np.array([p["h1"][0] for p in points])
    i = int(np.argmax(a))
    peak = (w[i], a[i])
    if 0 < i < len(a) - 1:
        vertex = parabola_vertex(w[i - 1:i + 2], a[i - 1:i + 2])
        if vertex:
            peak = vertex
    figure, axes = plt.subplots(figsize=(7, 4.5))
    axes.plot(w, a, "-", color="black", lw=1.3, label="nfrc (odd harmonics 1…21)")
    axes.plot(*peak, "o", mfc="none", mec="black", ms=8,
              label=f"nfrc peak: {peak[1]:.4f} at ω = {peak[0]:.4f}")
    axes.plot(*NLVIB_PEAK, "x", color="red", ms=10, mew=2,
              label=f"NLvib reference: {NLVIB_PEAK[1]} at ω ≈ {NLVIB_PEAK[0]}")
    inset = axes.inset_axes([0.50, 0.25, 0.32, 0.36])
    inset.plot(w, a, ".-", color="black", lw=1.0, ms=3)
    inset.plot(*peak, "o", mfc="none", mec="black", ms=8)
    inset.plot(*NLVIB_PEAK, "x", color="red", ms=9, mew=2)
    inset.set_xlim(peak[0] - 0.03, peak[0] + 0.03)
    inset.set_ylim(peak[1] - 0.25, peak[1] + 0.08)
    inset.tick_params(labelsize=7)
    inset.grid(True, alpha=0.3)
    inset.set_title("zoom on the peak (dots: branch points)", fontsize=7)
    axes.indicate_inset_zoom(inset, edgecolor="0.4")
    axes.set_xlabel("excitation frequency ω [rad/s]")
    axes.set_ylabel("first-harmonic amplitude of x")
    axes.set_title(r"One-DOF Coulomb oscillator $\ddot x + 0.1\dot x + x + r = \cos\omega t$, "
                   r"$|r| \leq 0.5$", fontsize=10)
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "one_dof_frc.png"), "friction"), peak


# ----------------------------------------------------------------------------- tables

def shoulder(omega, energy, target, window=MATCH_TOLERANCE):
    """Where log10(energy) stops rising steeply near target without a local maximum: the
    interior local minimum of the (3-point averaged) slope in the window whose slope is below a
    third of the steepest slope before it in the window. Returns (omega, slope before, slope
    at) or None."""
    y = np.log10(energy)
    dw = np.diff(omega)
    keep = dw > 0
    slope = np.diff(y)[keep] / dw[keep]
    middle = (0.5 * (omega[1:] + omega[:-1]))[keep]
    if len(slope) < 5:
        return None
    smooth = np.convolve(slope, np.ones(3) / 3.0, mode="same")
    best = None
    for k in range(1, len(smooth) - 1):
        if not target - window <= middle[k] <= target + window:
            continue
        if smooth[k] <= smooth[k - 1] and smooth[k] < smooth[k + 1]:
            before = smooth[(middle >= target - window) & (middle < middle[k])]
            if len(before) and before.max() > 3.0 * max(smooth[k], 0.0) and smooth[k] >= 0.0:
                if best is None or smooth[k] < best[2]:
                    best = (middle[k], before.max(), smooth[k])
    return best


def ripple_check(out):
    """Largest prominence among the extrema of the N_phi = 60 curve for N = 10 (frc_n10) that
    have no counterpart on the N_phi = 160 curve of the same case (point_e): numerical ripple."""
    coarse, fine = load(out, "frc_n10"), load(out, "point_e")
    if not coarse or not fine or termination(fine) != "reached_lambda_bound":
        return None
    a = extrema(*curve(coarse), threshold=0.0005)
    b = extrema(*curve(fine), threshold=0.0005)
    lonely = [x for x in a if not any(y[0] == x[0] and abs(y[1] - x[1]) < 0.006 for y in b)]
    if not lonely:
        return None
    return max(lonely, key=lambda x: x[3]), len(lonely)


def resonance_tables(out):
    """Markdown: all meaningful extrema per N, and the comparison with the published list."""
    all_rows, compare, notes = [], [], []
    found_by_load = {}
    for name, load_n in FRC_LOADS:
        document = load(out, name)
        if not document:
            continue
        w, e = curve(document)
        found = extrema(w, e)
        found_by_load[load_n] = (found, w, e, termination(document))
        maxima = ", ".join(f"{x[1]:.3f}" for x in found if x[0] == "max") or "—"
        minima = ", ".join(f"{x[1]:.3f}" for x in found if x[0] == "min") or "—"
        span = math.log10(e.max() / e.min())
        all_rows.append([f"{load_n:g}", maxima, minima, f"{span:.2f}", termination(document)])

    def add(load_n, what, target, kind, shown_target=None):
        found, w, e, _ = found_by_load[load_n]
        match = nearest(found, kind, target)
        ok = match is not None and abs(match[1] - target) <= MATCH_TOLERANCE
        if ok:
            compare.append([f"{load_n:g}", what, shown_target or f"{target}",
                            f"{match[1]:.4f}", f"{match[1] - target:+.4f}",
                            f"{match[3]:.3f}"])
            return match
        text = "no local " + ("maximum" if kind == "max" else "minimum")
        knee = shoulder(w, e, target) if kind == "max" else None
        if knee:
            text += (f"; shoulder at {knee[0]:.4f} (slope of log₁₀E drops from "
                     f"{knee[1]:.0f} to {knee[2]:.1f} per unit ω)")
        elif match:
            text += f" within ±{MATCH_TOLERANCE} (nearest {match[1]:.3f})"
        compare.append([f"{load_n:g}", what, shown_target or f"{target}", text, "—", "—"])
        return None

    for load_n in (8.0, 9.0, 10.0):
        if load_n in found_by_load:
            add(load_n, "primary resonance", PRIMARY, "max", f"≈ {PRIMARY}")
            for target in PUBLISHED_SUPERHARMONICS:
                add(load_n, "super-harmonic peak", target, "max", f"≈ {target}")
    if 10.5 in found_by_load:
        found = found_by_load[10.5][0]
        add(10.5, "anti-resonance", 0.299, "min")
        add(10.5, "resonance", 0.308, "max")
        peak_056 = add(10.5, "3:1 Mode-2 peak, dominating", 0.56, "max", "≈ 0.56")
        others = [x for x in found if x[0] == "max" and x is not peak_056 and x[1] > 0.45]
        if peak_056 and others:
            top = max(others, key=lambda x: x[2])
            notes.append(f"N = 10.5: the 3:1 peak ({peak_056[1]:.3f}) has energy "
                         f"{peak_056[2]:.4g}, the primary peak ({top[1]:.3f}) {top[2]:.4g}: "
                         f"ratio {peak_056[2] / top[2]:.2f}.")
    if 11.0 in found_by_load:
        found = found_by_load[11.0][0]
        match = add(11.0, "only resonance", 0.562, "max")
        others = [x for x in found if x[0] == "max" and x is not match]
        if others:
            notes.append("N = 11: besides 0.562, maxima above the threshold at " + ", ".join(
                f"{x[1]:.3f} (prominence {x[3]:.3f} decades, ×{10 ** x[3]:.2f} in energy)"
                for x in others) + "; the paper reports only the resonance at 0.562.")
    if 12.0 in found_by_load:
        found, w, e, _ = found_by_load[12.0]
        lin = load(out, "frc_linear")
        span_lin = math.log10(curve(lin)[1].max() / curve(lin)[1].min()) if lin else float("nan")
        compare.append(["12", "nearly flat", "—",
                        f"energy {e.min():.3g} … {e.max():.3g}: "
                        f"{math.log10(e.max() / e.min()):.2f} decades "
                        f"(linear curve {span_lin:.2f})", "—",
                        f"{len(found)} extrema"])
    # side of the anti-resonance next to each super-harmonic peak
    sides = []
    for load_n, (found, _, _, _) in sorted(found_by_load.items()):
        left = right = 0
        for i, x in enumerate(found):
            if x[0] != "max" or x[1] > 0.45:
                continue
            before = found[i - 1] if i > 0 and found[i - 1][0] == "min" else None
            after = found[i + 1] if i + 1 < len(found) and found[i + 1][0] == "min" else None
            if after and (not before or after[1] - x[1] < x[1] - before[1]):
                right += 1
            elif before:
                left += 1
        if left or right:
            sides.append(f"N = {load_n:g}: {right} right, {left} left")
    if sides:
        notes.append("Nearest anti-resonance of each super-harmonic peak below ω = 0.45 lies on "
                     "the high-ω side (right) or low-ω side (left): " + "; ".join(sides) +
                     ". The paper: “in most cases to the left of the peak but occasionally to "
                     "the right, for instance at ω = 0.299 for N = 10.5”.")
    ripple = ripple_check(out)
    if ripple:
        (kind, w_r, _, p_r), count = ripple
        notes.append(f"Threshold check: {count} extrema of the N_φ = 60 curve for N = 10 have "
                     f"no counterpart on the N_φ = 160 curve of the same case (`point_e`); the "
                     f"most prominent is a {kind} at ω = {w_r:.3f} with {p_r:.4f} decades — "
                     f"truncation ripple, below the {PROMINENCE_DECADES}-decade threshold.")
    return all_rows, compare, notes, found_by_load


def main():
    args = parse_arguments("friction", __doc__.splitlines()[0])
    started = time.monotonic()
    load_average = os.getloadavg()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    os.makedirs(args.figures, exist_ok=True)
    skipped = run_all(os.path.abspath(args.nfrc), out, args.force, args.jobs)
    runs_seconds = time.monotonic() - started
    failed = incomplete(out)
    for name, how, message in failed:
        print(f"friction_study: ERROR: {name} did not reach the end of its range: {how}: "
              f"{message}", file=sys.stderr, flush=True)

    md = []
    figure_dir = os.path.relpath(args.figures, REPO)

    def figure_ref(path, alt):
        return f"![{alt}]({os.path.join(figure_dir, os.path.basename(path))})"

    md.append("<!-- generated by tools/studies/friction_study.py; figure paths are relative to "
              "the repository root -->")
    md.append("## Friction study (Legrand & Pierre 2024, Section 5)\n")
    md.append("Two-DOF oscillator with Coulomb friction on mass 2 (`cases/friction/`, "
              "`../shared/cases.md` case 1): m1 = m2 = 1, k1 = k2 = 1, d1 = d2 = 0.02, "
              "μ = 0.9, f1 = 20 cos ωt; exact (min–max) equality, odd harmonics.\n")
    md.append("**Reproduce** (from the repository root, after the README's build): "
              "`/usr/bin/python3 tools/studies/friction_study.py --nfrc build/nfrc` — "
              f"{len(RUNS)} runs, figures and tables; " +
              ("measured wall time from scratch: @TOTAL_SECONDS@ s (Release build, this "
               "project's 2-core machine).\n" if not skipped else
               f"this page took @TOTAL_SECONDS@ s with {skipped} runs skipped as already "
               "finished (`--force` reruns them all).\n"))
    if failed:
        md.append("**Incomplete runs.** These case files did not reach the end of their ω "
                  "range; figures and tables use them as far as they got:\n")
        md.extend(f"- `{CASES}/{name}.json`: **{how}** — “{message}”."
                  for name, how, message in failed)
        md.append("")

    # a. Fig. 7
    path = figure7(out, args.figures)
    md.append("### Frequency responses (Fig. 7)\n")
    md.append(figure_ref(path, "Fig. 7: mean energy vs omega"))
    md.append("\n*Mean total energy over a period vs ω for N = 8 … 12 and the frictionless "
              "curve, N_φ = 60 (30 odd harmonics); A–E are the points of the time-signal "
              "figures.*\n")

    # b. resonance tables
    all_rows, compare, notes, found_by_load = resonance_tables(out)
    md.append("#### Resonances and anti-resonances\n")
    md.append(f"Method: local maxima (resonances) and minima (anti-resonances) of log₁₀(energy) "
              f"along the branch points (interior points only), each refined by the vertex of "
              f"the parabola through it and its two neighbours. An extremum counts only if its "
              f"prominence is at least {PROMINENCE_DECADES} decades "
              f"(×{10 ** PROMINENCE_DECADES:.3f} in energy); prominence = how far log₁₀E must "
              f"fall (rise, for a minimum) from the extremum before reaching a higher (lower) "
              f"point or the end of the curve, taking the smaller of the two sides. Smaller "
              f"ripples are ignored. A published value is matched by the nearest found extremum "
              f"of the same kind within ±{MATCH_TOLERANCE}; a published peak without a local "
              f"maximum is searched for as a shoulder (a local minimum of the slope of log₁₀E "
              f"below a third of the steepest slope before it).\n")
    md.append(table(["N", "maxima ω (resonances)", "minima ω (anti-resonances)",
                     "energy span (decades)", "run end"], all_rows))
    md.append("")
    md.append(table(["N", "feature", "published ω", "nfrc ω", "difference",
                     "prominence (decades)"], compare))
    md.append("")
    for note in notes:
        md.append(f"- {note}")
    md.append("")

    # c. points A–E
    point_paths = figure_points(out, args.figures)
    md.append("### Time signals at A–E (Figs. 8–11), N_φ = 160\n")
    point_rows = []
    for label, name, load_n, omega, published, published_count in POINTS:
        s = signals(out, name)
        if s is None:
            point_rows.append([label, f"{load_n:g}", omega, published, published_count,
                               "run missing", "", "", ""])
            continue
        found = int(s.stick_phases)
        point_rows.append([label, f"{load_n:g}", f"{omega}", published, published_count, found,
                           f"{100 * s.stick_fraction:.0f} %", f"{s.max_force_ratio:.3f}",
                           f"{s.entry['energy']:.4g}" + ("" if s.converged else " (not conv.)")])
    md.append(table(["point", "N", "ω", "paper", "paper stick phases", "nfrc stick phases",
                     "stick time / T", "max\\|r\\|/μN", "energy"], point_rows))
    some = signals(out, "signals_e")
    samples = len(some.t) - 1 if some else 0
    md.append("\nStick phases are counted by the solver (`laws[0].stick_phases` of the signals "
              f"entry): samples of the {samples}-point resampled period on the stick branch of "
              "the min–max law (ρ(r − μN) ≤ ẋ2 ≤ ρ(r + μN), ρ = 1), runs shorter than 1/H of "
              "the period (H = 159) dropped as ripple. Shaded intervals in the figures are "
              "these phases (recomputed by `tools/plot_signals.py` with the same rule). "
              "max\\|r\\|/μN > 1 is the Gibbs overshoot at the force jumps.\n")
    for label in "ABCDE":
        if label in point_paths:
            md.append(figure_ref(point_paths[label], f"Point {label}"))
    md.append("")

    # d. convergence
    rows = []
    for nphi, name in CONVERGENCE:
        s = signals(out, name)
        if s is None:
            continue
        x2 = s.doc["output_dofs"].index("x2") if "x2" in s.doc["output_dofs"] else 1
        rows.append({"nphi": nphi, "energy": s.entry["energy"],
                     "max_x2": s.entry["max_abs"][x2], "h1_x2": s.entry["h1"][x2],
                     "stick": s.stick_phases, "doc": s.doc})
    if rows and rows[-1]["nphi"] == 160:
        for r in rows:
            for key in ("energy", "max_x2", "h1_x2"):
                r[key + "_diff"] = r[key] - rows[-1][key]
        path = figure_convergence(out, args.figures, rows)
        md.append("### Convergence in N_φ at point E (Fig. 12)\n")
        md.append(table(["N_φ", "energy", "Δ energy", "max\\|x2\\|", "Δ max\\|x2\\|",
                         "h1(x2)", "Δ h1(x2)", "stick phases (solver)"],
                        [[r["nphi"], f"{r['energy']:.6g}", f"{r['energy_diff']:+.2e}",
                          f"{r['max_x2']:.6g}", f"{r['max_x2_diff']:+.2e}",
                          f"{r['h1_x2']:.6g}", f"{r['h1_x2_diff']:+.2e}", int(r["stick"])]
                         for r in rows]))
        md.append("\nΔ = value − value at N_φ = 160; h1 = first-harmonic amplitude. The "
                  "solver does not count stick phases shorter than one period of the highest "
                  "harmonic (T/H), the shortest feature the truncated basis resolves; at "
                  "N_φ = 10 (H = 9) E's two short stick phases (~0.08 T < T/9) are below that "
                  "resolution.\n")
        md.append(figure_ref(path, "Fig. 12: convergence at E"))
        md.append("")

    # e. damper mass
    path = figure_damper(out, args.figures)
    md.append("### Damper mass (Fig. 14): N = 6.5, ω = 0.4, N_φ = 160\n")
    damper_rows = []
    for m2, name, count, description in DAMPER:
        s = signals(out, name)
        if s is None:
            damper_rows.append([f"{m2:g}", description, "run missing", "", ""])
            continue
        damper_rows.append([f"{m2:g}" + (" (d2 = 0)" if m2 == 0 else ""),
                            f"{description} ({count})", int(s.stick_phases),
                            f"{100 * s.stick_fraction:.0f} %", f"{s.max_force_ratio:.3f}"])
    md.append(table(["m2", "paper: stick phases", "nfrc stick phases", "stick time / T",
                     "max\\|r\\|/μN"], damper_rows))
    md.append("")
    if path:
        md.append(figure_ref(path, "Fig. 14: damper mass"))
        md.append("")

    # f. piecewise-linear law
    path = figure_piecewise(out, args.figures)
    md.append("### Piecewise-linear law at point E (Fig. 15)\n")
    pwl_rows = []
    for delta, name in PIECEWISE + [(None, "signals_e")]:
        s = signals(out, name)
        if s is None:
            continue
        x2 = 1
        pwl_rows.append(["exact" if delta is None else f"{delta:g}",
                         int(s.stick_phases), f"{100 * s.stick_fraction:.0f} %",
                         f"{s.entry['energy']:.5g}", f"{s.entry['max_abs'][x2]:.5g}",
                         f"{s.max_force_ratio:.3f}"])
    md.append(table(["δ", "stick (exact) / \\|v2\\| ≤ δ (approx.) phases", "time / T",
                     "energy", "max\\|x2\\|", "max\\|r\\|/μN"], pwl_rows))
    md.append("")
    if path:
        md.append(figure_ref(path, "Fig. 15: piecewise-linear law"))
        md.append("")

    # g. one-DOF
    path, peak = figure_one_dof(out, args.figures)
    if path:
        md.append("### One-DOF Coulomb oscillator\n")
        md.append(f"Peak of the first-harmonic amplitude (largest branch point refined by a "
                  f"parabola): **{peak[1]:.4f} at ω = {peak[0]:.4f}**; NLvib's reference "
                  f"{NLVIB_PEAK[1]} at ω ≈ {NLVIB_PEAK[0]} (difference "
                  f"{peak[1] - NLVIB_PEAK[1]:+.4f}, {100 * (peak[1] / NLVIB_PEAK[1] - 1):+.2f} %)."
                  "\n")
        md.append(figure_ref(path, "one-DOF Coulomb FRC"))
        md.append("")
        print(f"friction_study: one-DOF peak {peak[1]:.5f} at omega = {peak[0]:.5f} "
              f"(NLvib {NLVIB_PEAK[1]} at {NLVIB_PEAK[0]})")

    # h. point_e full curve
    full = load(out, "point_e")
    direct = signals(out, "signals_e")
    if full:
        md.append("### The issue's case `cases/friction/point_e.json` (full curve, N_φ = 160)\n")
        summary = full["summary"]
        entry = full["signals"][0] if full.get("signals") else None
        lines = [f"- run: {summary.get('termination')}, {summary.get('points')} points, "
                 f"{summary.get('folds')} folds, wall time {summary.get('wall_time_s', 0):.1f} s "
                 f"({1000 * summary.get('wall_time_s', 0) / max(1, summary.get('points', 1)):.0f}"
                 f" ms/point)."]
        if entry and direct:
            e_full, e_direct = entry["energy"], direct.entry["energy"]
            stick_full = (entry.get("laws") or [{}])[0].get("stick_phases")
            lines.append(f"- signals at ω = {entry['omega']}: energy {e_full:.8g} "
                         f"(converged: {entry.get('converged')}, {int(stick_full)} stick "
                         f"phases) against {e_direct:.8g} from the direct run `signals_e` "
                         f"(relative difference {abs(e_full - e_direct) / e_direct:.1e}).")
        n10 = load(out, "frc_n10")
        if n10:
            w60, e60 = curve(n10)
            w160, e160 = curve(full)
            ok = (np.all(np.diff(w60) > 0) and np.all(np.diff(w160) > 0))
            if ok:
                grid = w160[(w160 >= w60[0]) & (w160 <= w60[-1])]
                rel = np.abs(np.interp(grid, w60, e60) / np.interp(grid, w160, e160) - 1.0)
                k = int(np.argmax(rel))
                lines.append(f"- N_φ = 60 (`frc_n10`) vs N_φ = 160 (`point_e`) energy on the "
                             f"N_φ = 160 points (linear interpolation): median relative "
                             f"difference {np.median(rel):.1e}, largest {rel[k]:.1e} at ω = "
                             f"{grid[k]:.4f}.")
        md.extend(lines)
        md.append("")

    # timing
    md.append("### Run times\n")
    timing_rows = []
    total_points, total_time = 0, 0.0
    for name in RUNS:
        document = load(out, name)
        if not document:
            timing_rows.append([f"`{name}`", "—", "—", "—", "—", "missing"])
            continue
        summary = document["summary"]
        points = summary.get("points", len(document.get("points", [])))
        seconds = summary.get("wall_time_s", float("nan"))
        total_points += points
        total_time += seconds
        nphi = sum(1 if h == 0 else 2 for h in document["harmonics"]["list"])
        timing_rows.append([f"`{name}`", nphi, points, f"{seconds:.2f}",
                            f"{1000 * seconds / max(points, 1):.1f}", summary.get("termination")])
    timing_rows.append(["**total**", "", total_points, f"{total_time:.1f}",
                        f"{1000 * total_time / max(total_points, 1):.1f}", ""])
    md.append(table(["run", "N_φ", "points", "wall time (s)", "ms/point", "termination"],
                    timing_rows))
    md.append("\nWall time is `summary.wall_time_s` of each `branch.json` (continuation "
              "only; Release build, this project's 2-core machine, one run at a time; load "
              f"average {load_average[0]:.1f} when the study started, so other work shared "
              "the cores). The single-point runs (signals, convergence, damper mass, δ) trace "
              "ω from the point to ω + 0.001; their signals come from the first point.\n")

    total = time.monotonic() - started
    with open(args.markdown, "w") as handle:
        handle.write("\n".join(md).rstrip().replace("@TOTAL_SECONDS@", f"{total:.0f}") + "\n")
    print(f"friction_study: runs {runs_seconds:.1f} s, total {total:.1f} s; "
          f"wrote {args.markdown} and {figure_dir}/")
    if failed:
        print(f"friction_study: ERROR: {len(failed)} case(s) did not reach the end of their "
              "range: " + ", ".join(name for name, _, _ in failed), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
