# find_package(OpenCVModules REQUIRED COMPONENTS core imgproc ...) -> imported targets
# OpenCV::<component>. Debian ships OpenCV's CMake config only in libopencv-dev, which pulls every
# module (VTK, dnn, Qt ...); plugslam installs just the modules it uses (libopencv-<c>-dev), so
# the libraries are found directly.
find_path(OpenCVModules_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4)
set(_ocv_missing)
foreach(c ${OpenCVModules_FIND_COMPONENTS})
  find_library(OpenCVModules_${c}_LIBRARY NAMES opencv_${c})
  if(OpenCVModules_${c}_LIBRARY AND OpenCVModules_INCLUDE_DIR)
    set(OpenCVModules_${c}_FOUND TRUE)
    if(NOT TARGET OpenCV::${c})
      add_library(OpenCV::${c} UNKNOWN IMPORTED)
      set_target_properties(OpenCV::${c} PROPERTIES
        IMPORTED_LOCATION "${OpenCVModules_${c}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${OpenCVModules_INCLUDE_DIR}")
    endif()
  else()
    list(APPEND _ocv_missing ${c})
  endif()
endforeach()
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCVModules REQUIRED_VARS OpenCVModules_INCLUDE_DIR
  HANDLE_COMPONENTS
  REASON_FAILURE_MESSAGE "missing OpenCV modules: ${_ocv_missing} (scripts/install-deps.sh installs libopencv-<module>-dev)")
