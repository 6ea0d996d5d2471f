#!/usr/bin/env bash
# Longer fuzzing runs of the fuzz targets (tests/fuzz/, docs/fuzzing.md): builds the host-fuzz
# build (scripts/build.sh host-fuzz) and runs each target in turn for S seconds over its committed
# seeds (tests/fuzz/corpus/<name>/) and the build's own corpus (build/host-fuzz/fuzz/corpus/<name>/,
# which keeps growing from run to run), then prints one line per target: executions, coverage
# (libFuzzer's cov: edges and ft: features at the end), corpus size and what it found.
#
#   scripts/fuzz.sh [--time S] [TARGET...]   each TARGET (default: all) for S seconds (default 300)
#   scripts/fuzz.sh --seeds                  rewrites the generated seeds in tests/fuzz/corpus/
#                                            (tests/fuzz/make_seeds.cpp)
#
# A finding (crash, sanitizer report, leak, an input slower than 10 s, an allocation over 512 MB
# or a process over 2048 MB; tests/fuzz/<name>.flags may change those) is kept as
# build/host-fuzz/fuzz/artifacts/<name>-<kind>-<sha1>; `build/host-fuzz/bin/fuzz_<name> FILE`
# replays it. The exit status is non-zero when any target found something.
# ALE_JOBS sets the build parallelism (default: number of cores); the runs use one core each.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=300
seeds=0
targets=()
while [ $# -gt 0 ]; do
  case $1 in
    --time) [ $# -ge 2 ] || { echo "fuzz.sh: --time needs seconds" >&2; exit 2; }; seconds=$2; shift 2 ;;
    --seeds) seeds=1; shift ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
case $seconds in ''|*[!0-9]*) echo "fuzz.sh: --time takes whole seconds, not '$seconds'" >&2; exit 2 ;; esac

build=$root/build/host-fuzz
if [ "$seeds" = 1 ]; then
  "$root/scripts/build.sh" host-fuzz Release fuzz_make_seeds
  "$build/bin/fuzz_make_seeds" "$root/tests/fuzz/corpus"
  echo "fuzz.sh: generated seeds written to tests/fuzz/corpus/"
  exit 0
fi

# The targets are the ale_fuzz_target() lines of tests/fuzz/CMakeLists.txt.
known=$(sed -n 's/^ale_fuzz_target(\([a-z0-9_]*\).*/\1/p' "$root/tests/fuzz/CMakeLists.txt")
[ ${#targets[@]} -gt 0 ] || read -r -a targets <<<"$(echo $known)"
for t in "${targets[@]}"; do
  grep -qx "$t" <<<"$known" || { echo "fuzz.sh: no target '$t' (known: $(echo $known))" >&2; exit 2; }
done
"$root/scripts/build.sh" host-fuzz Release "${targets[@]/#/fuzz_}"

work=$build/fuzz
mkdir -p "$work/artifacts" "$work/logs"
summary=()
found=0
for t in "${targets[@]}"; do
  mkdir -p "$work/corpus/$t"
  log=$work/logs/$t.log
  echo "fuzz.sh: fuzz_$t for ${seconds}s (log: ${log#$root/})"
  # the flags of its ctest test (tests/fuzz/run_fuzzer.cmake), then the target's own
  flags=()
  [ ! -f "$root/tests/fuzz/$t.flags" ] || read -r -a flags <<<"$(sed 's/#.*//' "$root/tests/fuzz/$t.flags" | tr '\n' ' ')"
  status=0
  "$build/bin/fuzz_$t" -max_total_time="$seconds" -rss_limit_mb=2048 -malloc_limit_mb=512 -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/$t-" "${flags[@]}" "$work/corpus/$t" "$root/tests/fuzz/corpus/$t" >"$log" 2>&1 ||
    status=$?
  # the last status line ("#N DONE cov: C ft: F corp: ...", or the last pulse before a finding)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9]*[a-zA-Z]*\).*/\1/p' <<<"$last")
  if [ "$status" = 0 ]; then
    result="nothing found"
  else
    found=$((found + 1))
    result="FOUND (exit $status): $(grep -m1 -E 'ERROR: |runtime error|==[0-9]+== ERROR' "$log" | sed 's/^==[0-9]*==//' | cut -c1-100); $(grep -m1 -o "Test unit written to .*" "$log" | sed "s|$root/||")"
  fi
  summary+=("$(printf '%-11s %6ss  %10s execs  cov: %-5s ft: %-6s corp: %-10s %s' "$t" "$seconds" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$result")")
done
echo
printf '%s\n' "${summary[@]}"
[ "$found" -eq 0 ]
