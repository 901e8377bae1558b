#!/usr/bin/python3
"""Runs the comparisons of the laws of issue 16 (contact_friction, equality_contact, jenkins,
dlft_friction) against their references with nfrc, and writes their figures and tables.

usage: laws_study.py [--nfrc PATH] [--out DIR] [--force] [--jobs N]
                     [--figures DIR] [--markdown PATH]

Runs every case of RUNS with `nfrc run CASE --out OUT/NAME` or `nfrc validate CASE --out OUT/NAME
--no-chirp` (output in OUT/NAME/nfrc.log), skipping a run whose branch.json already ended with
summary.termination == reached_lambda_bound (a validation: whose validation.json exists) unless
--force. Then draws docs/figures/laws/*.png (one figure per law against its reference) and
writes docs/laws_results.md (tables: points, folds, wall time, peaks and their differences,
the transient comparisons). Defaults: --nfrc build/nfrc, --out out/laws. A run that does not
reach the end of its range is named on stderr and in the markdown, and makes the exit status 1.
"""
import concurrent.futures
import os
import sys

sys.dont_write_bytecode = True  # keep tools/ free of __pycache__

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from study_common import (REPO, execute, fmt, load, parse_arguments, save, table,  # noqa: E402
                          termination)

# (run name, "run" or "validate", case file under cases/, label in figures and tables)
RUNS = [
    ("cf_oscillator", "run", "contact_friction/oscillator.json",
     "contact_friction, H = 63"),
    ("cf_oscillator_validate", "validate", "validation/contact_friction_oscillator.json",
     "contact_friction against IDA"),
    ("rod_4krod_equality", "run", "rod/flexible_4krod_equality.json", "equality_contact"),
    ("rod_4krod_dlft", "run", "rod/flexible_4krod.json", "dlft_contact"),
    ("rod_4krod_equality_validate", "validate", "validation/rod_flexible_4krod_equality.json",
     "equality_contact against IDA"),
    ("rod_rigid_equality", "run", "rod/rigid_nh20_equality.json", "equality_contact"),
    ("rod_rigid_dlft", "run", "rod/rigid_nh20.json", "dlft_contact"),
    ("rod_rigid_lcp", "run", "lcp/rigid_arclength_nt41.json",
     "lcp_contact (N_t = 2H+1, arclength)"),
    ("jenkins_n10_validate", "validate", "validation/jenkins_n10.json",
     "jenkins k_t = 10 against IDA"),
]


def run(args, name, kind, case):
    directory = os.path.join(args.out, name)
    if not args.force:
        if kind == "run" and termination(load(args.out, name)) == "reached_lambda_bound":
            return name, None, 0.0
        if kind == "validate" and load(args.out, name, "validation.json") is not None:
            return name, None, 0.0
    path = os.path.join(REPO, "cases", case)
    command = [args.nfrc, kind, path, "--out", directory]
    if kind == "validate":
        command += ["--no-chirp"]
    code, seconds = execute(command, directory)
    return name, code, seconds


def series(document, measure, dof):
    """ω, the measure of output DOF `dof` and the stability flags along a branch."""
    points = document.get("points", [])
    omega = [p["omega"] for p in points]
    values = [p[measure][dof] if isinstance(p[measure], list) else p[measure] for p in points]
    stable = [p.get("stable", True) for p in points]
    return omega, values, stable


def peak(document, measure, dof):
    omega, values, _ = series(document, measure, dof)
    if not values:
        return float("nan"), float("nan")
    i = max(range(len(values)), key=values.__getitem__)
    return omega[i], values[i]


def draw_branch(axis, document, measure, dof, label, color, style="-"):
    """The branch, stable parts solid and unstable parts dashed (one legend entry)."""
    omega, values, stable = series(document, measure, dof)
    start = 0
    first = True
    for i in range(1, len(omega) + 1):
        if i == len(omega) or stable[i] != stable[start]:
            segment = slice(start, min(i + 1, len(omega)))
            axis.plot(omega[segment], values[segment], style if stable[start] else "--",
                      color=color, lw=1.2, label=label if first else None)
            first = False
            start = i


def summary_row(args, name, label, measure, dof):
    document = load(args.out, name)
    if document is None:
        return [label, "not run", "—", "—", "—", "—", "—"]
    s = document["summary"]
    w, v = peak(document, measure, dof)
    return [label, s.get("termination"), s.get("points"), s.get("folds"),
            fmt(s.get("wall_time_s"), 3), fmt(w, 7), fmt(v, 6)]


def validation_rows(document, dofs):
    rows = []
    for point in document.get("points", []):
        for t in point.get("transients", []):
            d = t.get("differences", {})
            h1 = d.get("h1", [None] * len(dofs))
            rows.append([fmt(point["omega"], 6), t.get("start", "—"), t.get("matches", "—"),
                         t.get("status", "—")] + [fmt(h1[i], 2) for i in range(len(dofs))] +
                        [fmt(d.get("energy"), 2)])
    return rows


def stability_rows(document):
    """Per HBM solution: Hill's and the transient monodromy's largest |μ|, the largest distance
    from a multiplier of either to the nearest of the other, and the monodromy's closure."""
    rows = []
    for point in document.get("points", []):
        for solution in point.get("hbm_solutions", []):
            hill, monodromy = solution.get("hill") or {}, solution.get("monodromy") or {}
            a = [complex(*m) for m in hill.get("multipliers", [])]
            b = [complex(*m) for m in monodromy.get("multipliers", [])]
            worst = max([min(abs(x - y) for y in b) for x in a] +
                        [min(abs(x - y) for y in a) for x in b]) if a and b else None
            rows.append([fmt(point["omega"], 6), solution.get("branch", "—"),
                         fmt(hill.get("max_modulus"), 4), fmt(monodromy.get("max_modulus"), 4),
                         fmt(worst, 2), fmt(monodromy.get("closure"), 2)])
    return rows


def transient_points(document, measure, dof):
    """(ω, measure of the output DOF) of the periodic transients."""
    result = []
    for point in document.get("points", []):
        for t in point.get("transients", []):
            if t.get("status") == "periodic" and t.get(measure):
                result.append((point["omega"], t[measure][dof]))
    return result


def contact_friction_figure(args):
    branch = load(args.out, "cf_oscillator")
    validation = load(args.out, "cf_oscillator_validate", "validation.json")
    if branch is None:
        return None
    figure, axis = plt.subplots(figsize=(7.5, 4.2))
    for dof, (name, color) in enumerate([("normal", "C0"), ("tangent", "C1")]):
        draw_branch(axis, branch, "h1", dof, f"HBM, {name} DOF", color)
        if validation is not None:
            points = transient_points(validation, "h1", dof)
            axis.plot([p[0] for p in points], [p[1] for p in points], "o", mfc="none",
                      color=color, label=f"IDA transient, {name} DOF")
    axis.set_xlabel("excitation frequency ω (rad/s)")
    axis.set_ylabel("first-harmonic amplitude (m)")
    axis.set_yscale("log")
    axis.set_title("contact_friction: two-DOF contact oscillator (dashed: unstable)", fontsize=10)
    axis.legend(fontsize=8)
    axis.grid(alpha=0.3)
    figure.tight_layout()
    return save(figure, os.path.join(args.figures, "contact_friction.png"), "laws")


def equality_contact_figure(args):
    figure, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    panels = [(axes[0], "k_obs = 4 k_rod", [("rod_4krod_dlft", "C0", "-"),
                                           ("rod_4krod_equality", "C3", ":")],
               "rod_4krod_equality_validate"),
              (axes[1], "rigid obstacle", [("rod_rigid_dlft", "C0", "-"),
                                           ("rod_rigid_lcp", "C2", "-."),
                                           ("rod_rigid_equality", "C3", ":")], None)]
    labels = {name: label for name, _, _, label in RUNS}
    for axis, title, runs, validation_name in panels:
        for name, color, style in runs:
            document = load(args.out, name)
            if document is not None:
                draw_branch(axis, document, "max_abs", 0, labels[name], color, style)
        if validation_name is not None:
            validation = load(args.out, validation_name, "validation.json")
            if validation is not None:
                points = transient_points(validation, "max_abs", 0)
                axis.plot([p[0] for p in points], [p[1] for p in points], "ko", mfc="none",
                          label="IDA transient")
        axis.set_title(f"FE rod, {title}", fontsize=10)
        axis.set_xlabel("ω (rad/s)")
        axis.set_ylabel("max |x_end| (m)")
        axis.grid(alpha=0.3)
        axis.legend(fontsize=8)
    figure.tight_layout()
    return save(figure, os.path.join(args.figures, "equality_contact.png"), "laws")


def main():
    args = parse_arguments("laws", __doc__.splitlines()[0])
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        jobs = [pool.submit(run, args, name, kind, case) for name, kind, case, _ in RUNS]
        for job in jobs:
            name, code, seconds = job.result()
            print(f"laws_study: {name}: " +
                  ("kept the existing run" if code is None else f"exit {code}, {seconds:.1f} s"))
    os.makedirs(args.figures, exist_ok=True)
    failed = []
    for name, kind, case, _ in RUNS:
        if kind == "run" and termination(load(args.out, name)) != "reached_lambda_bound":
            document = load(args.out, name)
            message = document["summary"].get("message") if document else "no branch.json"
            failed.append(f"`{name}` ({case}): {termination(document)}: {message}")
    figures = [contact_friction_figure(args), equality_contact_figure(args)]

    header = ["run", "termination", "points", "folds", "wall time (s)", "ω at peak", "peak"]
    lines = ["# The laws of issue 16 against their references", "",
             "Generated by `tools/studies/laws_study.py` (cases in `cases/`; the run names are "
             "the directories under `out/laws/`). Wall times are on the machine that ran the "
             "study; `nfrc_bench` gives them in LU(320) units.", ""]
    lines += ["## contact_friction: the two-DOF contact oscillator", "",
              "`nfrc run cases/contact_friction/oscillator.json`, "
              "`nfrc validate cases/validation/contact_friction_oscillator.json --no-chirp`. "
              "Peak of h1 of the normal DOF.", "",
              table(header, [summary_row(args, "cf_oscillator", "HBM, H = 63", "h1", 0)]), ""]
    validation = load(args.out, "cf_oscillator_validate", "validation.json")
    if validation is not None:
        lines += [table(["ω", "start", "matches", "status", "h1 normal", "h1 tangent",
                         "energy"], validation_rows(validation, [0, 1])), ""]
    rows = [summary_row(args, name, label, "max_abs", 0) for name, kind, _, label in RUNS
            if name.startswith("rod_") and kind == "run"]
    lines += ["## equality_contact on the rod, against DLFT and LCP-HBM", "",
              "Peak of max |x_end|.", "", table(header, rows), ""]
    validation = load(args.out, "rod_4krod_equality_validate", "validation.json")
    if validation is not None:
        lines += ["`nfrc validate cases/validation/rod_flexible_4krod_equality.json --no-chirp`"
                  " (relative differences of h1 at the rod's end and of the energy):", "",
                  table(["ω", "start", "matches", "status", "h1 end", "energy"],
                        validation_rows(validation, [0])), ""]
    validation = load(args.out, "jenkins_n10_validate", "validation.json")
    if validation is not None:
        lines += ["## jenkins against IDA", "",
                  "`nfrc validate cases/validation/jenkins_n10.json --no-chirp` (Fig. 7's "
                  "oscillator, N = 10, k_t = 10 N/m, N_φ = 60; relative differences of h1 of "
                  "x1 and x2 and of the energy):", "",
                  table(["ω", "start", "matches", "status", "h1 x1", "h1 x2", "energy"],
                        validation_rows(validation, [0, 1])), "",
                  "Stability: Hill's multipliers (with the stick pieces' memory) against the "
                  "transient monodromy of each HBM solution (started with the slider's force "
                  "of the HBM solution; closure: how far one period moves that start, relative "
                  "to the orbit's size):", "",
                  table(["ω", "solution", "Hill max \\|μ\\|", "monodromy max \\|μ\\|",
                         "largest multiplier distance", "closure"], stability_rows(validation)),
                  ""]
    lines += ["## Figures", ""] + [f"![{os.path.basename(f)}]({os.path.relpath(f, REPO)})"
                                    for f in figures if f] + [""]
    if failed:
        lines += ["## Runs that did not reach the end of their range", ""]
        lines += [f"- {f}" for f in failed] + [""]
        for f in failed:
            print(f"laws_study: {f}", file=sys.stderr)
    with open(args.markdown, "w") as handle:
        handle.write("\n".join(lines))
    print(f"laws_study: wrote {args.markdown}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
