#!/usr/bin/env bash
# Installs what is missing, builds for the host, for armhf and for the host with sanitizers
# (host-asan: AddressSanitizer, LeakSanitizer, UndefinedBehaviorSanitizer), runs the host tests on
# both host builds and the armhf tests under qemu-arm, builds the fuzz targets (host-fuzz: libFuzzer
# with AddressSanitizer and UndefinedBehaviorSanitizer) and fuzzes each for 20 s (one test per
# target, docs/fuzzing.md), and ends with one line: "N passed, N failed"
# and, when there are any, ", N skipped" and ", N disabled (their names)" (every build counted;
# ctest names each skipped or disabled test above it).
#
#   scripts/test.sh
#   ALE_SANITIZE=0 scripts/test.sh      without the host-asan build and its tests (a quicker local run)
#   ALE_FUZZ=0 scripts/test.sh          without the host-fuzz build and its runs
#
# Tests that need ../shared/data skip with a message when it is missing; with CI=true they fail.
# ALE_DATA_DIR points them elsewhere. ALE_JOBS sets build and test parallelism.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=${ALE_JOBS:-$(nproc)}
start=$(date +%s)
step() { printf '\n== %s (%ds)\n' "$*" $(( $(date +%s) - start )); }

step "dependencies"
"$root/scripts/setup-deps.sh" all || { echo "test.sh: dependency setup failed"; echo "0 passed, 1 failed"; exit 1; }

failed_builds=0
# scripts/build.sh host-asan builds the sanitizer build on its own.
targets="host armhf"
case "${ALE_SANITIZE:-1}" in
  1) targets="$targets host-asan" ;;
  0) ;;
  *) echo "test.sh: ALE_SANITIZE must be 0 or 1, not '${ALE_SANITIZE}'"; echo "0 passed, 1 failed"; exit 1 ;;
esac
case "${ALE_FUZZ:-1}" in
  1) targets="$targets host-fuzz" ;;
  0) ;;
  *) echo "test.sh: ALE_FUZZ must be 0 or 1, not '${ALE_FUZZ}'"; echo "0 passed, 1 failed"; exit 1 ;;
esac
for target in $targets; do
  step "build $target"
  # A failed compile still lets every other target build, so one broken file costs its own
  # tests (they show as *_NOT_BUILT), not all of them.
  ALE_KEEP_GOING=1 ALE_JOBS=$jobs "$root/scripts/build.sh" "$target" Release || {
    echo "test.sh: $target build failed (the FAILED lines above name the files); disk and memory:"
    df -h "$root" | tail -1; free -m | sed -n 2p
    failed_builds=$((failed_builds + 1))
  }
done

passed=0 failed=$failed_builds skipped=0 disabled=0 disabled_names=
for target in $targets; do
  dir=$root/build/$target
  [ -f "$dir/CTestTestfile.cmake" ] || continue
  case $target in
    armhf) how=' (under qemu-arm)' ;; host-asan) how=' (ASan + LSan + UBSan)' ;;
    host-fuzz) how=' (libFuzzer + ASan + UBSan, 20 s per target)' ;; *) how= ;;
  esac
  step "tests $target$how"
  log=$dir/ctest.log
  # In host-asan every sanitizer report ends its process with exit 23 (the options are compiled
  # into each binary, cmake/sanitizer_defaults.cpp), so it fails its test.
  (cd "$dir" && ctest --output-on-failure -j "$jobs" --timeout 900) 2>&1 | tee "$log" | grep -vE '^ *[0-9]+/[0-9]+ Test +#[0-9]+: .* Passed'
  total=$(sed -n 's/.*tests passed, \([0-9]*\) tests failed out of \([0-9]*\).*/\2/p' "$log" | tail -1)
  nfail=$(sed -n 's/.*tests passed, \([0-9]*\) tests failed out of \([0-9]*\).*/\1/p' "$log" | tail -1)
  nskip=$(grep -c '\*\*\*Skipped' "$log" || true)
  # Disabled tests (gtest DISABLED_, ctest DISABLED) are in ctest's "did not run" list and in no count.
  names=$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Disabled)$/\1/p' "$log")
  ndis=$(printf '%s' "$names" | grep -c . || true)
  for n in $names; do
    case " $disabled_names " in *" $n "*) ;; *) disabled_names="${disabled_names:+$disabled_names }$n" ;; esac
  done
  if [ -z "$total" ]; then
    # ctest ends with "No tests were found" or crashed: count that as a failure
    grep -q 'No tests were found' "$log" && total=0 nfail=0 || { total=1 nfail=1; }
  fi
  echo "$target: $((total - nfail - nskip)) passed, $nfail failed, $nskip skipped, $ndis disabled"
  passed=$((passed + total - nfail - nskip)); failed=$((failed + nfail)); skipped=$((skipped + nskip))
  disabled=$((disabled + ndis))
done

step "done"
[ "$skipped" -gt 0 ] && echo "$skipped skipped (see the messages above)"
summary="$passed passed, $failed failed"
[ "$skipped" -gt 0 ] && summary="$summary, $skipped skipped"
[ "$disabled" -gt 0 ] && summary="$summary, $disabled disabled (${disabled_names// /, })"
echo "$summary"
[ "$failed" -eq 0 ]
