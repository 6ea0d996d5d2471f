#!/usr/bin/env bash
# scripts/experiments.sh --quick end to end: renders its subset, replays every enhancement.mode and
# writes the results page into a temporary folder. Asserts that the page and its tables were made
# (every section, every mode's row, the five-light loop's reports), not any figure.
# Needs ../shared/data (ALE_DATA_DIR): skipped with ALE_SKIP when it is missing, fails when CI=true.
#   experiments_quick_test.sh SOURCE_DIR BIN_DIR DEFAULT_DATA_DIR
set -euo pipefail
src=$1
bin=$2
data=${ALE_DATA_DIR:-$3}
for need in euroc_groundtruth tum_fr2_desk_20 lighting/webcam; do
  if [ ! -e "$data/$need" ]; then
    if [ "${CI:-}" = true ]; then
      echo "experiments_quick_test: CI=true but test data is missing: $data/$need" >&2
      exit 1
    fi
    echo "ALE_SKIP: test data missing ($data/$need); set ALE_DATA_DIR or put ../shared/data beside the repository"
    exit 0
  fi
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
BIN=$bin ALE_DATA_DIR=$data "$src/scripts/experiments.sh" --quick --out "$work/out" --results "$work/results.md"
echo "experiments_quick_test: --quick took $(( $(date +%s) - start )) s"
page=$work/results.md
fail=0
expect() {
  grep -qF -- "$1" "$page" || { echo "FAIL: results.md lacks: $1" >&2; fail=1; }
}
expect "## The issue's figures, as measured"
expect "## Per light condition and mode"
expect "## ale against each mode, paired by sequence"
expect "## The sweeper loop at the article's five light levels (its Fig. 10)"
expect "## EuRoC flights (the article's Table I and II)"
expect "## VIA per light condition (the article's Fig. 8)"
expect "## Features per light level (the article's Table III)"
expect "## Real sequences"
expect "the second replay's trajectory is identical"
for cond in bright normal_bright normal normal_dark dark off_on sunlit dimming; do expect "### $cond ("; done
for mode in off he clahe gamma ale; do expect "| $mode | "; done
reports=$(find "$work/results" -name '*.html' | wc -l)
[ "$reports" -eq 25 ] || { echo "FAIL: $reports reports of the five-light loop, not 25" >&2; fail=1; }
# a second run redoes nothing: every render and run is cached
BIN=$bin ALE_DATA_DIR=$data "$src/scripts/experiments.sh" --quick --out "$work/out" --results "$work/results2.md" \
  > "$work/second.log" 2>&1
if grep -E '^replay ' "$work/second.log" || grep -E '^render .*: time' "$work/second.log"; then
  echo "FAIL: the second run rendered or replayed again" >&2
  fail=1
fi
[ $fail -eq 0 ] || { cat "$page" >&2; exit 1; }
echo "experiments_quick_test: ok"
