# zstd, which compresses the compact octree files (Filters/Core/plodOctreeFile.cxx), as the
# imported target plod::zstd. Found as a plain library rather than through Debian's CMake package,
# whose targets carry no location for the Release and RelWithDebInfo configurations (the
# ParaView plugin's build fails on them). scripts/install-deps.sh installs libzstd-dev.
if (NOT TARGET plod::zstd)
  find_path(PLOD_ZSTD_INCLUDE_DIR zstd.h)
  find_library(PLOD_ZSTD_LIBRARY NAMES zstd)
  if (NOT PLOD_ZSTD_INCLUDE_DIR OR NOT PLOD_ZSTD_LIBRARY)
    message(FATAL_ERROR "zstd not found (zstd.h and libzstd): install libzstd-dev "
      "(scripts/install-deps.sh)")
  endif ()
  add_library(plod::zstd UNKNOWN IMPORTED)
  set_target_properties(plod::zstd PROPERTIES
    IMPORTED_LOCATION "${PLOD_ZSTD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${PLOD_ZSTD_INCLUDE_DIR}")
endif ()
