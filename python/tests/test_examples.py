"""The examples run (small configurations) and write their figures."""

import subprocess
import sys

import pytest

EXAMPLES = {
    "friction_study.py": ["--loads", "8,12", "--harmonics", "15", "--samples", "128"],
    "rod_contact_study.py": ["--gaps", "3e-4,4e-4"],
}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_example(name, source_dir, subprocess_env, tmp_path):
    output = tmp_path / "figure.png"
    run = subprocess.run([sys.executable, str(source_dir / "python/examples" / name),
                          str(output)] + EXAMPLES[name],
                         capture_output=True, text=True, env=subprocess_env, timeout=300)
    assert run.returncode == 0, run.stderr
    assert output.stat().st_size > 10000
    assert run.stdout.count("reached_lambda_bound") == 2, run.stdout
