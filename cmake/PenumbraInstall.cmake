# Installation of the embedding library: libpenumbra, its public headers
# (<penumbra/...>, standard types only), a CMake package (find_package(Penumbra)
# gives penumbra::penumbra) and a pkg-config file (penumbra.pc).
#
# The library links Embree, TBB, OpenImageIO, tinyobjloader and Assimp privately and
# its headers include none of them, so the installed package carries no
# dependencies for a shared build.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The headers spell the version out for hosts (PENUMBRA_VERSION); keep it equal to project(VERSION).
file(STRINGS ${PROJECT_SOURCE_DIR}/api/include/penumbra/version.h _penumbra_header_version
     REGEX "^#define PENUMBRA_VERSION \"")
string(REGEX REPLACE ".*\"([^\"]*)\".*" "\\1" _penumbra_header_version "${_penumbra_header_version}")
if(NOT _penumbra_header_version STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "api/include/penumbra/version.h says ${_penumbra_header_version}, "
                      "but the project version is ${PROJECT_VERSION}: update the header")
endif()

set(PENUMBRA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/Penumbra)

# Hosts need C++17 for penumbra.hpp (the library itself is built as C++20).
target_compile_features(penumbra INTERFACE cxx_std_17)

install(TARGETS penumbra EXPORT PenumbraTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Runtime NAMELINK_COMPONENT Development
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Development
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

install(FILES
  ${PROJECT_SOURCE_DIR}/api/include/penumbra/penumbra.h
  ${PROJECT_SOURCE_DIR}/api/include/penumbra/names.hpp
  ${PROJECT_SOURCE_DIR}/api/include/penumbra/penumbra.hpp
  ${PROJECT_SOURCE_DIR}/api/include/penumbra/types.hpp
  ${PROJECT_SOURCE_DIR}/api/include/penumbra/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/penumbra COMPONENT Development)

install(EXPORT PenumbraTargets NAMESPACE penumbra:: FILE PenumbraTargets.cmake
        DESTINATION ${PENUMBRA_CMAKE_DIR} COMPONENT Development)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/PenumbraConfig.cmake.in
  ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake
  INSTALL_DESTINATION ${PENUMBRA_CMAKE_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
# Before 1.0 a minor release may change the API, so only the same minor version matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/PenumbraConfig.cmake ${PROJECT_BINARY_DIR}/PenumbraConfigVersion.cmake
        DESTINATION ${PENUMBRA_CMAKE_DIR} COMPONENT Development)

# pkg-config: paths relative to the .pc file itself (${pcfiledir}), so the
# package stays correct when installed with `cmake --install --prefix` elsewhere.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(PENUMBRA_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
  set(PENUMBRA_PC_LIBDIR "${CMAKE_INSTALL_FULL_LIBDIR}")
  set(PENUMBRA_PC_INCLUDEDIR "${CMAKE_INSTALL_FULL_INCLUDEDIR}")
else()
  file(RELATIVE_PATH _penumbra_pc_up "/root/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/root")
  set(PENUMBRA_PC_PREFIX "\${pcfiledir}/${_penumbra_pc_up}")
  set(PENUMBRA_PC_LIBDIR "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(PENUMBRA_PC_INCLUDEDIR "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/penumbra.pc.in ${PROJECT_BINARY_DIR}/penumbra.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/penumbra.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT Development)

# ---- The image module (io): libpenumbra_oiio.so holds OpenImageIO and is
# dlopen()ed by libpenumbra on the first image, from the folder libpenumbra.so
# lies in, so it is installed beside it. Not part of the export set: hosts never link it.
install(TARGETS penumbra_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Runtime)
