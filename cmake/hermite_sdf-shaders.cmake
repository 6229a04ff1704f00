# hermite_sdf_add_shaders(<target> OUTPUT_DIR <folder> SOURCES <glsl>... [INCLUDE_DIRS <folder>...]
#                         [DEFINES <NAME>[=<VALUE>]...])
# Installed with the package (included by hermite_sdf-config.cmake), for a project's own shaders:
# each GLSL stage (file names ending in .vert, .frag, .comp, ...) becomes <OUTPUT_DIR>/<file>.spv
# at build time, compiled as the engine's are (glslangValidator, Vulkan 1.3, debug info), with the
# package's shader headers on the include path (#include "shared/host_device.h", the module's
# "hermite/..."; GL_GOOGLE_include_directive) and a depfile, so that editing an #included header
# rebuilds the stages that include it. DEFINES are preprocessor definitions for every source (as
# glslang's -D; a malformed one is refused naming it): a variant of a stage is another call, with
# its own OUTPUT_DIR. <target> builds them all and is built by default. The
# program adds OUTPUT_DIR with engine::gpu::addShaderDirectory before it makes its feature's
# pipelines; rebuilding <target> while it runs, then Renderer::reloadShaders(), is hot reload.
include(${CMAKE_CURRENT_LIST_DIR}/GlslCommand.cmake)  # the glslang command line, shared with the engine's build
function(hermite_sdf_add_shaders target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "OUTPUT_DIR" "SOURCES;INCLUDE_DIRS;DEFINES")
  if(NOT arg_OUTPUT_DIR OR NOT arg_SOURCES)
    message(FATAL_ERROR "hermite_sdf_add_shaders(${target}): OUTPUT_DIR and SOURCES are required")
  endif()
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "hermite_sdf_add_shaders(${target}): unexpected arguments '${arg_UNPARSED_ARGUMENTS}'")
  endif()
  foreach(define IN LISTS arg_DEFINES)
    if(NOT define MATCHES "^[A-Za-z_][A-Za-z0-9_]*(=[^ ]+)?$")
      message(FATAL_ERROR "hermite_sdf_add_shaders(${target}): define '${define}' is not NAME or NAME=VALUE")
    endif()
  endforeach()
  find_program(HERMITE_SDF_GLSLANG_VALIDATOR glslangValidator REQUIRED)
  set(include_dirs ${HERMITE_SDF_SHADER_INCLUDE_DIR})
  foreach(dir IN LISTS arg_INCLUDE_DIRS)
    get_filename_component(abs ${dir} ABSOLUTE)
    list(APPEND include_dirs ${abs})
  endforeach()
  set(outputs)
  foreach(source IN LISTS arg_SOURCES)
    get_filename_component(abs ${source} ABSOLUTE)
    get_filename_component(name ${source} NAME)
    hsdf_glsl_stage(${name} stage)
    set(spv ${arg_OUTPUT_DIR}/${name}.spv)
    hsdf_glsl_command(SPIRV ${spv} SOURCE ${abs} STAGE ${stage} GLSLANG ${HERMITE_SDF_GLSLANG_VALIDATOR}
      INCLUDE_DIRS ${include_dirs} DEFINES ${arg_DEFINES})
    list(APPEND outputs ${spv})
  endforeach()
  add_custom_target(${target} ALL DEPENDS ${outputs})
endfunction()
