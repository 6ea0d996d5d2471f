#!/usr/bin/env bash
# scripts/setup-deps.sh's version-skew resolution and lock wait, without a package archive:
# apt-cache and dpkg are fake_apt.sh answering from canned files written here, shaped like the
# fresh Debian 12 image of issue 29 (a native libpcre2-8-0 at a version the archive lacks, armhf
# seeing older versions than amd64, perl:any reachable through an armhf package).
#   setup_deps_test.sh REPO
set -uo pipefail
repo=$1
work=$(mktemp -d)
holder=
trap '[ -z "$holder" ] || kill "$holder" 2>/dev/null; rm -rf "$work"' EXIT
mkdir -p "$work/bin" "$work/apt/depends" "$work/apt/show" "$work/apt/policy"
for t in apt-cache dpkg; do ln -s "$repo/tests/host/scripts/fake_apt.sh" "$work/bin/$t"; done
export FAKE_APT_DIR=$work/apt
fail=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; fail=1; fi; }

a=$work/apt
# dependencies as apt-cache depends prints them
printf 'libpcre2-dev\n  Depends: libpcre2-8-0\n' >"$a/depends/libpcre2-dev"
printf 'libpcre2-dev:armhf\n  Depends: libpcre2-8-0:armhf\n' >"$a/depends/libpcre2-dev:armhf"
# an armhf package needing perl:any: the native perl satisfies it, perl:armhf is not installed
printf 'libfoo-dev:armhf\n  Depends: <perl:any>\n    perl\n    perl:armhf\n  |Depends: libz1:armhf\n  Depends: libzalt:armhf\n' >"$a/depends/libfoo-dev:armhf"
printf 'perl\n  Depends: libperl5.36\n' >"$a/depends/perl"
printf 'perl:armhf\n  Depends: libperl5.36:armhf\n' >"$a/depends/perl:armhf"
for p in libpcre2-8-0:armhf libperl5.36:armhf libz1:armhf libzalt:armhf; do
  printf 'Package: %s\nArchitecture: armhf\nMulti-Arch: same\n\n' "${p%:armhf}" >"$a/show/$p"
done
policy() { # name installed candidate "version prio source"...
  local name=$1 inst=$2 cand=$3; shift 3
  { printf '%s:\n  Installed: %s\n  Candidate: %s\n  Version table:\n' "$name" "$inst" "$cand"
    local row v prio src
    for row in "$@"; do
      read -r v prio src <<<"$row"
      if [ "$v" = "$inst" ]; then printf ' *** %s %s\n' "$v" "$prio"; else printf '     %s %s\n' "$v" "$prio"; fi
      [ "$src" = local ] || printf '        %s %s\n' "$prio" "$src"
      [ "$v" != "$inst" ] || printf '        100 /var/lib/dpkg/status\n'
    done; } >"$a/policy/$name"
}
sec="http://deb.example/debian-security bookworm-security/main amd64 Packages"
base="http://deb.example/debian bookworm/main amd64 Packages"
basea="http://deb.example/debian bookworm/main armhf Packages"
policy libpcre2-8-0 10.42-1+deb12u9 10.42-1+deb12u9 "10.42-1+deb12u9 100 local" "10.42-1+deb12u2 500 $sec" "10.42-1 500 $base"
policy libpcre2-8-0:armhf '(none)' 10.42-1 "10.42-1 500 $basea"
policy libpcre2-dev '(none)' 10.42-1+deb12u2 "10.42-1+deb12u2 500 $sec" "10.42-1 500 $base"
policy libperl5.36 5.36.0-7+deb12u4 5.36.0-7+deb12u4 "5.36.0-7+deb12u4 500 $base"
policy libperl5.36:armhf '(none)' 5.36.0-7+deb12u3 "5.36.0-7+deb12u3 500 $basea"
policy perl 5.36.0-7+deb12u4 5.36.0-7+deb12u4 "5.36.0-7+deb12u4 500 $base"
# installed at the armhf candidate, but the native candidate is newer: apt would upgrade it
policy libz1 1.0-1 1.0-1+deb12u1 "1.0-1+deb12u1 500 $sec" "1.0-1 500 $base"
policy libz1:armhf '(none)' 1.0-1 "1.0-1 500 $basea"
policy libzalt '(none)' 2.0-1 "2.0-1 500 $base"
policy libzalt:armhf '(none)' 1.9-1 "1.9-1 500 $basea"

run() { # function args...: in a shell with setup-deps.sh's functions and the fake tools first
  PATH=$work/bin:$PATH bash -c 'source "$1"; shift; "$@"' _ "$repo/scripts/setup-deps.sh" "$@"
}

out=$(run skew_prefs libpcre2-dev libpcre2-dev:armhf libfoo-dev:armhf); rc=$?
echo "$out"
check "skew_prefs exits 0" "[ $rc = 0 ]"
check "Multi-Arch: same library pinned to armhf's candidate on both architectures" \
  "grep -A2 -x 'Package: libpcre2-8-0 libpcre2-8-0:armhf' <<<\"\$out\" | grep -qx 'Pin: version 10.42-1'"
check "the skew is named in the comment line" "grep -qx '# libpcre2-8-0:amd64 10.42-1+deb12u9 -> 10.42-1' <<<\"\$out\""
check "pin priority allows the downgrade" "grep -qx 'Pin-Priority: 1001' <<<\"\$out\""
check "a native candidate newer than armhf's is pinned too" \
  "grep -A1 -x 'Package: libz1 libz1:armhf' <<<\"\$out\" | grep -qx 'Pin: version 1.0-1'"
check "only the first alternative is followed" "! grep -q libzalt <<<\"\$out\""
check "perl:any is the native perl: libperl5.36 not pinned to armhf's version" "! grep -q libperl <<<\"\$out\""

out=$(run skew_prefs libpcre2-dev); rc=$?
echo "$out"
check "host only: exits 0" "[ $rc = 0 ]"
check "host only: a version the archive lacks goes to the best served one" \
  "grep -A1 -x 'Package: libpcre2-8-0' <<<\"\$out\" | grep -qx 'Pin: version 10.42-1+deb12u2'"
check "host only: no armhf pin" "! grep -q ':armhf' <<<\"\$out\""

out=$(run skew_prefs libperl5.36); rc=$?
check "no skew: nothing printed" "[ $rc = 0 ] && [ -z \"\$out\" ]"

# the lock: a process holding an fcntl lock on one of apt's lock files is named, then waited for
lock=$work/lock-frontend
: >"$lock"
perl -e 'use Fcntl; open(my $f, ">>", $ARGV[0]) or die; my $l = pack("s s x4 q q i x4", F_WRLCK, 0, 0, 0, 0);
  fcntl($f, F_SETLK, $l) or die "lock: $!"; sleep 30;' "$lock" &
holder=$!
for _ in 1 2 3 4 5 6 7 8 9 10; do grep -q " $holder " /proc/locks && break; sleep 0.2; done
out=$(run eval "apt_locks=($lock); apt_lock_holder")
check "the holder is named" "[ \"\$out\" = \"$holder (perl)\" ]"
out=$(ALE_APT_LOCK_WAIT=5 run eval "apt_locks=($lock); wait_apt_locks" 2>&1); rc=$?
echo "$out"
check "waits with a message" "grep -q 'holds the dpkg/apt lock (process $holder (perl)); waiting up to 5s' <<<\"\$out\""
check "gives up with a clear error" "[ $rc != 0 ] && grep -q 'still held by process $holder (perl) after 5s' <<<\"\$out\""
kill "$holder"; wait "$holder" 2>/dev/null; holder=
out=$(run eval "apt_locks=($lock); wait_apt_locks && echo free" 2>&1)
check "a free lock is not waited for" "[ \"\$out\" = free ]"

[ $fail = 0 ] && echo "setup_deps_test: all passed"
exit $fail
