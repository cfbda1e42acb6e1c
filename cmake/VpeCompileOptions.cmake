# SPDX-License-Identifier: MIT
# Warnings (as errors) and sanitizers for vpe's own targets; third-party headers come in as
# SYSTEM includes through their imported targets and are not affected.

function(vpe_set_compile_options target)
    target_compile_options(${target} PRIVATE
        -Wall -Wextra -Wpedantic -Werror
        -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
        -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
        # -Wrestrict: GCC 12 reports false overlaps inside std::string at -O3 (GCC bug 105329).
        target_compile_options(${target} PRIVATE -Wduplicated-cond -Wlogical-op -Wno-restrict)
    endif()
    if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
        # Clang's -Wdouble-promotion also flags float → double in initializations and returns
        # (widening a float sample into a Vec3d), which the code does on purpose; GCC, whose
        # warning only covers arithmetic promotions, keeps guarding the float kernels.
        target_compile_options(${target} PRIVATE -Wno-double-promotion)
    endif()
endfunction()

if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # Clang writes its inputs' time stamps into a precompiled header, and a fresh clone's differ:
    # without this, every source that uses one would miss the compile cache in each new clone
    # (scripts/lib/compile-cache.sh; ccache's manual asks for it).
    add_compile_options("SHELL:-Xclang -fno-pch-timestamp")
endif()

if(VPE_SANITIZE)
    # Without UBSan's null and alignment checks, which GCC places at every reference binding
    # and were a third of this build's compile time (extended_chunk_fit.cpp: 26 s → 17 s, two
    # jobs): ASan reports a null dereference itself (SEGV on address 0, with the stack), and
    # the fuzz build below keeps both checks on the parsers of file and packet bytes, where a
    # misaligned read would come from. (The asan preset builds with clang since CI's time was
    # halved, docs/ci-budget.md; its instrumentation costs far less, and the checks stay off
    # until measured there.)
    add_compile_options(-fsanitize=address,undefined -fno-sanitize=null,alignment
                        -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
endif()

if(VPE_BUILD_FUZZERS)
    # libFuzzer is guided by coverage of the code under test, so every library is instrumented,
    # not only the fuzz targets; UBSan must abort for the fuzzer to notice. The fuzz
    # executables add -fsanitize=fuzzer at link time to get libFuzzer's main.
    add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                        -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
endif()
