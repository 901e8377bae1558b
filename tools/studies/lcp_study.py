#!/usr/bin/python3
"""Runs the LCP-HBM study of Vadcard, Batailly & Thouverez (2022), Sections 2.5, 3.3-3.6, 4.1,
4.2 (LCP-HBM by Lemke against DLFT-HBM on the clamped rod) with nfrc, and writes its figures and
tables.

usage: lcp_study.py [--nfrc PATH] [--out DIR] [--force] [--jobs N]
                    [--figures DIR] [--markdown PATH]

Runs every case of RUNS with `nfrc run CASE --out OUT/NAME` (output in OUT/NAME/nfrc.log),
skipping a run whose OUT/NAME/branch.json already ended with summary.termination ==
reached_lambda_bound unless --force, and the refinements of REFINEMENTS with `nfrc refine`
(skipped when OUT/NAME/refinement.json exists, unless --force). Then draws
docs/figures/lcp/*.png and writes docs/lcp_results.md. Defaults: --nfrc build/nfrc, --out
out/lcp, both relative to the repository root. Runs that stop short of their range and
refinements that stop early are reported on stderr and in the markdown (not an error: the
square-grid DLFT run is known to stall at a fold).
"""
import concurrent.futures
import os
import sys
import time

sys.dont_write_bytecode = True  # keep tools/ free of __pycache__

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from contact_study import (centred, contact_centre, fold_summary, omega_axis,  # noqa: E402
                           read_csv, sci, shown, unilateral_law)
from study_common import (REPO, execute, fmt, load, parse_arguments, save, table,  # noqa: E402
                          termination)

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # tools/
from nfrc_output import draw_branch as draw_stability  # noqa: E402

STUDY = "lcp"
OMEGA0 = 63953.9
GAP = 2e-4
K_ROD = 210e9 * 15.6e-4 / 0.13
K_OBS = 1.008e10  # obstacle_stiffness of cases/rod/flexible_4krod*.json (4 k_rod)
H = 20

# (run name, case file)
RUNS = [
    ("rigid_stepping_nt400", "cases/lcp/rigid_stepping_nt400.json"),
    ("rigid_arclength_nt41", "cases/lcp/rigid_arclength_nt41.json"),
    ("rigid_stepping_nt41", "cases/lcp/rigid_stepping_nt41.json"),
    ("rigid_dlft_eps1e11", "cases/lcp/rigid_dlft_eps1e11.json"),
    ("rigid_dlft_nt41_eps1e11", "cases/lcp/rigid_dlft_nt41_eps1e11.json"),
    ("rigid_nh20", "cases/rod/rigid_nh20.json"),
]
# (name, case, refine options after --omega)
EPS_NT600 = [1e8, 1e9, 1e10, 1e11]
REFINEMENTS = [
    ("refine_rigid_nt600", "cases/lcp/rigid_dlft_nt600.json",
     ["--epsilon0", "1e11", "--factor", "2", "--steps", "15"]),
    ("refine_flexible_4krod", "cases/rod/flexible_4krod.json", ["--epsilons", f"{K_OBS:g}"]),
    ("refine_flexible_4krod_nt600", "cases/rod/flexible.json#nt600",
     ["--epsilons", ",".join(f"{e:g}" for e in EPS_NT600)]),
]
EPS_COLOURS = {1e8: "tab:blue", 1e9: "tab:orange", 1e10: "tab:green", 1e11: "tab:red"}
LCP_STYLE = dict(color="black", ls="--", lw=1.1)


# ----------------------------------------------------------------------------- runs

def run_command(nfrc, name, case, out):
    return [nfrc, "run", os.path.join(REPO, case), "--out", os.path.join(out, name)]


def refine_command(nfrc, name, case, options, out):
    return ([nfrc, "refine", os.path.join(REPO, case), "--omega", f"{OMEGA0}"] + options +
            ["--out", os.path.join(out, name)])


def run_one(nfrc, out, name, case, force):
    if not force and termination(load(out, name)) == "reached_lambda_bound":
        return "skipped (already reached_lambda_bound)", 0.0
    code, seconds = execute(run_command(nfrc, name, case, out), os.path.join(out, name))
    return f"exit {code} ({termination(load(out, name))})", seconds


def refine_one(nfrc, out, name, case, options, force):
    if not force and load(out, name, "refinement.json") is not None:
        return "skipped (refinement.json exists)", 0.0
    code, seconds = execute(refine_command(nfrc, name, case, options, out),
                            os.path.join(out, name))
    document = load(out, name, "refinement.json")
    done = len(document["steps"]) if document else 0
    return f"exit {code} ({done} steps)", seconds


def run_all(nfrc, out, force, jobs):
    skipped, status = 0, {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        futures = {pool.submit(run_one, nfrc, out, name, case, force): name
                   for name, case in RUNS}
        futures.update({pool.submit(refine_one, nfrc, out, name, case, options, force): name
                        for name, case, options in REFINEMENTS})
        for future in concurrent.futures.as_completed(futures):
            text, took = future.result()
            skipped += text.startswith("skipped")
            status[futures[future]] = (text, took)
            print(f"{STUDY}_study: {futures[future]:30s} {text}  {took:7.1f} s", flush=True)
    return skipped, status


# ----------------------------------------------------------------------------- helpers

def refinement(out, name):
    """(document, LCP (samples, signals), [(step, samples, signals)] of converged steps)."""
    document = load(out, name, "refinement.json")
    if not document:
        return None, None, []
    directory = os.path.join(out, name)
    lcp = document.get("lcp")
    reference = None
    if lcp and lcp.get("status") == "solution":
        reference = (read_csv(os.path.join(directory, lcp["samples_file"])),
                     read_csv(os.path.join(directory, lcp["signals_file"])))
    steps = [(s, read_csv(os.path.join(directory, s["samples_file"])),
              read_csv(os.path.join(directory, s["signals_file"])))
             for s in document["steps"] if s.get("converged")]
    return document, reference, steps


def step_at(steps, epsilon):
    for step in steps:
        if abs(step[0]["epsilon"] / epsilon - 1.0) < 1e-9:
            return step
    return None


def spectrum(values):
    """One-sided amplitude spectrum of N periodic samples: harmonics 0..N/2."""
    n = len(values)
    c = np.abs(np.fft.rfft(values)) / n
    c[1:] *= 2.0
    if n % 2 == 0:
        c[-1] /= 2.0
    return c


def law_axes(axes, lam, gap, zoom):
    lam_max = max(float(np.max(lam)), 1.0)
    if zoom:
        unilateral_law(axes, lam_max, 2e-6)
    else:
        unilateral_law(axes, lam_max, float(np.max(gap)))
    axes.ticklabel_format(axis="x", style="sci", scilimits=(0, 0), useMathText=True)
    axes.set_xlabel("gap g [m]")
    axes.set_ylabel("λ [N]")
    axes.grid(True, alpha=0.25)


def stepping_points(document):
    points = document["points"]
    omega = np.array([p["omega"] for p in points])
    amp = np.array([p["max_abs"][0] for p in points])
    trivial = np.array([p["lcp"]["trivial"] for p in points])
    ok = np.array([p["lcp"]["status"] == "solution" for p in points])
    coexist = [(p["omega"], p["lcp"]["contact_branch"]["max_abs"][0]) for p in points
               if p["lcp"].get("coexisting_contact") and p["lcp"].get("contact_branch")]
    return omega, amp, trivial, ok, coexist


def branch_values_at(document, target):
    """max_abs and contact_fraction of every branch segment crossing omega = target."""
    points = document["points"]
    found = []
    for a, b in zip(points, points[1:]):
        lo, hi = a["omega"], b["omega"]
        if (lo - target) * (hi - target) <= 0.0 and lo != hi:
            t = (target - lo) / (hi - lo)
            amp = a["max_abs"][0] + t * (b["max_abs"][0] - a["max_abs"][0])
            frac = max(a["laws"][0]["contact_fraction"], b["laws"][0]["contact_fraction"])
            found.append((amp, frac))
    return found


def trivial_region(stepping, dlft):
    """Lemke grid points that are trivial while the DLFT branch has a contact solution there
    (some branch segment at that omega with max_abs > g0 and contact_fraction > 0)."""
    omega, _, trivial, _, _ = stepping_points(stepping)
    lo, hi = dlft["points"][0]["omega"], dlft["points"][-1]["omega"]
    hits = []
    for w, triv in zip(omega, trivial):
        if triv and lo <= w <= hi:
            if any(amp > GAP and frac > 0.0 for amp, frac in branch_values_at(dlft, w)):
                hits.append(w)
    return hits


def last_contact(stepping):
    """(last omega of a non-trivial Lemke point, next grid omega, last omega where a
    coexisting contact solution was found by warm start)."""
    omega, _, trivial, _, coexist = stepping_points(stepping)
    contact = [i for i in range(len(omega)) if not trivial[i]]
    if not contact:
        return None, None, None
    i = contact[-1]
    following = omega[i + 1] if i + 1 < len(omega) else None
    return omega[i], following, (max(w for w, _ in coexist) if coexist else None)


# ----------------------------------------------------------------------------- figures

def figure_refinement_distances(document, figures):
    steps = [s for s in document["steps"] if s.get("converged")]
    eps = np.array([s["epsilon"] for s in steps])
    figure, axes = plt.subplots(figsize=(6.4, 4.4))
    for key, label, marker in (("force_raw", "λ before truncation", "o"),
                               ("force", "λ after truncation", "s"),
                               ("gap", "gap", "^"), ("displacement", "displacement", "v")):
        axes.loglog(eps, [s["distance_to_lcp"][key] for s in steps], marker=marker, ms=4,
                    lw=1.0, label=label)
    failed = [s for s in document["steps"] if not s.get("converged")]
    if failed:
        axes.axvline(failed[0]["epsilon"], color="0.4", ls=":", label="first non-converged ε")
    axes.set_xlabel("ε [N/m]")
    axes.set_ylabel("relative distance to LCP-HBM")
    axes.set_title("DLFT ε refinement (rigid, $N_h$ = 20, $N_t$ = 600, ω0)", fontsize=10)
    axes.grid(True, which="both", alpha=0.25)
    axes.legend(fontsize=8)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "refinement_distances.png"), STUDY)


def figure_refinement_laws(reference, steps, figures):
    first, last = steps[0], steps[-1]
    figure, grid = plt.subplots(2, 2, figsize=(11, 8.2))
    curves = [(first, "tab:blue", f"DLFT ε0 = {first[0]['epsilon']:.3g}"),
              (last, "tab:red", f"DLFT ε = {last[0]['epsilon']:.3g} (last converged)")]
    for row, (index, key, what) in enumerate(((1, "law0_force_raw", "before truncation, "
                                               "$N_t$ = 600 samples"),
                                              (2, "law0_force", "after truncation, fine grid"))):
        for axes, zoom in zip(grid[row], (False, True)):
            for step, colour, label in curves:
                axes.plot(step[index]["law0_gap"], step[index][key], ".-", ms=2.0, lw=0.6,
                          color=colour, label=label)
            lcp = reference[index - 1]
            axes.plot(lcp["law0_gap"], lcp[key], "x" if row == 0 else "--", ms=4,
                      color="black", lw=1.0, label="LCP-HBM (Lemke)")
            law_axes(axes, lcp[key], lcp["law0_gap"], zoom)
            if zoom:
                axes.set_xlim(-1e-6, 2e-6 if row == 0 else 6e-6)
            axes.set_title(f"{what}: " + ("whole period" if not zoom else "around g = 0"),
                           fontsize=9.5)
            axes.legend(fontsize=7.5)
    figure.suptitle("(Fig. 21) ε refinement: contact law, rigid obstacle, $N_h$ = 20, "
                    "$N_t$ = 600, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig21_refinement_contact_law.png"), STUDY)


def figure12_13(reference, step, figures):
    lcp_samples, lcp_fine = reference
    _, samples, fine = step
    theta_c = contact_centre(lcp_samples)
    lcp_s, lcp_f = centred(lcp_samples, theta_c, OMEGA0), centred(lcp_fine, theta_c, OMEGA0)
    d_s, d_f = centred(samples, theta_c, OMEGA0), centred(fine, theta_c, OMEGA0)
    figure, grid = plt.subplots(3, 1, figsize=(8.5, 9.5), sharex=True)
    grid[0].plot(lcp_s["t"], lcp_s["law0_gap"], ".-", ms=2.5, lw=0.6, color="black",
                 label="LCP-HBM")
    grid[0].plot(d_s["t"], d_s["law0_gap"], ".-", ms=2.5, lw=0.6, color="tab:orange",
                 label=f"DLFT-HBM ε = {step[0]['epsilon']:.4g}")
    grid[0].axhline(0.0, color="0.4", lw=0.8)
    grid[0].set_ylabel("gap on the samples [m]")
    grid[0].set_title("(Fig. 12a/b) gap", fontsize=10)
    grid[1].plot(lcp_s["t"], lcp_s["law0_force_raw"], ".-", ms=2.5, lw=0.6, color="black",
                 label="LCP-HBM")
    grid[1].plot(d_s["t"], d_s["law0_force_raw"], ".-", ms=2.5, lw=0.6, color="tab:orange",
                 label="DLFT-HBM")
    grid[1].set_ylabel("λ before truncation [N]")
    grid[1].set_title("(Fig. 12c/d) contact force before truncation (on the $N_t$ samples)",
                      fontsize=10)
    grid[2].plot(lcp_f["t"], lcp_f["law0_force"], "-", lw=1.0, color="black", label="LCP-HBM")
    grid[2].plot(d_f["t"], d_f["law0_force"], "-", lw=1.0, color="tab:orange",
                 label="DLFT-HBM")
    grid[2].axhline(0.0, color="0.4", lw=0.8)
    grid[2].set_ylabel("λ after truncation [N]")
    grid[2].set_title("(Fig. 13) contact force after truncation to 20 harmonics", fontsize=10)
    grid[2].set_xlabel("t [µs] (contact centred at T/2)")
    for axes in grid:
        axes.grid(True, alpha=0.25)
        axes.legend(fontsize=8)
    figure.suptitle("Flexible obstacle 4 $k_{rod}$, $N_h$ = 20, $N_t$ = 400, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig12_13_gap_force_4krod.png"), STUDY)


def figure14(reference, step, figures):
    figure, grid = plt.subplots(1, 2, figsize=(11, 4.3))
    for axes, zoom in zip(grid, (False, True)):
        axes.plot(step[2]["law0_gap"], step[2]["law0_force"], "-", lw=1.0, color="tab:orange",
                  label=f"DLFT-HBM ε = {step[0]['epsilon']:.4g}")
        axes.plot(reference[1]["law0_gap"], reference[1]["law0_force"], **LCP_STYLE,
                  label="LCP-HBM")
        law_axes(axes, reference[1]["law0_force"], reference[1]["law0_gap"], zoom)
        if zoom:
            axes.set_xlim(-2e-6, 6e-6)
        axes.set_title("whole period" if not zoom else "around g = 0", fontsize=10)
        axes.legend(fontsize=8)
    figure.suptitle("(Fig. 14) contact law after truncation, flexible 4 $k_{rod}$, "
                    "$N_t$ = 400, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig14_contact_law_4krod.png"), STUDY)


def figure19(reference, steps, figures):
    theta_c = contact_centre(reference[0])
    lcp_s, lcp_f = (centred(reference[0], theta_c, OMEGA0),
                    centred(reference[1], theta_c, OMEGA0))
    figure, grid = plt.subplots(len(EPS_NT600), 2, figsize=(11, 10), sharex=True)
    for row, eps in zip(grid, EPS_NT600):
        step = step_at(steps, eps)
        row[0].plot(lcp_s["t"], lcp_s["law0_force_raw"], "x-", ms=3, lw=0.5, color="black",
                    label="LCP-HBM")
        row[1].plot(lcp_f["t"], lcp_f["law0_force"], **LCP_STYLE, label="LCP-HBM")
        if step:
            s, f = centred(step[1], theta_c, OMEGA0), centred(step[2], theta_c, OMEGA0)
            row[0].plot(s["t"], s["law0_force_raw"], ".-", ms=2.5, lw=0.6,
                        color=EPS_COLOURS[eps], label=f"DLFT ε = {eps:.0e}")
            row[1].plot(f["t"], f["law0_force"], "-", lw=1.0, color=EPS_COLOURS[eps],
                        label=f"DLFT ε = {eps:.0e}")
        for axes in row:
            axes.grid(True, alpha=0.25)
            axes.legend(fontsize=7.5, loc="upper left")
        row[0].set_ylabel("λ [N]")
    grid[0, 0].set_title("(a) before truncation ($N_t$ = 600 samples)", fontsize=10)
    grid[0, 1].set_title("(b) after truncation (20 harmonics)", fontsize=10)
    for axes in grid[-1]:
        axes.set_xlabel("t [µs] (contact centred at T/2)")
    figure.suptitle("(Fig. 19) flexible 4 $k_{rod}$, $N_h$ = 20, $N_t$ = 600, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig19_forces_eps_nt600.png"), STUDY)


def figure20(reference, steps, figures):
    figure, grid = plt.subplots(1, 2, figsize=(11, 4.3))
    for axes, zoom in zip(grid, (False, True)):
        for eps in EPS_NT600:
            step = step_at(steps, eps)
            if step:
                axes.plot(step[2]["law0_gap"], step[2]["law0_force"], "-", lw=1.0,
                          color=EPS_COLOURS[eps], label=f"DLFT ε = {eps:.0e}")
        axes.plot(reference[1]["law0_gap"], reference[1]["law0_force"], **LCP_STYLE,
                  label="LCP-HBM")
        law_axes(axes, reference[1]["law0_force"], reference[1]["law0_gap"], zoom)
        if zoom:
            axes.set_xlim(-2e-6, 6e-6)
        axes.set_title("whole period" if not zoom else "around g = 0", fontsize=10)
        axes.legend(fontsize=7.5)
    figure.suptitle("(Fig. 20) contact law after truncation, flexible 4 $k_{rod}$, "
                    "$N_t$ = 600, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig20_contact_laws_eps_nt600.png"), STUDY)


def figure22(reference, steps, figures):
    figure, grid = plt.subplots(1, 2, figsize=(11, 4.3))
    floor = 1e-3
    for axes, key, title in zip(grid, ("law0_force_raw", "law0_force"),
                                ("(a) before truncation", "(b) after truncation")):
        for eps in EPS_NT600:
            step = step_at(steps, eps)
            if step:
                c = spectrum(step[1][key])
                axes.semilogy(np.arange(len(c)), np.maximum(c, floor), "-", lw=0.8,
                              color=EPS_COLOURS[eps], label=f"DLFT ε = {eps:.0e}")
        c = spectrum(reference[0][key])
        axes.semilogy(np.arange(len(c)), np.maximum(c, floor), **LCP_STYLE, label="LCP-HBM")
        axes.axvspan(0, H, color="0.85", zorder=0, label="HBM bandwidth (20 harmonics)")
        axes.set_xlabel("harmonic k")
        axes.set_title(title, fontsize=10)
        axes.grid(True, alpha=0.25)
        axes.legend(fontsize=7.5)
    grid[1].set_xlim(0, 2 * H)
    grid[1].set_ylim(bottom=floor / 2)
    grid[0].set_ylabel(f"|λ_k| [N] (floored at {floor:g})")
    figure.suptitle("(Fig. 22) contact-force spectra of the $N_t$ = 600 samples, flexible "
                    "4 $k_{rod}$, ω0", fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig22_force_spectra_nt600.png"), STUDY)


def draw_stepping(axes, document, colour, label):
    omega, amp, trivial, ok, coexist = stepping_points(document)
    axes.plot(omega[~trivial & ok], amp[~trivial & ok], "o", ms=4, color=colour,
              label=f"{label}: contact")
    axes.plot(omega[trivial & ok], amp[trivial & ok], "o", ms=4, mfc="none", mec=colour,
              mew=0.8, label=f"{label}: trivial (no contact)")
    if (~ok).any():
        axes.plot(omega[~ok], amp[~ok], "x", ms=6, color="red", label=f"{label}: Lemke failed")
    if coexist:
        w, a = zip(*coexist)
        axes.plot(w, a, "D", ms=3.5, mfc="none", mec="tab:purple", mew=0.8,
                  label=f"{label}: coexisting contact (warm start)")


def draw_branch(axes, document, style, colour, label):
    w = [p["omega"] for p in document["points"]]
    a = [p["max_abs"][0] for p in document["points"]]
    if termination(document) != "reached_lambda_bound":
        label += f" ({termination(document)} at ω = {w[-1]:.0f})"
    if style == "-":  # solid where stable or not analysed, dashed where unstable
        stable = [p.get("stable") for p in document["points"]]
        draw_stability(axes, w, a, stable, label=label, lw=1.0, color=colour)
    else:
        axes.plot(w, a, style, lw=1.0, color=colour, label=label)
    summary = fold_summary(document)
    if summary:
        right = summary["right"]
        axes.plot(right["omega"], right["max_abs"][0], "*", ms=9, color=colour, mec="black",
                  mew=0.5)


def figure_nfrc(out, figures, region):
    figure, grid = plt.subplots(1, 2, figsize=(12.5, 5.0), sharey=True)
    axes = grid[0]
    for name, style, colour, label in (("rigid_nh20", "-", "tab:blue", "DLFT default ε"),
                                       ("rigid_dlft_eps1e11", "-", "tab:red", "DLFT ε = 1e11")):
        document = load(out, name)
        if document:
            draw_branch(axes, document, style, colour, label)
    stepping = load(out, "rigid_stepping_nt400")
    if stepping:
        draw_stepping(axes, stepping, "black", "LCP Lemke stepping")
    if region:
        axes.axvspan(region[0], region[-1], color="gold", alpha=0.3, zorder=0,
                     label="Lemke trivial, DLFT ε = 1e11 in contact")
    axes.set_title("$N_h$ = 20, $N_t$ = 400 (★: rightmost fold)", fontsize=10)
    axes = grid[1]
    for name, style, colour, label in (("rigid_arclength_nt41", "-", "black",
                                        "LCP-HBM arclength (smoothed FB)"),
                                       ("rigid_dlft_nt41_eps1e11", "-", "tab:red",
                                        "DLFT ε = 1e11")):
        document = load(out, name)
        if document:
            draw_branch(axes, document, style, colour, label)
    stepping = load(out, "rigid_stepping_nt41")
    if stepping:
        draw_stepping(axes, stepping, "tab:green", "Lemke stepping")
    axes.set_title("square grid $N_h$ = 20, $N_t$ = 41 (★: rightmost fold)", fontsize=10)
    for axes in grid:
        axes.axhline(GAP, color="0.4", ls="-.", lw=0.8)
        axes.set_xlim(5e4, 8e4)
        axes.set_xlabel("ω [rad/s]")
        axes.grid(True, alpha=0.25)
        omega_axis(axes)
        axes.legend(fontsize=7, loc="upper left")
    grid[0].set_ylabel("max |x_end| [m]")
    figure.suptitle("(Fig. 17/18) NFRC, rigid obstacle: LCP-HBM against DLFT-HBM",
                    fontsize=10)
    figure.tight_layout()
    return save(figure, os.path.join(figures, "fig17_nfrc_rigid_lcp.png"), STUDY)


# ----------------------------------------------------------------------------- main

def main():
    args = parse_arguments(STUDY, __doc__.splitlines()[0])
    started = time.monotonic()
    out = os.path.abspath(args.out)
    nfrc = os.path.abspath(args.nfrc)
    os.makedirs(out, exist_ok=True)
    os.makedirs(args.figures, exist_ok=True)
    skipped, status = run_all(nfrc, out, args.force, args.jobs)
    figure_dir = os.path.relpath(args.figures, REPO)
    missing = []

    def ref(path, alt):
        return f"![{alt}]({os.path.join(figure_dir, os.path.basename(path))})"

    md = ["<!-- generated by tools/studies/lcp_study.py; figure paths are relative to the "
          "repository root -->",
          "## LCP-HBM study (Vadcard, Batailly & Thouverez 2022, Sections 2.5, 3.3–3.6, 4.1, "
          "4.2)\n",
          "Clamped FE rod (20 elements, ρ = 7500, 25 kN cos ωt at the end, g0 = 0.2 mm) "
          f"against a rigid obstacle or a flexible one (k_obs = 4 k_rod = {K_OBS:.4g} N/m), "
          f"N_h = 20, at ω0 = {OMEGA0} rad/s or along ω. LCP-HBM (`lcp_contact`, Lemke) is "
          "compared with DLFT-HBM (`dlft_contact`).\n",
          "**Reproduce** (from the repository root): `/usr/bin/python3 "
          "tools/studies/lcp_study.py --nfrc build/nfrc` (add `--force` to rerun finished "
          "runs); " + (f"{skipped} runs were skipped as already finished; "
                       if skipped else "") + "this page took @TOTAL_SECONDS@ s.\n",
          "### Runs\n"]
    rows = []
    for name, case in RUNS:
        text, took = status[name]
        document = load(out, name)
        message = document["summary"].get("message", "") if document else "no branch.json"
        rows.append([f"`{name}`", f"`{shown(run_command('build/nfrc', name, case, 'out/lcp'))}`",
                     termination(document), f"{took:.1f}",
                     message if termination(document) != "reached_lambda_bound" else ""])
    for name, case, options in REFINEMENTS:
        text, took = status[name]
        rows.append([f"`{name}`",
                     f"`{shown(refine_command('build/nfrc', name, case, options, 'out/lcp'))}`",
                     text, f"{took:.1f}", ""])
    md.append(table(["name", "command", "result", "s", "note"], rows))
    md.append("")

    # 1. refinement --------------------------------------------------------------------
    md.append("### 1. ε refinement towards LCP-HBM (rigid obstacle, N_t = 600, ω0; Fig. 21)\n")
    document, reference, steps = refinement(out, "refine_rigid_nt600")
    if document and reference and steps:
        lcp = document["lcp"]
        md.append(f"LCP-HBM reference (Lemke at ω0): status **{lcp['status']}**, "
                  f"**{lcp['pivots']} pivots**, min gap on the samples = "
                  f"**{sci(lcp['min_gap'])} m**, complementarity gap = "
                  f"{sci(lcp['complementarity_gap'])}, max |x_end| = "
                  f"{sci(lcp['max_abs'][0])} m, min λ after truncation = "
                  f"{lcp['min_force']:.4g} N.\n")
        rows = []
        for s in document["steps"]:
            d = s.get("distance_to_lcp", {})
            law = s.get("laws", [{}])[0]
            rows.append([f"{s['epsilon']:.4g}", "yes" if s.get("converged") else "**no**",
                         s.get("newton_iterations", "—"), sci(s.get("min_gap")),
                         sci(law.get("max_penetration")), fmt(s.get("min_force")),
                         sci(d.get("force_raw")), sci(d.get("force")), sci(d.get("gap")),
                         sci(d.get("displacement"))])
        md.append(table(["ε [N/m]", "converged", "Newton it.", "min gap [m]",
                         "max penetration [m]", "min λ (truncated) [N]", "dist. λ raw",
                         "dist. λ truncated", "dist. gap", "dist. displacement"], rows))
        failed = [s for s in document["steps"] if not s.get("converged")]
        first, last = steps[0][0], steps[-1][0]
        md.append("\nDistances are relative distances to the LCP-HBM solution (λ before/after "
                  "truncation and gap on the samples, displacement harmonics). " +
                  (f"The refinement stopped at ε = {failed[0]['epsilon']:.4g} (not converged: "
                   f"{failed[0].get('message', '')}). " if failed else
                   f"All {len(steps)} steps converged; last ε = {last['epsilon']:.4g}. ") +
                  f"From ε0 to the last converged ε the distances go from "
                  f"{sci(first['distance_to_lcp']['force_raw'])} to "
                  f"{sci(last['distance_to_lcp']['force_raw'])} (λ raw), "
                  f"{sci(first['distance_to_lcp']['force'])} to "
                  f"{sci(last['distance_to_lcp']['force'])} (λ truncated), "
                  f"{sci(first['distance_to_lcp']['gap'])} to "
                  f"{sci(last['distance_to_lcp']['gap'])} (gap), "
                  f"{sci(first['distance_to_lcp']['displacement'])} to "
                  f"{sci(last['distance_to_lcp']['displacement'])} (displacement).\n")
        for label, key in (("λ raw", "force_raw"), ("λ truncated", "force"), ("gap", "gap"),
                           ("displacement", "displacement")):
            values = [s["distance_to_lcp"][key] for s, _, _ in steps]
            increases = [(steps[i][0]["epsilon"], steps[i + 1][0]["epsilon"])
                         for i in range(len(values) - 1) if values[i + 1] > values[i]]
            md.append(f"- {label}: " + ("decreases monotonically." if not increases else
                      "not monotone, increases between ε = " +
                      ", ".join(f"{a:.3g}→{b:.3g}" for a, b in increases) + "."))
        md.append("")
        md.append(ref(figure_refinement_distances(document, args.figures),
                      "refinement distances"))
        md.append("\nRelative distances of the DLFT solution to LCP-HBM along the refinement "
                  "(log-log).\n")
        md.append(ref(figure_refinement_laws(reference, steps, args.figures),
                      "Fig. 21 analogue"))
        md.append("\nContact law λ(g) of DLFT at ε0, DLFT at the last converged ε and LCP-HBM: "
                  "top, on the N_t samples before truncation; bottom, after truncation (fine "
                  "grid); right: zoom around g = 0.\n")
    else:
        missing.append("refine_rigid_nt600")
        md.append("**refine_rigid_nt600 missing or without an LCP reference.**\n")

    # 2. Figs 12-14 ----------------------------------------------------------------------
    md.append("### 2. Flexible obstacle 4 k_rod, N_t = 400, ω0 (Figs. 12–14)\n")
    document, reference, steps = refinement(out, "refine_flexible_4krod")
    if document and reference and steps:
        lcp, step = document["lcp"], steps[0]
        s = step[0]
        law = s["laws"][0]
        md.append(table(["", "min gap [m]", "max penetration [m]", "min λ truncated [N]",
                         "max abs x_end [m]", "pivots / Newton it."],
                        [["LCP-HBM", sci(lcp["min_gap"]), "—", fmt(lcp["min_force"]),
                          sci(lcp["max_abs"][0]), lcp["pivots"]],
                         [f"DLFT ε = {s['epsilon']:.4g}", sci(s["min_gap"]),
                          sci(law["max_penetration"]), fmt(s["min_force"]),
                          sci(s["max_abs"][0]), s["newton_iterations"]]]))
        d = s["distance_to_lcp"]
        md.append(f"\nDLFT distance to LCP-HBM: λ raw {sci(d['force_raw'])}, λ truncated "
                  f"{sci(d['force'])}, gap {sci(d['gap'])}, displacement "
                  f"{sci(d['displacement'])}.\n")
        md.append(ref(figure12_13(reference, step, args.figures), "Figs. 12-13 analogue"))
        md.append("\nGap and contact force on the N_t samples before truncation (Fig. 12), and "
                  "contact force after truncation to 20 harmonics (Fig. 13), LCP-HBM and "
                  "DLFT-HBM.\n")
        md.append(ref(figure14(reference, step, args.figures), "Fig. 14 analogue"))
        md.append("\nContact laws after truncation (fine-grid signals), whole period and around "
                  "g = 0.\n")
    else:
        missing.append("refine_flexible_4krod")
        md.append("**refine_flexible_4krod missing.**\n")

    # 3. Figs 19, 20, 22 -----------------------------------------------------------------
    md.append("### 3. ε study, flexible 4 k_rod, N_t = 600, ω0 (Figs. 19, 20, 22)\n")
    document, reference, steps = refinement(out, "refine_flexible_4krod_nt600")
    if document and reference and steps:
        lcp = document["lcp"]
        rows = [["LCP-HBM", sci(lcp["min_gap"]), "—", fmt(lcp["min_force"]), "—", "—", "—",
                 "—", f"{lcp['pivots']} pivots"]]
        for s, samples, _ in steps:
            d = s["distance_to_lcp"]
            c = spectrum(samples["law0_force_raw"])
            rows.append([f"DLFT ε = {s['epsilon']:.0e}", sci(s["min_gap"]),
                         sci(s["laws"][0]["max_penetration"]), fmt(s["min_force"]),
                         sci(d["force_raw"]), sci(d["force"]), sci(d["gap"]),
                         sci(float(np.sum(c[H + 1:] ** 2) / np.sum(c ** 2))),
                         f"{s['newton_iterations']} Newton it."])
        c = spectrum(reference[0]["law0_force_raw"])
        rows[0][7] = sci(float(np.sum(c[H + 1:] ** 2) / np.sum(c ** 2)))
        md.append(table(["", "min gap [m]", "max penetration [m]", "min λ truncated [N]",
                         "dist. λ raw", "dist. λ truncated", "dist. gap",
                         "share of Σ λ_k² above k = 20 (raw)", "cost"], rows))
        md.append("")
        md.append(ref(figure19(reference, steps, args.figures), "Fig. 19 analogue"))
        md.append("\nContact forces before (samples) and after truncation for each ε, with "
                  "LCP-HBM.\n")
        md.append(ref(figure20(reference, steps, args.figures), "Fig. 20 analogue"))
        md.append("\nContact laws after truncation for each ε and LCP-HBM.\n")
        md.append(ref(figure22(reference, steps, args.figures), "Fig. 22 analogue"))
        md.append("\nOne-sided amplitude spectra of the N_t = 600 force samples before and "
                  "(harmonics 0..300) and after truncation (zoom on harmonics 0..40); the shaded band "
                  "is the HBM bandwidth. After truncation the amplitudes above k = 20 are "
                  "below the 1e-3 N floor at which they are drawn.\n")
    else:
        missing.append("refine_flexible_4krod_nt600")
        md.append("**refine_flexible_4krod_nt600 missing.**\n")

    # 4. NFRC ------------------------------------------------------------------------------
    md.append("### 4. NFRC, rigid obstacle (Fig. 17/18)\n")
    stepping = load(out, "rigid_stepping_nt400")
    dlft = load(out, "rigid_dlft_eps1e11")
    region = trivial_region(stepping, dlft) if stepping and dlft else []
    md.append(ref(figure_nfrc(out, args.figures, region), "NFRC rigid LCP vs DLFT"))
    md.append("\nLeft: Lemke stepping on N_t = 400 (filled: contact solution; hollow: trivial "
              "no-contact solution) over the DLFT NFRCs at the default ε and ε = 1e11; the "
              "shaded band spans the Lemke grid points that are trivial where the DLFT "
              "ε = 1e11 branch has a contact solution (max |x_end| > g0, contact fraction > 0). "
              "Right: square grid N_t = 41: LCP-HBM arclength branch, DLFT ε = 1e11, Lemke "
              "stepping with warm-started contact tracking (diamonds: max |x_end| of a "
              "coexisting contact solution found where the cold Lemke solution is trivial).\n")
    rows = []
    for name, label in (("rigid_nh20", "DLFT default ε, N_t = 400 (arclength)"),
                        ("rigid_dlft_eps1e11", "DLFT ε = 1e11, N_t = 400 (arclength)"),
                        ("rigid_arclength_nt41", "LCP-HBM, N_t = 41 (arclength)"),
                        ("rigid_dlft_nt41_eps1e11", "DLFT ε = 1e11, N_t = 41 (arclength)")):
        document = load(out, name)
        if not document:
            missing.append(name)
            rows.append([label, "missing", "—", "—", "—"])
            continue
        summary = fold_summary(document)
        end = document["points"][-1]["omega"]
        rows.append([label, f"{summary['right']['omega']:.1f}" if summary else "no fold",
                     len(document.get("folds", [])), termination(document)
                     + ("" if termination(document) == "reached_lambda_bound"
                        else f" at ω = {end:.1f}"),
                     sci(summary["right"]["max_abs"][0]) if summary else "—"])
    for name, label in (("rigid_stepping_nt400", "LCP-HBM Lemke stepping, N_t = 400"),
                        ("rigid_stepping_nt41", "LCP-HBM Lemke stepping, N_t = 41")):
        document = load(out, name)
        if not document:
            missing.append(name)
            continue
        last, following, coexist = last_contact(document)
        spacing = document["points"][1]["omega"] - document["points"][0]["omega"]
        text = (f"last contact point {last:.1f}, next grid point {following:.1f} trivial"
                if last is not None else "no contact point")
        if coexist is not None:
            text += f"; warm-started contact found up to {coexist:.1f}"
        rows.append([label, text, "—", f"grid step {spacing:.0f} rad/s", "—"])
    md.append(table(["NFRC", "jump ω [rad/s] (rightmost fold)", "folds", "termination",
                     "max abs x_end at the jump [m]"], rows))
    if region:
        spacing = stepping["points"][1]["omega"] - stepping["points"][0]["omega"]
        md.append(f"\n**Trivial-solution region** (N_t = 400): Lemke gives the trivial "
                  f"(no-contact) solution while DLFT ε = 1e11 has a contact solution at "
                  f"{len(region)} grid points, ω = {region[0]:.0f} … {region[-1]:.0f} rad/s "
                  f"(width {region[-1] - region[0]:.0f} rad/s on a {spacing:.0f} rad/s grid)"
                  + (f"; the DLFT ε = 1e11 contact branch ends at its rightmost fold "
                     f"ω = {fold_summary(dlft)['right']['omega']:.1f} rad/s, and the last "
                     f"non-trivial Lemke point is ω = {last_contact(stepping)[0]:.0f} rad/s."
                     if fold_summary(dlft) else "."))
    else:
        md.append("\nNo trivial-solution region found on the N_t = 400 grid.")
    md.append("")
    square = load(out, "rigid_dlft_nt41_eps1e11")
    arclength = load(out, "rigid_arclength_nt41")
    if square and arclength and termination(square) != "reached_lambda_bound":
        folds = arclength.get("folds", [])
        first = folds[0]["omega"] if folds else float("nan")
        md.append(f"The square-grid DLFT run (ε = 1e11, N_t = 41) {termination(square)} at "
                  f"ω = {square['points'][-1]['omega']:.1f} rad/s "
                  f"(“{square['summary'].get('message', '')}”); the first fold along the "
                  f"square-grid LCP-HBM arclength branch is at ω = {first:.1f} rad/s.\n")
    if missing:
        md.append("**Missing results:** " + ", ".join(missing) + "\n")

    total = time.monotonic() - started
    text = "\n".join(md).replace("@TOTAL_SECONDS@", f"{total:.0f}")
    with open(args.markdown, "w") as handle:
        handle.write(text + "\n")
    print(f"{STUDY}_study: wrote {args.markdown} and {args.figures} in {total:.1f} s")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
