#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Installs the Debian 12 packages vpe needs that are missing. As root it runs apt-get;
# otherwise it prints the exact apt line and stops, so nothing is installed behind your back.
#   scripts/install-deps.sh          build + run the offline tools
#   scripts/install-deps.sh --test   also GoogleTest, Google Benchmark, clang + libFuzzer, clang-format
#   scripts/install-deps.sh --demo   also what only the demo runs (ffmpeg for its MP4)
#   scripts/install-deps.sh --arm64  also what cross-builds the device for arm64 and runs its
#                                    tests under qemu-user (scripts/arm64-sysroot.sh)
#   scripts/install-deps.sh --list [--test] [--demo] [--arm64]
#                                    print the packages named here, one per line
#                                    (scripts/audit-deps.sh reads them)
#   scripts/install-deps.sh --list-arm64-root
#                                    print the arm64 packages of the device's sysroot: what the
#                                    device build and its tests need on a Pi, nothing offline
#   scripts/install-deps.sh --list-device-runtime
#                                    print what the player's package Depends on at run time
#                                    (the base of the roots that install it: root-cache.sh)
#
# Every file the build finds on the system must come from a package named here or from one of
# their dependencies (the audit in scripts/test.sh checks it).
set -euo pipefail

packages=(
    cmake ninja-build g++ pkg-config          # build
    zlib1g-dev libflatbuffers-dev flatbuffers-compiler  # device bundle (proto/BUNDLE.md)
    libopenimageio-dev openimageio-tools      # image codecs (JPEG, PNG, TIFF), oiiotool
    libeigen3-dev nlohmann-json3-dev libcli11-dev libfftw3-dev
    libhwy-dev                                # the fit's SIMD kernels, one source for AVX-512, AVX2,
                                              # SSE4 and NEON, picked at run time (Google Highway)
    libassimp-dev libopencv-core-dev          # screen meshes, projector calibration files
    libopencv-imgproc-dev                     # streak widths (exact distance transform)
    libopencv-calib3d-dev                     # vpe calibrate: checkerboards, camera + stereo calibration
    libopencv-photo-dev                       # camera response from exposure brackets (Debevec)
    libopen3d-dev                             # vpe bake --scan: global registration (FPFH + RANSAC), ICP
    fonts-dejavu-core                         # labels on contact sheets
    libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri  # GLES 3.1 renderer, headless (llvmpipe)
    libdrm-dev libgbm-dev                     # GLES renderer's KMS platform (DRM + GBM + EGL)
    libtomlplusplus-dev                       # vpe-player's board files (boards/*.toml)
    libgpiod-dev liblo-dev libcamera-dev      # vpe-player's inputs: knobs (1.6 API), OSC, tracked lamp
    libsystemd-dev                            # vpe-player's sd_notify watchdog (boards/vpe-player.service)
    libmosquitto-dev                          # vpe-player's shared light: the MQTT client (firmware/bus/)
    libtinyobjloader-dev                      # the procam simulator's scene files (object OBJ), on the device too
)
test_packages=(
    libgtest-dev libgmock-dev libbenchmark-dev
    clang libclang-rt-14-dev                  # libFuzzer, sanitizers
    jq                                        # the dependency audit reads CMake's file API
    clang-format                              # scripts/check-format.sh (the style check)
    mosquitto mosquitto-clients               # the bus tests' own broker, mosquitto_passwd; scripts/multi-node-report.sh
    openssl                                   # the bus tests' TLS certificates
    chromium chromium-driver                  # the control page's test: a headless browser and its driver
    python3-selenium                          # the control page's test drives chromium-driver with it
    glslang-dev glslang-tools spirv-tools     # vpe_shader_cost: GLSL → SPIR-V, optimizer (glslang-dev's
                                              # CMake config names glslangValidator, in glslang-tools)
    ccache                                    # scripts/lib/compile-cache.sh: one compile cache per machine for every build
    dpkg-dev                                  # cpack's DEB generator: dpkg-shlibdeps computes the package's Depends
    mmdebstrap                                # scripts/package-check.sh, kms-vm-check.sh: fresh Debian 12 roots
    qemu-system-x86                           # scripts/kms-vm-check.sh: Debian's kernel and virtio-gpu under TCG
    e2fsprogs                                 # scripts/kms-vm-check.sh: the guest's disk (mkfs.ext4 -d)
)
demo_packages=(
    ffmpeg                                    # the demo's animation of the visitor view (MP4, H.264)
)
arm64_packages=(
    crossbuild-essential-arm64                # aarch64-linux-gnu-g++ (cmake/aarch64-linux-gnu.cmake)
    qemu-user-static                          # the device tests under qemu-aarch64 (binfmt_misc)
    mmdebstrap arch-test                      # the arm64 sysroot: a Debian 12 arm64 root (arch-test:
                                              # mmdebstrap checks it can run arm64)
)
# The sysroot's own packages, arm64, installed by scripts/arm64-sysroot.sh into build/arm64-root
# (never on this machine): the device build's libraries (no offline one), its test frameworks,
# and Mesa's llvmpipe for the headless GLES tests.
arm64_root_packages=(
    libc6-dev libstdc++-12-dev
    zlib1g-dev libflatbuffers-dev nlohmann-json3-dev
    libegl-dev libgles-dev libegl-mesa0 libgl1-mesa-dri libdrm-dev libgbm-dev
    libtomlplusplus-dev libtinyobjloader-dev libgpiod-dev liblo-dev libcamera-dev libsystemd-dev
    libmosquitto-dev
    libgtest-dev libgmock-dev libbenchmark-dev
    dpkg-dev                                  # the arm64 package's Depends: dpkg-shlibdeps run here
)

# What vpe-player's package (cpack, dpkg-shlibdeps) Depends on, without versions, any
# architecture: the base roots the package check and the KMS VM install it into are made of these
# ahead of the package (scripts/device-roots.sh, beside the builds). A library the package comes
# to need that is missing here still gets installed by apt, from Debian, when the package is.
device_runtime_packages=(
    adduser libc6 libgcc-s1 libstdc++6 zlib1g libsystemd0
    libegl1 libgles2 libgbm1 libdrm2 libgl1-mesa-dri
    libcamera0.0.3 libgpiod2 liblo7 libmosquitto1 libtinyobjloader2rc10 libtomlplusplus3
)

test=0
demo=0
arm64=0
list=0
for argument in "$@"; do
    case "$argument" in
        --test) test=1 ;;
        --demo) demo=1 ;;
        --arm64) arm64=1 ;;
        --list) list=1 ;;
        --list-arm64-root) printf '%s\n' "${arm64_root_packages[@]}"; exit 0 ;;
        --list-device-runtime) printf '%s\n' "${device_runtime_packages[@]}"; exit 0 ;;
        *) echo "install-deps: unknown option $argument" >&2; exit 2 ;;
    esac
done
if [[ $test -eq 1 ]]; then
    packages+=("${test_packages[@]}")
fi
if [[ $demo -eq 1 ]]; then
    packages+=("${demo_packages[@]}")
fi
if [[ $arm64 -eq 1 ]]; then
    packages+=("${arm64_packages[@]}")
fi
if [[ $list -eq 1 ]]; then
    printf '%s\n' "${packages[@]}"
    exit 0
fi

missing=()
for package in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done
if [[ ${#missing[@]} -eq 0 ]]; then
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    echo "vpe: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
    echo "vpe: missing Debian packages; install them with:" >&2
    echo "  sudo apt-get install --no-install-recommends ${missing[*]}" >&2
    exit 1
fi
