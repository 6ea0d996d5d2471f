# Host (x86_64) build with AddressSanitizer (LeakSanitizer included) and UndefinedBehaviorSanitizer:
# the host toolchain's flags plus the sanitizers, frame pointers for readable stacks, and every
# UB report fatal (-fno-sanitize-recover) so a finding fails its test. scripts/build.sh host-asan
# builds it into build/host-asan with the benchmarks off; scripts/test.sh runs the host tests on it.
# Its Release is -O1, the level AddressSanitizer's authors recommend: an instrumented GoogleTest
# file costs about 4.1x the plain -O3 compile's CPU at -O3 and 2.0x at -O1
# (tests/host/core/geometry/triangulation_test.cpp: 30.6 s, 15.2 s, plain 7.4 s), and the
# sanitizer build is the largest part of CI. The -O3 code that ships is tested on host and armhf.
# GCC 12 miscompiles `(p->obj->*p->method)(...)` (p polymorphic) under -fsanitize=vptr; avoid that
# form (LCM's member-function subscribe is one: use subscribeFunction), see docs/architecture.md.
set(_ale_sanitizers address,undefined)
include(${CMAKE_CURRENT_LIST_DIR}/host-sanitized.cmake)
# Read by cmake/AleTargets.cmake: every executable gets the runtime's default options
# (cmake/sanitizer_defaults.cpp, a report exits 23) and every test ALE_TEST_REDUCED=1.
set(ALE_SANITIZED TRUE)
