# SPDX-License-Identifier: MIT
# The device's systemd unit and its Debian package (docs/device-package.md): `cpack` in a
# device build (build/device) writes vpe-player_<version>_<arch>.deb.
#
# CPack's DEB generator rather than a debian/ tree: the package is exactly what the install
# rules above install — one list of files, kept next to the targets — and it builds from the
# same build directory as the binary (native or cross), with no second packaging tree to keep
# in step and no dpkg-buildpackage run that would configure and build everything again.

# The unit names the player and its documents by their installed paths, so it is written when
# it is installed, with the prefix of that install: /usr/local for `cmake --install`, /usr for
# the package (CPACK_SET_DESTDIR below: CPack installs with CMAKE_INSTALL_PREFIX=/usr into
# DESTDIR, as dpkg will). file(INSTALL) honours DESTDIR and records the file in the manifest.
install(CODE "set(VPE_UNIT_TEMPLATE \"${PROJECT_SOURCE_DIR}/boards/vpe-player.service.in\")
set(VPE_UNIT_CONFIGURED \"${PROJECT_BINARY_DIR}/package/unit/vpe-player.service\")
set(VPE_UNIT_BINDIR_RELATIVE \"${CMAKE_INSTALL_BINDIR}\")
set(VPE_UNIT_DOCDIR_RELATIVE \"${CMAKE_INSTALL_DOCDIR}\")")
install(CODE [[
set(VPE_UNIT_BINDIR "${CMAKE_INSTALL_PREFIX}/${VPE_UNIT_BINDIR_RELATIVE}")
set(VPE_UNIT_DOCDIR "${CMAKE_INSTALL_PREFIX}/${VPE_UNIT_DOCDIR_RELATIVE}")
configure_file("${VPE_UNIT_TEMPLATE}" "${VPE_UNIT_CONFIGURED}" @ONLY)
file(INSTALL "${VPE_UNIT_CONFIGURED}" DESTINATION "${CMAKE_INSTALL_PREFIX}/lib/systemd/system")
]])

# The example bundles: the GLES tests' vase (tests/renderer/gles_test_bundle.h, written from
# the bundle schema by vpe_write_test_bundle, no offline dependency), generated at build time
# for two projector sizes — 1920x1080 for a 1080p projector, 640x360 for quick checks (the
# install test, docs/kms-vm.md). The renderer refuses a bundle whose projector is not the
# display mode, hence one per size. Without the test suite (VPE_BUILD_TESTS=OFF) the same
# writer is built here. Cross-compiled, CMake runs it through CMAKE_CROSSCOMPILING_EMULATOR
# (qemu-user); the bundle is the same bytes on every architecture (little-endian FlatBuffers).
if(NOT TARGET vpe_write_test_bundle)
    add_executable(vpe_write_test_bundle
        ${PROJECT_SOURCE_DIR}/tests/firmware/bus/write_test_bundle.cpp
        ${PROJECT_SOURCE_DIR}/tests/renderer/gles_test_bundle.cpp
        ${PROJECT_SOURCE_DIR}/tests/renderer/test_scenes.cpp)
    target_include_directories(vpe_write_test_bundle PRIVATE ${PROJECT_SOURCE_DIR}/tests/renderer)
    target_link_libraries(vpe_write_test_bundle PRIVATE vpe::renderer_cpu vpe::proto
        vpe::proto_bundle)
    vpe_set_compile_options(vpe_write_test_bundle)
endif()
set(VPE_EXAMPLE_BUNDLES)
foreach(size 1920x1080 640x360)
    set(bundle ${PROJECT_BINARY_DIR}/package/examples/vase-${size}.vpeb)
    # Written to a temporary name and renamed: an interrupted build leaves no half bundle.
    add_custom_command(OUTPUT ${bundle}
        COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/package/examples
        COMMAND vpe_write_test_bundle --out ${bundle}.tmp --size ${size}
        COMMAND ${CMAKE_COMMAND} -E rename ${bundle}.tmp ${bundle}
        DEPENDS vpe_write_test_bundle
        COMMENT "Example bundle vase-${size}.vpeb"
        VERBATIM)
    list(APPEND VPE_EXAMPLE_BUNDLES ${bundle})
endforeach()
add_custom_target(vpe_example_bundles ALL DEPENDS ${VPE_EXAMPLE_BUNDLES})
install(FILES ${VPE_EXAMPLE_BUNDLES} DESTINATION ${CMAKE_INSTALL_DATADIR}/vpe/examples)

# The Debian architecture of the target: the host's (dpkg) when native, else the toolchain's
# CMAKE_SYSTEM_PROCESSOR in Debian's names.
if(CMAKE_CROSSCOMPILING)
    string(TOLOWER "${CMAKE_SYSTEM_PROCESSOR}" processor)
    if(processor MATCHES "^(aarch64|arm64)$")
        set(VPE_DEB_ARCHITECTURE arm64)
    elseif(processor MATCHES "^(x86_64|amd64)$")
        set(VPE_DEB_ARCHITECTURE amd64)
    elseif(processor MATCHES "^armv?[67]")
        set(VPE_DEB_ARCHITECTURE armhf)
    elseif(processor MATCHES "^i[3-6]86$")
        set(VPE_DEB_ARCHITECTURE i386)
    else()
        message(FATAL_ERROR "VpePackaging: no Debian architecture for CMAKE_SYSTEM_PROCESSOR "
                            "\"${CMAKE_SYSTEM_PROCESSOR}\"")
    endif()
else()
    find_program(VPE_DPKG dpkg)
    if(VPE_DPKG)
        execute_process(COMMAND ${VPE_DPKG} --print-architecture
                        OUTPUT_VARIABLE VPE_DEB_ARCHITECTURE OUTPUT_STRIP_TRAILING_WHITESPACE)
    else()
        set(VPE_DEB_ARCHITECTURE amd64)  # no dpkg: cpack -G DEB cannot run here anyway
    endif()
endif()

# The maintainer scripts, executable (dpkg refuses others): the vpe user and groups, and no
# service started on a fresh install (cmake/debian/postinst).
foreach(script postinst prerm postrm)
    file(COPY ${PROJECT_SOURCE_DIR}/cmake/debian/${script}
         DESTINATION ${PROJECT_BINARY_DIR}/package/debian
         FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE
                          WORLD_READ WORLD_EXECUTE)
endforeach()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME vpe-player)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "vpe maintainers <vpe@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "virtual photometric environment: the projector's player (EGL, GLES 3.1, DRM/KMS)")
set(CPACK_PACKAGE_DESCRIPTION
    "vpe-player renders a measured BRDF onto a white object through a projector, steered by \
knobs, a tracked lamp, OSC or a show's MQTT bus. With board files for the Raspberry Pi 4 and 5 \
and headless EGL, a systemd unit with a watchdog, and example bundles.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_SET_DESTDIR ON)
set(CPACK_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # vpe-player_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${VPE_DEB_ARCHITECTURE})
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The libraries the player links come from dpkg-shlibdeps. By hand only what no ELF header
# names: Mesa's DRI drivers (llvmpipe, kms_swrast, v3d, vc4), which libEGL's Mesa vendor
# loads at run time and nothing else depends on, and adduser for the maintainer scripts.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, libgl1-mesa-dri")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "mosquitto")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${PROJECT_BINARY_DIR}/package/debian/postinst ${PROJECT_BINARY_DIR}/package/debian/prerm
    ${PROJECT_BINARY_DIR}/package/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
# Cross-compiled, dpkg-shlibdeps runs inside the sysroot, a Debian root of the target's own
# (cmake/debian/cross-shlibdeps.cmake.in): this machine's dpkg knows no arm64 library.
if(CMAKE_CROSSCOMPILING AND CMAKE_SYSROOT)
    set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS OFF)
    set(VPE_PLAYER_BINARY $<TARGET_FILE:vpe-player>)
    configure_file(${PROJECT_SOURCE_DIR}/cmake/debian/cross-shlibdeps.cmake.in
                   ${PROJECT_BINARY_DIR}/package/cross-shlibdeps.cmake.in @ONLY)
    file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/package/cross-shlibdeps.cmake
         INPUT ${PROJECT_BINARY_DIR}/package/cross-shlibdeps.cmake.in)
    set(CPACK_PROJECT_CONFIG_FILE ${PROJECT_BINARY_DIR}/package/cross-shlibdeps.cmake)
endif()
# The .deb lands in the build directory (build/device).
set(CPACK_OUTPUT_FILE_PREFIX ${PROJECT_BINARY_DIR})
include(CPack)
