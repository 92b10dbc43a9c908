# Install rules (docs/install.md): the `deepsea` binary, the public headers, the layer libraries,
# the Blender script, an exported CMake package and a pkg-config file.
#
#   find_package(deepsea CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE deepsea::deepsea)   # or one layer: deepsea::runtime, ...
include(CMakePackageConfigHelpers)

set(DEEPSEA_LAYERS
  deepsea_core deepsea_colour deepsea_optics deepsea_camera deepsea_asset deepsea_io deepsea_scene
  deepsea_bake deepsea_runtime deepsea_batch deepsea_reference deepsea_live)

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
# The public headers: <deepsea/deepsea.h> and what it includes, followed through the tree (the
# front door, the setup, asset and image types it takes). The rest of include/ belongs to the
# layers, the CLI, the Python module and the tests in this tree, and is not installed.
set(_todo deepsea/deepsea.h)
set(DEEPSEA_PUBLIC_HEADERS)
while(_todo)
  list(POP_FRONT _todo _h)
  if(_h IN_LIST DEEPSEA_PUBLIC_HEADERS)
    continue()
  endif()
  list(APPEND DEEPSEA_PUBLIC_HEADERS ${_h})
  set(_file ${PROJECT_SOURCE_DIR}/include/${_h})
  if(NOT EXISTS ${_file})  # deepsea/version.h: configured into the build tree
    continue()
  endif()
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_file})
  file(STRINGS ${_file} _includes REGEX "^#include \"deepsea/")
  foreach(_line ${_includes})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" _inc "${_line}")
    list(APPEND _todo ${_inc})
  endforeach()
endwhile()
foreach(_h ${DEEPSEA_PUBLIC_HEADERS})
  if(EXISTS ${PROJECT_SOURCE_DIR}/include/${_h})
    get_filename_component(_dir ${_h} DIRECTORY)
    install(FILES ${PROJECT_SOURCE_DIR}/include/${_h}
      DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/${_dir})
  endif()
endforeach()
install(FILES ${PROJECT_BINARY_DIR}/include/deepsea/version.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/deepsea)
install(FILES ${PROJECT_SOURCE_DIR}/tools/blender/open_asset.py
  DESTINATION ${CMAKE_INSTALL_DATADIR}/deepsea/blender)
# The example configs: the demo's setup (what `deepsea demo` and `deepsea bench` read by
# default, found from bin/ as ../share/deepsea/demo.yaml), the library manifest and the
# cameras, rigs and waters it names (paths relative to it, so the tree is copied as is).
install(FILES ${PROJECT_SOURCE_DIR}/volumes/demo.yaml ${PROJECT_SOURCE_DIR}/volumes/library.yaml
  DESTINATION ${CMAKE_INSTALL_DATADIR}/deepsea)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/volumes/cameras ${PROJECT_SOURCE_DIR}/volumes/rigs
  ${PROJECT_SOURCE_DIR}/volumes/waters DESTINATION ${CMAKE_INSTALL_DATADIR}/deepsea
  FILES_MATCHING PATTERN "*.yaml")

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
foreach(_t deepsea_live deepsea_reference deepsea_batch deepsea_runtime deepsea_bake deepsea_scene deepsea_io
           deepsea_asset deepsea_camera deepsea_optics deepsea_colour deepsea_core)
  string(APPEND DEEPSEA_PC_LIBS " -l${_t}")
endforeach()
if(DEEPSEA_STATIC)
  # OpenVDB has no .pc file on Debian: named directly; its headers call Imath (half) inline.
  set(DEEPSEA_PC_REQUIRES "tbb OpenEXR yaml-cpp Imath libcrypto spng libdeflate libisal libjpeg")
  string(APPEND DEEPSEA_PC_LIBS " -lopenvdb")
  # The static io, inside the user's program, finds the OpenImageIO module through this run
  # path (src/io/CMakeLists.txt does the same for the CMake package).
  string(APPEND DEEPSEA_PC_LIBS " -Wl,-rpath,\${libdir}/deepsea")
else()
  set(DEEPSEA_PC_REQUIRES "tbb")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/deepsea.pc.in ${PROJECT_BINARY_DIR}/deepsea.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/deepsea.pc DESTINATION ${DEEPSEA_PC_DIR})
