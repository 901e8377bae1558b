"""The plotting scripts draw stability from branch.json: unstable parts dashed, bifurcations
marked by type. A hand-made branch.json stands in for the analysis's output."""

import json
import subprocess
import sys

import pytest


@pytest.fixture
def tools(source_dir):
    sys.path.insert(0, str(source_dir / "tools"))
    yield source_dir / "tools"
    sys.path.remove(str(source_dir / "tools"))


def test_stability_runs_split_where_stability_changes(tools):
    from nfrc_output import stability_runs
    omega = [0, 1, 2, 3, 4, 5]
    runs = stability_runs(omega, omega, [True, True, False, False, True, True])
    # Segments touching an unstable point are dashed; runs share their end points.
    assert [(r[0], r[2]) for r in runs] == [([0, 1], False), ([1, 2, 3, 4], True),
                                            ([4, 5], False)]
    # Not analysed (None) draws as before: one solid run.
    assert stability_runs(omega, omega, [None] * 6) == [(omega, omega, False)]
    assert stability_runs([1.0], [2.0], [False]) == [([1.0], [2.0], False)]
    assert stability_runs([], [], []) == []


def fake_branch(directory, with_stability):
    points = []
    for i in range(30):
        omega = 0.5 + 0.04 * i
        a = 1.0 / (1.0 + (omega - 1.0) ** 2)
        stable = (not 10 <= i < 20) if with_stability else None
        floquet = {"max_modulus": 0.9 if stable else 1.2, "unstable": 0 if stable else 1,
                   "method": "hill", "multipliers": [[0.9, 0.0]]} if with_stability else None
        points.append({"index": i, "omega": omega, "energy": a * a, "max_abs": [a], "min": [-a],
                       "max": [a], "h1": [a], "stable": stable, "floquet": floquet})

    def bifurcation(kind, i):
        p = points[i]
        return {"type": kind, "omega": p["omega"], "omega_accuracy": 1e-8, "converged": True,
                "iterations": 3, "after_point": i, "crossing_multipliers": [[-1.0, 0.0]],
                "energy": p["energy"], "max_abs": p["max_abs"], "min": p["min"],
                "max": p["max"], "h1": p["h1"]}

    bifurcations = [bifurcation("period_doubling", 9), bifurcation("neimark_sacker", 19),
                    bifurcation("branch_point", 25)] if with_stability else []
    document = {"program": "nfrc", "output_dofs": ["x"], "case": {"title": "fake"},
                "points": points, "folds": [], "bifurcations": bifurcations,
                "summary": {"termination": "reached_lambda_bound"}}
    directory.mkdir()
    (directory / "branch.json").write_text(json.dumps(document))


@pytest.mark.parametrize("with_stability", [True, False])
def test_plot_frc_draws_a_branch_with_and_without_stability(tools, tmp_path, with_stability,
                                                            subprocess_env):
    out = tmp_path / "run"
    fake_branch(out, with_stability)
    for measure in ["max_abs", "energy"]:
        subprocess.run([sys.executable, str(tools / "plot_frc.py"), str(out), "--measure",
                        measure], check=True, capture_output=True, env=subprocess_env)
        assert (out / "frc.png").stat().st_size > 1000


def test_legend_lists_only_the_bifurcation_types_present(tools):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from nfrc_output import mark_bifurcations
    figure, axes = plt.subplots()
    labelled = set()
    bifurcations = [{"type": "neimark_sacker", "omega": 1.0, "h1": [1.0]},
                    {"type": "neimark_sacker", "omega": 1.1, "h1": [1.1]},
                    {"type": "fold", "omega": 1.2, "h1": [1.2]}]
    mark_bifurcations(axes, bifurcations, lambda b: b["h1"][0], "black", labelled)
    mark_bifurcations(axes, bifurcations, lambda b: b["h1"][0], "red", labelled)  # a second DOF
    labels = [line.get_label() for line in axes.get_lines()
              if not line.get_label().startswith("_")]
    assert labels == ["fold", "Neimark–Sacker"]
    plt.close(figure)
