"""Shared fixtures: where the sources and the build are, and the friction oscillator."""

import os
import pathlib
import sys

import pytest

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
# ctest sets NFRC_BUILD_DIR and PYTHONPATH; run by hand, the README's build/ is assumed.
BUILD_DIR = pathlib.Path(os.environ.get("NFRC_BUILD_DIR", SOURCE_DIR / "build"))
if str(BUILD_DIR / "python") not in sys.path:
    sys.path.insert(0, str(BUILD_DIR / "python"))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def build_dir():
    return BUILD_DIR


@pytest.fixture
def subprocess_env():
    """Environment for child processes (examples, a numpy-free import)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(BUILD_DIR / "python")] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    env["MPLBACKEND"] = "Agg"
    return env


FRC_N10_TITLE = ("Two-DOF friction oscillator (Legrand & Pierre 2024, Fig. 7): "
                 "N = 10, N_phi = 60, N_t = 1024")


def friction_dict(normal_load=10.0, max_harmonic=59, samples=1024, omega=(0.1, 0.8),
                  title=FRC_N10_TITLE, signals_at=None, plot_steps=True):
    """The two-DOF friction oscillator of cases/friction/ (by default frc_n10.json), with
    its matrices as numpy arrays; plot_steps: the FRC files' steps sized by the plotted
    energy."""
    import numpy as np
    harmonics = {"max": max_harmonic, "odd_only": True}
    if samples:
        harmonics["samples"] = samples
    output = {"dofs": ["x1", "x2"]}
    if signals_at is not None:
        output["signals_at"] = signals_at
    continuation = {"omega_start": omega[0], "omega_end": omega[1]}
    if plot_steps:
        continuation.update(plot_tolerance=5e-4, max_step=0.5, plot_measure="energy")
    return {
        "title": title,
        "model": {
            "type": "matrices",
            "M": np.eye(2),
            "C": np.array([[0.04, -0.02], [-0.02, 0.02]]),
            "K": np.array([[2.0, -1.0], [-1.0, 1.0]]),
            "dof_names": ["x1", "x2"],
            "forcing": [{"dof": "x1", "cos": np.float64(20.0)}],
        },
        "nonlinearities": [{"type": "coulomb_friction", "dof": np.int64(1), "mu": 0.9,
                            "normal_load": normal_load}],
        "harmonics": harmonics,
        "continuation": continuation,
        "output": output,
    }


@pytest.fixture
def friction_case():
    import nfrc
    return nfrc.Case.from_dict(friction_dict())
