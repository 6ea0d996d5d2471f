# Host (x86_64) build: the same floating-point contract as the armhf build, so that
# float-based references (OpenCV's CLAHE) give the same results on both.
set(CMAKE_C_FLAGS_INIT   "-ffp-contract=off")
set(CMAKE_CXX_FLAGS_INIT "-ffp-contract=off")
