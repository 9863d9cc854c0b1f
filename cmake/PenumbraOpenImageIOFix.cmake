# Debian 12's OpenImageIO CMake package lists /usr/include/opencv4 among the
# include directories of OpenImageIO::OpenImageIO although only libopencv-dev
# creates it; CMake then refuses to generate. Penumbra does not use OpenCV, so
# drop include directories that do not exist instead of pulling in OpenCV.
if(TARGET OpenImageIO::OpenImageIO)
  get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
  set(_kept "")
  foreach(_dir IN LISTS _oiio_inc)
    if(EXISTS "${_dir}" OR _dir MATCHES "^\\$<")
      list(APPEND _kept "${_dir}")
    endif()
  endforeach()
  set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_kept}")
endif()
