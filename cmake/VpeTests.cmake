# SPDX-License-Identifier: MIT
# vpe_discover_tests: GoogleTest discovery with ctest LABELS, so a developer can run a part of
# the suite (`ctest -L unit`, `ctest -LE 'slow|fuzz'`, what `scripts/test.sh --quick` runs).
#
# The labels, one or more per test:
#   unit  quick, CPU only: none of the others
#   gpu   draws through EGL (Mesa llvmpipe headless here) or asks for a display device
#   slow  takes seconds on an idle 2-core machine (a whole pipeline: synth, fit, bake, render)
#   data  reads the real captures (../shared/data or $VPE_DATA; skips when they are absent)
#   fuzz  a libFuzzer target (tests/fuzz, labelled there)
# and, beside one of those:
#   realtime  its subject is behaviour in real time at a board's frame rate (nodes agreeing
#             within a frame at 60 Hz, a show riding out faults within seconds, a page seeing
#             a node within 2 s): it needs the device's own speed, so the arm64 run under
#             qemu-user, 10-50x slower than a Pi, leaves it out (scripts/test.sh says so);
#             a discovered one runs alone (RUN_SERIAL): a test beside it starved its players
#             of frames (cmake/VpeDiscoverTests.cmake); the control page's scenario, judged
#             in seconds, not frames, shares the machine
#   heavy     a second or more in release that AddressSanitizer multiplies 4-80x: large
#             numeric fits, or many small decodes each of which OpenImageIO gives a 64 MiB
#             scratch buffer that ASan poisons. The sanitizer run leaves it out (test.sh);
#             smaller tests take the same code paths there
#
#   vpe_discover_tests(TARGET
#       [GPU]                  every test of TARGET draws (else: those matching GPU_MATCHING)
#       [GPU_MATCHING regex] [SLOW_MATCHING regex] [DATA_MATCHING regex]
#       [REALTIME_MATCHING regex] [HEAVY_MATCHING regex]
#       [ENVIRONMENT "NAME=value"]   set for every test of TARGET
#       [PRECOMPILE header ...])     precompiled for TARGET beside GoogleTest's and the
#                                    standard library's (without: the build's one shared
#                                    precompiled header is reused)
#
# Regexes match the full test name (Suite.Test). Tests of real captures are named
# *RealData* or *RealCapture* by convention, and match without being listed.
#
# The tests labelled only unit or only gpu run a suite per process, as "Suite (N tests)"; the
# others one per process under their own names (cmake/VpeDiscoverTests.cmake says why). The
# binaries' main (tests/test_main.cpp) exits 77 when every test it ran was skipped, which ctest
# reports as skipped.
#
# Discovery runs after each build of TARGET (through the cross-compiling emulator when there is
# one) and writes the ctest file that ctest includes.
#
# Test sources compile with their target's precompiled headers (GoogleTest, nlohmann/json, the
# standard headers): parsing them was about 40 % of a test file's compile. In the release build
# the test code itself compiles at -O1: code generation at -O3 was most of the rest (e.g.
# radiometry_test.cpp 10.2 s at -O3, 4.2 s at -O1 with the headers precompiled), and the code
# under test lives in the libraries, which stay at -O3.
# The headers every test source parses, precompiled once for the whole build on vpe_test_main
# (vpe_test_main_library below) and reused by each suite that adds none of its own: a suite's
# own copy took 8-9 s to build, about 17 of them per build (release, ASan and arm64 each).
set(VPE_TEST_PRECOMPILED_HEADERS <gtest/gtest.h> <algorithm> <array> <chrono> <cmath> <cstdint>
    <cstdio> <cstdlib> <cstring> <filesystem> <fstream> <functional> <iostream> <limits> <map>
    <memory> <optional> <random> <sstream> <stdexcept> <string> <thread> <utility> <vector>)

# Test code compiles at -O1 in the release build (the code under test lives in the libraries,
# at -O3). A precompiled header is reused only by sources compiled with the same optimization.
function(vpe_compile_as_test_code target)
    if(CMAKE_BUILD_TYPE STREQUAL "Release")
        target_compile_options(${target} PRIVATE -O1)
    endif()
endfunction()

# vpe_test_main_library(NAME SOURCE): every GoogleTest binary's main, and the precompiled
# headers that the suites reuse.
function(vpe_test_main_library name source)
    add_library(${name} STATIC ${source})
    target_link_libraries(${name} PUBLIC GTest::gtest)
    vpe_set_compile_options(${name})
    vpe_compile_as_test_code(${name})
    target_precompile_headers(${name} PRIVATE ${VPE_TEST_PRECOMPILED_HEADERS})
endfunction()

set(VPE_DISCOVER_TESTS_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/VpeDiscoverTests.cmake)

function(vpe_discover_tests target)
    cmake_parse_arguments(PARSE_ARGV 1 arg "GPU"
        "GPU_MATCHING;SLOW_MATCHING;DATA_MATCHING;REALTIME_MATCHING;HEAVY_MATCHING;ENVIRONMENT"
        "PRECOMPILE")
    set(gpu_matching "${arg_GPU_MATCHING}")
    if(arg_GPU)
        set(gpu_matching ".")
    endif()

    target_link_libraries(${target} PRIVATE vpe_test_main)
    if(arg_PRECOMPILE)
        target_precompile_headers(${target} PRIVATE ${VPE_TEST_PRECOMPILED_HEADERS}
            ${arg_PRECOMPILE})
    else()
        target_precompile_headers(${target} REUSE_FROM vpe_test_main)
    endif()
    vpe_compile_as_test_code(${target})

    set(ctest_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_tests.cmake)
    set(include_file ${CMAKE_CURRENT_BINARY_DIR}/${target}_include.cmake)
    add_custom_command(TARGET ${target} POST_BUILD
        COMMAND ${CMAKE_COMMAND}
            -D "TEST_EXECUTABLE=$<TARGET_FILE:${target}>"
            -D "TEST_EXECUTOR=$<TARGET_PROPERTY:${target},CROSSCOMPILING_EMULATOR>"
            -D "TEST_WORKING_DIR=${CMAKE_CURRENT_BINARY_DIR}"
            -D "CTEST_FILE=${ctest_file}"
            -D "TEST_ENVIRONMENT=${arg_ENVIRONMENT}"
            -D "GPU_MATCHING=${gpu_matching}"
            -D "SLOW_MATCHING=${arg_SLOW_MATCHING}"
            -D "DATA_MATCHING=${arg_DATA_MATCHING}"
            -D "REALTIME_MATCHING=${arg_REALTIME_MATCHING}"
            -D "HEAVY_MATCHING=${arg_HEAVY_MATCHING}"
            -P ${VPE_DISCOVER_TESTS_SCRIPT}
        BYPRODUCTS ${ctest_file}
        VERBATIM)
    file(WRITE ${include_file}
        "if(EXISTS \"${ctest_file}\")\n"
        "    include(\"${ctest_file}\")\n"
        "else()\n"
        "    add_test(${target}_NOT_BUILT ${target}_NOT_BUILT)\n"
        "endif()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${include_file})
endfunction()
