# cmake -DFUZZER=BIN -DSECONDS=S -DSEEDS=DIR -DWORK=DIR -P run_fuzzer.cmake: one bounded libFuzzer
# run of BIN (a ctest test, tests/fuzz/CMakeLists.txt). New inputs go to WORK/corpus/<name>/ (the
# first corpus folder is the one libFuzzer writes to; the committed seeds stay as they are), a
# finding to WORK/artifacts/<name>-<kind>-<sha1>. Fails on any finding: a crash, a sanitizer
# report, a leak, an input slower than 10 s, a single allocation over 512 MB (what a length
# taken on trust from a header looks like) or a process over 2048 MB (AddressSanitizer's
# quarantine alone holds up to 256 MB of freed blocks: five-minute runs peak at 366-731 MB). The
# target's own flags (tests/fuzz/<name>.flags: libFuzzer flags, '#' comments) come last and win.
get_filename_component(name "${FUZZER}" NAME)
string(REGEX REPLACE "^fuzz_" "" name "${name}")
set(flags)
set(flags_file "${CMAKE_CURRENT_LIST_DIR}/${name}.flags")
if(EXISTS "${flags_file}")
  file(STRINGS "${flags_file}" lines)
  foreach(line ${lines})
    string(REGEX REPLACE "#.*" "" line "${line}")
    separate_arguments(words UNIX_COMMAND "${line}")
    list(APPEND flags ${words})
  endforeach()
endif()
file(MAKE_DIRECTORY "${WORK}/corpus/${name}" "${WORK}/artifacts")
execute_process(
  COMMAND "${FUZZER}" -max_total_time=${SECONDS} -rss_limit_mb=2048 -malloc_limit_mb=512 -timeout=10 -print_final_stats=1
          "-artifact_prefix=${WORK}/artifacts/${name}-" ${flags} "${WORK}/corpus/${name}" "${SEEDS}"
  RESULT_VARIABLE exit_status)
if(NOT exit_status EQUAL 0)
  message(FATAL_ERROR "fuzz_${name} exited with ${exit_status}: the input is in ${WORK}/artifacts/ (docs/fuzzing.md says how to replay it)")
endif()
