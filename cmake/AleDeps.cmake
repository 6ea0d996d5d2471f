# Finds ale-slam's dependencies. OpenCV and LCM come from ALE_DEPS_PREFIX (built by
# scripts/setup-deps.sh); the rest from Debian's packages of the target architecture.
# Static archives are preferred so the armhf daemon links fully statically.
find_package(Threads REQUIRED)

if(ALE_DEPS_PREFIX)
  list(PREPEND CMAKE_PREFIX_PATH ${ALE_DEPS_PREFIX})
endif()
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc
             HINTS ${ALE_DEPS_PREFIX}/lib/cmake/opencv4 ${ALE_DEPS_PREFIX}/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/opencv4)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

# A static library from the target architecture's multiarch folder, as an imported target.
function(ale_find_static target header lib)
  find_path(${target}_INCLUDE_DIR ${header} REQUIRED)
  find_library(${target}_LIBRARY NAMES ${lib} HINTS ${ALE_DEPS_PREFIX}/lib REQUIRED)
  add_library(${target} INTERFACE IMPORTED GLOBAL)
  target_include_directories(${target} SYSTEM INTERFACE ${${target}_INCLUDE_DIR})
  target_link_libraries(${target} INTERFACE ${${target}_LIBRARY} ${ARGN})
endfunction()

ale_find_static(ale::zlib zlib.h libz.a)
ale_find_static(ale::png png.h libpng16.a ale::zlib m)
ale_find_static(ale::jpeg jpeglib.h libjpeg.a)

if(ALE_WITH_LINUX_BACKENDS)
  ale_find_static(ale::gpiod gpiod.h libgpiod.a)
  find_library(ALE_GLIB_STATIC NAMES libglib-2.0.a REQUIRED)
  find_library(ALE_PCRE2_STATIC NAMES libpcre2-8.a REQUIRED)
  ale_find_static(ale::lcm lcm/lcm.h liblcm.a ${ALE_GLIB_STATIC} ${ALE_PCRE2_STATIC} Threads::Threads m)
  # lcm-gen runs on the build machine, also when cross-compiling
  find_program(ALE_LCM_GEN lcm-gen REQUIRED NO_CMAKE_FIND_ROOT_PATH)
endif()

if(ALE_BUILD_TESTS)
  if(CMAKE_CROSSCOMPILING)
    # Debian ships GoogleTest's sources; build them for the target.
    set(INSTALL_GTEST OFF CACHE BOOL "" FORCE)
    set(BUILD_GMOCK OFF CACHE BOOL "" FORCE)
    add_subdirectory(/usr/src/googletest ${CMAKE_BINARY_DIR}/_deps/googletest EXCLUDE_FROM_ALL)
    # googletest 1.12 defines GTest::gtest and GTest::gtest_main itself
  else()
    find_package(GTest REQUIRED)
  endif()
  include(GoogleTest)
endif()

if(ALE_BUILD_BENCHMARKS)
  find_package(benchmark QUIET HINTS ${ALE_DEPS_PREFIX}/lib/cmake/benchmark)
  if(NOT benchmark_FOUND)
    message(STATUS "Google Benchmark not found for this target: benchmarks are not built")
    set(ALE_BUILD_BENCHMARKS OFF)
  endif()
endif()
