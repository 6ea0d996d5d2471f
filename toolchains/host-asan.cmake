# Host (x86_64) build with AddressSanitizer (LeakSanitizer included) and UndefinedBehaviorSanitizer:
# the host toolchain's flags plus the sanitizers, frame pointers for readable stacks, and every
# UB report fatal (-fno-sanitize-recover) so a finding fails its test. scripts/build.sh host-asan
# builds it in Release (the optimised code is what ships, and the suite stays quick) into
# build/host-asan with the benchmarks off; scripts/test.sh runs the host tests on it.
# GCC 12 miscompiles `(p->obj->*p->method)(...)` (p polymorphic) under -fsanitize=vptr; avoid that
# form (LCM's member-function subscribe is one: use subscribeFunction), see docs/architecture.md.
include(${CMAKE_CURRENT_LIST_DIR}/host.cmake)
set(_ale_sanitize "-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g1")
set(CMAKE_C_FLAGS_INIT   "${CMAKE_C_FLAGS_INIT} ${_ale_sanitize}")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_CXX_FLAGS_INIT} ${_ale_sanitize}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-fsanitize=address,undefined")
