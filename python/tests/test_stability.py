"""Stability at the Python edge: the case's stability options and, on a traced branch, the
Floquet result per point and the bifurcations. The analysis fills them; these tests check
the structure and types, which hold whether or not it has computed anything."""

import json
import math
import subprocess

import numpy as np
import pytest

import nfrc

TYPES = {"fold", "branch_point", "period_doubling", "neimark_sacker"}


def duffing_dict(**stability):
    """The one-harmonic Duffing case of cases/duffing_h1.json (a short, fast branch)."""
    case = {"model": {"type": "matrices", "M": [[1]], "C": [[0.05]], "K": [[1]],
                      "forcing": [{"dof": 0, "cos": 0.18}]},
            "nonlinearities": [{"type": "cubic_spring", "dof": 0, "coefficient": 0.1}],
            "harmonics": {"max": 1, "odd_only": True, "samples": 16},
            "continuation": {"omega_start": 0.5, "omega_end": 1.6, "step": 0.01},
            "output": {"dofs": [0]}}
    if stability:
        case["stability"] = stability
    return case


def test_stability_options_default_and_from_dict():
    defaults = nfrc.Case.from_dict(duffing_dict()).stability
    assert defaults.to_dict() == {"enabled": True, "unstable_tolerance": 1e-6,
                                  "bifurcation_tolerance": 1e-6, "max_bifurcation_iterations": 40,
                                  "jump_tolerance": 1e-4, "hill_modes": -1}
    case = nfrc.Case.from_dict(duffing_dict(enabled=False, unstable_tolerance=1e-4,
                                            max_bifurcation_iterations=7))
    assert case.stability.enabled is False
    assert case.stability.unstable_tolerance == 1e-4
    assert case.stability["max_bifurcation_iterations"] == 7
    assert case.stability.bifurcation_tolerance == 1e-6


def test_stability_options_are_set_and_validated():
    case = nfrc.Case.from_dict(duffing_dict())
    case.stability.enabled = False
    assert case.stability.enabled is False
    case.stability.update(unstable_tolerance=1e-3, bifurcation_tolerance=1e-9)
    assert case.stability.unstable_tolerance == 1e-3
    case.stability = {"max_bifurcation_iterations": 5}
    assert case.stability.max_bifurcation_iterations == 5
    copied = case.copy()
    assert copied.stability == case.stability
    for key, value, message in [("unstable_tolerance", -1.0, r"stability\.unstable_tolerance"),
                                ("bifurcation_tolerance", 2.0, r"stability\.bifurcation_tolerance"),
                                ("max_bifurcation_iterations", 0, r"stability\.max_bifurcation"),
                                ("jump_tolerance", 0.0, r"stability\.jump_tolerance"),
                                ("hill_modes", -2, r"stability\.hill_modes"),
                                ("enabled", 1, r"stability\.enabled"),
                                ("enabled", "yes", r"stability\.enabled"),
                                ("tolerance", 1e-3, r"stability\.tolerance: unknown")]:
        with pytest.raises(nfrc.InputError, match=message):
            setattr(case.stability, key, value)
    assert case.stability.unstable_tolerance == 1e-3  # a refused change leaves the case as it was
    with pytest.raises(AttributeError, match="no stability option"):
        case.stability.tolerance
    with pytest.raises(nfrc.InputError, match=r"stability\.enabled"):
        nfrc.Case.from_dict(duffing_dict(enabled="no"))
    with pytest.raises(nfrc.InputError, match=r"stability\.foo: unknown key"):
        nfrc.Case.from_dict(duffing_dict(foo=1))


def check_floquet(floquet, stable):
    assert isinstance(floquet, nfrc.Floquet)
    assert isinstance(floquet.computed, bool)
    assert isinstance(floquet.method, str) and isinstance(floquet.message, str)
    assert isinstance(floquet.max_modulus, float) and isinstance(floquet.num_unstable, int)
    assert all(isinstance(mu, complex) for mu in floquet.multipliers)
    assert all(isinstance(s, complex) for s in floquet.exponents)
    assert floquet.stable == stable
    if not floquet.computed:
        assert stable is None
        return
    assert isinstance(stable, bool) and stable == (floquet.num_unstable == 0)
    assert floquet.method != "hill" or floquet.operator_applications > 0
    moduli = [abs(mu) for mu in floquet.multipliers]
    assert moduli == sorted(moduli, reverse=True)
    assert math.isclose(floquet.max_modulus, moduli[0])


def check_bifurcation(bifurcation, branch):
    assert isinstance(bifurcation, nfrc.Bifurcation)
    assert bifurcation.type in TYPES
    assert isinstance(bifurcation.omega, float) and isinstance(bifurcation.omega_accuracy, float)
    assert isinstance(bifurcation.converged, bool) and isinstance(bifurcation.iterations, int)
    assert 0 <= bifurcation.after_point < branch.points
    assert all(isinstance(mu, complex) for mu in bifurcation.crossing_multipliers)
    measures = bifurcation.measures
    assert set(measures) == {"energy", "max_abs", "min", "max", "h1"}
    assert bifurcation.measure("max_abs", 0) == measures["max_abs"][0]
    with pytest.raises(nfrc.InputError, match="not recorded at bifurcations"):
        bifurcation.measure("law0_epsilon")


@pytest.mark.parametrize("enabled", [False, True])
def test_branch_carries_floquet_results_and_bifurcations(enabled):
    branch = nfrc.trace(nfrc.Case.from_dict(duffing_dict(enabled=enabled)))
    assert branch.points > 10
    stable, floquet = branch.stable, branch.floquet
    assert len(stable) == len(floquet) == branch.points
    for flag, result in zip(stable, floquet):
        check_floquet(result, flag)
    if not enabled:
        assert stable == [None] * branch.points
        assert not any(result.computed for result in floquet)
        assert branch.bifurcations == []
    for bifurcation in branch.bifurcations:
        check_bifurcation(bifurcation, branch)
    omegas = [b.after_point for b in branch.bifurcations]
    assert omegas == sorted(omegas)  # in branch order


def test_nfrc_run_writes_what_python_reads(build_dir, tmp_path):
    case_file = tmp_path / "duffing.json"
    case_file.write_text(json.dumps(duffing_dict(enabled=True)))
    out = tmp_path / "out"
    subprocess.run([str(build_dir / "nfrc"), "run", str(case_file), "--out", str(out)],
                   check=True, capture_output=True)
    written = json.loads((out / "branch.json").read_text())
    branch = nfrc.trace(nfrc.load_case(case_file))
    assert written["stability"]["enabled"] is True
    assert [p["stable"] for p in written["points"]] == branch.stable
    for point, result in zip(written["points"], branch.floquet):
        if result.computed:
            assert point["floquet"]["unstable"] == result.num_unstable
            np.testing.assert_allclose([complex(*mu) for mu in point["floquet"]["multipliers"]],
                                       result.multipliers)
        else:
            assert point["floquet"] is None
    assert [b["type"] for b in written["bifurcations"]] == [b.type for b in branch.bifurcations]
    header = (out / "branch.csv").read_text().splitlines()[0].split(",")
    assert header[-3:] == ["stable", "max_multiplier", "unstable"]


def test_switch_branch_follows_the_period_doubling_in_forcing_frequency(source_dir):
    """The escape oscillator's period doubling (the C++ branch_switching test checks the
    period-2 orbit against a transient): here, that Python gets the same branch, with omega
    as the forcing frequency (2 x the continuation parameter) and the next doubling on it."""
    case = nfrc.load_case(source_dir / "cases/escape_oscillator.json")
    branch = nfrc.trace(case)
    doublings = [b for b in branch.bifurcations if b.type == "period_doubling"]
    assert len(doublings) == 1
    pd = doublings[0]
    period2 = nfrc.switch_branch(case, pd)
    assert period2.period_multiple == 2
    assert period2.summary.success
    # It starts 0.2 % beside the doubling, on the side where period 1 is unstable.
    assert pd.omega * 0.99 < period2.omega[0] < pd.omega
    assert all(np.diff(period2.omega) < 0)
    again = [b for b in period2.bifurcations if b.type == "period_doubling"]
    assert again and again[0].omega < pd.omega
    assert period2.quasi_periodic_windows == []
    with pytest.raises(nfrc.InputError, match="bifurcation: a fold"):
        duffing = nfrc.load_case(source_dir / "cases/duffing.json")
        nfrc.switch_branch(duffing, nfrc.trace(duffing).bifurcations[0])


def test_validate_reports_hill_next_to_the_transient_monodromy(source_dir):
    """Duffing inside its fold: three solutions, the middle one unstable by both methods,
    and Hill within 1e-6 of the monodromy (the bar of the C++ stability test)."""
    case = nfrc.load_case(source_dir / "cases/duffing.json")
    result = nfrc.validate(case, omegas=[1.2])
    solutions = result["points"][0]["solutions"]
    assert len(solutions) == 3
    for s in solutions:
        assert isinstance(s["hill"], nfrc.Floquet) and s["monodromy"]["ok"]
        assert s["difference_to_monodromy"] < 1e-6
        transient_stable = s["monodromy"]["max_modulus"] < 1.0
        assert s["hill"].stable == transient_stable
    assert [s["hill"].stable for s in solutions].count(False) == 1


def test_validate_jenkins_starts_on_the_orbit_and_hill_with_memory_equals_the_monodromy(source_dir):
    """The Jenkins oscillator (k_t = 10) at 0.4: the transient starts with the HBM slider
    force (closure 1.7e-5; 0.15 with the slider at rest), and Hill's multipliers with the stick
    memory match the monodromy's (6e-5 measured; 0.11 in max |mu| without the memory)."""
    case = nfrc.load_case(source_dir / "cases/validation/jenkins_n10.json")
    result = nfrc.validate(case, omegas=[0.4])
    (solution,) = result["points"][0]["solutions"]
    monodromy = solution["monodromy"]
    assert monodromy["ok"] and monodromy["closure"] < 1e-3
    assert isinstance(monodromy["state_own"], list)  # a sticking slider's force, if free at t = 0
    assert abs(solution["hill"].max_modulus - monodromy["max_modulus"]) < 5e-3
