# SPDX-License-Identifier: MIT
# Finds OpenCV's calib3d module alone (vpe calibrate: checkerboard corners, camera, projector and
# stereo calibration, homographies), as the imported target OpenCV::calib3d. Not
# find_package(OpenCV): see FindOpenCVCore.cmake. libopencv-calib3d-dev brings its headers and
# those of features2d and flann, which calib3d's own library links.
include(FindPackageHandleStandardArgs)
find_package(OpenCVImgproc REQUIRED)

find_path(OpenCVCalib3d_INCLUDE_DIR NAMES opencv2/calib3d.hpp PATH_SUFFIXES opencv4
          DOC "OpenCV 4 calib3d headers (libopencv-calib3d-dev)")
find_library(OpenCVCalib3d_LIBRARY NAMES opencv_calib3d
             DOC "libopencv_calib3d (libopencv-calib3d-dev)")

find_package_handle_standard_args(OpenCVCalib3d
    REQUIRED_VARS OpenCVCalib3d_LIBRARY OpenCVCalib3d_INCLUDE_DIR)

if(OpenCVCalib3d_FOUND AND NOT TARGET OpenCV::calib3d)
    add_library(OpenCV::calib3d UNKNOWN IMPORTED)
    set_target_properties(OpenCV::calib3d PROPERTIES
        IMPORTED_LOCATION "${OpenCVCalib3d_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVCalib3d_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES OpenCV::imgproc)
endif()
mark_as_advanced(OpenCVCalib3d_INCLUDE_DIR OpenCVCalib3d_LIBRARY)
