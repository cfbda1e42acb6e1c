# SPDX-License-Identifier: MIT
# Cross-compiles the device build for a Raspberry Pi 4/5 (arm64, Debian 12 / Raspberry Pi OS
# bookworm) with Debian's cross compiler against a sysroot made by scripts/arm64-sysroot.sh,
# and runs what the build runs (GoogleTest's test discovery, ctest) through qemu-aarch64.
#   cmake --preset device-arm64        (CMakePresets.json; the sysroot in build/arm64-root)
# The sysroot is a whole Debian arm64 root rather than multiarch packages on this machine:
# liblo-dev is not Multi-Arch: same, so its arm64 and amd64 builds cannot be installed side by
# side, and a separate root keeps the offline libraries out of the device's reach.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(VPE_ARM64_SYSROOT "${CMAKE_CURRENT_LIST_DIR}/../build/arm64-root"
    CACHE PATH "Debian 12 arm64 root to build against (scripts/arm64-sysroot.sh)")
get_filename_component(VPE_ARM64_SYSROOT "${VPE_ARM64_SYSROOT}" ABSOLUTE)
if(NOT EXISTS "${VPE_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu")
    message(FATAL_ERROR "${VPE_ARM64_SYSROOT}: no arm64 sysroot; make it with scripts/arm64-sysroot.sh")
endif()

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_SYSROOT "${VPE_ARM64_SYSROOT}")
# Headers, libraries and package configs only from the sysroot; programs (flatc, pkg-config,
# glslang) from this machine.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config reads only the sysroot's .pc files and prefixes their paths with it (without
# PKG_CONFIG_LIBDIR it would find this machine's amd64 EGL).
set(ENV{PKG_CONFIG_DIR} "")
set(ENV{PKG_CONFIG_LIBDIR}
    "${VPE_ARM64_SYSROOT}/usr/lib/aarch64-linux-gnu/pkgconfig:${VPE_ARM64_SYSROOT}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${VPE_ARM64_SYSROOT}")

# Test discovery and ctest run the arm64 programs through qemu with the sysroot as their root
# for the dynamic loader and libraries; programs they start themselves (vpe-player from a
# test, through sh) find qemu through binfmt_misc and the same root through QEMU_LD_PREFIX,
# which the device-arm64 test preset sets.
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64-static -L "${VPE_ARM64_SYSROOT}")
