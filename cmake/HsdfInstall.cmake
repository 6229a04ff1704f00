# `cmake --install`: the engine and module libraries, their headers, the GPU headers shared by C++
# and GLSL, the compiled SPIR-V, the hsdf_bake tool and a CMake package, so that an outside project
# can write
#   find_package(hermite_sdf CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE hermite_sdf::hermite_sdf)
# Layout under the prefix (every path relative, so the installed tree can be moved):
#   include/hermite_sdf/{engine,hermite_sdf}/...   C++ headers (#include "engine/...", "hermite_sdf/...")
#   include/hermite_sdf/shaders/{shared,hermite}/  host/device headers and GLSL includes
#   lib/libengine_*.a lib/libhermite_sdf_*.a       the libraries (static)
#   lib/cmake/hermite_sdf/                         hermite_sdf-config.cmake, version, targets,
#                                                  hermite_sdf-shaders.cmake (a project's own shaders)
#                                                  and its glslang command line, GlslCommand.cmake
#   share/hermite_sdf/shaders/*.spv                SPIR-V (hermite_sdf_SHADER_DIR in the package)
#   bin/hsdf_bake
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(HSDF_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/hermite_sdf)
set(HSDF_INSTALL_SHADERDIR ${CMAKE_INSTALL_DATADIR}/hermite_sdf/shaders)
set(HSDF_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/hermite_sdf)
# An installed program finds the SPIR-V where this file installs it (engine/gpu/pipeline.h); the
# engine itself names no package.
target_compile_definitions(engine_gpu PRIVATE HSDF_INSTALLED_SHADER_DIR="${HSDF_INSTALL_SHADERDIR}")

# Include folders in the source tree become $<BUILD_INTERFACE:...> and their installed twin
# $<INSTALL_INTERFACE:...>; exporting a target whose interface names the source tree is an error.
# One place maps source folders to installed ones, so the targets' own CMakeLists stay as they are.
function(hsdf_relocate_interface_includes target)
  get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    return()
  endif()
  set(mapped)
  foreach(dir IN LISTS dirs)
    if(dir STREQUAL PROJECT_SOURCE_DIR)
      list(APPEND mapped "$<BUILD_INTERFACE:${dir}>" "$<INSTALL_INTERFACE:${HSDF_INSTALL_INCLUDEDIR}>")
    elseif(dir STREQUAL "${PROJECT_SOURCE_DIR}/shaders"
           OR dir STREQUAL "${PROJECT_SOURCE_DIR}/modules/hermite_sdf/shaders")
      list(APPEND mapped "$<BUILD_INTERFACE:${dir}>" "$<INSTALL_INTERFACE:${HSDF_INSTALL_INCLUDEDIR}/shaders>")
    elseif(dir STREQUAL "${PROJECT_SOURCE_DIR}/modules/hermite_sdf/include")
      list(APPEND mapped "$<BUILD_INTERFACE:${dir}>" "$<INSTALL_INTERFACE:${HSDF_INSTALL_INCLUDEDIR}>")
    elseif(dir MATCHES "^${PROJECT_SOURCE_DIR}/" OR dir MATCHES "^${PROJECT_BINARY_DIR}/")
      message(FATAL_ERROR "${target}: no installed location for the include folder ${dir} (cmake/HsdfInstall.cmake)")
    else()
      list(APPEND mapped "${dir}")  # system folders (e.g. /usr/include/imgui/backends) stay
    endif()
  endforeach()
  list(REMOVE_DUPLICATES mapped)  # the engine's and the module's shaders/ install as one folder
  set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${mapped}")
endfunction()

set(HSDF_EXPORTED_LIBRARIES
  engine_core engine_ecs engine_scene engine_gpu engine_render engine_platform engine_ui imgui_backends
  hermite_sdf_core hermite_sdf_render)
foreach(target IN LISTS HSDF_EXPORTED_LIBRARIES)
  hsdf_relocate_interface_includes(${target})
endforeach()

# hermite_sdf::hermite_sdf: the module with everything it needs (CPU bake + GPU features).
add_library(hermite_sdf INTERFACE)
target_link_libraries(hermite_sdf INTERFACE hermite_sdf_core hermite_sdf_render)
add_library(hermite_sdf::hermite_sdf ALIAS hermite_sdf)

install(TARGETS ${HSDF_EXPORTED_LIBRARIES} hermite_sdf EXPORT hermite_sdf-targets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS hsdf_bake RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

install(DIRECTORY ${PROJECT_SOURCE_DIR}/engine/ DESTINATION ${HSDF_INSTALL_INCLUDEDIR}/engine
  FILES_MATCHING PATTERN "*.h")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/modules/hermite_sdf/include/hermite_sdf/
  DESTINATION ${HSDF_INSTALL_INCLUDEDIR}/hermite_sdf FILES_MATCHING PATTERN "*.h")
# The engine's shaders/shared/ and the module's shaders/hermite/ side by side, as in one include folder.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/ ${PROJECT_SOURCE_DIR}/modules/hermite_sdf/shaders/
  DESTINATION ${HSDF_INSTALL_INCLUDEDIR}/shaders FILES_MATCHING PATTERN "*.h" PATTERN "*.glsl")
install(DIRECTORY ${HSDF_SHADER_OUTPUT_DIR}/ DESTINATION ${HSDF_INSTALL_SHADERDIR}
  FILES_MATCHING PATTERN "*.spv")

install(EXPORT hermite_sdf-targets NAMESPACE hermite_sdf:: DESTINATION ${HSDF_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hermite_sdf-config.cmake.in
  ${PROJECT_BINARY_DIR}/hermite_sdf-config.cmake
  INSTALL_DESTINATION ${HSDF_INSTALL_CMAKEDIR}
  PATH_VARS HSDF_INSTALL_SHADERDIR HSDF_INSTALL_INCLUDEDIR)
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hermite_sdf-config-version.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hermite_sdf-config.cmake ${PROJECT_BINARY_DIR}/hermite_sdf-config-version.cmake
  ${PROJECT_SOURCE_DIR}/cmake/hermite_sdf-shaders.cmake ${PROJECT_SOURCE_DIR}/cmake/GlslCommand.cmake
  DESTINATION ${HSDF_INSTALL_CMAKEDIR})
