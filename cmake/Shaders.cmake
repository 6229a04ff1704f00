# Build-time SPIR-V: every GLSL stage becomes <name>.spv in HSDF_SHADER_OUTPUT_DIR, one flat folder
# for the engine's shaders (shaders/) and each module's (modules/<module>/shaders/): programs load
# SPIR-V by file name, and the GPU packers copy build/<preset>/shaders/*.spv.
# A stage is either a stage file (cells.vert: compiled as it is) or a variant, a row of the folder's
# variant table (hsdf_shader_variant below): one GLSL source compiled with its own -D defines, so
# that a pipeline variant is data in the folder's CMakeLists, not a file of its own.
# glslangValidator writes a depfile, so editing any #included header rebuilds exactly
# the shaders that include it. Hot reload = rebuild the `shaders` target while running: the same
# command lines, defines included (samples/common/shader_build.h).
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
set(HSDF_SHADER_OUTPUT_DIR ${CMAKE_BINARY_DIR}/shaders CACHE INTERNAL "")
include(${CMAKE_CURRENT_LIST_DIR}/GlslCommand.cmake)

# Registers one stage: the SPIR-V <name>.spv from <source>, compiled as <name>'s stage with
# <defines>; two stages of one name anywhere in the build are an error (one .spv file).
function(hsdf_register_shader name source defines include_dirs)
  hsdf_glsl_stage(${name} stage)
  get_property(earlier GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name})
  if(earlier)
    message(FATAL_ERROR "Two shaders named ${name} (${earlier}, ${source}): their SPIR-V would be one file")
  endif()
  set_property(GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name} ${source})
  set_property(GLOBAL PROPERTY HSDF_SHADER_STAGE_${name} ${stage})
  set_property(GLOBAL PROPERTY HSDF_SHADER_DEFINES_${name} ${defines})
  set_property(GLOBAL PROPERTY HSDF_SHADER_INCLUDE_DIRS_${name} ${include_dirs})
  set_property(GLOBAL APPEND PROPERTY HSDF_SHADER_NAMES ${name})
endfunction()

# Each shader folder registers its stages and the folders their #includes resolve in (a module's
# shaders see its own folder and the engine's shaders/, the engine's only its own). Nothing is
# compiled yet: hsdf_compile_shaders, called once after every folder, makes the one target, so that
# the stale-SPIR-V sweep below knows every output of the shared folder.
function(hsdf_add_shaders)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "" "SOURCES;INCLUDE_DIRS")
  foreach(source IN LISTS arg_SOURCES)
    get_filename_component(abs ${source} ABSOLUTE)
    get_filename_component(name ${source} NAME)
    hsdf_register_shader(${name} ${abs} "" "${arg_INCLUDE_DIRS}")
  endforeach()
  # The folder's variants resolve their #includes as its stage files do.
  set_property(DIRECTORY PROPERTY HSDF_SHADER_INCLUDE_DIRS ${arg_INCLUDE_DIRS})
endfunction()

# hsdf_shader_variant(<name> SOURCE <glsl> [DEFINES <NAME=VALUE>...]): one row of a folder's
# variant table, after the folder's hsdf_add_shaders (whose INCLUDE_DIRS it uses). <name> is the
# SPIR-V's name without .spv, and its extension the stage: hsdf_shader_variant(lit_counted.frag
# SOURCE lit.glsl DEFINES HSDF_COUNT_WORK=1) makes lit_counted.frag.spv.
# SOURCE is relative to the folder and starts with #version (it is the stage's whole source).
function(hsdf_shader_variant name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "SOURCE" "DEFINES")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "shader variant ${name}: unexpected arguments '${arg_UNPARSED_ARGUMENTS}' (SOURCE <glsl> DEFINES <NAME=VALUE>...)")
  endif()
  if(NOT arg_SOURCE)
    message(FATAL_ERROR "shader variant ${name}: SOURCE <glsl> is required")
  endif()
  get_filename_component(abs ${arg_SOURCE} ABSOLUTE)
  if(NOT EXISTS ${abs})
    message(FATAL_ERROR "shader variant ${name}: its SOURCE ${abs} does not exist")
  endif()
  foreach(define IN LISTS arg_DEFINES)
    if(NOT define MATCHES "^[A-Za-z_][A-Za-z0-9_]*=[^ ]+$")
      message(FATAL_ERROR "shader variant ${name}: define '${define}' is not NAME=VALUE")
    endif()
  endforeach()
  get_property(include_dirs DIRECTORY PROPERTY HSDF_SHADER_INCLUDE_DIRS)
  if(NOT include_dirs)
    message(FATAL_ERROR "shader variant ${name}: call hsdf_add_shaders(... INCLUDE_DIRS ...) in this folder first (its variants #include through those folders)")
  endif()
  hsdf_register_shader(${name} ${abs} "${arg_DEFINES}" "${include_dirs}")
endfunction()

function(hsdf_compile_shaders target)
  get_property(names GLOBAL PROPERTY HSDF_SHADER_NAMES)
  set(spirv_files)
  foreach(name IN LISTS names)
    get_property(abs GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name})
    get_property(stage GLOBAL PROPERTY HSDF_SHADER_STAGE_${name})
    get_property(defines GLOBAL PROPERTY HSDF_SHADER_DEFINES_${name})
    get_property(include_dirs GLOBAL PROPERTY HSDF_SHADER_INCLUDE_DIRS_${name})
    set(spv ${HSDF_SHADER_OUTPUT_DIR}/${name}.spv)
    hsdf_glsl_command(SPIRV ${spv} SOURCE ${abs} STAGE ${stage} GLSLANG ${GLSLANG_VALIDATOR}
      INCLUDE_DIRS ${include_dirs} DEFINES ${defines})
    list(APPEND spirv_files ${spv})
  endforeach()
  add_custom_target(${target} ALL DEPENDS ${spirv_files})
  # SPIR-V whose source is gone (a renamed or deleted shader) would otherwise stay in the folder,
  # where the loader and the prepass SPIR-V check would still find it. The source globs are
  # CONFIGURE_DEPENDS, so a rename re-runs this at the next build.
  file(GLOB outputs ${HSDF_SHADER_OUTPUT_DIR}/*.spv)
  foreach(output IN LISTS outputs)
    if(NOT output IN_LIST spirv_files)
      get_filename_component(stale ${output} NAME)
      message(STATUS "Removing stale SPIR-V ${stale} (its source is gone)")
      file(REMOVE ${output})
      string(REGEX REPLACE "\\.spv$" ".d" depfile ${output})
      file(REMOVE ${depfile})
    endif()
  endforeach()
endfunction()
