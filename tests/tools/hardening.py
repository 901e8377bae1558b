#!/usr/bin/env python3
"""End-to-end checks of what an interrupted, concurrent or oversized use of the nfrc program
does: a stop signal takes effect within a Newton iteration, a sweep's run folders are locked
and a finished sweep's are not overwritten, studies killed part-way keep what they found, an
interrupted validation says so, and a manifest of 10 000 members costs what one member does.

usage: hardening.py NFRC_BINARY SOURCE_DIR [SLOWDOWN]
SLOWDOWN (default 1) scales the time bounds for instrumented builds (AddressSanitizer at -O1
runs the dense linear algebra about ten times slower)."""

import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

NFRC, SRC = sys.argv[1], sys.argv[2]
SLOWDOWN = float(sys.argv[3]) if len(sys.argv) > 3 else 1.0
WORK = tempfile.mkdtemp(prefix="nfrc_hardening_")
FAILURES = []


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        FAILURES.append(what)


def case(name):
    with open(os.path.join(SRC, "cases", name)) as f:
        return json.load(f)


def write(name, content):
    path = os.path.join(WORK, name)
    with open(path, "w") as f:
        json.dump(content, f)
    return path


def run(*args, timeout=600):
    return subprocess.run([NFRC, *args], capture_output=True, text=True, timeout=timeout)


def start(*args):
    """A background nfrc whose stderr goes to a file; SIGINT restored to its default (a script's
    background job inherits it ignored, which nfrc respects)."""
    err = tempfile.NamedTemporaryFile(dir=WORK, delete=False, suffix=".err")
    process = subprocess.Popen([NFRC, *args], stdout=subprocess.DEVNULL, stderr=err,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    return process, err.name


def wait_for(path, text, process, limit):
    """Until the file holds `text` (True) or the process ended or `limit` seconds passed."""
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        with open(path) as f:
            if text in f.read():
                return True
        if process.poll() is not None:
            return False
        time.sleep(0.005)
    return False


def load(path):
    with open(path) as f:
        return json.load(f)


def test_stop_within_a_newton_iteration():
    # The two-DOF friction oscillator at N_phi = 2560 coefficients: its start's last rung is a
    # Newton solve of 2560 unknowns (about 1.5 s in Release, 10 iterations), with no point in
    # between: a stop request read only between points waited for all of it and the first point.
    fine = case("friction/point_e.json")
    fine["harmonics"] = {"max": 1279, "odd_only": True}
    fine["continuation"]["omega_start"] = 0.75
    del fine["output"]["signals_at"]
    path = write("fine.json", fine)
    out = os.path.join(WORK, "fine")
    process, err = start("run", path, "--out", out, "--threads", "0")
    reached = wait_for(err, "start at H=425", process, 300 * SLOWDOWN)
    check(reached, "stop: the fine start reached its last rung")
    if not reached:
        process.kill()
        return
    signalled = time.monotonic()
    process.send_signal(signal.SIGTERM)
    code = process.wait(timeout=600)
    latency = time.monotonic() - signalled
    print(f"     SIGTERM to exit: {latency:.2f} s", flush=True)
    check(code == 3, f"stop: exit 3 after SIGTERM (got {code})")
    # Read between points only, the stop waited for the rung's remaining iterations and wrote
    # its point first: a point on disk says so whatever the machine's load.
    check(latency <= 1.0 * SLOWDOWN, f"stop: SIGTERM took effect within {SLOWDOWN:g} s")
    branch = load(os.path.join(out, "branch.json"))
    check(len(branch["points"]) == 0,
          f"stop: the interrupted start wrote no point (got {len(branch['points'])})")
    summary = branch["summary"]
    check(summary["termination"] == "stopped_by_observer" and
          "interrupted" in summary["message"], "stop: branch.json says it was interrupted")


def test_run_folders_are_locked():
    sweep_dir = os.path.join(WORK, "locked_sweep")
    point_e = os.path.join(SRC, "cases", "friction", "point_e.json")
    process, err = start("sweep", point_e, "--parameter", "nonlinearities[0].normal_load",
                         "--values", "10,10.5,11", "--out", sweep_dir)
    # A sweep reports each run as it ends: after run 0 the next one is being traced.
    busy = wait_for(err, "nfrc: run 0 (", process, 120 * SLOWDOWN)
    check(busy and process.poll() is None, "lock: the sweep is running")
    duffing = os.path.join(SRC, "cases", "duffing_h1.json")
    # Run 2's folder: not begun yet, so only the sweep's lock on its directory guards it.
    inner = run("run", duffing, "--out", os.path.join(sweep_dir, "2"))
    check(inner.returncode == 1 and "lies inside" in inner.stderr and sweep_dir in inner.stderr,
          "lock: nfrc run into a running sweep's run folder is refused (exit 1, naming it): "
          + inner.stderr.strip()[:200])
    process.send_signal(signal.SIGTERM)
    process.wait(timeout=600)
    after = run("run", duffing, "--out", os.path.join(sweep_dir, "0"))
    check(after.returncode == 1 and "run folder of a sweep" in after.stderr,
          "lock: nfrc run into a stopped sweep's run folder is refused: "
          + after.stderr.strip()[:200])
    # The other way: a sweep into a directory holding a running run's folder.
    outer = os.path.join(WORK, "outer")
    process, err = start("run", point_e, "--out", os.path.join(outer, "inner"))
    busy = wait_for(err, "point 1 ", process, 60 * SLOWDOWN)
    refused = run("sweep", duffing, "--parameter", "model.forcing[0].cos", "--values", "0.1",
                  "--out", outer)
    check(busy and refused.returncode == 1 and "inside it" in refused.stderr,
          "lock: a sweep into a directory a run writes inside is refused: "
          + refused.stderr.strip()[:200])
    process.send_signal(signal.SIGTERM)
    process.wait(timeout=600)


def test_killed_studies_keep_their_points():
    # A fold curve killed (SIGKILL: no handler, no last write) part-way: fold_curve.json,
    # rewritten as points come, keeps those of the last second. Duffing with 61 harmonics:
    # its fold curve takes about 10 s.
    duffing = case("duffing.json")
    duffing["harmonics"] = {"max": 61, "samples": 512}
    out = os.path.join(WORK, "fold_killed")
    process, err = start("fold-curve", write("duffing_h61.json", duffing), "--parameter",
                         "model.forcing[0].cos", "--to", "0.03", "--max-step", "0.002",
                         "--out", out)
    following = wait_for(err, "following", process, 120 * SLOWDOWN)
    time.sleep(2.5)
    alive = process.poll() is None
    process.kill()
    process.wait()
    document = load(os.path.join(out, "fold_curve.json"))
    check(following and alive, "fold curve: killed while following a fold")
    check(len(document["points"]) > 0 and document["status"] == "running",
          f"fold curve: {len(document['points'])} points kept after SIGKILL, status running")

    # A refinement killed after its third step keeps its steps in refinement.json.
    out = os.path.join(WORK, "refine_killed")
    process, err = start("refine", os.path.join(SRC, "cases", "rod", "rigid.json#nh40"),
                         "--omega", "63953.9", "--epsilon0", "1e9", "--steps", "40", "--out", out)
    stepping = True
    for _ in range(3):
        stepping = stepping and wait_for(err, "refine: epsilon", process, 300 * SLOWDOWN)
    deadline = time.monotonic() + 60 * SLOWDOWN
    while stepping and process.poll() is None and time.monotonic() < deadline:
        steps = load(os.path.join(out, "refinement.json"))["steps"]
        if len(steps) >= 2:
            break
        time.sleep(0.05)
    process.kill()
    process.wait()
    document = load(os.path.join(out, "refinement.json"))
    check(len(document["steps"]) >= 2 and document["status"] == "running",
          f"refine: {len(document['steps'])} steps kept after SIGKILL, status running")


def test_interrupted_validation():
    # A transient that never settles (steady_tolerance below rounding): 20 000 periods, stopped
    # by SIGINT a moment after it begins.
    duffing = case("duffing.json")
    duffing["validation"] = {"transient": {"steady_tolerance": 1e-30, "max_periods": 20000},
                             "monodromy": {"enabled": False}}
    path = write("duffing_long_transient.json", duffing)
    out = os.path.join(WORK, "validate_interrupted")
    process, err = start("validate", path, "--omega", "1.2", "--start", "rest", "--no-chirp",
                         "--no-plot", "--out", out)
    reached = wait_for(err, "HBM solution", process, 120 * SLOWDOWN)
    time.sleep(0.5)
    signalled = time.monotonic()
    process.send_signal(signal.SIGINT)
    code = process.wait(timeout=600)
    latency = time.monotonic() - signalled
    document = load(os.path.join(out, "validation.json"))
    check(reached and code == 3, f"validate: exit 3 after SIGINT (got {code})")
    check(latency <= 1.0 * SLOWDOWN, f"validate: SIGINT took effect in {latency:.2f} s")
    check(document.get("interrupted") is True and document.get("status") == "interrupted",
          "validate: validation.json says it was interrupted")
    transients = document["points"][0]["transients"] if document["points"] else []
    check(len(transients) == 1 and transients[0].get("status") == "interrupted",
          "validate: the interrupted transient is kept with its status")


def chain_case(n):
    """A fixed-free chain of n unit masses and springs, its matrices written inline (3 n^2
    numbers: a base case whose every copy is costly), a cubic spring at the tip."""
    k = [[0.0] * n for _ in range(n)]
    for i in range(n):
        k[i][i] = 2.0 if i + 1 < n else 1.0
        if i + 1 < n:
            k[i][i + 1] = k[i + 1][i] = -1.0
    return {"title": f"chain of {n}",
            "model": {"type": "matrices",
                      "M": [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)],
                      "K": k, "C": [[0.01 * v for v in row] for row in k],
                      "forcing": [{"dof": n - 1, "cos": 0.01}]},
            "nonlinearities": [{"type": "cubic_spring", "dof": n - 1, "coefficient": 0.1}],
            "harmonics": {"max": 1, "odd_only": True, "samples": 16},
            "continuation": {"omega_start": 0.01, "omega_end": 0.05},
            "stability": {"enabled": False},
            "output": {"dofs": [n - 1]}}


def test_manifest_of_ten_thousand_members():
    # A 100 x 100 grid over a base of 10 800 inline matrix entries: reading the manifest must
    # not build the members (building each copied the base, ten thousand times); a member then
    # runs in about the time of the base itself.
    base_path = write("chain_base.json", chain_case(60))
    manifest = write("grid.json", {
        "manifest": "10 000 members", "base": base_path,
        "parameters": [{"path": "model.forcing[0].cos",
                        "values": [0.0001 * (i + 1) for i in range(100)]},
                       {"path": "model.C[0][0]", "values": [0.02 + 0.001 * i for i in range(100)]}]})

    def best(argv):
        times = []
        for attempt in range(2):
            begun = time.monotonic()
            result = run(*argv, "--out", os.path.join(WORK, f"member_{attempt}"))
            times.append(time.monotonic() - begun)
            check(result.returncode == 0, f"manifest: {argv[1]} ran")
        return min(times)

    member = best(["run", manifest + "#9999"])
    alone = best(["run", base_path])
    print(f"     member of the 10 000 grid {member:.2f} s, the base alone {alone:.2f} s")
    # Building every member copied the base's 10 800 numbers 10 000 times: seconds, and
    # gigabytes. The allowance of 1 s covers a shared machine's noise (other tests run
    # beside this one), not that.
    check(member <= 1.5 * alone + 1.0 * SLOWDOWN,
          "manifest: one member of 10 000 costs about one case")


def main():
    try:
        test_stop_within_a_newton_iteration()
        test_run_folders_are_locked()
        test_killed_studies_keep_their_points()
        test_interrupted_validation()
        test_manifest_of_ten_thousand_members()
    finally:
        shutil.rmtree(WORK, ignore_errors=True)
    print(f"{len(FAILURES)} failed" if FAILURES else "all hardening checks passed")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
