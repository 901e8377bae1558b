"""Energy FRCs of the two-DOF friction oscillator (Legrand & Pierre 2024, Fig. 7) for several
normal loads, built in Python from numpy arrays (no case file).

    PYTHONPATH=build/python /usr/bin/python3 python/examples/friction_study.py [OUT.png]
        [--loads 8,10,12] [--harmonics 59] [--samples 1024]
"""

import argparse
import os
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import nfrc  # noqa: E402


def oscillator(harmonics, samples):
    """x1 forced by 20 cos(wt), x2 rubbing on the ground (mu = 0.9) through a spring."""
    return nfrc.Case.from_dict({
        "title": "Two-DOF friction oscillator",
        "model": {
            "type": "matrices",
            "M": np.eye(2),
            "C": np.array([[0.04, -0.02], [-0.02, 0.02]]),
            "K": np.array([[2.0, -1.0], [-1.0, 1.0]]),
            "dof_names": ["x1", "x2"],
            "forcing": [{"dof": "x1", "cos": 20.0}],
        },
        "nonlinearities": [{"type": "coulomb_friction", "dof": "x2", "mu": 0.9,
                            "normal_load": 10.0}],
        "harmonics": {"max": harmonics, "odd_only": True, "samples": samples},
        "continuation": {"omega_start": 0.1, "omega_end": 0.8},
        "output": {"dofs": ["x1", "x2"]},
    })


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", nargs="?",
                        default=os.path.join(tempfile.mkdtemp(), "friction_study.png"))
    parser.add_argument("--loads", default="8,9,10,11,12", help="normal loads N, comma-separated")
    parser.add_argument("--harmonics", type=int, default=59, help="highest (odd) harmonic")
    parser.add_argument("--samples", type=int, default=1024, help="time samples per period")
    args = parser.parse_args()

    case = oscillator(args.harmonics, args.samples)
    figure, axes = plt.subplots(figsize=(7, 4.5))
    for load in [float(n) for n in args.loads.split(",")]:
        law = case.laws[0]  # a copy: change it and assign it back (validated)
        law.normal_load = load
        case.laws[0] = law
        start = time.monotonic()
        branch = nfrc.trace(case)
        print(f"N = {load:g}: {branch.points} points, {branch.summary.termination}, "
              f"{time.monotonic() - start:.2f} s")
        axes.semilogy(branch.omega, branch.measure("energy"), label=f"N = {load:g}")
    axes.set_xlabel("ω")
    axes.set_ylabel("mean energy ½ẋᵀMẋ + ½xᵀKx")
    axes.set_title(f"Two-DOF friction oscillator, μ = 0.9, H = {args.harmonics} (odd)")
    axes.legend()
    axes.grid(True, which="both", alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
