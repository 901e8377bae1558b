"""solve_at: every solution at one omega, with coefficients and time signals."""

import numpy as np
import pytest

import nfrc


def test_duffing_has_three_solutions_at_1_2(source_dir):
    case = nfrc.load_case(source_dir / "cases/duffing.json")
    solutions = nfrc.solve_at(case, 1.2)
    assert len(solutions) == 3
    by_label = {s.label: s for s in solutions}
    assert set(by_label) == {"lower", "middle", "upper"}  # by period-mean energy
    energies = [by_label[k].measure("energy") for k in ("lower", "middle", "upper")]
    assert energies == sorted(energies)
    branch = nfrc.trace(case)
    amplitude = branch.measure("max_abs")
    for s in solutions:
        assert s.omega == 1.2 and s.converged
        assert s.coefficients.shape == (1, case.harmonics.num_coefficients)
        np.testing.assert_array_equal(s.coefficients[0], s.y[:15])
        assert set(s.signals) == {"theta", "t", "x_0", "v_0"}
        np.testing.assert_allclose(s.signals["t"], s.signals["theta"] / 1.2)
        x = s.signals["x_0"]
        assert s.measure("max_abs") == pytest.approx(np.abs(x).max(), rel=1e-12)
        # Between the two branch points around the crossing.
        a, b = amplitude[s.after_point], amplitude[s.after_point + 1]
        assert min(a, b) - 1e-9 <= s.measure("max_abs") <= max(a, b) + 1e-9
    assert len({round(s.measure("max_abs"), 6) for s in solutions}) == 3


def test_friction_solution_signals(source_dir):
    case = nfrc.load_case(source_dir / "cases/friction/convergence_e.json#nphi10")
    (solution,) = nfrc.solve_at(case, 0.3085)
    assert solution.label == "only" and isinstance(solution.phases, list)
    assert solution.coefficients.shape == (2, 10)
    assert {"x_x1", "v_x2", "law0_force", "law0_velocity"} <= set(solution.signals)
    force = solution.signals["law0_force"]
    assert np.abs(force).max() <= 9.0 * 1.2  # |r| <= mu N, up to truncation ripple
    assert 0.0 <= solution.measure("law0_stick_fraction") <= 1.0


def test_omega_outside_the_range(source_dir):
    case = nfrc.load_case(source_dir / "cases/duffing.json")
    with pytest.raises(nfrc.InputError, match="omega"):
        nfrc.solve_at(case, 2.0)


def test_validate_duffing_transients_match_the_hbm_and_the_middle_solution_leaves(source_dir):
    # Independent reference: IDA transients started on each HBM solution. Inside the folds
    # (ω = 1.2) the lower and upper solutions are stable (the transient stays) and the middle
    # one is not; where they stay, the first harmonics agree to the HBM truncation (~1e-7).
    case = nfrc.load_case(source_dir / "cases/duffing.json")
    result = nfrc.validate(case, [1.2])
    assert result["complete"]
    (point,) = result["points"]
    assert sorted(s["label"] for s in point["solutions"]) == ["lower", "middle", "upper"]
    stayed = {t["start"]: t.get("stayed") for t in point["transients"]}
    assert stayed["hbm lower"] and stayed["hbm upper"] and not stayed["hbm middle"]
    for t in point["transients"]:
        if t.get("stayed"):
            assert max(t["difference"]["h1"]) < 1e-5
