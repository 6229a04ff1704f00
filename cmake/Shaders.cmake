# Build-time SPIR-V: every GLSL stage becomes <name>.spv in HSDF_SHADER_OUTPUT_DIR, one flat folder
# for the engine's shaders (shaders/) and each module's (modules/<module>/shaders/): programs load
# SPIR-V by file name, and the GPU packers copy build/<preset>/shaders/*.spv.
# glslangValidator writes a depfile, so editing any #included header rebuilds exactly
# the shaders that include it. Hot reload = rebuild the `shaders` target while running.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
set(HSDF_SHADER_OUTPUT_DIR ${CMAKE_BINARY_DIR}/shaders CACHE INTERNAL "")

# Each shader folder registers its stages and the folders their #includes resolve in (a module's
# shaders see its own folder and the engine's shaders/, the engine's only its own). Nothing is
# compiled yet: hsdf_compile_shaders, called once after every folder, makes the one target, so that
# the stale-SPIR-V sweep below knows every output of the shared folder.
function(hsdf_add_shaders)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "" "SOURCES;INCLUDE_DIRS")
  foreach(source IN LISTS arg_SOURCES)
    get_filename_component(abs ${source} ABSOLUTE)
    get_filename_component(name ${source} NAME)
    get_property(earlier GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name})
    if(earlier)
      message(FATAL_ERROR "Two shaders named ${name} (${earlier}, ${abs}): their SPIR-V would be one file")
    endif()
    set_property(GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name} ${abs})
    set_property(GLOBAL PROPERTY HSDF_SHADER_INCLUDE_DIRS_${name} ${arg_INCLUDE_DIRS})
    set_property(GLOBAL APPEND PROPERTY HSDF_SHADER_NAMES ${name})
  endforeach()
endfunction()

function(hsdf_compile_shaders target)
  get_property(names GLOBAL PROPERTY HSDF_SHADER_NAMES)
  set(spirv_files)
  foreach(name IN LISTS names)
    get_property(abs GLOBAL PROPERTY HSDF_SHADER_SOURCE_${name})
    get_property(include_dirs GLOBAL PROPERTY HSDF_SHADER_INCLUDE_DIRS_${name})
    list(TRANSFORM include_dirs PREPEND "-I")
    set(spv ${HSDF_SHADER_OUTPUT_DIR}/${name}.spv)
    set(dep ${HSDF_SHADER_OUTPUT_DIR}/${name}.d)
    add_custom_command(
      OUTPUT ${spv}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${HSDF_SHADER_OUTPUT_DIR}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.3 -g
              ${include_dirs} --depfile ${dep} -o ${spv} ${abs}
      MAIN_DEPENDENCY ${abs}
      DEPFILE ${dep}
      COMMENT "GLSL ${name}"
      VERBATIM)
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
