# Dependencies used by examples, tests and benchmarks only (not by the library).

# OpenImageIO: Debian bookworm's config lists /usr/include/opencv4 as an include dir
# although libopenimageio-dev does not depend on OpenCV. Drop non-existent entries
# instead of pulling in all of libopencv-dev.
find_package(OpenImageIO QUIET CONFIG)
if(TARGET OpenImageIO::OpenImageIO)
  foreach(prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(dirs OpenImageIO::OpenImageIO ${prop})
    if(dirs)
      set(kept)
      foreach(d IN LISTS dirs)
        if(EXISTS "${d}" OR d MATCHES "^\\$<")
          list(APPEND kept "${d}")
        endif()
      endforeach()
      set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${prop} "${kept}")
    endif()
  endforeach()
endif()

# MPFR (and GMP) for high-precision references in tests and benchmarks.
find_path(MPFR_INCLUDE_DIR mpfr.h)
find_library(MPFR_LIBRARY mpfr)
find_library(GMP_LIBRARY gmp)
if(MPFR_INCLUDE_DIR AND MPFR_LIBRARY AND GMP_LIBRARY AND NOT TARGET algray_mpfr)
  add_library(algray_mpfr INTERFACE)
  target_include_directories(algray_mpfr SYSTEM INTERFACE ${MPFR_INCLUDE_DIR})
  target_link_libraries(algray_mpfr INTERFACE ${MPFR_LIBRARY} ${GMP_LIBRARY})
endif()
