# What toolchains/host-asan.cmake and toolchains/host-fuzz.cmake share: the host toolchain's flags
# plus the sanitizers they name in _ale_sanitizers (compiling; every executable links AddressSanitizer
# and UndefinedBehaviorSanitizer), frame pointers for readable stacks, every UB report fatal
# (-fno-sanitize-recover), and Release at -O1 (host-asan.cmake says why).
include(${CMAKE_CURRENT_LIST_DIR}/host.cmake)
set(_ale_sanitize "-fsanitize=${_ale_sanitizers} -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g1")
set(CMAKE_C_FLAGS_INIT   "${CMAKE_C_FLAGS_INIT} ${_ale_sanitize}")
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_CXX_FLAGS_INIT} ${_ale_sanitize}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-fsanitize=address,undefined")
# Tests may use the host build's tools for their inputs (tests/host/app/CMakeLists.txt).
set(ALE_SANITIZED_BUILD ON)
# CMake appends its own "-O3 -DNDEBUG" to the *_RELEASE_INIT values, so the level is set here as
# the cache entry itself (a fresh build folder picks it up).
set(CMAKE_C_FLAGS_RELEASE "-O1 -DNDEBUG" CACHE STRING "sanitizer build: -O1 (toolchains/host-sanitized.cmake)")
set(CMAKE_CXX_FLAGS_RELEASE "-O1 -DNDEBUG" CACHE STRING "sanitizer build: -O1 (toolchains/host-sanitized.cmake)")
