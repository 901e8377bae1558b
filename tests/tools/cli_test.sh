#!/usr/bin/env bash
# End-to-end checks of the nfrc program: exit codes, messages and files on disk.
# usage: cli_test.sh NFRC_BINARY SOURCE_DIR
set -u
nfrc=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0

expect() {  # expect NAME EXIT_CODE MESSAGE_SUBSTRING -- command...
  local name=$1 code=$2 message=$3
  shift 4
  "$@" >"$work/out" 2>"$work/err"
  local got=$?
  if [ "$got" -ne "$code" ] || ! grep -qF -- "$message" "$work/err" "$work/out"; then
    echo "FAIL $name: exit $got (want $code), output:"; cat "$work/err" "$work/out"
    failures=$((failures + 1))
  else
    echo "ok   $name"
  fi
}

expect "usage" 2 "usage:" -- "$nfrc"
expect "unknown command" 2 "unknown command" -- "$nfrc" frobnicate
expect "missing --out" 2 "needs a case file and --out DIR" -- "$nfrc" run "$src/cases/duffing.json"
expect "missing case" 1 "cannot open case file" -- "$nfrc" run "$work/none.json" --out "$work/o"
expect "invalid json" 1 "not valid JSON" -- "$nfrc" run "$src/tests/tools/data/not_json.json" --out "$work/o"
expect "singular model" 1 "model: the linear dynamic stiffness is singular" -- \
  "$nfrc" run "$src/tests/tools/data/singular.json" --out "$work/o"

expect "duffing run" 0 "2 folds" -- "$nfrc" run "$src/cases/duffing.json" --out "$work/duffing"
for f in branch.json branch.csv; do
  [ -s "$work/duffing/$f" ] || { echo "FAIL duffing run: $f missing"; failures=$((failures + 1)); }
done
grep -q "omega=" "$work/err" || { echo "FAIL progress lines missing on stderr"; failures=$((failures + 1)); }
# Hill's analyses beside the trace change the time, never the results: the same CSV and the
# same branch.json but for its wall time, with and without threads.
for threads in 0 3; do
  expect "nlvib --threads $threads" 0 "points" -- "$nfrc" run "$src/cases/contact/nlvib.json#penalty" \
    --out "$work/nlvib_$threads" --threads "$threads"
done
cmp -s "$work/nlvib_0/branch.csv" "$work/nlvib_3/branch.csv" ||
  { echo "FAIL --threads 0 and 3 wrote different branch.csv"; failures=$((failures + 1)); }
diff <(grep -v wall_time_s "$work/nlvib_0/branch.json") <(grep -v wall_time_s "$work/nlvib_3/branch.json") \
  >/dev/null || { echo "FAIL --threads 0 and 3 wrote different branch.json"; failures=$((failures + 1)); }
grep -q neimark_sacker "$work/nlvib_3/branch.json" ||
  { echo "FAIL nlvib: no Neimark-Sacker point in branch.json"; failures=$((failures + 1)); }
expect "duffing fold curve" 0 "wrote $work/fc/fold_curve.json" -- "$nfrc" fold-curve \
  "$src/cases/duffing.json" --parameter "model.forcing[0].cos" --to 0.03 --out "$work/fc"
/usr/bin/python3 - "$work/fc/fold_curve.json" <<'PY' || { echo "FAIL fold_curve.json"; failures=$((failures + 1)); }
import json, sys
d = json.load(open(sys.argv[1]))
assert d["parameter"] == "model.forcing[0].cos" and d["from"] == 0.18 and d["to"] == 0.03
assert len(d["cusps"]) == 1 and len(d["points"]) > 10, d["cusps"]
assert all(set(p) >= {"parameter", "omega", "energy", "max_abs_0"} for p in d["points"])
PY
expect "duffing peak curve" 0 "wrote $work/pc/peak_curve.json" -- "$nfrc" fold-curve \
  "$src/cases/duffing_h1.json" --kind peak --measure h1:0 --parameter "model.forcing[0].cos" \
  --to 0.1 --at 0.12 --out "$work/pc"
grep -q "nfrc: peak 0 point" "$work/err" || { echo "FAIL peak curve progress"; failures=$((failures + 1)); }
/usr/bin/python3 - "$work/pc/peak_curve.json" <<'PY' || { echo "FAIL peak_curve.json"; failures=$((failures + 1)); }
import json, math, sys
d = json.load(open(sys.argv[1]))
assert d["measure"] == "h1_0" and d["branch_events"] == 1 and d["from"] == 0.18
(curve,) = d["curves"]
assert curve["termination"] == "reached_to", curve
# The one-harmonic maximum: k - w^2 + b A^2 = c^2/2, (c^4/4 + c^2 w^2) A^2 = P^2 (c 0.05, b 0.075).
c, b = 0.05, 0.075
for p in d["points"]:
    q = c * c - c ** 4 / 4
    a = (-q + math.sqrt(q * q + 4 * c * c * b * p["parameter"] ** 2)) / (2 * c * c * b)
    assert abs(p["omega"] - math.sqrt(1 + b * a - c * c / 2)) < 1e-7, p
assert [p["parameter"] for p in d["points"]].count(0.12) == 1
PY
expect "nes neimark-sacker curve" 0 "wrote $work/ns/neimark_sacker_curve.json" -- "$nfrc" \
  fold-curve "$src/cases/nes_neimark_sacker.json" --kind neimark_sacker \
  --parameter "model.forcing[0].cos" --to 0.01 --out "$work/ns"
/usr/bin/python3 - "$work/ns/neimark_sacker_curve.json" <<'PY' || { echo "FAIL neimark_sacker_curve.json"; failures=$((failures + 1)); }
import json, sys
d = json.load(open(sys.argv[1]))
assert d["branch_events"] == 2 and len(d["curves"]) == 2, d["curves"]
assert all(c["termination"] == "reached_to" for c in d["curves"])
ends = sorted(p["omega"] for p in d["points"] if p["parameter"] == 0.01)
# The fixed-forcing trace at P = 0.01 localises them at 0.955933 and 1.05962.
assert abs(ends[0] - 0.955933) < 1e-5 and abs(ends[1] - 1.05962) < 1e-5, ends
PY

# Contact: the issue's rigid rod case runs as written; refine validates its input.
expect "rigid rod run" 0 "reached_lambda_bound" -- \
  "$nfrc" run "$src/cases/rod/rigid_nh20.json" --out "$work/rigid"
grep -q '"min_gap"' "$work/rigid/branch.json" ||
  { echo "FAIL rigid rod: points lack min_gap"; failures=$((failures + 1)); }
expect "refine without omega" 2 "needs --omega" -- \
  "$nfrc" refine "$src/cases/rod/rigid_nh20.json" --out "$work/r"
expect "refine omega outside range" 1 "omega: must lie in the case's range" -- \
  "$nfrc" refine "$src/cases/rod/rigid_nh20.json" --omega 1e6 --epsilon0 1e9 --out "$work/r"
expect "refine bad epsilon" 2 "--epsilons: not a number" -- \
  "$nfrc" refine "$src/cases/rod/rigid_nh20.json" --omega 6e4 --epsilons 1e9,abc --out "$work/r"
expect "refine without dlft" 1 "refinement needs a dlft_contact law" -- \
  "$nfrc" refine "$src/cases/duffing.json" --omega 1.2 --epsilons 1 --out "$work/r"
expect "refine" 0 "3 of 3 refinement steps" -- \
  "$nfrc" refine "$src/cases/rod/rigid_nh20.json" --omega 63953 --epsilons 1e9,2e9,4e9 --out "$work/r"
for f in refinement.json samples_0.csv signals_2.csv lcp/samples_0.csv; do
  [ -s "$work/r/$f" ] || { echo "FAIL refine: $f missing"; failures=$((failures + 1)); }
done
expect "contact bad field" 1 "nonlinearities[0].obstacle_stiffness: must be finite and > 0" -- \
  "$nfrc" run "$src/tests/tools/data/bad_obstacle.json" --out "$work/o"

grep -q '"distance_to_lcp"' "$work/r/refinement.json" ||
  { echo "FAIL refine: steps lack distance_to_lcp"; failures=$((failures + 1)); }

# LCP-HBM: Lemke stepping runs and records its solver data; bad set-ups name the field.
expect "lemke stepping" 0 "152 of 152 frequencies solved" -- \
  "$nfrc" run "$src/cases/lcp/rigid_stepping_nt400.json" --out "$work/lcp"
grep -q '"coexisting_contact"' "$work/lcp/branch.json" ||
  { echo "FAIL lemke stepping: points lack lcp data"; failures=$((failures + 1)); }
[ -s "$work/lcp/samples_0.csv" ] || { echo "FAIL lemke stepping: samples_0.csv missing"; failures=$((failures + 1)); }
expect "lcp oversampled arclength" 1 "harmonics.samples: lcp_contact on an arclength branch needs square" -- \
  "$nfrc" run "$src/tests/tools/data/lcp_oversampled.json" --out "$work/o"
expect "lemke stepping with dlft" 1 "nonlinearities[0]: LCP-HBM needs every law to be lcp_contact" -- \
  "$nfrc" run "$src/tests/tools/data/stepping_dlft.json" --out "$work/o"

# Transient validation: input errors name the option or field; a Duffing run writes its files.
expect "validate without out" 2 "needs a case file and --out DIR" -- \
  "$nfrc" validate "$src/cases/duffing.json" --omega 1
expect "validate bad omega" 2 "--omega: not a number" -- \
  "$nfrc" validate "$src/cases/duffing.json" --omega 1,x --out "$work/v"
expect "validate bad start" 2 "--start: expected one of hbm|rest" -- \
  "$nfrc" validate "$src/cases/duffing.json" --omega 1 --start cold --out "$work/v"
expect "validate no omega" 1 "no frequencies to validate" -- \
  "$nfrc" validate "$src/cases/duffing.json" --out "$work/v"
sed 's/"output"/"validation": {"transient": {"steady_tolerance": -1}}, "output"/' \
  "$src/cases/duffing.json" > "$work/bad_validation.json"
expect "validate bad field" 1 "validation.transient.steady_tolerance" -- \
  "$nfrc" validate "$work/bad_validation.json" --omega 1 --out "$work/v"
expect "validate duffing" 0 "wrote $work/v/validation.json" -- \
  "$nfrc" validate "$src/cases/duffing.json" --omega 0.8,1.2 --start rest --out "$work/v"
grep -q "periodic" "$work/out" || { echo "FAIL validate table missing"; failures=$((failures + 1)); }
for f in validation.json signals_0.csv signals_0.png validation.png hbm/branch.json; do
  [ -s "$work/v/$f" ] || { echo "FAIL validate: $f missing"; failures=$((failures + 1)); }
done

# Writing: a branch.csv that is a link to /dev/full is refused (never written through), and a
# directory another run holds is refused at once.
mkdir -p "$work/full" && ln -s /dev/full "$work/full/branch.csv"
expect "branch.csv linked to /dev/full" 4 "branch.csv" -- \
  "$nfrc" run "$src/cases/duffing.json" --out "$work/full"
mkdir -p "$work/held"
flock "$work/held/.nfrc.lock" sleep 30 &
holder=$!
sleep 0.5
expect "output directory in use" 1 "in use by another nfrc run" -- \
  "$nfrc" run "$src/cases/duffing.json" --out "$work/held"
kill "$holder" 2>/dev/null
[ -z "$(ls "$work/held")" ] || { echo "FAIL directory in use: files written"; failures=$((failures + 1)); }

# Signals: SIGHUP stops a run and SIGTERM a refinement (a background job of a script starts
# with SIGINT ignored, which nfrc leaves so) after the current point: exit 3, the
# points on disk and a final summary (never left "running").
# AFTER is seconds, or "stderr:TEXT": as soon as the command has written TEXT to stderr (a
# fixed delay lands in different phases of a run as the code gets faster or the machine slower).
stopped() {  # stopped NAME SIGNAL AFTER FILE -- command...
  local name=$1 signal=$2 after=$3 file=$4
  shift 5
  "$@" >/dev/null 2>"$work/err_$name" &
  local pid=$!
  if [[ $after == stderr:* ]]; then
    local waited=0
    until grep -q -- "${after#stderr:}" "$work/err_$name" 2>/dev/null || [ $waited -ge 3000 ]; do
      sleep 0.01
      waited=$((waited + 1))
    done
  else
    sleep "$after"
  fi
  kill -s "$signal" "$pid"
  wait "$pid"
  local got=$?
  if [ "$got" -ne 3 ] || [ ! -s "$file" ] || grep -q '"running"' "$file" ||
     ! grep -q 'interrupted' "$file"; then
    echo "FAIL $name: exit $got (want 3), $file:"; head -c 300 "$file" 2>/dev/null; echo
    failures=$((failures + 1))
  else
    echo "ok   $name"
  fi
}
# Point E's ~870 points take under 2 s now: stopped once its 100th point is reported.
stopped "run stopped by SIGHUP" HUP "stderr:point 100 " "$work/hup/branch.json" -- \
  "$nfrc" run "$src/cases/friction/point_e.json" --out "$work/hup"
stopped "refine stopped by SIGTERM" TERM "stderr:refine: epsilon" "$work/int/refinement.json" -- \
  "$nfrc" refine "$src/cases/rod/rigid.json#nh40" --omega 63953.9 --epsilon0 1e9 --steps 40 \
  --out "$work/int"
# Sweeps are stopped once their first run has reported (two or more runs still to go), not
# after a fixed delay: a whole sweep of these cases takes about a second.
stopped "sweep stopped by SIGTERM" TERM "stderr:run 0 (" "$work/sweep/sweep.json" -- \
  "$nfrc" sweep "$src/cases/friction/frc_n10.json" --parameter "nonlinearities[0].normal_load" \
  --values 10,12,14 --out "$work/sweep"
expect "sweep resumed" 0 "3 of 3 runs complete" -- \
  "$nfrc" sweep "$src/cases/friction/frc_n10.json" --parameter "nonlinearities[0].normal_load" \
  --values 10,12,14 --out "$work/sweep" --jobs 2
expect "sweep of another parameter refused" 1 "--out" -- \
  "$nfrc" sweep "$src/cases/friction/frc_n10.json" --parameter "nonlinearities[0].mu" \
  --values 0.5 --out "$work/sweep"
# A grid (normal load x mu, 4 runs): stopped by SIGINT in its first run, resumed, and a grid
# with other values refused in its directory.
fgrid=(--parameter "nonlinearities[0].normal_load" --values 10,12
       --parameter "nonlinearities[0].mu" --values 0.9,0.8)
# A shell without job control starts background commands with SIGINT ignored, which nfrc
# respects: the launcher restores its default so that the SIGINT reaches nfrc's handler.
sigint_default=(/usr/bin/python3 -c 'import os, signal, sys
signal.signal(signal.SIGINT, signal.SIG_DFL)
os.execv(sys.argv[1], sys.argv[1:])')
stopped "grid sweep stopped by SIGINT" INT "stderr:run 0 (" "$work/grid/sweep.json" -- \
  "${sigint_default[@]}" "$nfrc" sweep "$src/cases/friction/frc_n10.json" "${fgrid[@]}" --out "$work/grid"
expect "grid sweep resumed" 0 "4 of 4 runs complete" -- \
  "$nfrc" sweep "$src/cases/friction/frc_n10.json" "${fgrid[@]}" --out "$work/grid" --jobs 2
expect "grid sweep of other values refused" 1 "--out" -- \
  "$nfrc" sweep "$src/cases/friction/frc_n10.json" "${fgrid[@]:0:4}" \
  --parameter "nonlinearities[0].mu" --values 0.9,0.7 --out "$work/grid"

# A manifest: run one member by name, sweep all of them, and a grid over a field outside the
# laws (the damping matrix) on the command line.
cat > "$work/manifest.json" <<EOF
{"manifest": "Duffing at two damping levels", "base": "$src/cases/duffing_h1.json",
 "variants": [{"name": "light"}, {"name": "heavy", "set": {"model.C[0][0]": 0.2}}]}
EOF
expect "run a member of a manifest" 0 "reached_lambda_bound" -- \
  "$nfrc" run "$work/manifest.json#heavy" --out "$work/member"
expect "a manifest run without a member" 1 "a manifest of 2 cases (light, heavy)" -- \
  "$nfrc" run "$work/manifest.json" --out "$work/member2"
expect "an unknown member" 1 "no member \"medium\"" -- \
  "$nfrc" run "$work/manifest.json#medium" --out "$work/member2"
expect "sweep of a manifest" 0 "2 of 2 runs complete" -- \
  "$nfrc" sweep "$work/manifest.json" --out "$work/msweep"
expect "sweep of a case-file field outside the laws" 0 "2 of 2 runs complete" -- \
  "$nfrc" sweep "$src/cases/duffing_h1.json" --parameter "model.C[0][0]" --values 0.05,0.2 \
  --out "$work/csweep"
expect "sweep of a path that names no number" 1 "names no number" -- \
  "$nfrc" sweep "$src/cases/duffing_h1.json" --parameter "model.C[0][1]" --values 0.05 \
  --out "$work/csweep2"

# MPI: the same sweep on two ranks writes the same sweep.json as one process (the timings
# aside). Open MPI refuses root without the first two. Under the sanitizers its start-up
# allocations, made in plugins it unloads before exit, are reported as leaks that can be
# neither attributed nor suppressed: leak detection is off for this command only (address
# and UB checks stay on; the sweep code itself is leak-checked by the one-process sweeps).
if command -v mpirun >/dev/null; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  asan="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
  expect "sweep on two MPI ranks" 0 "3 of 3 runs complete" -- env ASAN_OPTIONS="$asan" \
    mpirun --oversubscribe -n 2 "$nfrc" sweep "$src/cases/duffing_h1.json" \
    --parameter "model.forcing[0].cos" --values 0.05,0.1,0.18 --out "$work/mpi"
  expect "the same sweep in one process" 0 "3 of 3 runs complete" -- "$nfrc" sweep \
    "$src/cases/duffing_h1.json" --parameter "model.forcing[0].cos" --values 0.05,0.1,0.18 \
    --out "$work/one"
  # Without the shared-memory single-copy mechanism (as some containers require) Open MPI 4.1
  # offers no one-sided window here and the branches are dealt out round-robin ("round-robin"
  # on stderr); the record must not change either way.
  expect "sweep on two MPI ranks without a window" 0 "3 of 3 runs complete" -- env ASAN_OPTIONS="$asan" \
    OMPI_MCA_btl_vader_single_copy_mechanism=none mpirun --oversubscribe -n 2 "$nfrc" sweep \
    "$src/cases/duffing_h1.json" --parameter "model.forcing[0].cos" --values 0.05,0.1,0.18 \
    --out "$work/mpi_rr"
  # A grid (forcing x k3, the last varying fastest): the same on two ranks as in one process.
  grid=(--parameter "model.forcing[0].cos" --values 0.05,0.18
        --parameter "nonlinearities[0].coefficient" --range 0.1:0.2:2)
  expect "grid sweep on two MPI ranks" 0 "4 of 4 runs complete" -- env ASAN_OPTIONS="$asan" \
    mpirun --oversubscribe -n 2 "$nfrc" sweep "$src/cases/duffing_h1.json" "${grid[@]}" \
    --out "$work/mpi_grid"
  expect "the same grid sweep in one process" 0 "4 of 4 runs complete" -- "$nfrc" sweep \
    "$src/cases/duffing_h1.json" "${grid[@]}" --out "$work/one_grid"
  /usr/bin/python3 - "$work/mpi_grid/sweep.json" "$work/one_grid/sweep.json" <<'PY' ||
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:])
for run in a["runs"] + b["runs"]:
    run.pop("seconds")
assert a == b, (a, b)
assert [p["path"] for p in a["parameters"]] == ["model.forcing[0].cos",
                                                "nonlinearities[0].coefficient"]
assert [list(r["values"].values()) for r in a["runs"]] == [
    [0.05, 0.1], [0.05, 0.2], [0.18, 0.1], [0.18, 0.2]], a["runs"]
assert [r["folds"] for r in a["runs"]] == [0, 2, 2, 2], [r["folds"] for r in a["runs"]]
PY
    { echo "FAIL grid sweep.json differs between two ranks and one process"; failures=$((failures + 1)); }
  /usr/bin/python3 - "$work/mpi/sweep.json" "$work/one/sweep.json" "$work/mpi_rr/sweep.json" <<'PY' ||
import json, sys
a, b, c = (json.load(open(f)) for f in sys.argv[1:])
for run in a["runs"] + b["runs"] + c["runs"]:
    run.pop("seconds")
assert a == b == c, (a, b, c)
PY
    { echo "FAIL sweep.json differs between two ranks and one process"; failures=$((failures + 1)); }
else
  echo "skip sweep on two MPI ranks: no mpirun"
fi

if [ "$failures" -ne 0 ]; then
  echo "$failures CLI check(s) failed"
  exit 1
fi
echo "all CLI checks passed"
