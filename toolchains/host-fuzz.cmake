# Host (x86_64) build of the fuzz targets (tests/fuzz/): Clang 14's libFuzzer with
# AddressSanitizer and UndefinedBehaviorSanitizer. Every library is compiled with libFuzzer's
# coverage instrumentation but without its main (-fsanitize=fuzzer-no-link); the fuzz targets add
# -fsanitize=fuzzer at their link (tests/fuzz/CMakeLists.txt). GCC has no libFuzzer, hence Clang
# here while every other build uses GCC; OpenCV and LCM from scripts/setup-deps.sh (built by GCC
# against libstdc++, which Clang uses too) link unchanged and uninstrumented.
# scripts/build.sh host-fuzz builds only the fuzz targets and what they link, into build/host-fuzz.
# The rest as host-asan (toolchains/host-sanitized.cmake): Release at -O1, UB reports fatal, so
# that libFuzzer keeps the input.
set(CMAKE_C_COMPILER clang-14)
set(CMAKE_CXX_COMPILER clang++-14)
set(_ale_sanitizers fuzzer-no-link,address,undefined)
include(${CMAKE_CURRENT_LIST_DIR}/host-sanitized.cmake)
# Read by CMakeLists.txt: tests/fuzz/ instead of tests/host/ and the benchmarks.
set(ALE_FUZZING TRUE)
