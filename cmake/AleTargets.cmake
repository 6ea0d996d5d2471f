# Helpers shared by every folder: warnings, static linking, tests.

add_library(ale_warnings INTERFACE)
target_compile_options(ale_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
  -Wno-sign-conversion -Wno-psabi $<$<BOOL:${ALE_WERROR}>:-Werror>)

# Layers are enforced by include paths: no target sees the repository root. Each library gets its
# own include root, build/include-roots/<lib>/, holding a link to every header of the folders it
# owns (keeping the spelling "core/base/status.h"), and exposes only that root; so a header is
# reachable only through a library one links, and a wrong-way include (core including hal/ or app/,
# hal including app/, base including anything above it) fails to compile
# (tests/host/layers/ proves it). Links are file by file because hal/ and app/ hold headers of one
# library beside folders of others.
set(ALE_INCLUDE_ROOTS ${PROJECT_BINARY_DIR}/include-roots)

# ale_include_root(TARGET VISIBILITY FOLDER...): FOLDERs (relative to the repository root; their
# headers, not their subfolders) become reachable through TARGET's include root.
function(ale_include_root target visibility)
  set(root ${ALE_INCLUDE_ROOTS}/${target})
  file(REMOVE_RECURSE ${root})  # drop links of headers that were deleted or moved
  foreach(folder ${ARGN})
    file(GLOB headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.h ${PROJECT_SOURCE_DIR}/${folder}/*.hpp)
    file(MAKE_DIRECTORY ${root}/${folder})
    foreach(header ${headers})
      get_filename_component(name ${header} NAME)
      file(CREATE_LINK ${header} ${root}/${folder}/${name} SYMBOLIC)
    endforeach()
  endforeach()
  target_include_directories(${target} ${visibility} ${root})
endfunction()

# ale_library(NAME SOURCES... [DEPS targets...] [HEADERS folders...]): one layer's library. Its
# headers are those of the folder of its CMakeLists.txt, or of the HEADERS folders (relative to
# the repository root).
function(ale_library name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS;HEADERS" ${ARGN})
  add_library(${name} STATIC ${A_SOURCES})
  if(NOT A_HEADERS)
    file(RELATIVE_PATH A_HEADERS ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
  ale_include_root(${name} PUBLIC ${A_HEADERS})
  target_link_libraries(${name} PUBLIC ${A_DEPS} PRIVATE ale_warnings)
endfunction()

# ale_executable(NAME SOURCES... [DEPS targets...])
# In the sanitizer build (ALE_SANITIZED, toolchains/host-asan.cmake) every executable carries the
# sanitizers' default options (cmake/sanitizer_defaults.cpp: a report exits 23).
function(ale_executable name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${A_SOURCES} $<$<BOOL:${ALE_SANITIZED}>:${PROJECT_SOURCE_DIR}/cmake/sanitizer_defaults.cpp>)
  target_link_libraries(${name} PRIVATE ${A_DEPS} ale_warnings)
  target_link_options(${name} PRIVATE -Wl,--gc-sections $<$<BOOL:${ALE_FULLY_STATIC}>:-static>)
  target_compile_options(${name} PRIVATE -ffunction-sections -fdata-sections)
endfunction()

# ale_test(NAME [PREFIX p] SOURCES... [DEPS targets...]): a GoogleTest binary whose cases become
# ctest tests named <p><Suite>.<Case> (run through qemu-arm when cross-compiling). In the
# sanitizer build they run with ALE_TEST_REDUCED=1: the few tests that are slow under the
# sanitizers run a smaller form of the same work then, and say so (ale::test::reduced_run(),
# tests/host/support/test_data.h).
function(ale_test name)
  cmake_parse_arguments(A "" "PREFIX" "SOURCES;DEPS" ${ARGN})
  ale_executable(${name} SOURCES ${A_SOURCES} DEPS ${A_DEPS} ale_test_support GTest::gtest_main)
  set(env)
  if(ALE_SANITIZED)
    set(env ENVIRONMENT ALE_TEST_REDUCED=1)
  endif()
  gtest_discover_tests(${name} DISCOVERY_MODE PRE_TEST DISCOVERY_TIMEOUT 120 TEST_PREFIX "${A_PREFIX}"
                       PROPERTIES TIMEOUT 600 SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]" ${env})
endfunction()

# ale_benchmark(NAME SOURCES... [DEPS targets...]): a Google Benchmark binary (not a test).
function(ale_benchmark name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  if(ALE_BUILD_BENCHMARKS)
    ale_executable(${name} SOURCES ${A_SOURCES} DEPS ${A_DEPS} benchmark::benchmark)
  endif()
endfunction()

# ale_cli_test(TEST_NAME TARGET EXPECTED_EXIT [REQUIRES PATH] [EXPECT_OUTPUT REGEX] ARGS...): runs a
# tool (through qemu-arm when cross-compiling) and passes when it exits with EXPECTED_EXIT and,
# with EXPECT_OUTPUT, its output matches REGEX (tests/host/support/expect_exit.cmake checks both;
# never PASS_REGULAR_EXPRESSION, which makes ctest ignore the exit status). REQUIRES names
# recorded data the test reads: missing, the test is skipped, or fails when CI=true.
function(ale_cli_test test_name target expected_exit)
  if(NOT TARGET ${target})
    message(FATAL_ERROR "ale_cli_test(${test_name}): ${target} is not a target")
  endif()
  set(args ${ARGN})
  set(options)
  while(args)
    list(GET args 0 first)
    if(first STREQUAL "REQUIRES" OR first STREQUAL "EXPECT_OUTPUT")
      list(LENGTH args n)
      if(n LESS 2)
        message(FATAL_ERROR "ale_cli_test(${test_name}): ${first} needs a value")
      endif()
      list(GET args 1 value)
      list(APPEND options "-D${first}=${value}")
      list(REMOVE_AT args 0 1)
    else()
      break()
    endif()
  endwhile()
  add_test(NAME ${test_name}
           COMMAND ${CMAKE_COMMAND} -DEXPECTED_EXIT=${expected_exit} ${options} -P
                   ${PROJECT_SOURCE_DIR}/tests/host/support/expect_exit.cmake --
                   ${CMAKE_CROSSCOMPILING_EMULATOR} $<TARGET_FILE:${target}> ${args})
  set_tests_properties(${test_name} PROPERTIES SKIP_REGULAR_EXPRESSION "ALE_SKIP")
endfunction()

# ale_missing_reference(TEST_NAME TEXT): a test standing in for the tests a missing reference
# (TEXT names it and how to install it) left out of the build: skipped ("ALE_SKIP"), or failed
# when CI=true (tests/host/support/missing_reference.cmake).
function(ale_missing_reference test_name what)
  message(STATUS "${test_name}: ${what}")
  add_test(NAME ${test_name}
           COMMAND ${CMAKE_COMMAND} "-DWHAT=${what}" -P ${PROJECT_SOURCE_DIR}/tests/host/support/missing_reference.cmake)
  set_tests_properties(${test_name} PROPERTIES SKIP_REGULAR_EXPRESSION "ALE_SKIP")
endfunction()
