# Install rules (docs/install.md): the `deepsea` binary, the public headers, the layer libraries,
# the Blender script, an exported CMake package and a pkg-config file.
#
#   find_package(deepsea CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE deepsea::deepsea)   # or one layer: deepsea::runtime, ...
include(CMakePackageConfigHelpers)

set(DEEPSEA_LAYERS
  deepsea_core deepsea_colour deepsea_optics deepsea_asset deepsea_io deepsea_scene deepsea_bake
  deepsea_runtime)

# Position-independent even when static: they may be linked into a shared library or a Python
# module.
set_target_properties(${DEEPSEA_LAYERS} PROPERTIES POSITION_INDEPENDENT_CODE ON)

# deepsea::deepsea: every layer. Installed targets are named as in the tree (deepsea::core, ...).
add_library(deepsea_all INTERFACE)
add_library(deepsea::deepsea ALIAS deepsea_all)
target_link_libraries(deepsea_all INTERFACE ${DEEPSEA_LAYERS})
set_target_properties(deepsea_all PROPERTIES EXPORT_NAME deepsea)
foreach(_t ${DEEPSEA_LAYERS} deepsea_warnings)
  string(REPLACE "deepsea_" "" _name ${_t})
  set_target_properties(${_t} PROPERTIES EXPORT_NAME ${_name})
endforeach()

set(DEEPSEA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/deepsea)

# deepsea_warnings is linked PRIVATE by every layer; a static library records that as a
# link-only dependency (it adds nothing to a consumer's link line), so the export needs it too.
install(TARGETS ${DEEPSEA_LAYERS} deepsea_all deepsea_warnings
  EXPORT deepseaTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS deepsea RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# io's OpenImageIO module, where the installed program and libraries look for it first.
install(TARGETS deepsea_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/deepsea)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/deepsea
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/include/deepsea/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/deepsea)
install(FILES ${PROJECT_SOURCE_DIR}/tools/blender/open_asset.py
  DESTINATION ${CMAKE_INSTALL_DATADIR}/deepsea/blender)

install(EXPORT deepseaTargets NAMESPACE deepsea:: DESTINATION ${DEEPSEA_CMAKE_DIR})
# A static library's private dependencies are its users' link dependencies: the config file
# finds them (find_dependency) only in that case.
if(BUILD_SHARED_LIBS)
  set(DEEPSEA_STATIC OFF)
else()
  set(DEEPSEA_STATIC ON)
endif()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/deepseaConfig.cmake.in
  ${PROJECT_BINARY_DIR}/deepseaConfig.cmake INSTALL_DESTINATION ${DEEPSEA_CMAKE_DIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/deepseaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/deepseaConfig.cmake
  ${PROJECT_BINARY_DIR}/deepseaConfigVersion.cmake DESTINATION ${DEEPSEA_CMAKE_DIR})

# pkg-config: relocatable (paths relative to the .pc file), so `cmake --install --prefix` works.
set(DEEPSEA_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH DEEPSEA_PC_TO_PREFIX /${DEEPSEA_PC_DIR} /)
string(REGEX REPLACE "/$" "" DEEPSEA_PC_TO_PREFIX "${DEEPSEA_PC_TO_PREFIX}")
set(DEEPSEA_PC_LIBS "")
foreach(_t deepsea_runtime deepsea_bake deepsea_scene deepsea_io deepsea_asset deepsea_optics
           deepsea_colour deepsea_core)
  string(APPEND DEEPSEA_PC_LIBS " -l${_t}")
endforeach()
if(DEEPSEA_STATIC)
  # OpenVDB has no .pc file on Debian: named directly; its headers call Imath (half) inline.
  set(DEEPSEA_PC_REQUIRES "tbb OpenEXR yaml-cpp Imath libcrypto spng libdeflate libjpeg")
  string(APPEND DEEPSEA_PC_LIBS " -lopenvdb")
else()
  set(DEEPSEA_PC_REQUIRES "tbb")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/deepsea.pc.in ${PROJECT_BINARY_DIR}/deepsea.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/deepsea.pc DESTINATION ${DEEPSEA_PC_DIR})
