#!/usr/bin/env bash
# Watches a robot's (or a replay's) LCM traffic with lcm-spy, decoding ale-slamd's messages.
#   scripts/lcm-spy.sh [--jar-only] [LCM_URL]     (default: the daemon's udpm://239.255.76.67:7667?ttl=0)
# Builds the Java classes of app/lcm/*.lcm with lcm-gen and javac into build/lcm-java/ale_lcm.jar
# (again whenever a .lcm file is newer), then starts LCM's spy with that jar on its class path.
# Debian 12's /usr/bin/lcm-spy wrapper passes -Xincgc, which Java 17 no longer accepts, so the
# spy's class is started here directly. Needs liblcm-java and a JDK (scripts/setup-deps.sh
# installs both) and a display (ssh -X, or Xvfb).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jar_only=false
if [ "${1:-}" = "--jar-only" ]; then
  jar_only=true
  shift
fi
url=${1:-udpm://239.255.76.67:7667?ttl=0}
lcm_jar=/usr/share/java/lcm.jar
die() { echo "lcm-spy.sh: $*" >&2; exit 1; }
[ -f "$lcm_jar" ] || die "$lcm_jar is missing: apt-get install liblcm-java (or scripts/setup-deps.sh host)"
[ -f /usr/share/java/jchart2d.jar ] || die "the spy's charts need /usr/share/java/jchart2d.jar: apt-get install libjchart2d-java"
command -v lcm-gen >/dev/null || die "lcm-gen is missing: apt-get install liblcm-bin"
command -v javac >/dev/null || die "javac is missing: apt-get install openjdk-17-jdk-headless"

out=$root/build/lcm-java
types_jar=$out/ale_lcm.jar
stale=true
if [ -f "$types_jar" ]; then
  stale=false
  for def in "$root"/app/lcm/*.lcm; do [ "$def" -nt "$types_jar" ] && stale=true; done
fi
if $stale; then
  rm -rf "$out"
  mkdir -p "$out/src" "$out/classes"
  lcm-gen -j --jpath "$out/src" "$root"/app/lcm/*.lcm
  javac -nowarn -encoding UTF-8 -cp "$lcm_jar" -d "$out/classes" "$out"/src/ale_lcm/*.java
  jar cf "$types_jar" -C "$out/classes" ale_lcm
fi
if $jar_only; then
  echo "$types_jar"
  exit 0
fi
# The spy finds message types by scanning CLASSPATH as well as its own class path.
export CLASSPATH=$types_jar
exec java -Djava.net.preferIPv4Stack=true -Xmx128m -cp "$lcm_jar:/usr/share/java/jchart2d.jar:$types_jar" lcm.spy.Spy \
  --lcm-url="$url"
