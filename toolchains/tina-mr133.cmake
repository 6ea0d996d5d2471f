# The vendor's Tina Linux toolchain for the MR133 (an arm-openwrt-linux-gnueabi or
# arm-openwrt-linux-muslgnueabi GCC shipped in the Tina SDK).
#
#   cmake -DCMAKE_TOOLCHAIN_FILE=toolchains/tina-mr133.cmake \
#         -DTINA_TOOLCHAIN_DIR=/opt/tina/prebuilt/gcc/linux-x86/arm/toolchain-sunxi-musl/toolchain \
#         [-DTINA_TRIPLE=arm-openwrt-linux-muslgnueabi] -DALE_DEPS_PREFIX=...
#
# TINA_TOOLCHAIN_DIR (or the environment variable of the same name) is the folder that holds
# bin/<triple>-g++. The dependencies (OpenCV core+imgproc, LCM, glib, libgpiod, libpng,
# libjpeg) must be built with the same toolchain into ALE_DEPS_PREFIX; see docs/building.md.
if(NOT TINA_TOOLCHAIN_DIR AND DEFINED ENV{TINA_TOOLCHAIN_DIR})
  set(TINA_TOOLCHAIN_DIR "$ENV{TINA_TOOLCHAIN_DIR}")
endif()
if(NOT TINA_TOOLCHAIN_DIR)
  message(FATAL_ERROR "tina-mr133.cmake: set TINA_TOOLCHAIN_DIR to the Tina SDK toolchain folder")
endif()
if(NOT TINA_TRIPLE)
  file(GLOB _tina_gxx "${TINA_TOOLCHAIN_DIR}/bin/*-g++")
  list(LENGTH _tina_gxx _n)
  if(NOT _n EQUAL 1)
    message(FATAL_ERROR "tina-mr133.cmake: found ${_n} *-g++ in ${TINA_TOOLCHAIN_DIR}/bin; set TINA_TRIPLE")
  endif()
  get_filename_component(_gxx "${_tina_gxx}" NAME)
  string(REGEX REPLACE "-g\\+\\+$" "" TINA_TRIPLE "${_gxx}")
endif()
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(CMAKE_C_COMPILER   "${TINA_TOOLCHAIN_DIR}/bin/${TINA_TRIPLE}-gcc")
set(CMAKE_CXX_COMPILER "${TINA_TOOLCHAIN_DIR}/bin/${TINA_TRIPLE}-g++")
set(CMAKE_SYSROOT "${TINA_TOOLCHAIN_DIR}" CACHE PATH "")
set(_ale_cpu "-mcpu=cortex-a7 -mfpu=neon-vfpv4 -mfloat-abi=hard -ffp-contract=off")
set(CMAKE_C_FLAGS_INIT   "${_ale_cpu}")
set(CMAKE_CXX_FLAGS_INIT "${_ale_cpu}")
set(CMAKE_FIND_ROOT_PATH "${TINA_TOOLCHAIN_DIR}" ${ALE_DEPS_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
find_program(_qemu qemu-arm-static)
if(_qemu)
  set(CMAKE_CROSSCOMPILING_EMULATOR "${_qemu}")
endif()
