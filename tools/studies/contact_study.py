#!/usr/bin/python3
"""Runs the contact study of Vadcard, Batailly & Thouverez (2022), Sections 3-4 (FE rod against
a flexible or rigid obstacle, DLFT), and NLvib's two-DOF unilateral-spring example, with nfrc,
and writes their figures and tables.

usage: contact_study.py [--nfrc PATH] [--out DIR] [--force] [--jobs N]
                        [--figures DIR] [--markdown PATH]

Runs every case of RUNS (cases/rod/, cases/contact/) with `nfrc run CASE --out OUT/NAME`
(stderr to OUT/NAME/nfrc.log), skipping a run whose OUT/NAME/branch.json already ended with
summary.termination == reached_lambda_bound unless --force, and the epsilon refinements of
REFINEMENTS with `nfrc refine CASE --omega W --epsilons ... --out OUT/NAME` (skipped when
OUT/NAME/refinement.json exists, unless --force). Then draws docs/figures/contact/*.png and
writes docs/contact_results.md (tables and figure references, paths relative to the repository
root). Defaults: --nfrc build/nfrc, --out out/contact, both relative to the repository root.
A case that does not reach the end of its range, or a refinement that stops before its last
epsilon, is named on stderr and in the markdown with the command that reproduces it; a run that
does not reach the end of its range makes the exit status 1.
"""
import concurrent.futures
import csv
import math
import os
import sys
import time

sys.dont_write_bytecode = True  # keep tools/ free of __pycache__

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from study_common import (REPO, execute, fmt, load, parse_arguments, save, table,  # noqa: E402
                          termination, value_at)

# ----------------------------------------------------------------------------- the study

ROD = dict(elements=20, length=0.13, area=15.6e-4, young=210e9, gap=2e-4)
K_ROD = ROD["young"] * ROD["area"] / ROD["length"]  # EA/L = 2.52e9 N/m
RHO = 7500.0        # the density of the figures (reproduces the paper's omega0)
RHO_TABLE = 7800.0  # the paper's Table 1
OMEGA0_CASES = 63953.9  # signals_at of the rho = 7500 case files (omega0, rounded)
OMEGA0_CASES_7800 = 62712.0

# (run name, case file relative to the repository root)
FLEXIBLE = [(0.4, "flexible_0_4krod"), (4.0, "flexible_4krod"), (20.0, "flexible_20krod"),
            (40.0, "flexible_40krod")]
RIGID = [(20, "rigid_nh20"), (30, "rigid_nh30"), (40, "rigid_nh40")]
RIGID_FINE = [(20, "rigid_nh20_fine"), (30, "rigid_nh30_fine"), (40, "rigid_nh40_fine")]
PENALTY = {4.0: "penalty_4krod", 40.0: "penalty_40krod"}  # penalty twins (paper Sec. 3.4)
NLVIB = [("nlvib_penalty", "penalty, H = 21 (NLvib's settings)"),
         ("nlvib_dlft_flexible", "DLFT flexible obstacle, default ε, H = 21"),
         ("nlvib_dlft_flexible_eps0_5", "DLFT flexible obstacle, ε = 0.4975 (static stiffness), H = 21"),
         ("nlvib_penalty_h84", "penalty, H = 84"),
         ("nlvib_dlft_flexible_h84", "DLFT flexible obstacle, default ε, H = 84")]
ROD_RUNS = ([name for _, name in FLEXIBLE] + [name for _, name in RIGID] + ["linear_rod"] +
            ["rigid_nh20_rho7800", "flexible_4krod_rho7800", "linear_rod_rho7800",
             "flexible_4krod_nt600"] + [name for _, name in RIGID_FINE] +
            list(PENALTY.values()))
# Run names whose case is a member of a manifest (FILE#NAME); the others are files.
MEMBERS = {
    "flexible_0_4krod": "rod/flexible.json#k0_4",
    "flexible_20krod": "rod/flexible.json#k20",
    "flexible_40krod": "rod/flexible.json#k40",
    "flexible_4krod_nt600": "rod/flexible.json#nt600",
    "flexible_4krod_rho7800": "rod/flexible.json#rho7800",
    "rigid_nh30": "rod/rigid.json#nh30",
    "rigid_nh40": "rod/rigid.json#nh40",
    "rigid_nh20_fine": "rod/rigid.json#nh20_fine",
    "rigid_nh30_fine": "rod/rigid.json#nh30_fine",
    "rigid_nh40_fine": "rod/rigid.json#nh40_fine",
    "rigid_nh20_rho7800": "rod/rigid.json#rho7800",
    "penalty_40krod": "rod/penalty.json#k40",
    "linear_rod_rho7800": "rod/linear.json#rho7800",
    "nlvib_dlft_flexible_eps0_5": "contact/nlvib.json#dlft_eps0_5",
    "nlvib_dlft_flexible_h84": "contact/nlvib.json#dlft_h84",
    "nlvib_penalty": "contact/nlvib.json#penalty",
    "nlvib_penalty_h84": "contact/nlvib.json#penalty_h84",
}
RUNS = ([(name, "cases/" + MEMBERS.get(name, f"rod/{name}.json")) for name in ROD_RUNS] +
        [(name, "cases/" + MEMBERS.get(name, f"contact/{name}.json")) for name, _ in NLVIB])

EPS_SWEEP = [1e8, 2e8, 5e8, 1e9, 2e9, 5e9, 1e10, 2e10, 5e10, 1e11]
EPS_REFINE = [1e11 * 2 ** i for i in range(16)]  # the paper's refinement, eps_i = 2 eps_{i-1}
EPS_LAWS = [1e8, 1e9, 1e10, 1e11]  # contact-law diagrams (Fig. 20 analogue)
# (name, case, omega, epsilons)
REFINEMENTS = [
    ("refine_flexible_4krod", "cases/rod/flexible_4krod.json", OMEGA0_CASES, EPS_SWEEP),
    ("refine_flexible_4krod_nt600", "cases/rod/flexible.json#nt600", OMEGA0_CASES,
     EPS_SWEEP),
    ("refine_flexible_4krod_beyond", "cases/rod/flexible_4krod.json", OMEGA0_CASES,
     EPS_REFINE),
    # the default epsilon first: step 0 is the rigid solution compared in the signal figure
    ("refine_rigid_nh20", "cases/rod/rigid_nh20.json", OMEGA0_CASES, [K_ROD] + EPS_REFINE),
]

# Published values (../shared/cases.md, case 2; the paper's Sections 3.1 and 3.6).
PAPER_OMEGA0 = 63953.0
PAPER_JUMP = 6.6e4
PAPER_LINEAR_AMPLITUDE = 5.36e-4
NLVIB_PEAK = (0.752, 0.937)  # NLvib's example: omega, first-harmonic amplitude of DOF 2

KOBS_COLOURS = {0.4: "tab:blue", 4.0: "tab:orange", 20.0: "tab:green", 40.0: "tab:purple"}
NH_COLOURS = {20: "tab:blue", 30: "tab:orange", 40: "tab:green"}
EPS_COLOURS = {1e8: "tab:blue", 1e9: "tab:orange", 1e10: "tab:green", 1e11: "tab:red"}


# ----------------------------------------------------------------------------- runs

def eps_list(epsilons):
    return ",".join(f"{e:.6g}" for e in epsilons)


def run_command(nfrc, name, case, out):
    return [nfrc, "run", os.path.join(REPO, case), "--out", os.path.join(out, name)]


def refine_command(nfrc, name, case, omega, epsilons, out):
    return [nfrc, "refine", os.path.join(REPO, case), "--omega", f"{omega}",
            "--epsilons", eps_list(epsilons), "--out", os.path.join(out, name)]


def shown(command):
    """A command as typed from the repository root."""
    parts = [os.path.relpath(p, REPO) if os.path.isabs(p) else p for p in command]
    return " ".join(parts)


def run_one(nfrc, out, name, case, force):
    if not force and termination(load(out, name)) == "reached_lambda_bound":
        return "skipped (already reached_lambda_bound)", 0.0
    code, seconds = execute(run_command(nfrc, name, case, out), os.path.join(out, name))
    return f"exit {code} ({termination(load(out, name))})", seconds


def refine_one(nfrc, out, name, case, omega, epsilons, force):
    if not force and load(out, name, "refinement.json") is not None:
        return "skipped (refinement.json exists)", 0.0
    code, seconds = execute(refine_command(nfrc, name, case, omega, epsilons, out),
                            os.path.join(out, name))
    document = load(out, name, "refinement.json")
    done = len(document["steps"]) if document else 0
    return f"exit {code} ({done} of {len(epsilons)} steps)", seconds


def run_all(nfrc, out, force, jobs):
    """Runs RUNS and REFINEMENTS; returns (skipped, {name: seconds})."""
    skipped, seconds = 0, {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_one, nfrc, out, name, case, force): name
                   for name, case in RUNS}
        futures.update({pool.submit(refine_one, nfrc, out, name, case, omega, eps, force): name
                        for name, case, omega, eps in REFINEMENTS})
        for future in concurrent.futures.as_completed(futures):
            status, took = future.result()
            skipped += status.startswith("skipped")
            seconds[futures[future]] = took
            print(f"contact_study: {futures[future]:32s} {status}  {took:7.1f} s", flush=True)
    return skipped, seconds


def incomplete(out, nfrc):
    """[(name, termination, message, command)] of runs short of their range end."""
    found = []
    for name, case in RUNS:
        document = load(out, name)
        if termination(document) != "reached_lambda_bound":
            message = (document["summary"].get("message", "") if document else
                       f"no readable branch.json (see {os.path.join(out, name, 'nfrc.log')})")
            found.append((name, termination(document), message,
                          shown(run_command(nfrc, name, case, "out/contact"))))
    return found


def short_refinements(out, nfrc):
    """[(name, first failed epsilon, message, command)] of refinements that stopped early."""
    found = []
    for name, case, omega, epsilons in REFINEMENTS:
        document = load(out, name, "refinement.json")
        steps = document["steps"] if document else []
        failed = [s for s in steps if not s.get("converged")]
        if failed or len(steps) < len(epsilons):
            eps = failed[0]["epsilon"] if failed else (
                epsilons[len(steps)] if len(steps) < len(epsilons) else float("nan"))
            message = failed[0].get("message", "") if failed else "missing steps"
            found.append((name, eps, message,
                          shown(refine_command(nfrc, name, case, omega, epsilons,
                                               "out/contact"))))
    return found


# ----------------------------------------------------------------------------- helpers

def rod_omega0(rho, elements=ROD["elements"]):
    """First eigenfrequency of the clamped rod with consistent linear elements (rad/s)."""
    n = elements
    h = ROD["length"] / n
    me = rho * ROD["area"] * h / 6.0 * np.array([[2.0, 1.0], [1.0, 2.0]])
    ke = ROD["young"] * ROD["area"] / h * np.array([[1.0, -1.0], [-1.0, 1.0]])
    m = np.zeros((n + 1, n + 1))
    k = np.zeros((n + 1, n + 1))
    for e in range(n):
        m[e:e + 2, e:e + 2] += me
        k[e:e + 2, e:e + 2] += ke
    values = np.linalg.eigvals(np.linalg.solve(m[1:, 1:], k[1:, 1:])).real
    return math.sqrt(min(values))


def curve(document, key="max_abs", dof=0):
    points = document["points"]
    return (np.array([p["omega"] for p in points]), np.array([p[key][dof] for p in points]))


def fold_summary(document):
    """Rightmost fold (where the nonlinear branch turns back: the jump down on a sweep up),
    leftmost fold (where the overhanging branch rejoins the low-amplitude one) and the
    micro-folds in between."""
    folds = document.get("folds", []) if document else []
    if not folds:
        return None
    right = max(folds, key=lambda f: f["omega"])
    left = min(folds, key=lambda f: f["omega"])
    micro = [f for f in folds if f is not right and f is not left]
    return {"right": right, "left": left, "micro": micro, "all": folds}


def sci(value, digits=3):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "—"
    return f"{value:.{digits}e}".replace("e-0", "e-").replace("e+0", "e+").replace("e+", "e")


def read_csv(path):
    with open(path) as handle:
        rows = list(csv.reader(handle))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    return {name: data[:, i] for i, name in enumerate(header)}


def signals_of(out, name, index=0):
    """(entry, fine-grid columns, N_t-sample columns) of a run's signals entry."""
    document = load(out, name)
    if not document or len(document.get("signals", [])) <= index:
        return None
    entry = document["signals"][index]
    directory = os.path.join(out, name)
    return (entry, read_csv(os.path.join(directory, entry["file"])),
            read_csv(os.path.join(directory, entry["samples_file"])))


def refinement_step(out, name, epsilon):
    """(step, fine-grid columns, sample columns) of the refinement step at epsilon."""
    document = load(out, name, "refinement.json")
    if not document:
        return None
    for step in document["steps"]:
        if abs(step["epsilon"] / epsilon - 1.0) < 1e-9 and step.get("converged"):
            directory = os.path.join(out, name)
            return (step, read_csv(os.path.join(directory, step["signals_file"])),
                    read_csv(os.path.join(directory, step["samples_file"])))
    return None


def closed(values):
    """The periodic signal with its first sample appended (for line plots over a period)."""
    return np.append(values, values[0])


def contact_centre(samples):
    """Circular mean of the phase θ of the samples in contact (force before truncation > 0)."""
    theta = samples["theta"][samples["law0_force_raw"] > 0.0]
    if len(theta) == 0:
        return math.pi
    return math.atan2(np.sin(theta).mean(), np.cos(theta).mean()) % (2.0 * math.pi)


def centred(columns, theta_c, omega):
    """The signal over one closed period with the time origin moved so that phase theta_c sits
    at T/2: {"t": µs, column: values}, sorted in time, first sample repeated at the end."""
    theta = (columns["theta"] - theta_c + math.pi) % (2.0 * math.pi)
    order = np.argsort(theta)
    result = {"t": np.append(theta[order], theta[order][0] + 2.0 * math.pi) / omega * 1e6}
    for key, values in columns.items():
        if key not in ("theta", "t"):
            result[key] = np.append(values[order], values[order][0])
    return result


def unilateral_law(axes, lam_max, g_max):
    axes.plot([0.0, 0.0], [0.0, lam_max], color="0.35", lw=2.2, alpha=0.45, zorder=0,
              label="unilateral contact")
    axes.plot([0.0, g_max], [0.0, 0.0], color="0.35", lw=2.2, alpha=0.45, zorder=0)


def mark_folds(axes, document, colour, label_right=True, size=3.5):
    summary = fold_summary(document)
    if not summary:
        return
    for fold in summary["all"]:
        axes.plot(fold["omega"], fold["max_abs"][0], "o", ms=size, mfc="none", mec=colour,
                  mew=0.9, zorder=4)
    right = summary["right"]
    axes.plot(right["omega"], right["max_abs"][0], "o", ms=size + 2.5, mfc=colour, mec="black",
              mew=0.8, zorder=5)
    if label_right:
        axes.annotate(f"{right['omega']:.0f}", (right["omega"], right["max_abs"][0]),
                      textcoords="offset points", xytext=(5, 4), fontsize=7.5)


def omega_axis(axes):
    axes.ticklabel_format(axis="x", style="sci", scilimits=(4, 4), useMathText=True)
    axes.ticklabel_format(axis="y", style="sci", scilimits=(-4, -4), useMathText=True)


# ----------------------------------------------------------------------------- figures

def figure17(out, figures):
    linear = load(out, "linear_rod")
    figure, grid = plt.subplots(2, 2, figsize=(10.5, 7.6), sharex=True)
    for axes, (mult, name) in zip(grid.flat, FLEXIBLE):
        if linear:
            w, a = curve(linear)
            axes.plot(w, a, ":", color="black", lw=1.2, label="linear")
        axes.axhline(ROD["gap"], color="0.4", ls="-.", lw=1.0, label="$g_0$")
        document = load(out, name)
        if document:
            w, a = curve(document)
            label = "DLFT-HBM"
            if termination(document) != "reached_lambda_bound":
                label += f" (incomplete, stopped at ω = {w[-1]:.0f})"
            axes.plot(w, a, "-", color=KOBS_COLOURS[mult], lw=1.2, label=label)
            mark_folds(axes, document, KOBS_COLOURS[mult])
        penalty = load(out, PENALTY[mult]) if mult in PENALTY else None
        if penalty:
            w, a = curve(penalty)
            axes.plot(w, a, "--", color="black", lw=0.8,
                      label="penalty_contact (AFT), k = $k_{obs}$")
        axes.plot([], [], "o", ms=4, mfc="none", mec="0.3", label="folds (filled: rightmost)")
        axes.set_title(f"$k_{{obs}}$ = {mult:g} $k_{{rod}}$ ({mult * K_ROD:.3g} N/m)",
                       fontsize=10)
        axes.set_xlim(5e4, 8e4)
        axes.set_ylim(0.0, 6e-4)
        axes.grid(True, alpha=0.25)
        omega_axis(axes)
        axes.legend(fontsize=7, loc="upper left")
    for axes in grid[1]:
        axes.set_xlabel("ω [rad/s]")
    for axes in grid[:, 0]:
        axes.set_ylabel("max$_t$ |$x_{end}$| [m]")
    figure.suptitle("FE rod against a flexible obstacle, $N_h$ = 20, $N_t$ = 400, ρ = 7500 "
                    "(cf. Vadcard et al. 2022, Fig. 17)", fontsize=10.5)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig17_flexible_nfrc.png"), "contact")


def figure18(out, figures):
    linear = load(out, "linear_rod")
    flexible = load(out, "flexible_40krod")
    figure, (full, zoom) = plt.subplots(1, 2, figsize=(12.0, 4.9),
                                        gridspec_kw={"width_ratios": [1.0, 1.15]})
    for axes in (full, zoom):
        if linear:
            w, a = curve(linear)
            axes.plot(w, a, ":", color="black", lw=1.2, label="linear")
        axes.axhline(ROD["gap"], color="0.4", ls="-.", lw=1.0, label="$g_0$")
        if flexible:
            w, a = curve(flexible)
            axes.plot(w, a, "--", color="tab:purple", lw=1.1,
                      label="flexible, $k_{obs}$ = 40 $k_{rod}$, $N_h$ = 20")
        for nh, name in RIGID:
            document = load(out, name)
            if not document:
                continue
            w, a = curve(document)
            axes.plot(w, a, "-", color=NH_COLOURS[nh], lw=1.1, label=f"rigid, $N_h$ = {nh}")
            if axes is zoom:
                mark_folds(axes, document, NH_COLOURS[nh], label_right=False)
        axes.grid(True, alpha=0.25)
        omega_axis(axes)
        axes.set_xlabel("ω [rad/s]")
    for nh, name in RIGID_FINE:
        summary = fold_summary(load(out, name))
        if summary:
            right = summary["right"]
            zoom.plot(right["omega"], right["max_abs"][0], "*", ms=11, color=NH_COLOURS[nh],
                      mec="black", mew=0.6, zorder=6)
    zoom.plot([], [], "*", ms=9, color="0.6", mec="black", mew=0.6,
              label="rightmost fold with max_step 0.003")
    zoom.plot([], [], "o", ms=6, color="0.6", mec="black", mew=0.6,
              label="rightmost fold (default steps)")
    zoom.axvline(PAPER_JUMP, color="tab:red", lw=0.9, ls=(0, (4, 2)),
                 label="paper: jump ≈ 6.6·10$^4$ (TI)")
    full.set_xlim(5e4, 8e4)
    full.set_ylim(0.0, 6e-4)
    full.set_ylabel("max$_t$ |$x_{end}$| [m]")
    full.legend(fontsize=7, loc="upper left")
    full.set_title("whole range", fontsize=9.5)
    zoom.set_xlim(6.45e4, 6.63e4)
    zoom.set_ylim(1.8e-4, 2.25e-4)
    zoom.legend(fontsize=6.5, loc="lower right", ncol=2)
    zoom.set_title("zoom near the jump (folds: circles)", fontsize=9.5)
    figure.suptitle("FE rod against a rigid obstacle, $N_h$ = 20/30/40, $N_t$ = 400, ρ = 7500 "
                    "(cf. Vadcard et al. 2022, Fig. 18)", fontsize=10.5)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig18_rigid_nfrc.png"), "contact")


def figure_signals(out, figures):
    """Figs. 11-14 analogue: k_obs = 4 k_rod at omega0."""
    flexible = signals_of(out, "flexible_4krod")
    if flexible is None:
        return None, None
    entry, fine_raw, samples_raw = flexible
    omega = entry["omega"]
    theta_c = contact_centre(samples_raw)
    fine, samples = centred(fine_raw, theta_c, omega), centred(samples_raw, theta_c, omega)
    rigid = refinement_step(out, "refine_rigid_nh20", K_ROD)
    g0 = ROD["gap"]
    period = 2.0 * math.pi / omega * 1e6
    figure, grid = plt.subplots(2, 3, figsize=(13.5, 7.6))
    (ax_x, ax_xz, ax_g), (ax_f, ax_law, ax_lawz) = grid
    obstacle = g0 + fine["law0_obstacle"]
    for axes in (ax_x, ax_xz):
        axes.plot(fine["t"], fine["x_end"] * 1e3, "-", color="tab:orange", lw=1.4,
                  label="$x_{end}$, flexible $k_{obs}$ = 4 $k_{rod}$")
        axes.plot(fine["t"], obstacle * 1e3, "-", color="0.35", lw=0.9,
                  label="obstacle surface $g_0 + x_{obs}$")
        if rigid:
            rfine = centred(rigid[1], theta_c, omega)
            axes.plot(rfine["t"], rfine["x_end"] * 1e3, "--", color="tab:blue", lw=1.0,
                      label="$x_{end}$, rigid obstacle ($N_h$ = 20)")
        axes.axhline(g0 * 1e3, color="black", ls="-.", lw=0.8, label="$g_0$")
        axes.set_xlabel("t [µs] (contact phase centred at T/2)")
        axes.grid(True, alpha=0.25)
    ax_x.set_xlim(0.0, period)
    ax_x.set_ylabel("displacement [mm]")
    ax_x.legend(fontsize=7, loc="lower left")
    ax_x.set_title("(a) displacement of the contact node", fontsize=9.5)
    in_contact = samples["t"][samples["law0_force_raw"] > 0.0]
    lo, hi = (in_contact.min(), in_contact.max()) if len(in_contact) else (0.0, period)
    window = (lo - 0.5 * (hi - lo) - 1.0, hi + 0.5 * (hi - lo) + 1.0)
    ax_xz.set_xlim(*window)
    ax_xz.set_ylim((g0 - 0.12e-4) * 1e3, (g0 + 0.2e-4) * 1e3)
    ax_xz.set_title("(b) around the contact phase", fontsize=9.5)
    ax_g.plot(fine["t"], fine["law0_gap"] * 1e6, "-", color="tab:orange", lw=1.0,
              label="fine grid")
    ax_g.plot(samples["t"], samples["law0_gap"] * 1e6, ".", color="tab:red", ms=3,
              label=f"the $N_t$ = {len(samples_raw['t'])} samples")
    ax_g.axhline(0.0, color="black", lw=0.7)
    ax_g.set_xlim(*window)
    ax_g.set_ylim(-2.0, 10.0)
    ax_g.set_xlabel("t [µs]")
    ax_g.set_ylabel("gap g [µm]")
    ax_g.set_title(f"(c) gap (min on the samples {entry['laws'][0]['min_gap'] * 1e6:.3f} µm)",
                   fontsize=9.5)
    ax_g.legend(fontsize=7)
    ax_g.grid(True, alpha=0.25)
    ax_f.plot(fine["t"], fine["law0_force"] / 1e3, "-", color="tab:orange", lw=1.6,
              label="after truncation ($N_h$ = 20, fine grid)")
    ax_f.plot(samples["t"], samples["law0_force_raw"] / 1e3, ".-", color="tab:red", lw=0.6,
              ms=2.5, label="before truncation ($N_t$ samples)")
    ax_f.axhline(0.0, color="black", lw=0.7)
    ax_f.set_xlim(0.0, period)
    ax_f.set_xlabel("t [µs]")
    ax_f.set_ylabel("contact force λ [kN]")
    ax_f.set_title("(d) contact force", fontsize=9.5)
    ax_f.legend(fontsize=7, loc="upper right")
    ax_f.grid(True, alpha=0.25)
    inset = ax_f.inset_axes([0.08, 0.42, 0.36, 0.36])
    inset.plot(fine["t"], fine["law0_force"] / 1e3, "-", color="tab:orange", lw=1.2)
    inset.plot(samples["t"], samples["law0_force_raw"] / 1e3, ".-", color="tab:red", lw=0.5,
               ms=2)
    inset.axhline(0.0, color="black", lw=0.6)
    inset.set_ylim(-5.0, 5.0)
    inset.tick_params(labelsize=6)
    inset.set_title("truncation oscillations", fontsize=7)
    lam_max = max(samples["law0_force_raw"].max(), fine["law0_force"].max()) / 1e3
    for axes in (ax_law, ax_lawz):
        unilateral_law(axes, lam_max * 1.05, fine["law0_gap"].max() * 1e6)
        axes.plot(fine["law0_gap"] * 1e6, fine["law0_force"] / 1e3, "-", color="tab:orange",
                  lw=1.4, label="after truncation")
        axes.plot(samples["law0_gap"] * 1e6, samples["law0_force_raw"] / 1e3, ".-",
                  color="tab:red", lw=0.6, ms=2.5, label="before truncation")
        axes.axhline(0.0, color="black", lw=0.5)
        axes.axvline(0.0, color="black", lw=0.5)
        axes.set_xlabel("gap g [µm]")
        axes.grid(True, alpha=0.25)
    ax_law.set_ylabel("contact force λ [kN]")
    ax_law.set_title("(e) contact law, whole period", fontsize=9.5)
    ax_law.legend(fontsize=7)
    ax_lawz.set_xlim(-2.0, 6.0)
    ax_lawz.set_title("(f) contact law around g = 0", fontsize=9.5)
    figure.suptitle(f"k$_{{obs}}$ = 4 k$_{{rod}}$ at ω = {omega} rad/s ≈ ω$_0$, "
                    f"$N_h$ = 20, $N_t$ = 400, default ε = {entry['laws'][0]['epsilon']:.4g} N/m "
                    "(cf. Vadcard et al. 2022, Figs. 11-14)", fontsize=10.5)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig11_14_signals_4krod.png"), "contact"), entry


def figure_epsilon_curves(out, figures):
    series = [("refine_flexible_4krod", "flexible 4 $k_{rod}$, $N_t$ = 400", "o-", "tab:orange"),
              ("refine_flexible_4krod_nt600", "flexible 4 $k_{rod}$, $N_t$ = 600", "s--",
               "tab:brown"),
              ("refine_flexible_4krod_beyond", "flexible 4 $k_{rod}$, $N_t$ = 400, refinement",
               "^:", "tab:orange"),
              ("refine_rigid_nh20", "rigid, $N_t$ = 400, refinement", "v:", "tab:blue")]
    figure, (ax_p, ax_f) = plt.subplots(1, 2, figsize=(11.5, 4.5))
    for name, label, style, colour in series:
        document = load(out, name, "refinement.json")
        if not document:
            continue
        steps = [s for s in document["steps"] if s.get("converged")]
        eps = np.array([s["epsilon"] for s in steps])
        pen = np.array([s["laws"][0]["max_penetration"] for s in steps])
        force = np.array([-s["laws"][0]["min_force"] for s in steps])
        kw = dict(color=colour, ms=7 if "600" in label else 4, lw=1.0, label=label,
                  mfc="none" if ("refinement" in label or "600" in label) else colour)
        ax_p.loglog(eps, pen, style, **kw)
        ax_f.loglog(eps, force, style, **kw)
    for axes in (ax_p, ax_f):
        axes.axvspan(1e8, 1e11, color="0.9", zorder=0)
        axes.set_xlabel("ε [N/m]")
        axes.grid(True, which="both", alpha=0.25)
    for axes in (ax_p, ax_f):
        axes.axvline(4 * K_ROD, color="0.4", lw=0.8, ls="--")
    ax_f.annotate("default ε of the flexible case", (4 * K_ROD, 1.0), xycoords=("data",
                  "axes fraction"), textcoords="offset points", xytext=(3, -8), fontsize=7,
                  rotation=90, va="top")
    ax_p.set_ylabel("residual penetration max(0, −min g) [m]")
    ax_p.set_title("(a) penetration on the $N_t$ samples", fontsize=9.5)
    ax_f.set_ylabel("−min λ after truncation [N]")
    ax_f.set_title("(b) most negative truncated contact force", fontsize=9.5)
    ax_p.legend(fontsize=7, loc="upper right")
    figure.suptitle("ε at ω$_0$ (grey band: the paper's range 10$^8$–10$^{11}$; beyond: "
                    "the refinement ε$_i$ = 2ε$_{i-1}$ from 10$^{11}$, warm-started)",
                    fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig20_epsilon_penetration.png"), "contact")


def figure_epsilon_laws(out, figures):
    steps = [(eps, refinement_step(out, "refine_flexible_4krod", eps)) for eps in EPS_LAWS]
    steps = [(eps, s) for eps, s in steps if s is not None]
    if not steps:
        return None
    document = load(out, "refine_flexible_4krod", "refinement.json")
    omega = document["omega"]
    theta_c = contact_centre(steps[0][1][2])
    figure, grid = plt.subplots(2, 3, figsize=(13.5, 7.6))
    (ax_raw_t, ax_tr_t, ax_g_t), (ax_raw, ax_tr, ax_trz) = grid
    lam_max = 0.0
    contact_t = []
    for eps, (step, fine_raw, samples_raw) in steps:
        fine, samples = centred(fine_raw, theta_c, omega), centred(samples_raw, theta_c, omega)
        colour = EPS_COLOURS.get(eps, "gray")
        label = f"ε = {eps:.0e} N/m".replace("e+", "e")
        ax_raw_t.plot(samples["t"], samples["law0_force_raw"] / 1e3, ".-", color=colour,
                      lw=0.8, ms=2.5, label=label)
        ax_tr_t.plot(fine["t"], fine["law0_force"] / 1e3, "-", color=colour, lw=1.0,
                     label=label)
        ax_g_t.plot(samples["t"], samples["law0_gap"] * 1e6, ".-", color=colour, lw=0.8,
                    ms=2.5, label=label)
        for axes in (ax_tr, ax_trz):
            axes.plot(fine["law0_gap"] * 1e6, fine["law0_force"] / 1e3, "-", color=colour,
                      lw=1.0, label=label)
        ax_raw.plot(samples["law0_gap"] * 1e6, samples["law0_force_raw"] / 1e3, ".-",
                    color=colour, lw=0.7, ms=2.5, label=label)
        lam_max = max(lam_max, samples["law0_force_raw"].max() / 1e3)
        contact_t.extend(samples["t"][samples["law0_force_raw"] > 0.0])
    lo, hi = (min(contact_t), max(contact_t)) if contact_t else (0.0, 100.0)
    pad = 0.5 * (hi - lo) + 1.0
    for axes in (ax_raw_t, ax_tr_t, ax_g_t):
        axes.set_xlim(lo - pad, hi + pad)
        axes.axhline(0.0, color="black", lw=0.6)
        axes.set_xlabel("t [µs] (contact phase centred at T/2)")
        axes.grid(True, alpha=0.25)
    ax_raw_t.set_ylabel("λ [kN]")
    ax_raw_t.set_title("(a) contact force before truncation", fontsize=9.5)
    ax_tr_t.set_title("(b) contact force after truncation", fontsize=9.5)
    ax_g_t.set_ylabel("gap g [µm]")
    ax_g_t.set_ylim(-2.0, 8.0)
    ax_g_t.set_title("(c) gap on the samples", fontsize=9.5)
    ax_raw_t.legend(fontsize=7)
    for axes in (ax_raw, ax_tr, ax_trz):
        unilateral_law(axes, lam_max * 1.05, 200.0)
        axes.axhline(0.0, color="black", lw=0.5)
        axes.axvline(0.0, color="black", lw=0.5)
        axes.set_xlabel("gap g [µm]")
        axes.grid(True, alpha=0.25)
    ax_raw.set_ylabel("λ [kN]")
    ax_raw.set_xlim(-2.0, 6.0)
    ax_raw.set_title("(d) contact law before truncation (around g = 0)", fontsize=9.5)
    ax_tr.set_title("(e) contact law after truncation, whole period", fontsize=9.5)
    ax_trz.set_xlim(-2.0, 6.0)
    ax_trz.set_title("(f) contact law after truncation, around g = 0", fontsize=9.5)
    ax_tr.legend(fontsize=7)
    figure.suptitle(f"ε study at ω = {omega} rad/s ≈ ω$_0$, $k_{{obs}}$ = 4 $k_{{rod}}$, "
                    "$N_h$ = 20, $N_t$ = 400 (cf. Vadcard et al. 2022, Figs. 19-20)",
                    fontsize=10.5)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig19_20_epsilon_laws.png"), "contact")


def nlvib_peak(document):
    w, h = curve(document, "h1", 1)
    i = int(np.argmax(h))
    return w[i], h[i]


def figure_nlvib(out, figures):
    styles = {"nlvib_penalty": ("-", "black", 1.6), "nlvib_dlft_flexible": ("-", "tab:red", 1.2),
              "nlvib_dlft_flexible_eps0_5": ("--", "tab:orange", 1.1),
              "nlvib_penalty_h84": (":", "tab:blue", 1.6),
              "nlvib_dlft_flexible_h84": ("-.", "tab:green", 1.1)}
    figure, (axes, zoom) = plt.subplots(1, 2, figsize=(12.5, 4.9),
                                        gridspec_kw={"width_ratios": [1.2, 1.0]})
    drawn = False
    for name, label in NLVIB:
        document = load(out, name)
        if not document:
            continue
        drawn = True
        w, h = curve(document, "h1", 1)
        style, colour, lw = styles[name]
        if termination(document) != "reached_lambda_bound":
            label += f" (incomplete, stopped at ω = {w[-1]:.3f})"
        for target in (axes, zoom):
            target.plot(w, h, style, color=colour, lw=lw, label=label)
        pw, ph = nlvib_peak(document)
        zoom.plot(pw, ph, "o", ms=5, color=colour, mec="black", mew=0.5, zorder=5)
    if not drawn:
        plt.close(figure)
        return None
    for target in (axes, zoom):
        target.plot(*NLVIB_PEAK, "*", ms=12, color="gold", mec="black", mew=0.7, zorder=6,
                    label="NLvib's HB peak (0.937 at ω ≈ 0.752)")
        target.grid(True, alpha=0.25)
        target.set_xlabel("excitation frequency ω")
    zoom.set_xlim(0.735, 0.7575)
    zoom.set_ylim(0.90, 0.965)
    zoom.set_title("zoom on the peak (dots: largest h1 of each run)", fontsize=9.5)
    axes.indicate_inset_zoom(zoom, edgecolor="0.4")
    axes.set_xlim(0.5, 0.8)
    axes.set_ylim(0.0, 1.05)
    axes.set_ylabel("first-harmonic amplitude of $x_2$")
    axes.set_title("whole range, traced from ω = 0.8 down to 0.5", fontsize=9.5)
    axes.legend(fontsize=7, loc="upper left")
    figure.suptitle("NLvib's 2-DOF oscillator with a unilateral spring (k = 100, gap 1 on "
                    "DOF 1): penalty vs DLFT with a flexible obstacle", fontsize=10.5)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "nlvib_unilateral_frc.png"), "contact")


# ----------------------------------------------------------------------------- main

def main():
    args = parse_arguments("contact", __doc__.splitlines()[0])
    started = time.monotonic()
    load_average = os.getloadavg()
    out = os.path.abspath(args.out)
    nfrc = os.path.abspath(args.nfrc)
    os.makedirs(out, exist_ok=True)
    os.makedirs(args.figures, exist_ok=True)
    skipped, _ = run_all(nfrc, out, args.force, args.jobs)
    runs_seconds = time.monotonic() - started
    failed = incomplete(out, nfrc)
    short = short_refinements(out, nfrc)
    for name, how, message, command in failed:
        print(f"contact_study: ERROR: {name} did not reach the end of its range: {how}: "
              f"{message}\n  reproduce: {command}", file=sys.stderr, flush=True)
    for name, eps, message, command in short:
        print(f"contact_study: note: refinement {name} stopped at epsilon = {eps:.4g}: "
              f"{message}\n  reproduce: {command}", file=sys.stderr, flush=True)

    md = []
    figure_dir = os.path.relpath(args.figures, REPO)

    def figure_ref(path, alt):
        return f"![{alt}]({os.path.join(figure_dir, os.path.basename(path))})"

    omega0 = rod_omega0(RHO)
    omega0_table = rod_omega0(RHO_TABLE)
    scale = math.sqrt(RHO / RHO_TABLE)
    md.append("<!-- generated by tools/studies/contact_study.py; figure paths are relative to "
              "the repository root -->")
    md.append("## Contact study (Vadcard, Batailly & Thouverez 2022, Sections 3–4)\n")
    md.append("FE rod (20 consistent linear elements, L = 0.13 m, A = 15.6 cm², E = 210 GPa, "
              "modal damping 0.75 %, 25 kN cos ωt at the free end, which is also the contact "
              f"node, g0 = 0.2 mm; k_rod = EA/L = {K_ROD:.4g} N/m) against a massless flexible "
              "obstacle k_obs ∈ {0.4, 4, 20, 40}·k_rod or a rigid obstacle, by DLFT "
              "(`dlft_contact`), N_h = 20 (rigid also 30, 40), N_t = 400, ω from 5·10⁴ to "
              "8·10⁴ rad/s (`cases/rod/`, `../shared/cases.md` case 2); and NLvib's two-DOF "
              "unilateral-spring example (`cases/contact/`).\n")
    md.append(f"**Density.** Every rod figure and table uses **ρ = 7500 kg/m³**, which gives "
              f"ω0 = {omega0:.1f} rad/s (paper: 63 953 rad/s). The paper's Table 1 says "
              f"ρ = 7800, which gives ω0 = {omega0_table:.1f} rad/s; with the same stiffness "
              f"every frequency scales by √(7500/7800) = {scale:.5f} (the `_rho7800` runs "
              "below check it).\n")
    md.append("**Reproduce** (from the repository root, after the README's build): "
              "`/usr/bin/python3 tools/studies/contact_study.py --nfrc build/nfrc` — "
              f"{len(RUNS)} `nfrc run` and {len(REFINEMENTS)} `nfrc refine` calls, figures and "
              "tables; " +
              ("measured wall time from scratch: @TOTAL_SECONDS@ s (Release build, this "
               "project's 2-core machine).\n" if not skipped else
               f"this page took @TOTAL_SECONDS@ s with {skipped} runs skipped as already "
               "finished (`--force` reruns them all).\n"))
    md.append("Every case file runs as it is, with the default continuation options, except "
              "`rigid_nh{20,30,40}_fine.json`, which set `step` = `max_step` = 0.003 (default "
              "0.01/0.05) only to check how well the default steps resolve the turning point "
              "(see the jump table). The refinements are:\n")
    md.extend(f"- `{shown(refine_command('build/nfrc', name, case, omega, eps, 'out/contact'))}`"
              for name, case, omega, eps in REFINEMENTS)
    md.append("")
    if failed:
        md.append("**Incomplete runs.** These case files did not reach the end of their ω "
                  "range; figures and tables use them as far as they got:\n")
        md.extend(f"- `{name}`: **{how}** — “{message}” (`{command}`)."
                  for name, how, message, command in failed)
        md.append("")

    # linear check
    linear = load(out, "linear_rod")
    if linear:
        w, a = curve(linear)
        amplitude = value_at(w, a, omega0)
        md.append(f"Linear check (`linear_rod`): max|x_end| at ω0 = {sci(amplitude)} m "
                  f"(paper: 5.36e-4 m).\n")

    # a. Fig. 17
    path = figure17(out, args.figures)
    md.append("### Flexible obstacle, k_obs = 0.4 … 40 k_rod (Fig. 17)\n")
    md.append(figure_ref(path, "Fig. 17 analogue"))
    md.append("\n*max|x_end| vs ω, N_h = 20, N_t = 400, default ε (= k_obs for a flexible "
              "obstacle); linear curve dotted, g0 dash-dot; "
              "every fold an open circle, the rightmost one (where the nonlinear branch turns "
              "back) filled and labelled. Thin dashed (4 and 40 k_rod): the same obstacle as a "
              "rigid wall with the bilinear penalty law k·max(0, −g) by AFT (`penalty_Nkrod`), "
              "physically the same model (paper, Sec. 3.4).*\n")

    # b. Fig. 18
    path = figure18(out, args.figures)
    md.append("### Rigid obstacle, N_h = 20/30/40 (Fig. 18)\n")
    md.append(figure_ref(path, "Fig. 18 analogue"))
    md.append("\n*Rigid obstacle N_h = 20/30/40 (solid), flexible k_obs = 40 k_rod (dashed), "
              "linear (dotted), g0 (dash-dot). Right: zoom on the end of the nonlinear branch; "
              "circles are folds of the default runs, stars the rightmost fold found with "
              "max_step 0.003. max|x_end| exceeds g0 on the contact branch because the "
              "excursion away from the obstacle after the rebound is larger than g0; the maximum "
              "towards the obstacle stays at g0 plus the residual penetration and the "
              "truncation ripple between samples (`max` in branch.json).*\n")

    # c. folds tables
    fold_rows = []
    all_fold_lines = []
    for name, _ in RUNS:
        document = load(out, name)
        summary = fold_summary(document)
        if document is None:
            fold_rows.append([f"`{name}`", "missing", "", "", "", ""])
            continue
        if summary is None:
            fold_rows.append([f"`{name}`", termination(document), "0", "—", "—", "—"])
            continue
        right, left, micro = summary["right"], summary["left"], summary["micro"]
        span = (f"{len(micro)} in [{min(f['omega'] for f in micro):.6g}, "
                f"{max(f['omega'] for f in micro):.6g}]" if micro else "0")
        unconverged = sum(1 for f in summary["all"] if not f.get("converged", True))
        fold_rows.append([f"`{name}`", termination(document), len(summary["all"]),
                          f"**{right['omega']:.6g}** (max\\|x\\| {fmt(right['max_abs'][0])})",
                          f"{left['omega']:.6g}", span +
                          (f"; {unconverged} not converged" if unconverged else "")])
        all_fold_lines.append(f"- `{name}`: " + ", ".join(
            f"{f['omega']:.6g}" + ("*" if not f.get("converged", True) else "")
            for f in summary["all"]))
    md.append("#### Folds of every curve\n")
    md.append(table(["run", "termination", "folds", "rightmost fold ω (jump on a sweep up)",
                     "leftmost fold ω", "folds in between (micro-folds)"], fold_rows))
    md.append("\nRightmost fold: where the nonlinear (contact) branch turns back — the jump "
              "down to the low-amplitude branch on an upward sweep. Leftmost fold: where the "
              "overhanging (unstable) branch rejoins the low-amplitude branch, at the frequency "
              "where the linear response falls below g0 — the jump up on a downward sweep. "
              "The micro-folds between them are a zig-zag of the discrete branch along the "
              "steep end of the nonlinear branch: each of the N_t samples that enters or leaves "
              "contact puts a kink in the branch (DLFT and penalty/AFT alike), and where the "
              "branch is nearly vertical in ω a "
              "kink turns it back over a few rad/s (their number changes with the step size and "
              "with N_t; physically they are one turning point). For the NLvib runs ω is "
              "dimensionless.\n")
    md.append("<details><summary>All fold frequencies, in branch order (* = not converged to "
              "the fold tolerance)</summary>\n")
    md.extend(all_fold_lines)
    md.append("\n</details>\n")

    # d. rigid jump table
    jump_rows = []
    for (nh, name), (_, fine_name) in zip(RIGID, RIGID_FINE):
        coarse, fine = fold_summary(load(out, name)), fold_summary(load(out, fine_name))
        wc = coarse["right"]["omega"] if coarse else float("nan")
        wf = fine["right"]["omega"] if fine else float("nan")
        jump_rows.append([nh, f"{wc:.0f}", f"{wf:.0f}", f"{PAPER_JUMP:.3g}",
                          f"{100 * (wc / PAPER_JUMP - 1):+.2f} %",
                          f"{100 * (wf / PAPER_JUMP - 1):+.2f} %",
                          f"{(coarse['left']['omega'] if coarse else float('nan')):.0f}"])
    md.append("#### Rigid-obstacle jump frequency\n")
    md.append(table(["N_h", "rightmost fold, default steps [rad/s]",
                     "rightmost fold, max_step 0.003 [rad/s]", "paper (TI jump)",
                     "difference (default)", "difference (fine)", "leftmost fold [rad/s]"],
                    jump_rows))
    md.append("\nThe paper gives no fold frequencies for its HBM curves, only the time "
              "integration's jump “around ω = 6.6·10⁴ rad/s” (a chirp, which depends on the "
              "sweep rate); ours is the rightmost turning point of the periodic branch. With "
              "the default steps the continuation crosses the last few micro-folds of the "
              "steep branch end with steps longer than them, so the rightmost fold it reports "
              "can sit a few tens of rad/s (≲ 0.1 %) short of the one found with smaller "
              "steps.\n")
    fine_jumps = {nh: fold_summary(load(out, name)) for nh, name in RIGID_FINE}
    if all(fine_jumps.values()):
        w20, w30, w40 = (fine_jumps[nh]["right"]["omega"] for nh in (20, 30, 40))
        md.append(f"Convergence in N_h (fine steps): the jump moves by "
                  f"{100 * (w30 / w20 - 1):+.2f} % from N_h = 20 to 30 and by "
                  f"{100 * (w40 / w30 - 1):+.3f} % from 30 to 40; the curves away from the "
                  "branch end are indistinguishable (Fig. 18), in line with the paper's "
                  "“N_h ≈ 20 converges the NFRC”.\n")

    # d2. DLFT flexible obstacle vs its penalty twin
    twin_rows = []
    for mult, penalty_name in PENALTY.items():
        flexible_name = dict((m, n) for m, n in FLEXIBLE)[mult]
        a, b = fold_summary(load(out, flexible_name)), fold_summary(load(out, penalty_name))
        if not (a and b):
            continue
        amax = max(p["max_abs"][0] for p in load(out, flexible_name)["points"])
        bmax = max(p["max_abs"][0] for p in load(out, penalty_name)["points"])
        twin_rows.append([f"{mult:g} k_rod", f"{a['right']['omega']:.0f}",
                          f"{b['right']['omega']:.0f}",
                          f"{100 * (b['right']['omega'] / a['right']['omega'] - 1):+.2f} %",
                          sci(amax), sci(bmax), len(a["all"]), len(b["all"])])
    if twin_rows:
        md.append("#### Flexible obstacle (DLFT) vs rigid wall with a penalty law (AFT)\n")
        md.append(table(["k_obs = k_penalty", "rightmost fold, DLFT [rad/s]",
                         "rightmost fold, penalty [rad/s]", "penalty vs DLFT",
                         "largest max\\|x_end\\|, DLFT [m]",
                         "largest max\\|x_end\\|, penalty [m]", "folds DLFT", "folds penalty"],
                        twin_rows))
        md.append("\nThe paper (Sec. 3.4) notes that the two models are the same dynamics; "
                  "the formulations differ only in how the truncated, sampled problem enforces "
                  "it (DLFT: the obstacle in relative coordinates and the ε-weighted prediction; "
                  "penalty: AFT of the kinked force k·max(0, −g)). The stiffer the obstacle, the "
                  "more the two differ at N_h = 20, N_t = 400; which one is closer to the "
                  "converged answer is not established here.\n")

    # e. rho = 7800
    rows_7800 = []
    for name_7500, name_7800, what in (("rigid_nh20", "rigid_nh20_rho7800", "rigid, N_h = 20"),
                                       ("flexible_4krod", "flexible_4krod_rho7800",
                                        "flexible 4 k_rod")):
        a, b = fold_summary(load(out, name_7500)), fold_summary(load(out, name_7800))
        if not (a and b):
            continue
        for key, label in (("right", "rightmost fold"), ("left", "leftmost fold")):
            wa, wb = a[key]["omega"], b[key]["omega"]
            rows_7800.append([what, label, f"{wa:.1f}", f"{wb:.1f}", f"{wa * scale:.1f}",
                              f"{100 * (wb / (wa * scale) - 1):+.3f} %"])
    md.append("#### ρ = 7800 (the paper's Table 1)\n")
    md.append(f"ω0 = {omega0_table:.1f} rad/s at ρ = 7800 against {omega0:.1f} at ρ = 7500 "
              f"(ratio {omega0_table / omega0:.5f} = √(7500/7800)); the linear run "
              "`linear_rod_rho7800` and the two nonlinear ones scale the same way. The "
              "harmonic-balance equations at ρ = 7800 and ω are exactly those at ρ = 7500 and "
              "ω/√(7500/7800) (ε is a stiffness, independent of ρ), so any difference below is "
              "the continuation resolving the steep end of the branch differently.\n")
    md.append(table(["curve", "fold", "ρ = 7500 [rad/s]", "ρ = 7800 [rad/s]",
                     "ρ = 7500 value × √(7500/7800)", "ρ = 7800 vs scaled"], rows_7800))
    md.append("")

    # f. signals at omega0
    path, entry = figure_signals(out, args.figures)
    if path:
        law = entry["laws"][0]
        md.append("### Signals at ω0, k_obs = 4 k_rod (Figs. 11–14)\n")
        md.append(figure_ref(path, "Figs. 11-14 analogue"))
        rigid = refinement_step(out, "refine_rigid_nh20", K_ROD)
        md.append(f"\n*`flexible_4krod` at ω = {entry['omega']} (its `signals_at`), "
                  f"default ε = {law['epsilon']:.4g} N/m: max|x_end| = "
                  f"{sci(entry['max_abs'][0])} m, h1 = {sci(entry['h1'][0])} m; contact on "
                  f"{100 * law['contact_fraction']:.1f} % of the N_t samples; residual "
                  f"penetration {sci(law['max_penetration'])} m "
                  f"({100 * law['max_penetration'] / ROD['gap']:.2f} % of g0); largest force "
                  f"before truncation {law['max_force'] / 1e3:.1f} kN; most negative truncated "
                  f"force {law['min_force'] / 1e3:.2f} kN." +
                  (f" Dashed: the rigid obstacle at the same ω (`nfrc refine` step at ε = "
                   f"k_rod), max|x_end| = {sci(rigid[0]['max_abs'][0])} m, penetration "
                   f"{sci(rigid[0]['laws'][0]['max_penetration'])} m, min truncated force "
                   f"{rigid[0]['laws'][0]['min_force'] / 1e3:.2f} kN." if rigid else "") +
                  " Before truncation: λ on the N_t samples inside the DLFT (after the "
                  "positive-part correction); after truncation: the same λ kept to its first "
                  "20 harmonics, i.e. the force the rod actually receives, drawn on a fine "
                  "grid.*\n")

    # g. epsilon
    path_curves = figure_epsilon_curves(out, args.figures)
    path_laws = figure_epsilon_laws(out, args.figures)
    md.append("### Influence of ε at ω0, k_obs = 4 k_rod (Figs. 19–21)\n")
    sweep400 = load(out, "refine_flexible_4krod", "refinement.json")
    sweep600 = load(out, "refine_flexible_4krod_nt600", "refinement.json")

    def by_eps(document):
        return {round(math.log10(s["epsilon"]), 6): s for s in document["steps"]} \
            if document else {}

    s400, s600 = by_eps(sweep400), by_eps(sweep600)
    eps_rows = []
    for eps in EPS_SWEEP:
        key = round(math.log10(eps), 6)
        row = [f"{eps:.0e}".replace("e+", "e")]
        for steps in (s400, s600):
            step = steps.get(key)
            if step is None:
                row += ["—", "—", "—"]
                continue
            law = step["laws"][0]
            row += [sci(law["max_penetration"]) + ("" if step["converged"] else " (not conv.)"),
                    f"{law['min_force']:.0f}", f"{100 * law['contact_fraction']:.1f} %"]
        step = s400.get(key)
        row.append(f"{step['h1'][0]:.6e}" if step else "—")
        eps_rows.append(row)
    md.append(table(["ε [N/m]", "penetration [m], N_t = 400", "min λ trunc. [N], N_t = 400",
                     "contact samples, N_t = 400", "penetration [m], N_t = 600",
                     "min λ trunc. [N], N_t = 600", "contact samples, N_t = 600",
                     "h1(x_end) [m], N_t = 400"], eps_rows))
    if len(s400) >= 2:
        first, last = s400[min(s400)], s400[max(s400)]
        p0, p1 = first["laws"][0]["max_penetration"], last["laws"][0]["max_penetration"]
        f0, f1 = -first["laws"][0]["min_force"], -last["laws"][0]["min_force"]
        e0, e1 = first["epsilon"], last["epsilon"]
        md.append(f"\nPenetration = max(0, −min g) on the N_t samples; min λ = most negative "
                  f"contact force after truncation (fine grid). Over ε = {e0:.0e} … {e1:.0e} "
                  f"(N_t = 400) the penetration falls by ×{p0 / p1:.1f} (log-log slope "
                  f"{math.log(p1 / p0) / math.log(e1 / e0):.2f}) while the truncation "
                  f"undershoot grows by ×{f1 / f0:.1f} (slope "
                  f"{math.log(f1 / f0) / math.log(e1 / e0):+.2f}); h1 of x_end changes by "
                  f"{100 * abs(last['h1'][0] / first['h1'][0] - 1):.2f} %. This is the "
                  "paper's trade-off (Sec. 4.1): larger ε, less penetration, larger truncation "
                  "oscillations of λ; the displacement barely depends on ε.\n")
    md.append(figure_ref(path_curves, "penetration and truncated force vs epsilon"))
    md.append("")
    refine_rows = []
    beyond = by_eps(load(out, "refine_flexible_4krod_beyond", "refinement.json"))
    rigid_ref = by_eps(load(out, "refine_rigid_nh20", "refinement.json"))
    for eps in EPS_REFINE:
        key = round(math.log10(eps), 6)
        row = [f"{eps:.4g}"]
        for steps in (beyond, rigid_ref):
            step = steps.get(key)
            if step is None:
                row += ["not attempted", "—"]
            elif not step["converged"]:
                row += [f"**not converged** ({step.get('message', '')})", "—"]
            else:
                row += [sci(step["laws"][0]["max_penetration"]),
                        f"{step['laws'][0]['min_force']:.0f}"]
        refine_rows.append(row)
    md.append("Refinement beyond 10¹¹ (the paper's Fig. 21 procedure, ε_i = 2ε_{i−1} from "
              "10¹¹, 15 steps, each warm-started from the previous solution), for the flexible "
              "obstacle and for the rigid one (the paper refines the rigid case):\n")
    md.append(table(["ε [N/m]", "flexible 4 k_rod: penetration [m]", "flexible: min λ [N]",
                     "rigid N_h = 20: penetration [m]", "rigid: min λ [N]"], refine_rows))
    md.append("\nThe penetration keeps falling roughly like 1/ε at large ε while the truncated "
              "force's undershoot saturates: DLFT tends to the gap-exact (LCP-HBM-like) contact "
              "law, as the paper reports.\n")
    if path_laws:
        md.append(figure_ref(path_laws, "contact laws for several epsilon"))
        md.append("\n*Contact force and gap around the contact phase and the contact laws "
                  "(g, λ) before and after truncation for ε = 10⁸, 10⁹, 10¹⁰, 10¹¹ N/m.*\n")

    # h. NLvib
    path = figure_nlvib(out, args.figures)
    nl_rows = []
    for name, label in NLVIB:
        document = load(out, name)
        if not document:
            nl_rows.append([f"`{name}`", label, "missing", "", "", ""])
            continue
        pw, ph = nlvib_peak(document)
        eps = ""
        for p in document["points"][:1]:
            laws = p.get("laws") or [{}]
            eps = f"{laws[0]['epsilon']:.4g}" if "epsilon" in laws[0] else "—"
        nl_rows.append([f"`{name}`", label, eps, f"**{ph:.4f}**", f"{pw:.4f}",
                        f"{100 * (ph / NLVIB_PEAK[1] - 1):+.2f} %"])
    md.append("### NLvib's two-DOF unilateral-spring example\n")
    md.append("M = I, K = [[1, −1], [−1, 2]], C = 0.03 K, 0.1 cos ωt on DOF 2, spring "
              "100·max(0, x1 − 1) on DOF 1, ω from 0.8 down to 0.5, harmonics 0…21 and N = 1024 "
              "samples as in NLvib's `EXAMPLES/03_twoDOFoscillator_unilateralSpring`. "
              "Peak = the branch point with the largest first-harmonic amplitude of x2.\n")
    md.append(table(["run", "law", "ε", "peak h1(x2)", "at ω", "vs NLvib 0.937"], nl_rows))
    md.append("\nThe penalty law (AFT of k·max(0, x1 − 1)) is NLvib's formulation and "
              "reproduces its peak. A massless flexible obstacle of stiffness k is the same "
              "physics, but DLFT enforces it differently: the obstacle displacement is a "
              "truncated Fourier series and the gap condition is imposed through the "
              "ε-weighted prediction on the samples, so at H = 21 the DLFT curve depends on ε: "
              "with the default ε = k_obs = 100 it is within 0.1 % of the penalty peak, while "
              "ε = 0.4975 (the static condensed stiffness, an earlier default; run "
              "`nlvib_dlft_flexible_eps0_5`) gives a peak about 2 % high. Both "
              "laws converge to the same curve as H grows (H = 84 rows).\n")
    if path:
        md.append(figure_ref(path, "NLvib unilateral spring FRC"))
        md.append("")

    # i. disagreements
    md.append("### Where this differs from the paper\n")
    notes = [
        "The paper's Table 1 gives ρ = 7800 but its ω0 = 63 953 rad/s needs ρ = 7500; the "
        "figures use 7500, and the `_rho7800` runs show that 7800 only rescales ω.",
        "Damping is not stated in the paper; 0.75 % modal damping reproduces its linear "
        "amplitude at ω0 (see the linear check).",
        "No time integration or LCP-HBM here: the paper's reference curves (chirp TI) and "
        "LCP-HBM points are not reproduced; the comparison is with the published numbers "
        "(ω0, the jump near 6.6·10⁴ rad/s, the qualitative ε and N_h trends).",
        "The paper's jump (≈ 6.6·10⁴ rad/s) is a chirp time integration falling off the "
        "nonlinear branch, which depends on the sweep rate; ours is the rightmost turning point "
        "of the periodic HBM branch, an upper bound for a slow sweep-up jump (stability is "
        "not computed, so an earlier loss of stability would go unnoticed); see the jump "
        "table for the differences.",
        "The paper's Figs. 19–20 use N_t = 600; the ε table gives both N_t = 400 (the NFRC "
        "setting) and 600.",
    ]
    spans = []
    for name in ROD_RUNS:
        summary = fold_summary(load(out, name))
        if summary and summary["micro"]:
            lo = min(f["omega"] for f in summary["micro"])
            spans.append((100 * (summary["right"]["omega"] - lo) / summary["right"]["omega"],
                          name))
    if spans:
        widest = max(spans)
        notes.append(
            "The branches of the stiff cases carry many micro-folds (a zig-zag from the samples "
            "switching between contact and separation) near the steep end of the nonlinear "
            "branch; the paper's curves show one smooth turning point. Their count depends on "
            "the step size and on N_t (`flexible_4krod_nt600` has fewer than `flexible_4krod`); "
            f"they lie within {widest[0]:.2f} % of ω below the rightmost fold (widest: "
            f"`{widest[1]}`).")
    four = fold_summary(load(out, "flexible_4krod"))
    twin = fold_summary(load(out, "penalty_4krod"))
    others = [fold_summary(load(out, n)) for m, n in FLEXIBLE if m != 4.0]
    if four and twin and all(others):
        notes.append(
            "The paper's Fig. 17 cannot be compared point by point (its data are not in the "
            f"text); our k_obs = 4 k_rod branch climbs much further (its rightmost fold at "
            f"ω = {four['right']['omega']:.0f}, max|x_end| = {sci(four['right']['max_abs'][0])} "
            "m) than 0.4, 20 and 40 k_rod (rightmost folds " +
            ", ".join(f"{o['right']['omega']:.0f}" for o in others) + " rad/s). The penalty "
            f"twin `penalty_4krod` turns at {twin['right']['omega']:.0f} rad/s "
            f"({100 * (twin['right']['omega'] / four['right']['omega'] - 1):+.2f} %), so this "
            "is the model's behaviour, not a DLFT artefact.")
    for name, eps, message, command in short:
        notes.append(f"`nfrc refine` ({name}) stops at ε = {eps:.4g} N/m: “{message}” — the "
                     f"paper's refinement reached 2¹⁵·10¹¹ ≈ 3.3·10¹⁵ on the rigid case; "
                     f"reproduce with `{command}`.")
    md.extend(f"- {note}" for note in notes)
    md.append("")

    # j. timing
    md.append("### Run times\n")
    rows = []
    total = 0.0
    for name, _ in RUNS:
        document = load(out, name)
        if not document:
            rows.append([f"`{name}`", "—", "—", "—", "missing"])
            continue
        summary = document["summary"]
        seconds = summary.get("wall_time_s", float("nan"))
        total += seconds
        rows.append([f"`{name}`", summary.get("points"), summary.get("folds"),
                     f"{seconds:.2f}", summary.get("termination")])
    rows.append(["**total**", "", "", f"{total:.1f}", ""])
    md.append(table(["run", "points", "folds", "wall time (s)", "termination"], rows))
    md.append("\nWall time is `summary.wall_time_s` of each `branch.json` (continuation only; "
              "Release build, this project's 2-core machine, one run at a time; load average "
              f"{load_average[0]:.1f} when the study started, so other work shared the cores). "
              "Each refinement takes well under a second.\n")

    total = time.monotonic() - started
    with open(args.markdown, "w") as handle:
        handle.write("\n".join(md).rstrip().replace("@TOTAL_SECONDS@", f"{total:.0f}") + "\n")
    print(f"contact_study: runs {runs_seconds:.1f} s, total {total:.1f} s; "
          f"wrote {args.markdown} and {figure_dir}/")
    if failed:
        print(f"contact_study: ERROR: {len(failed)} case(s) did not reach the end of their "
              "range: " + ", ".join(name for name, _, _, _ in failed), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
