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
endfunction()

if(VPE_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                        -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
endif()
