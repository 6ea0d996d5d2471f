# cmake -DWHAT=TEXT -P missing_reference.cmake: stands in for tests that were not built because a
# reference they compare against is not installed (Ceres, the Java LCM decoder). Without CI it
# prints ALE_SKIP and ctest counts the test as skipped, so the smaller run shows in the summary;
# with CI=true it fails: CI must run the whole suite.
if("$ENV{CI}" STREQUAL "true")
  message(FATAL_ERROR "CI=true but a reference is missing: ${WHAT}")
endif()
message("ALE_SKIP: reference missing, its tests are not built: ${WHAT}")
