# Helpers shared by the bench scripts (place-bench.sh, loop-bench.sh, odometry-bench.sh,
# experiments.sh; slam-runs.sh takes die and takeoff_start); sourced, not run.
# The caller sets root, bench (its name, for messages), out (its default folder), render_base
# (ale-render options every render gets) and max_jobs (the most --jobs may ask for, empty: no
# limit), then calls parse_bench_args "$@"; and defines suite() printing `name|quick|...` lines.

BIN=${BIN:-$root/build/host/bin}
SLAMD_ARGS=${SLAMD_ARGS:-}

die() { echo "$bench: $*" >&2; exit 2; }

# The options every bench takes (its header says them; --help prints the header): sets out, jobs,
# quick, render_only and only, then checks the tools are there.
parse_bench_args() {
  jobs=2
  quick=0
  render_only=0
  only=()
  while [ $# -gt 0 ]; do
    case $1 in
      --quick) quick=1 ;;
      --out) [ $# -ge 2 ] || die "--out needs a folder"; out=$2; shift ;;
      --jobs)
        [ $# -ge 2 ] && [[ $2 =~ ^[1-9][0-9]*$ ]] && [ -z "$max_jobs" -o "${2:-0}" -le "${max_jobs:-0}" ] ||
          die "--jobs needs a whole number >= 1${max_jobs:+ and <= $max_jobs}"
        jobs=$2; shift ;;
      --render-only) render_only=1 ;;
      --only) [ $# -ge 2 ] || die "--only needs a sequence name"; only+=("$2"); shift ;;
      -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
      *) die "unknown option '$1' (see --help)" ;;
    esac
    shift
  done
  need_tools
}

need_tools() {
  local tool
  for tool in ale-render ale-slamd ale-eval; do
    [ -x "$BIN/$tool" ] || die "$BIN/$tool is missing: build it (ninja -C build/host $tool)"
  done
  command -v python3 >/dev/null || die "python3 is needed for the table"
}

# selected NAME QUICK: whether the sequence is asked for (--only, else --quick, else all).
selected() {
  local name=$1 q=$2 o
  if [ ${#only[@]} -gt 0 ]; then
    for o in "${only[@]}"; do [ "$o" = "$name" ] && return 0; done
    return 1
  fi
  [ "$quick" -eq 0 ] || [ "$q" = 1 ]
}

# The names of the selected sequences, one a line; dies when there are none.
selected_names() {
  local name q rest n=0
  while IFS='|' read -r name q rest; do
    selected "$name" "$q" || continue
    echo "$name"
    n=$((n + 1))
  done < <(suite)
  [ $n -gt 0 ] || die "no sequence selected (names: $(suite | cut -d'|' -f1 | tr '\n' ' '))"
}

# cached NAME OPTIONS: whether DIR/renders/NAME was made with these options.
cached() {
  [ -f "$out/renders/$1/options.txt" ] && [ "$(cat "$out/renders/$1/options.txt")" = "$2" ]
}

# render_one NAME OPTIONS: DIR/renders/NAME, with the options it was made with in NAME/options.txt
# (render_suite renders again only a folder whose options differ or that never finished).
render_one() {
  local name=$1 options=$2 dir=$out/renders/$1
  rm -rf "$dir" "$dir.part"
  # shellcheck disable=SC2086  # the options are words
  if ! "$BIN/ale-render" --out "$dir.part" $render_base $options > "$dir.part.log" 2>&1; then
    echo "render $name: FAILED (see $dir.part.log)" >&2
    return 1
  fi
  mv "$dir.part.log" "$dir.part/render.log"
  echo "$options" > "$dir.part/options.txt"
  mv "$dir.part" "$dir"
  echo "render $name: $(grep -E '^time:' "$dir/render.log")"
}

# in_parallel CMD ARGS...: runs CMD ARGS in the background, at most $jobs at a time; the
# pids wait in the array pids and a failure sets failed=1 (wait_all waits for the rest).
pids=()
failed=0
in_parallel() {
  "$@" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
}
wait_all() {
  local p
  for p in "${pids[@]}"; do wait "$p" || failed=1; done
  pids=()
}

# render_args EVENT: the event's ale-render flag and value (blackout:S,D or kidnap:A,T,G; - none).
render_args() {
  local event=$1
  case $event in
    blackout:*) echo "--blackout ${event#blackout:}" ;;
    kidnap:*) echo "--kidnap ${event#kidnap:}" ;;
    *) echo "" ;;
  esac
}

# Renders the selected sequences of the suite (`name|quick|event|ale-render options` lines) into
# DIR/renders, $jobs at a time, and makes DIR/runs; dies when a render failed, exits after them
# with --render-only.
render_suite() {
  local name q event args
  selected_names > /dev/null || exit 2
  mkdir -p "$out/renders" "$out/runs"
  while IFS='|' read -r name q event args; do
    selected "$name" "$q" || continue
    # A cached render takes no slot: the next render starts at once.
    if cached "$name" "$args $(render_args "$event")"; then
      echo "render $name: cached"
    else
      in_parallel render_one "$name" "$args $(render_args "$event")"
    fi
  done < <(suite)
  wait_all
  [ $failed -eq 0 ] || die "a render failed"
  [ "$render_only" -eq 0 ] || exit 0
}

# replay_and_table SCRIPT: replays the selected sequences with ale-slamd one at a time (each is
# single-threaded and deterministic) into DIR/runs/NAME.tum, .frames.csv and .log, then prints
# scripts/SCRIPT's table (below); a failed replay sets failed=1.
replay_and_table() {
  local script=$1 name run names
  mapfile -t names < <(selected_names)
  for name in "${names[@]}"; do
    run=$out/runs/$name
    # shellcheck disable=SC2086  # SLAMD_ARGS are words
    if ! "$BIN/ale-slamd" --replay "$out/renders/$name" --lcm-url memq:// --trajectory "$run.tum" \
         --frame-log "$run.frames.csv" $SLAMD_ARGS > "$run.log" 2>&1; then
      echo "replay $name: FAILED (see $run.log)" >&2
      failed=1
    fi
  done
  table "$script"
  echo "renders in $out/renders, runs in $out/runs; replayed with $BIN/ale-slamd $SLAMD_ARGS"
}

# table SCRIPT: scripts/SCRIPT's table (--eval, --renders, --runs, the caller's table_args, then
# NAME|EVENT of each selected sequence); its exit status.
table_args=()
table() {
  local script=$1 name q event args rows=()
  while IFS='|' read -r name q event args; do
    selected "$name" "$q" || continue
    rows+=("$name|$event")
  done < <(suite)
  python3 "$root/scripts/$script" --eval "$BIN/ale-eval" --renders "$out/renders" --runs "$out/runs" \
    ${table_args[@]+"${table_args[@]}"} "${rows[@]}"
}

# takeoff_start FILE: seconds from a TUM file's first pose to 3 s before the body is first 1 m from
# where it started, whole seconds, at least 0: the EuRoC MH flights hover on the spot for their
# first 20-50 s.
takeoff_start() {
  awk '!/^#/ { if (!n++) { t0 = $1; x = $2; y = $3; z = $4 }
               if (sqrt(($2-x)^2 + ($3-y)^2 + ($4-z)^2) > 1.0) { s = int($1 - t0 - 3); print (s > 0 ? s : 0); exit } }' "$1"
}
