#!/usr/bin/python3
"""Draws the time signals of nfrc runs with friction (DIR/signals_K.csv, like Legrand & Pierre
2024, Figs. 8-15).

usage: plot_signals.py DIR [DIR ...] [--signal K] [--output BASE] [--title TEXT]
       [--labels A,B,...] [--panels x,v,r,rv] [--rows] [--svg]

One DIR: panels x1, x2 vs t (x2, the friction damper, solid; x1 dashed); v1, v2 vs t; friction
force r vs t; r vs v2 (Coulomb graph), with dashed lines at +-muN. Time intervals the solver
classifies as sticking are shaded. The title gives omega, the normal load N, N_phi and the
stick-phase count of the signals entry in branch.json.

Several DIRs: the same panels with the runs overlaid (one colour per run, --labels names them),
or with --rows one row of panels per run. Panels (--panels, comma separated):
  x   x1 (dashed) and x2 (solid) vs t      x1, x2   one displacement vs t
  v   v1 (dashed) and v2 (solid) vs t      v1, v2   one velocity vs t
  r   friction force vs t                  rv       friction force vs friction velocity
  rx  friction force vs x1 (hysteresis)
Writes BASE.png (and BASE.svg with --svg); BASE defaults to DIR/signals_K.
"""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from nfrc_output import load_branch  # noqa: E402

PANEL_NAMES = ("x", "x1", "x2", "v", "v1", "v2", "r", "rv", "rx")
RUN_COLOURS = ["black", "tab:red", "tab:blue", "tab:green", "tab:orange", "tab:purple",
               "tab:brown", "tab:cyan"]


def fail(message):
    sys.exit(f"plot_signals: {message}")


def _resolve_dof(value, dof_names):
    """A case-file DOF (index or name) as an index."""
    if isinstance(value, str):
        if value in dof_names:
            return dof_names.index(value)
        try:
            return int(value)
        except ValueError:
            fail(f"unknown DOF name {value!r}")
    return int(value)


def count_phases(flags, min_fraction):
    """Python port of nonlinearities/phase_count.cc: (count, fraction, runs) of the cyclic
    True-runs of `flags`, after dropping runs (True, then False) shorter than min_fraction of
    the period. runs = [(start, length, value)] covering the period cyclically."""
    n = len(flags)
    on = int(sum(flags))
    if on in (0, n):
        return (1 if on == n else 0), (1.0 if on == n else 0.0), [(0, n, on == n)]
    start = 0
    while flags[start] == flags[(start + n - 1) % n]:
        start += 1
    runs = []
    for i in range(n):
        value = flags[(start + i) % n]
        if runs and runs[-1][2] == value:
            runs[-1][1] += 1
        else:
            runs.append([(start + i) % n, 1, value])
    min_length = max(1, math.ceil(min_fraction * n))

    def drop(runs, value):
        for run in runs:
            if run[2] == value and run[1] < min_length:
                run[2] = not value
        merged = []
        for run in runs:
            if merged and merged[-1][2] == run[2]:
                merged[-1][1] += run[1]
            else:
                merged.append(list(run))
        if len(merged) > 1 and merged[0][2] == merged[-1][2]:
            merged[-1][1] += merged[0][1]
            merged.pop(0)
        return merged

    runs = drop(drop(runs, True), False)
    count = sum(1 for run in runs if run[2])
    covered = sum(run[1] for run in runs if run[2])
    fraction = covered / n
    if fraction == 1.0:
        count = 1
    return count, fraction, [tuple(run) for run in runs]


class Signals:
    """One signals entry of a run: samples over one period plus what the case says."""

    def __init__(self, directory, index=0):
        self.directory = directory
        self.doc = load_branch(directory, "plot_signals")
        entries = self.doc.get("signals", [])
        if not entries:
            fail(f"{directory}/branch.json has no signals (the case needs output.signals_at)")
        if not -len(entries) <= index < len(entries):
            fail(f"{directory}: --signal {index} out of range ({len(entries)} signals)")
        self.entry = entries[index]
        case = self.doc.get("case", {})
        model = case.get("model", {})
        dof_names = model.get("dof_names", [])
        laws = case.get("nonlinearities", [])
        self.law = laws[0] if laws else {}
        self.mu = self.law.get("mu")
        self.normal_load = self.law.get("normal_load")
        self.mu_n = (self.mu * self.normal_load
                     if self.mu is not None and self.normal_load is not None else None)
        self.law_type = self.law.get("law", "min_max")
        self.omega = self.entry["omega"]
        self.period = 2.0 * math.pi / self.omega
        harmonics = self.doc.get("harmonics", {}).get("list", [])
        # N_phi counts the cosine and sine coefficients (the constant term has one).
        self.nphi = sum(1 if h == 0 else 2 for h in harmonics)
        self.max_harmonic = self.doc.get("harmonics", {}).get("max", 0)
        diagnostics = (self.entry.get("laws") or [{}])[0]
        self.stick_phases = diagnostics.get("stick_phases")
        self.stick_fraction = diagnostics.get("stick_fraction")
        self.max_force_ratio = diagnostics.get("max_force_ratio")
        self.converged = self.entry.get("converged", True)
        mass = model.get("M")
        friction_dof = _resolve_dof(self.law.get("dof", 1), dof_names) if self.law else 1
        self.m2 = (mass[friction_dof][friction_dof]
                   if isinstance(mass, list) and friction_dof < len(mass) else None)

        path = os.path.join(directory, self.entry["file"])
        try:
            with open(path) as handle:
                reader = csv.reader(handle)
                header = next(reader)
                rows = np.array([[float(v) for v in row] for row in reader if row])
        except OSError as error:
            fail(f"cannot read {path}: {error.strerror}")
        columns = {name: rows[:, i] for i, name in enumerate(header)}
        # Output DOFs in order; x1 = the first, x2 = the friction DOF (else the second).
        outputs = [_resolve_dof(name, dof_names) for name in self.doc.get("output_dofs", [])]
        x_columns = [name for name in header if name.startswith("x_")]
        v_columns = [name for name in header if name.startswith("v_")]
        if not x_columns:
            fail(f"{path}: no displacement columns")
        second = outputs.index(friction_dof) if friction_dof in outputs else min(
            1, len(x_columns) - 1)
        first = 0 if second != 0 else min(1, len(x_columns) - 1)

        def closed(values):  # append the sample at t = T so curves close over the period
            return np.append(values, values[0])

        self.t = np.append(columns["t"], self.period)
        self.x1 = closed(columns[x_columns[first]])
        self.v1 = closed(columns[v_columns[first]])
        self.x2 = closed(columns[x_columns[second]])
        self.v2 = closed(columns[v_columns[second]])
        self.r = closed(columns["law0_force"]) if "law0_force" in columns else None
        self.v_slip = (closed(columns["law0_velocity"]) if "law0_velocity" in columns
                       else self.v2)
        self.stick_flags = None  # per sample of one period: on the stick branch
        self.stick_runs = self._stick_runs(columns)

    def _stick_runs(self, columns):
        """Stick intervals [(t0, t1)] by the rule of CoulombFriction::Diagnostics."""
        if self.r is None or self.mu_n is None or self.mu_n <= 0.0:
            return []
        r = columns["law0_force"]
        v = columns.get("law0_velocity", columns.get("v_" + "x2"))
        if self.law_type == "min_max":
            rho = self.law.get("rho", 1.0)
            flags = list((rho * (r - self.mu_n) <= v) & (v <= rho * (r + self.mu_n)))
        elif self.law_type == "hueber":
            rho = self.law.get("rho", 1.0)
            flags = list(np.abs(r - rho * v) <= self.mu_n)
        elif self.law_type == "piecewise_linear":
            flags = list(np.abs(v) <= self.law["delta"])
        else:
            return []
        self.stick_flags = flags
        n = len(flags)
        count, _, runs = count_phases(flags, 1.0 / max(1, self.max_harmonic))
        self.python_stick_phases = count
        dt = self.period / n
        return [(start * dt, (start + length) * dt) for start, length, value in runs if value]

    def describe(self):
        """ω, N, N_φ and stick phases, for titles."""
        parts = [f"ω = {self.omega:.4g}"]
        if self.normal_load is not None:
            parts.append(f"N = {self.normal_load:g}")
        parts.append(f"$N_\\phi$ = {self.nphi}")
        if self.stick_phases is not None:
            word = "stick phase" if self.stick_phases == 1 else "stick phases"
            if self.law_type == "piecewise_linear":
                word = word.replace("stick", "viscous-band")
            parts.append(f"{int(self.stick_phases)} {word}")
            if self.stick_fraction:
                parts[-1] += f" ({100 * self.stick_fraction:.0f}% of T)"
        if not self.converged:
            parts.append("NOT CONVERGED")
        return ", ".join(parts)


def _shade_stick(axes, signals, colour="0.85"):
    for t0, t1 in signals.stick_runs:
        if t1 <= signals.period:
            axes.axvspan(t0, t1, color=colour, lw=0, zorder=0)
        else:  # wraps around the period
            axes.axvspan(t0, signals.period, color=colour, lw=0, zorder=0)
            axes.axvspan(0.0, t1 - signals.period, color=colour, lw=0, zorder=0)


def _limit_lines(axes, mu_n, horizontal=True):
    if mu_n is None:
        return
    for value in (mu_n, -mu_n):
        if horizontal:
            axes.axhline(value, ls="--", lw=0.8, color="0.45", zorder=1)


def draw_panel(axes, panel, signals, colour, label=None, single=False, lw=1.2):
    """Draws one panel of one run onto axes."""
    solid = dict(color=colour, lw=lw, ls="-")
    dashed = dict(color=colour if not single else "tab:blue", lw=lw, ls="--")
    t = signals.t
    if panel == "x":
        axes.plot(t, signals.x2, label=(label if not single else "$x_2$ (damper)"), **solid)
        axes.plot(t, signals.x1, label=(None if not single else "$x_1$"), **dashed)
        axes.set_ylabel("displacement $x_1$, $x_2$")
    elif panel == "v":
        axes.plot(t, signals.v2, label=(label if not single else r"$\dot x_2$ (damper)"),
                  **solid)
        axes.plot(t, signals.v1, label=(None if not single else r"$\dot x_1$"), **dashed)
        axes.set_ylabel(r"velocity $\dot x_1$, $\dot x_2$")
    elif panel in ("x1", "x2", "v1", "v2"):
        values = getattr(signals, panel)
        axes.plot(t, values, label=label, **solid)
        axes.set_ylabel({"x1": "displacement $x_1$", "x2": "damper displacement $x_2$",
                         "v1": r"velocity $\dot x_1$",
                         "v2": r"damper velocity $\dot x_2$"}[panel])
    elif panel == "r":
        if signals.r is not None:
            axes.plot(t, signals.r, label=label, **solid)
        axes.set_ylabel("friction force $r$")
    elif panel == "rv":
        if signals.r is not None:
            axes.plot(signals.v_slip, signals.r, label=label, **solid)
        axes.set_xlabel(r"damper velocity $\dot x_2$")
        axes.set_ylabel("friction force $r$")
    elif panel == "rx":
        if signals.r is not None:
            axes.plot(signals.x1, signals.r, label=label, **solid)
        axes.set_xlabel("displacement $x_1$")
        axes.set_ylabel("friction force $r$")
    else:
        raise ValueError(panel)
    if panel not in ("rv", "rx"):
        axes.set_xlabel("time $t$ [s]")
        axes.set_xlim(0.0, signals.period)


def finish_panel(axes, panel, runs):
    """±μN lines and axis cosmetics once all runs are drawn."""
    mu_ns = sorted({s.mu_n for s in runs if s.mu_n})
    if panel in ("r", "rv", "rx"):
        for mu_n in mu_ns:
            _limit_lines(axes, mu_n)
        if panel == "rv" and mu_ns:
            axes.axvline(0.0, ls=":", lw=0.7, color="0.45", zorder=1)
        if mu_ns:
            axes.set_ylim(-1.35 * mu_ns[-1], 1.35 * mu_ns[-1])
    axes.grid(True, alpha=0.3)
    axes.tick_params(labelsize=8)
    axes.xaxis.label.set_size(9)
    axes.yaxis.label.set_size(9)


def plot(runs, labels, panels, rows=False, title=None, output=None, ncols=None, svg=False,
         dpi=130, panel_size=(3.4, 2.6), legend_panel=None):
    """Draws the figure; returns the PNG path."""
    for panel in panels:
        if panel not in PANEL_NAMES:
            fail(f"unknown panel {panel!r} (known: {', '.join(PANEL_NAMES)})")
    single = len(runs) == 1
    if rows and not single:
        nrows, ncols = len(runs), len(panels)
    else:
        ncols = ncols or min(len(panels), 2 if len(panels) == 4 else 3)
        nrows = math.ceil(len(panels) / ncols)
    figure, grid = plt.subplots(nrows, ncols, squeeze=False,
                                figsize=(panel_size[0] * ncols, panel_size[1] * nrows + 0.6))
    if rows and not single:
        for i, signals in enumerate(runs):
            colour = "black"
            for j, panel in enumerate(panels):
                axes = grid[i][j]
                if panel in ("x", "v", "r", "x1", "x2", "v1", "v2"):
                    _shade_stick(axes, signals)
                draw_panel(axes, panel, signals, colour, single=True)
                finish_panel(axes, panel, [signals])
                if j == 0:
                    axes.set_title(labels[i], fontsize=9, loc="left")
                if j == len(panels) - 1 and signals.stick_phases is not None:
                    axes.set_title(f"{int(signals.stick_phases)} stick phases", fontsize=8,
                                   loc="right")
        handles, names = grid[0][0].get_legend_handles_labels()
        if handles:
            grid[0][0].legend(handles, names, fontsize=7, loc="best")
    else:
        for k, panel in enumerate(panels):
            axes = grid[k // ncols][k % ncols]
            if single and panel in ("x", "v", "r", "x1", "x2", "v1", "v2"):
                _shade_stick(axes, runs[0])
            for i, signals in enumerate(runs):
                colour = "black" if single else RUN_COLOURS[i % len(RUN_COLOURS)]
                draw_panel(axes, panel, signals, colour,
                           label=None if single else labels[i], single=single,
                           lw=1.2 if single else 1.0)
            finish_panel(axes, panel, runs)
            if single and panel in ("x", "v"):
                axes.legend(fontsize=7, loc="best")
        for k in range(len(panels), nrows * ncols):
            grid[k // ncols][k % ncols].axis("off")
        if not single:
            where = legend_panel if legend_panel is not None else 0
            axes = grid[where // ncols][where % ncols]
            handles, names = axes.get_legend_handles_labels()
            if any(p in ("x", "v") for p in panels):  # explain the line styles
                handles += [plt.Line2D([], [], color="0.4", ls="-"),
                            plt.Line2D([], [], color="0.4", ls="--")]
                names += ["solid: damper DOF $x_2$", "dashed: $x_1$"]
            axes.legend(handles, names, fontsize=7, loc="best")
    if title is None:
        titles = {s.doc.get("case", {}).get("title", "") for s in runs}
        title = (runs[0].describe() if single else titles.pop() if len(titles) == 1
                 else "time signals: " + ", ".join(labels))
        if single and any(p in ("x", "v", "r") for p in panels) and runs[0].stick_runs:
            title += "\n(shaded: sticking)"
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    base = output or os.path.join(runs[0].directory,
                                  os.path.splitext(runs[0].entry["file"])[0])
    os.makedirs(os.path.dirname(os.path.abspath(base)), exist_ok=True)
    figure.savefig(base + ".png", dpi=dpi)
    if svg:
        figure.savefig(base + ".svg")
    plt.close(figure)
    return base + ".png"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.splitlines()[2:]))
    parser.add_argument("dirs", nargs="+")
    parser.add_argument("--signal", type=int, default=0,
                        help="which signals entry of branch.json (default 0)")
    parser.add_argument("--output", help="output path without extension")
    parser.add_argument("--title")
    parser.add_argument("--labels", help="comma-separated labels, one per DIR")
    parser.add_argument("--panels", default="x,v,r,rv")
    parser.add_argument("--rows", action="store_true", help="one row of panels per DIR")
    parser.add_argument("--svg", action="store_true", help="also write BASE.svg")
    args = parser.parse_args()

    runs = [Signals(d, args.signal) for d in args.dirs]
    if args.labels:
        labels = args.labels.split(",")
        if len(labels) != len(runs):
            fail(f"--labels has {len(labels)} names for {len(runs)} directories")
    else:
        labels = [os.path.basename(os.path.normpath(d)) for d in args.dirs]
    if len(runs) > 1:
        labels = [f"{label} ({int(s.stick_phases)} stick phases)" if s.stick_phases is not None
                  and not args.rows else label for label, s in zip(labels, runs)]
    path = plot(runs, labels, args.panels.split(","), rows=args.rows, title=args.title,
                output=args.output, svg=args.svg)
    print(f"plot_signals: wrote {path}")


if __name__ == "__main__":
    main()
