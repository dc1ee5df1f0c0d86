# Installation: the header, both libraries, the tool, a CMake package (lazytraceConfig.cmake,
# its version file and exported targets) and a pkg-config file. The kernels are embedded in the
# libraries, so an installed lazytrace needs nothing from the source tree.
#   cmake --install build --prefix PREFIX
# find_package(lazytrace) then gives lazytrace::lazytrace (shared) and lazytrace::lazytrace_static.
include(CMakePackageConfigHelpers)

set(LT_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/lazytrace)
install(FILES include/lazytrace.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS lazytrace_shared EXPORT lazytraceTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS lazytrace EXPORT lazytraceStaticTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS lazytrace_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT lazytraceTargets NAMESPACE lazytrace:: DESTINATION ${LT_CMAKE_DIR})
install(EXPORT lazytraceStaticTargets NAMESPACE lazytrace:: DESTINATION ${LT_CMAKE_DIR})

configure_package_config_file(cmake/lazytraceConfig.cmake.in ${CMAKE_BINARY_DIR}/lazytraceConfig.cmake
  INSTALL_DESTINATION ${LT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/lazytraceConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/lazytraceConfig.cmake ${CMAKE_BINARY_DIR}/lazytraceConfigVersion.cmake
  DESTINATION ${LT_CMAKE_DIR})

# pkg-config: paths relative to the .pc file, so that an installed tree can be moved.
set(LT_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH LT_PC_TO_PREFIX /${LT_PC_DIR} /)
string(REGEX REPLACE "/$" "" LT_PC_TO_PREFIX "${LT_PC_TO_PREFIX}")
configure_file(cmake/lazytrace.pc.in ${CMAKE_BINARY_DIR}/lazytrace.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/lazytrace.pc DESTINATION ${LT_PC_DIR})

# The Python module goes where Debian's python3 looks for packages under the prefix
# (/usr/lib/python3/dist-packages for /usr); elsewhere PYTHONPATH names it (README).
set(LT_PYTHON_DIR lib/python3/dist-packages CACHE STRING "where the Python module is installed, under the prefix")
install(DIRECTORY python/lazytrace DESTINATION ${LT_PYTHON_DIR}
  PATTERN __pycache__ EXCLUDE)
file(RELATIVE_PATH LT_PYTHON_TO_LIBRARY /${LT_PYTHON_DIR}/lazytrace
  /${CMAKE_INSTALL_LIBDIR}/liblazytrace.so.${PROJECT_VERSION_MAJOR})
file(WRITE ${CMAKE_BINARY_DIR}/python_installed.py
  "# Written at install time: where the shared library lies, relative to this package.\n"
  "LIBRARY = \"${LT_PYTHON_TO_LIBRARY}\"\n")
install(FILES ${CMAKE_BINARY_DIR}/python_installed.py DESTINATION ${LT_PYTHON_DIR}/lazytrace
  RENAME _installed.py)
