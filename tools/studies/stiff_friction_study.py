"""Runs the hysteretic friction laws with a stiff stick phase on the Fig. 7 oscillator of
Legrand & Pierre (2024) and compares them with the equality-based Coulomb law.

usage: stiff_friction_study.py [--nfrc PATH] [--out DIR] [--force] [--figures DIR]

Runs `nfrc run CASE#VARIANT --out OUT/NAME` (stderr to OUT/NAME/nfrc.log) for
- the equality law at N = 8, 10, 10.5, 11 (cases/friction/fig7.json),
- DLFT friction at the same loads with epsilon = 1e4, and at N = 10 with the default epsilon
  (cases/friction/fig7_dlft.json),
- the Jenkins element at N = 10 with k_t = 1e2, 1e3, 1e4 (cases/friction/jenkins_fig7.json),
all at N_phi = 60 (odd harmonics 1..59, N_t = 1024), one run at a time, skipping a run whose
branch.json already reached the end of the range (unless --force). Prints a Markdown table:
per run its termination, points, folds and wall time (the whole `nfrc run`, start and
stability included, and the engine's summary.wall_time_s), the resonance peak of max|x1|
(parabola through the largest point and its neighbours) against the equality law's at the same
load, and the largest difference of max|x1| and max|x2| over the common omega range (the
equality-law curve interpolated linearly in omega; it is a graph over omega at these loads).
Draws DIR/jenkins.png (Jenkins against the equality law at N = 10) and DIR/dlft_friction.png
(DLFT, epsilon = 1e4, against the equality law at the four loads). Defaults: --nfrc
build/nfrc, --out out/stiff_friction, --figures docs/figures/laws, relative to the repository
root.
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from study_common import REPO, execute, load, save, termination  # noqa: E402

CASES = os.path.join(REPO, "cases", "friction")
RUNS = [  # name, case, variant, reference run
    ("coulomb_n8", "fig7.json", "n8", None),
    ("coulomb_n10", "fig7.json", "n10", None),
    ("coulomb_n10_5", "fig7.json", "n10_5", None),
    ("coulomb_n11", "fig7.json", "n11", None),
    ("dlft_n8", "fig7_dlft.json", "n8", "coulomb_n8"),
    ("dlft_n10", "fig7_dlft.json", "n10", "coulomb_n10"),
    ("dlft_n10_5", "fig7_dlft.json", "n10_5", "coulomb_n10_5"),
    ("dlft_n11", "fig7_dlft.json", "n11", "coulomb_n11"),
    ("dlft_n10_default_epsilon", "fig7_dlft.json", "n10_default_epsilon", "coulomb_n10"),
    ("jenkins_k1e2", "jenkins_fig7.json", "k1e2", "coulomb_n10"),
    ("jenkins_k1e3", "jenkins_fig7.json", "k1e3", "coulomb_n10"),
    ("jenkins_k1e4", "jenkins_fig7.json", "k1e4", "coulomb_n10"),
]


def run(nfrc, out, name, case, variant, force):
    """Runs one case unless done; returns the whole run's wall time (s) or the recorded one."""
    directory = os.path.join(out, name)
    timing = os.path.join(directory, "seconds.json")
    if not force and termination(load(out, name)) == "reached_lambda_bound" and os.path.exists(timing):
        with open(timing) as handle:
            return json.load(handle)["seconds"]
    code, seconds = execute([nfrc, "run", os.path.join(CASES, case) + "#" + variant, "--out", directory],
                            directory)
    with open(timing, "w") as handle:
        json.dump({"seconds": seconds, "exit_code": code}, handle)
    return seconds


def curve(document):
    points = document["points"]
    omega = [p["omega"] for p in points]
    x1 = [p["max_abs"][0] for p in points]
    x2 = [p["max_abs"][1] for p in points]
    return omega, x1, x2


def peak(omega, values):
    """The vertex of the parabola through the largest point and its two neighbours."""
    i = max(range(len(values)), key=values.__getitem__)
    if 0 < i < len(values) - 1:
        (x0, x1, x2), (y0, y1, y2) = omega[i - 1:i + 2], values[i - 1:i + 2]
        denominator = (x0 - x1) * (x0 - x2) * (x1 - x2)
        a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denominator
        b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / denominator
        if a < 0.0:
            vertex = -b / (2.0 * a)
            if min(x0, x2) <= vertex <= max(x0, x2):
                c = y1 - a * x1 * x1 - b * x1
                return vertex, a * vertex * vertex + b * vertex + c
    return omega[i], values[i]


def interpolate(omega, values, target):
    """Linear interpolation on a curve increasing in omega."""
    lo, hi = 0, len(omega) - 1
    while hi - lo > 1:
        middle = (lo + hi) // 2
        if omega[middle] <= target:
            lo = middle
        else:
            hi = middle
    t = (target - omega[lo]) / (omega[hi] - omega[lo]) if omega[hi] != omega[lo] else 0.0
    return values[lo] + t * (values[hi] - values[lo])


def largest_difference(reference, branch, which):
    """max |values − reference(omega)| over the branch's points in the reference's range, and
    where; None if the reference is not a graph over omega."""
    omega_r, values_r = reference[0], reference[which]
    if any(b <= a for a, b in zip(omega_r, omega_r[1:])):
        return None
    worst = (0.0, float("nan"))
    for w, value in zip(branch[0], branch[which]):
        if omega_r[0] <= w <= omega_r[-1]:
            difference = abs(value - interpolate(omega_r, values_r, w))
            worst = max(worst, (difference, w))
    return worst


def stability(document):
    """Hill's verdicts along the branch: unstable points, bifurcations by type, largest |μ|."""
    points = [p for p in document["points"] if p.get("stable") is not None]
    if not points:
        return ["stability off"] * 3
    unstable = sum(1 for p in points if not p["stable"])
    kinds = {}
    for b in document.get("bifurcations", []):
        kinds[b["type"]] = kinds.get(b["type"], 0) + 1
    largest = max(p["floquet"]["max_modulus"] for p in points)
    return [f"{unstable} of {len(points)}",
            ", ".join(f"{n} {k}" for k, n in sorted(kinds.items())) or "none", f"{largest:.4f}"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nfrc", default=os.path.join(REPO, "build", "nfrc"))
    parser.add_argument("--out", default=os.path.join(REPO, "out", "stiff_friction"))
    parser.add_argument("--force", action="store_true")
    parser.add_argument("--figures", default=os.path.join(REPO, "docs", "figures", "laws"))
    args = parser.parse_args()
    if not os.access(args.nfrc, os.X_OK):
        sys.exit(f"stiff_friction_study: {args.nfrc} is not an executable (build nfrc, or --nfrc)")
    out = os.path.abspath(args.out)
    seconds = {name: run(os.path.abspath(args.nfrc), out, name, case, variant, args.force)
               for name, case, variant, _ in RUNS}
    print("| run | termination | points | folds | wall time, whole run (s) | engine (s) | "
          "peak max\\|x1\\| at ω | reference peak at ω | Δ peak | Δω | "
          "max Δ max\\|x1\\| (at ω) | max Δ max\\|x2\\| (at ω) | "
          "unstable points | bifurcations | largest \\|μ\\| |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, _, _, reference_name in RUNS:
        document = load(out, name)
        if document is None:
            print(f"| {name} | missing | | | {seconds[name]:.2f} | | | | | | | | | | |")
            continue
        summary = document["summary"]
        branch = curve(document)
        w_peak, a_peak = peak(branch[0], branch[1])
        row = [name, summary["termination"], str(summary["points"]), str(summary["folds"]),
               f"{seconds[name]:.2f}", f"{summary['wall_time_s']:.2f}", f"{a_peak:.4f} at {w_peak:.5f}"]
        reference = load(out, reference_name) if reference_name else None
        if reference is None:
            row += ["—"] * 5
        else:
            ref = curve(reference)
            w_ref, a_ref = peak(ref[0], ref[1])
            row += [f"{a_ref:.4f} at {w_ref:.5f} ({reference_name})",
                    f"{a_peak - a_ref:+.4f} ({(a_peak - a_ref) / a_ref:+.2%})", f"{w_peak - w_ref:+.5f}"]
            for which in (1, 2):
                worst = largest_difference(ref, branch, which)
                row.append("not a graph over ω" if worst is None else
                           f"{worst[0]:.4f} ({worst[0] / max(ref[which]):.2%} of the peak) at {worst[1]:.4f}")
        row += stability(document)
        print("| " + " | ".join(row) + " |")
    draw(out, args.figures)


def draw(out, figures):
    """max|x1| against ω: Jenkins' convergence to the Coulomb curve, and DLFT on it."""
    os.makedirs(figures, exist_ok=True)
    panels = [("jenkins.png", "jenkins (k_t, N = 10) against the equality-based Coulomb law",
               [("coulomb_n10", "coulomb_friction (equality)", "k", "-")] +
               [(f"jenkins_k{k}", f"jenkins, k_t = {k.replace('e', 'e+')}", c, "--")
                for k, c in (("1e2", "C0"), ("1e3", "C1"), ("1e4", "C3"))]),
              ("dlft_friction.png", "dlft_friction (ε = 1e4) against the equality law, N = 8, 10, "
               "10.5, 11", [(f"coulomb_{n}", "coulomb_friction (equality)" if n == "n8" else None,
                             "k", "-") for n in ("n8", "n10", "n10_5", "n11")] +
               [(f"dlft_{n}", "dlft_friction, ε = 1e4" if n == "n8" else None, "C3", "--")
                for n in ("n8", "n10", "n10_5", "n11")])]
    for file, title, runs in panels:
        figure, axis = plt.subplots(figsize=(7.5, 4.2))
        for name, label, color, style in runs:
            document = load(out, name)
            if document is None:
                continue
            omega, x1, _ = curve(document)
            axis.plot(omega, x1, style, color=color, lw=1.1, label=label)
        axis.set_yscale("log")
        axis.set_xlabel("excitation frequency ω")
        axis.set_ylabel("max |x1|")
        axis.set_title(title + ", N_φ = 60", fontsize=9)
        axis.grid(alpha=0.3)
        axis.legend(fontsize=8)
        figure.tight_layout()
        print(f"stiff_friction_study: wrote {save(figure, os.path.join(figures, file), 'stiff_friction')}")


if __name__ == "__main__":
    main()
