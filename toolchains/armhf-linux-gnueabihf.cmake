# Debian's cross compiler (crossbuild-essential-armhf) for the Allwinner MR133:
# ARMv7-A Cortex-A7, NEON, VFPv4, hard float. Libraries come from Debian's multiarch
# armhf packages (/usr/lib/arm-linux-gnueabihf), so no sysroot is needed.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(CMAKE_LIBRARY_ARCHITECTURE arm-linux-gnueabihf)
set(CMAKE_C_COMPILER   arm-linux-gnueabihf-gcc)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)
set(CMAKE_AR     arm-linux-gnueabihf-ar     CACHE FILEPATH "")
set(CMAKE_RANLIB arm-linux-gnueabihf-ranlib CACHE FILEPATH "")
set(CMAKE_STRIP  arm-linux-gnueabihf-strip  CACHE FILEPATH "")
set(PKG_CONFIG_EXECUTABLE arm-linux-gnueabihf-pkg-config CACHE FILEPATH "")
# All CPU flags live here (a -DCMAKE_CXX_FLAGS on the command line would drop them).
# -ffp-contract=off keeps GCC from fusing a*b+c into vfma, so float results match x86.
set(_ale_cpu "-mcpu=cortex-a7 -mfpu=neon-vfpv4 -mfloat-abi=hard -ffp-contract=off")
set(CMAKE_C_FLAGS_INIT   "${_ale_cpu}")
set(CMAKE_CXX_FLAGS_INIT "${_ale_cpu}")
set(CMAKE_FIND_ROOT_PATH /usr/arm-linux-gnueabihf)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)   # host tools such as lcm-gen
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# ctest and try_run start ARM binaries through qemu (no binfmt registration is assumed)
set(CMAKE_CROSSCOMPILING_EMULATOR /usr/bin/qemu-arm-static)
