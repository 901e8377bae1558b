"""nfrc_bench's arguments: a typo is an error naming it (exit 2), never a run of nothing, and
case=TEXT runs only the acceptance cases whose name contains TEXT, nostability traces them
without Hill's analyses."""

import re
import subprocess
import sys


def run(bench, *args):
    return subprocess.run([bench, *args], capture_output=True, text=True, timeout=600)


def main(bench):
    failures = []

    def check(condition, what):
        if not condition:
            failures.append(what)

    for bad, said in [("acuracy", 'unknown argument "acuracy"'),
                      ("16", 'unknown argument "16"'),
                      ("0", 'unknown argument "0"'),
                      ("9x", 'unknown argument "9x"'),
                      ("runs=0", "runs=0 needs a whole number from 1 to 1000"),
                      ("threads=two", "threads=two needs a whole number")]:
        result = run(bench, bad)
        check(result.returncode == 2, f"{bad}: exit {result.returncode}, expected 2")
        check(said in result.stderr, f"{bad}: stderr {result.stderr!r} lacks {said!r}")
        check("calibration" not in result.stdout, f"{bad}: ran something")

    result = run(bench, "9", "case=no_such_case")
    check(result.returncode == 2, f"case=no_such_case: exit {result.returncode}")
    check("case=no_such_case names no case of section 9" in result.stderr
          and '"friction/point_e.json"' in result.stderr,
          f"case=no_such_case: stderr {result.stderr!r}")
    check("calibration" not in result.stdout, "case=no_such_case: ran something")

    result = run(bench, "1", "case=duffing")
    check(result.returncode == 2 and "section 9, which is not run" in result.stderr,
          f"case= without section 9: exit {result.returncode}, stderr {result.stderr!r}")

    # One small case: it runs, and no other case does.
    result = run(bench, "9", "case=duffing")
    check(result.returncode == 0, f"9 case=duffing: exit {result.returncode}: {result.stderr}")
    check("duffing.json: reached_lambda_bound" in result.stdout,
          f"9 case=duffing did not run Duffing: {result.stdout!r}")
    for other in ["one_dof_coulomb", "nlvib", "fig7", "point_e", "rod/", "N_phi = 640"]:
        check(other not in result.stdout, f"9 case=duffing also ran {other}")

    # nostability: the same trace (stability does not steer it) without Hill's analyses, so
    # without the bifurcations that the default run finds at Duffing's two folds.
    with_stability = re.search(r"(\d+) points, .* (\d+) bifurcations", result.stdout)
    result = run(bench, "9", "case=duffing", "nostability")
    check(result.returncode == 0, f"9 case=duffing nostability: exit {result.returncode}")
    without = re.search(r"(\d+) points, .* (\d+) bifurcations", result.stdout)
    check("stability off" in result.stdout and with_stability is not None and without is not None
          and without.group(1) == with_stability.group(1) and int(with_stability.group(2)) > 0
          and without.group(2) == "0",
          f"9 case=duffing nostability: {result.stdout!r}")

    for failure in failures:
        print("FAILED:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
