# SPDX-License-Identifier: MIT
# Finds OpenCV's core module alone (vpe reads projector calibrations with cv::FileStorage and
# needs nothing else), as the imported target OpenCV::core.
#
# Why not find_package(OpenCV): Debian ships OpenCVConfig.cmake and opencv4.pc only in the
# libopencv-dev meta-package, which pulls in every OpenCV module and, through them, VTK, Qt 5,
# Open MPI, Tesseract and FFmpeg (77 more packages on a fresh Debian 12). libopencv-core-dev
# holds everything core needs: its headers and libopencv_core.so.
include(FindPackageHandleStandardArgs)

find_path(OpenCVCore_INCLUDE_DIR NAMES opencv2/core.hpp PATH_SUFFIXES opencv4
          DOC "OpenCV 4 headers (libopencv-core-dev)")
find_library(OpenCVCore_LIBRARY NAMES opencv_core DOC "libopencv_core (libopencv-core-dev)")

if(OpenCVCore_INCLUDE_DIR AND EXISTS "${OpenCVCore_INCLUDE_DIR}/opencv2/core/version.hpp")
    file(STRINGS "${OpenCVCore_INCLUDE_DIR}/opencv2/core/version.hpp" _vpe_opencv_version
         REGEX "^#define CV_VERSION_(MAJOR|MINOR|REVISION) +[0-9]+")
    foreach(_part MAJOR MINOR REVISION)
        string(REGEX REPLACE ".*#define CV_VERSION_${_part} +([0-9]+).*" "\\1" _vpe_${_part}
               "${_vpe_opencv_version}")
    endforeach()
    set(OpenCVCore_VERSION "${_vpe_MAJOR}.${_vpe_MINOR}.${_vpe_REVISION}")
endif()

find_package_handle_standard_args(OpenCVCore
    REQUIRED_VARS OpenCVCore_LIBRARY OpenCVCore_INCLUDE_DIR
    VERSION_VAR OpenCVCore_VERSION)

if(OpenCVCore_FOUND AND NOT TARGET OpenCV::core)
    add_library(OpenCV::core UNKNOWN IMPORTED)
    set_target_properties(OpenCV::core PROPERTIES
        IMPORTED_LOCATION "${OpenCVCore_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVCore_INCLUDE_DIR}")
endif()
mark_as_advanced(OpenCVCore_INCLUDE_DIR OpenCVCore_LIBRARY)
