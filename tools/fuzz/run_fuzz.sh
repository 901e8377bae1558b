#!/usr/bin/env bash
# Fuzzes the case reader (case_reader_fuzzer.cc) for SECONDS seconds, building it first if
# needed, with a seed corpus copied from cases/**/*.json, tools/fuzz/seeds/*.json (a sweep
# record, a grid manifest) and tools/fuzz/regressions/*.json (past findings, each run again
# first) and the dictionary case.dict.
# Everything the fuzzer writes (corpus, crash inputs) goes to a temporary directory, never
# into the repository.
#
# Usage: tools/fuzz/run_fuzz.sh SECONDS
#   NFRC_FUZZ_BUILD      build directory (default <repo>/build-fuzz, configured if missing)
#   NFRC_FUZZ_JOBS       parallel build jobs (default 2)
#   NFRC_FUZZ_KEEP_GOING 1: run in libFuzzer's fork mode and keep fuzzing after a finding,
#                        to collect several in one run (default: stop at the first)
# Exit status: 0 no finding; 1 a crash, leak, timeout, out-of-memory or sanitizer report
# (the inputs are kept and their paths printed); 2 bad usage or build failure.
set -uo pipefail

usage() { echo "usage: $0 SECONDS" >&2; exit 2; }
[[ $# -eq 1 && $1 =~ ^[1-9][0-9]*$ ]] || usage
seconds=$1

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${NFRC_FUZZ_BUILD:-$repo/build-fuzz}
if [[ ! -f $build/CMakeCache.txt ]]; then
  CC=clang CXX=clang++ cmake -S "$repo" -B "$build" -DNFRC_FUZZ=ON -DNFRC_BUILD_TESTS=OFF \
    >/dev/null || exit 2
fi
cmake --build "$build" -j"${NFRC_FUZZ_JOBS:-2}" --target case_reader_fuzzer >/dev/null || exit 2
fuzzer=$build/case_reader_fuzzer

work=$(mktemp -d "${TMPDIR:-/tmp}/nfrc_fuzz.XXXXXX") || exit 2
corpus=$work/corpus        # seeds, then whatever new coverage the fuzzer finds
artifacts=$work/artifacts  # crash-*, leak-*, timeout-*, oom-* inputs
base_dir=$work/base_dir    # empty: relative matrix paths of fuzzed cases resolve here
mkdir -p "$corpus" "$artifacts" "$base_dir"

biggest=0
count=0
while IFS= read -r -d '' seed; do
  cp "$seed" "$corpus/$(printf '%03d' "$count")_$(basename "$seed")"
  size=$(stat -c %s "$seed")
  (( size > biggest )) && biggest=$size
  count=$((count + 1))
done < <(find "$repo/cases" "$repo/tools/fuzz/seeds" "$repo/tools/fuzz/regressions" -name '*.json' \
           -print0 | sort -z)
(( count > 0 )) || { echo "no seed cases under $repo/cases" >&2; exit 2; }
# Inputs up to twice the biggest case (at least 4 KiB): room for mutations to grow a case,
# small enough to keep executions fast.
max_len=$(( 2 * biggest > 4096 ? 2 * biggest : 4096 ))

mode=()
if [[ ${NFRC_FUZZ_KEEP_GOING:-0} == 1 ]]; then
  mode=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
fi
echo "fuzzing $seconds s: $count seeds, -max_len=$max_len, work directory $work"
# halt_on_error: a UBSan report is fatal (the build also sets -fno-sanitize-recover=all).
# -use_value_profile: comparisons count as coverage, which leads mutations towards the limits
# the parsers check (a size's upper bound, an enumerated value).
ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0} \
UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1} \
NFRC_FUZZ_BASE_DIR=$base_dir \
  "$fuzzer" "${mode[@]}" -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 \
  -timeout=10 -dict="$repo/tools/fuzz/case.dict" -use_value_profile=1 \
  -artifact_prefix="$artifacts/" -print_final_stats=1 "$corpus"
status=$?

findings=$(find "$artifacts" -type f | sort)
if [[ -n $(find "$base_dir" -mindepth 1 -print -quit) ]]; then
  echo "the fuzzer wrote into its base directory $base_dir" >&2
  status=1
fi
if [[ $status -ne 0 || -n $findings ]]; then
  echo "FUZZING FOUND A PROBLEM (fuzzer exit status $status); inputs kept in $work:" >&2
  [[ -n $findings ]] && echo "$findings" >&2
  echo "reproduce: $fuzzer <input>" >&2
  exit 1
fi
rm -rf "$work"
echo "fuzzing: no finding in $seconds s"
