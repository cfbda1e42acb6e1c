# SPDX-License-Identifier: MIT
# Finds OpenCV modules one by one, as imported targets OpenCV::<module>:
#
#   find_package(OpenCVModules REQUIRED COMPONENTS imgproc calib3d photo)
#
# Not find_package(OpenCV): see FindOpenCVCore.cmake, which this module uses for OpenCV::core.
# Each module comes from its own Debian package, libopencv-<module>-dev (the header
# opencv2/<module>.hpp and libopencv_<module>.so), so the build needs exactly the packages of
# the modules it names. What vpe uses them for:
#
#   imgproc  streak widths through its exact Euclidean distance transform (texture/).
#            libopencv-imgproc-dev adds only headers and a link to a library OpenImageIO
#            already pulls in.
#   calib3d  vpe calibrate: checkerboard corners, camera, projector and stereo calibration,
#            homographies (calibrate/). libopencv-calib3d-dev brings its headers and those of
#            features2d and flann, which calib3d's own library links.
#   photo    the camera's response from exposure brackets, Debevec & Malik (radiometry/).
#
# A module's OpenCV::<module> links OpenCV::core and the modules its headers use (the table
# below); what its shared library links on its own (calib3d's features2d and flann) the
# dynamic linker finds, so it is not named here. A module needed by a requested one is found
# too, as if requested.
include(FindPackageHandleStandardArgs)
find_package(OpenCVCore 4 REQUIRED)

# The OpenCV modules, besides core, that each module needs: all of them, in link order.
set(_vpe_opencv_needs_imgproc "")
set(_vpe_opencv_needs_calib3d imgproc)
set(_vpe_opencv_needs_photo imgproc)

set(_vpe_opencv_modules "")
foreach(_vpe_module IN LISTS OpenCVModules_FIND_COMPONENTS)
    list(APPEND _vpe_opencv_modules ${_vpe_opencv_needs_${_vpe_module}} ${_vpe_module})
endforeach()
list(REMOVE_DUPLICATES _vpe_opencv_modules)

foreach(_vpe_module IN LISTS _vpe_opencv_modules)
    find_path(OpenCVModules_${_vpe_module}_INCLUDE_DIR NAMES opencv2/${_vpe_module}.hpp
              PATH_SUFFIXES opencv4
              DOC "OpenCV 4 ${_vpe_module} headers (libopencv-${_vpe_module}-dev)")
    find_library(OpenCVModules_${_vpe_module}_LIBRARY NAMES opencv_${_vpe_module}
                 DOC "libopencv_${_vpe_module} (libopencv-${_vpe_module}-dev)")
    mark_as_advanced(OpenCVModules_${_vpe_module}_INCLUDE_DIR
                     OpenCVModules_${_vpe_module}_LIBRARY)

    # Found when its files are and so are the modules it needs (found earlier in this loop).
    set(OpenCVModules_${_vpe_module}_FOUND FALSE)
    if(OpenCVCore_FOUND AND OpenCVModules_${_vpe_module}_INCLUDE_DIR AND
       OpenCVModules_${_vpe_module}_LIBRARY)
        set(OpenCVModules_${_vpe_module}_FOUND TRUE)
        foreach(_vpe_needed IN LISTS _vpe_opencv_needs_${_vpe_module})
            if(NOT OpenCVModules_${_vpe_needed}_FOUND)
                set(OpenCVModules_${_vpe_module}_FOUND FALSE)
            endif()
        endforeach()
    endif()

    if(OpenCVModules_${_vpe_module}_FOUND AND NOT TARGET OpenCV::${_vpe_module})
        set(_vpe_links OpenCV::core)
        foreach(_vpe_needed IN LISTS _vpe_opencv_needs_${_vpe_module})
            list(APPEND _vpe_links OpenCV::${_vpe_needed})
        endforeach()
        add_library(OpenCV::${_vpe_module} UNKNOWN IMPORTED)
        set_target_properties(OpenCV::${_vpe_module} PROPERTIES
            IMPORTED_LOCATION "${OpenCVModules_${_vpe_module}_LIBRARY}"
            INTERFACE_INCLUDE_DIRECTORIES "${OpenCVModules_${_vpe_module}_INCLUDE_DIR}"
            INTERFACE_LINK_LIBRARIES "${_vpe_links}")
    endif()
endforeach()

# Reports each requested component (OpenCVModules_<module>_FOUND) and fails a REQUIRED call
# naming the missing ones, and the packages that hold them.
set(_vpe_missing "")
foreach(_vpe_module IN LISTS _vpe_opencv_modules)
    if(NOT OpenCVModules_${_vpe_module}_FOUND)
        list(APPEND _vpe_missing libopencv-${_vpe_module}-dev)
    endif()
endforeach()
set(_vpe_reason "")
if(_vpe_missing)
    list(JOIN _vpe_missing " " _vpe_missing)
    set(_vpe_reason "OpenCV modules come from ${_vpe_missing} (scripts/install-deps.sh)")
endif()
find_package_handle_standard_args(OpenCVModules
    REQUIRED_VARS OpenCVCore_LIBRARY OpenCVCore_INCLUDE_DIR
    HANDLE_COMPONENTS
    REASON_FAILURE_MESSAGE "${_vpe_reason}")

unset(_vpe_opencv_modules)
unset(_vpe_module)
unset(_vpe_needed)
unset(_vpe_links)
unset(_vpe_missing)
unset(_vpe_reason)
