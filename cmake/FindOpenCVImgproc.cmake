# SPDX-License-Identifier: MIT
# Finds OpenCV's imgproc module alone (vpe measures streak widths with its exact Euclidean
# distance transform), as the imported target OpenCV::imgproc. Not find_package(OpenCV): see
# FindOpenCVCore.cmake. libopencv-imgproc-dev adds only headers and a link to a library
# OpenImageIO already pulls in.
include(FindPackageHandleStandardArgs)
find_package(OpenCVCore 4 REQUIRED)

find_path(OpenCVImgproc_INCLUDE_DIR NAMES opencv2/imgproc.hpp PATH_SUFFIXES opencv4
          DOC "OpenCV 4 imgproc headers (libopencv-imgproc-dev)")
find_library(OpenCVImgproc_LIBRARY NAMES opencv_imgproc
             DOC "libopencv_imgproc (libopencv-imgproc-dev)")

find_package_handle_standard_args(OpenCVImgproc
    REQUIRED_VARS OpenCVImgproc_LIBRARY OpenCVImgproc_INCLUDE_DIR)

if(OpenCVImgproc_FOUND AND NOT TARGET OpenCV::imgproc)
    add_library(OpenCV::imgproc UNKNOWN IMPORTED)
    set_target_properties(OpenCV::imgproc PROPERTIES
        IMPORTED_LOCATION "${OpenCVImgproc_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVImgproc_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES OpenCV::core)
endif()
mark_as_advanced(OpenCVImgproc_INCLUDE_DIR OpenCVImgproc_LIBRARY)
