# Third-party packages, all from Debian 12 (scripts/install-deps.sh installs them).
find_package(Threads REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(Imath CONFIG REQUIRED)
find_package(OpenEXR CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(yaml-cpp CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(nlohmann_json CONFIG REQUIRED)
find_package(OpenSSL REQUIRED COMPONENTS Crypto)  # SHA-256 of asset files (libssl-dev)
# io's fast paths (docs/runtime.md): PNG decoding (libspng-dev), PNG inflate and CRCs
# (libdeflate-dev), PNG deflate (libisal-dev: ISA-L's igzip),
# JPEG encoding (libjpeg62-turbo-dev).
find_package(PkgConfig REQUIRED)
pkg_check_modules(SPNG REQUIRED IMPORTED_TARGET spng)
pkg_check_modules(DEFLATE REQUIRED IMPORTED_TARGET libdeflate)
pkg_check_modules(ISAL REQUIRED IMPORTED_TARGET libisal)
pkg_check_modules(JPEG REQUIRED IMPORTED_TARGET libjpeg)

# Debian's OpenImageIO config names /usr/include/opencv4 even when OpenCV is not installed.
get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _oiio_inc EXCLUDE REGEX "opencv")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_inc}")

# OpenVDB ships no CMake config on Debian, only a Find module (which needs boost-iostreams).
# That module sets BUILD_SHARED_LIBS ON in the caller's scope (for Boost's sake); our libraries'
# kind is our own choice (BUILD_SHARED_LIBS in the top-level CMakeLists.txt), so put it back.
# deepseaConfig.cmake looks in the same places.
set(DEEPSEA_OPENVDB_MODULE_PATH
  /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB /usr/lib/cmake/OpenVDB)
list(APPEND CMAKE_MODULE_PATH ${DEEPSEA_OPENVDB_MODULE_PATH})
set(_deepsea_shared ${BUILD_SHARED_LIBS})
find_package(OpenVDB REQUIRED)
set(BUILD_SHARED_LIBS ${_deepsea_shared})

if(DEEPSEA_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()
