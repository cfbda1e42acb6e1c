# SPDX-License-Identifier: MIT
# One room's static library, declared the same way everywhere (offline/, firmware/, renderer/):
# vpe_<name> with the alias vpe::<name>, its include directories and libraries, and the project's
# compile options (VpeCompileOptions.cmake).
#
#   vpe_room_library(<name> SOURCES <files>...
#                    [PUBLIC_INCLUDES <dirs>...] [PRIVATE_INCLUDES <dirs>...]
#                    [PUBLIC_LIBS <targets>...] [PRIVATE_LIBS <targets>...])
#
# A hardware or file library belongs in PRIVATE_LIBS: it stays in its room.

function(vpe_room_library name)
    cmake_parse_arguments(ROOM "" ""
        "SOURCES;PUBLIC_INCLUDES;PRIVATE_INCLUDES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
    add_library(vpe_${name} STATIC ${ROOM_SOURCES})
    add_library(vpe::${name} ALIAS vpe_${name})
    if(ROOM_PUBLIC_INCLUDES)
        target_include_directories(vpe_${name} PUBLIC ${ROOM_PUBLIC_INCLUDES})
    endif()
    if(ROOM_PRIVATE_INCLUDES)
        target_include_directories(vpe_${name} PRIVATE ${ROOM_PRIVATE_INCLUDES})
    endif()
    target_link_libraries(vpe_${name}
        PUBLIC ${ROOM_PUBLIC_LIBS} PRIVATE ${ROOM_PRIVATE_LIBS})
    vpe_set_compile_options(vpe_${name})
endfunction()
