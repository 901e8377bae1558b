"""The clamped rod against a rigid obstacle (cases/rod/rigid_nh20.json, DLFT) for several
gaps: the case file is loaded, its contact law changed in Python, each branch traced and
the end displacement plotted.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/rod_contact_study.py [OUT.png]
        [--gaps 2e-4,3e-4]
"""

import argparse
import os
import pathlib
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import nfrc  # noqa: E402

CASE = pathlib.Path(__file__).resolve().parents[2] / "cases" / "rod" / "rigid_nh20.json"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", nargs="?",
                        default=os.path.join(tempfile.mkdtemp(), "rod_contact_study.png"))
    parser.add_argument("--gaps", default="2e-4,3e-4", help="initial gaps (m), comma-separated")
    args = parser.parse_args()

    case = nfrc.load_case(CASE)
    figure, axes = plt.subplots(figsize=(7, 4.5))
    window = []  # ω where the end comes within half a gap of the obstacle
    for gap in [float(g) for g in args.gaps.split(",")]:
        law = case.laws[0]  # DlftContact at the free end; a copy until assigned back
        law.gap = gap
        case.laws[0] = law
        start = time.monotonic()
        branch = nfrc.trace(case)
        print(f"gap {gap:g} m: {branch.points} points, {len(branch.folds)} folds, "
              f"{branch.summary.termination}, {time.monotonic() - start:.2f} s")
        omega_khz = branch.omega / 1e3
        amplitude = branch.measure("max_abs", "end")
        window += list(omega_khz[amplitude > 0.5 * gap])
        line, = axes.plot(omega_khz, amplitude * 1e3, label=f"gap {gap * 1e3:g} mm")
        axes.plot([f.omega / 1e3 for f in branch.folds],
                  [f.measure("max_abs", "end") * 1e3 for f in branch.folds], "o",
                  color=line.get_color(), markersize=3)
        axes.axhline(gap * 1e3, color=line.get_color(), linestyle=":", linewidth=0.8)
    if window:
        pad = 0.2 * (max(window) - min(window))
        axes.set_xlim(min(window) - pad, max(window) + pad)
    axes.set_xlabel("ω (10³ rad/s)")
    axes.set_ylabel("max |x_end| (mm)")
    axes.set_title(f"Rod against a rigid obstacle, H = {case.harmonics.max} (folds: circles)")
    axes.legend()
    axes.grid(True, alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
