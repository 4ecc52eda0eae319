# Cross-compiling for 64-bit ARM Linux with Debian's g++-aarch64-linux-gnu; its target libraries
# (libc, libstdc++) live in /usr/aarch64-linux-gnu, which is also the root qemu-aarch64 runs from.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
# Programs (the build's own tools) from the host; libraries and headers from the target only.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# How `ctest` runs the target's binaries on an x86 host (scripts/test.d/75-aarch64 calls qemu itself).
find_program(RC_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(RC_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${RC_QEMU_AARCH64} -L /usr/aarch64-linux-gnu)
endif()
