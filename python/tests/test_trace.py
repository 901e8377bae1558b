"""Traces: the acceptance test against `nfrc run`, measures, folds and the summary."""

import json
import subprocess

import numpy as np
import pytest

import nfrc
from conftest import friction_dict


# Friction cases of cases/friction/ (a file, and a member of a manifest) and the same content
# built from numpy arrays: a short branch (13 points) and the full FRC of Legrand & Pierre's
# Fig. 7 (about 1300 points).
ACCEPTANCE = {
    "convergence_e.json#nphi40": dict(max_harmonic=39, samples=None, omega=(0.308, 0.309),
                                 title="Point E (N = 10, omega = 0.308) with N_phi = 40",
                                 signals_at=[0.308], plot_steps=False),
    "frc_n10.json": dict(),
}


@pytest.mark.parametrize("name", sorted(ACCEPTANCE))
def test_numpy_case_traces_like_nfrc_run(name, source_dir, build_dir, tmp_path):
    """A friction case built from numpy arrays gives the branch `nfrc run` gives on its file."""
    from nfrc import _plain  # the dict as JSON would see it
    case_file = source_dir / "cases/friction" / name
    source = friction_dict(**ACCEPTANCE[name])
    out = tmp_path / "out"
    subprocess.run([str(build_dir / "nfrc"), "run", str(case_file), "--out", str(out)],
                   check=True, capture_output=True)
    written = json.loads((out / "branch.json").read_text())
    assert _plain(source) == written["case"]  # the same content as the case that was run
    branch = nfrc.trace(nfrc.Case.from_dict(source))
    points = written["points"]
    assert branch.points == len(points) == written["summary"]["points"] > 10
    assert branch.summary.termination == written["summary"]["termination"] == "reached_lambda_bound"
    np.testing.assert_allclose(branch.omega, [p["omega"] for p in points], rtol=0, atol=1e-12)
    for dof, dof_name in enumerate(["x1", "x2"]):
        np.testing.assert_allclose(branch.measure("max_abs", dof),
                                   [p["max_abs"][dof] for p in points], rtol=1e-12)
        np.testing.assert_allclose(branch.measure("h1", dof_name),
                                   [p["h1"][dof] for p in points], rtol=1e-12)
    assert branch.num_unknowns == written["unknowns"]
    assert branch.summary.folds == len(written["folds"]) == len(branch.folds)
    assert len(branch.solutions) == len(written.get("signals", []))
    # The step history, entry by entry as nfrc run writes it; its counts add up to the totals.
    history = branch.summary.history
    assert [(s.step, s.newton_iterations, s.accepted, s.fixed_lambda, s.note) for s in history] \
        == [(h["step"], h["newton_iterations"], h["accepted"], h["fixed_lambda"], h["note"])
            for h in written["summary"]["history"]]
    assert sum(s.accepted for s in history) == branch.summary.accepted_steps
    assert sum(not s.accepted for s in history) == branch.summary.rejected_steps
    assert all(s.note for s in history if not s.accepted)


def test_measures_by_name_and_dof(friction_case):
    case = friction_case
    case.harmonics = nfrc.HarmonicSet(9, odd_only=True)
    branch = nfrc.trace(case)
    n = branch.points
    assert n > 20 and branch.omega.shape == (n,) and branch.y.shape == (n, branch.num_unknowns)
    for name in ["max_abs", "min", "max", "h1", "energy", "law0_stick_fraction",
                 "law0_max_force_ratio"]:
        values = branch.measure(name, "x1")
        assert values.shape == (n,) and np.all(np.isfinite(values)), name
    np.testing.assert_array_equal(branch.measure("max_abs", "x2"), branch.measure("max_abs", 1))
    assert np.all(branch.measure("min", 0) <= branch.measure("max", 0))
    np.testing.assert_allclose(branch.measure("max_abs", 0),
                               np.maximum(-branch.measure("min", 0), branch.measure("max", 0)))
    with pytest.raises(nfrc.InputError, match="min_gap.*contact law"):
        branch.measure("min_gap")
    with pytest.raises(nfrc.InputError, match="unknown \"amplitude\".*max_abs"):
        branch.measure("amplitude")
    with pytest.raises(nfrc.InputError, match="dof: \"x3\" is not an output"):
        branch.measure("max_abs", "x3")
    with pytest.raises(nfrc.InputError, match="dof: output index 2"):
        branch.measure("max_abs", 2)
    s = branch.summary
    assert s.success and s.points == n and s.newton_iterations >= n and s.wall_time > 0
    assert s.notes == []  # a plain run: no retry or other departure from the algorithm
    assert s.accepted_steps >= n - 1 and s.evaluations > 0 and s.message


def test_duffing_folds(source_dir):
    branch = nfrc.trace(nfrc.load_case(source_dir / "cases/duffing.json"))
    assert branch.points == 114
    assert [round(f.omega, 6) for f in branch.folds] == [1.269602, 1.1157]
    top = branch.folds[0]
    assert top.converged and top.omega_accuracy < 1e-6
    assert not any(f.corner for f in branch.folds)  # a smooth law: smooth folds
    # The peak is close to the upper fold, not at it.
    assert top.measure("max_abs") == pytest.approx(branch.measure("max_abs").max(), rel=1e-2)
    with pytest.raises(nfrc.InputError, match="not recorded at folds"):
        top.measure("law0_x")


def test_contact_measures(source_dir):
    case = nfrc.load_case(source_dir / "cases/contact/nlvib.json#penalty")
    case.harmonics = nfrc.HarmonicSet(7, samples=128)  # stalls at 0.70 but has contact by then
    branch = nfrc.trace(case)
    min_gap = branch.measure("min_gap")
    assert min_gap.shape == (branch.points,) and np.any(min_gap < 0)  # the spring engages
    assert np.all(np.isfinite(branch.measure("min_force")))
    np.testing.assert_array_equal(branch.measure("law0_min_gap"), min_gap)


def test_signals_at_solutions_come_with_the_branch(source_dir):
    case = nfrc.load_case(source_dir / "cases/duffing.json")
    case.signals_at = [1.2]
    branch = nfrc.trace(case)
    assert [s.omega for s in branch.solutions] == [1.2] * 3
    assert branch.solutions[0].coefficients is None
    assert "x_0" in branch.solutions[0].signals


def test_input_errors_surface_when_tracing(source_dir):
    case = nfrc.load_case(source_dir / "cases/lcp/rigid_arclength_nt41.json")
    case.harmonics = nfrc.HarmonicSet(20, samples=400)  # oversampled: singular for arclength
    with pytest.raises(nfrc.InputError, match="harmonics.samples"):
        nfrc.trace(case)
