#!/usr/bin/env bash
# apt-cache and dpkg for setup_deps_test.sh (linked under both names): answers from the canned
# files in $FAKE_APT_DIR (depends/NAME, show/NAME, policy/NAME), as the real ones print them, so
# that setup-deps.sh's skew resolution can be tested without a package archive.
set -uo pipefail
dir=${FAKE_APT_DIR:?}
case "$(basename "$0")" in
  dpkg)
    [ "${1:-}" = --print-architecture ] && { echo amd64; exit 0; }
    echo "fake dpkg: unexpected $*" >&2; exit 2 ;;
  apt-cache)
    sub=$1; shift
    names=()
    for a in "$@"; do case "$a" in -*) ;; *) names+=("$a") ;; esac; done
    for n in "${names[@]}"; do
      n=${n%:amd64}
      if [ -f "$dir/$sub/$n" ]; then cat "$dir/$sub/$n"
      elif [ "$sub" = depends ]; then echo "$n"  # no dependencies
      fi
    done ;;
esac
