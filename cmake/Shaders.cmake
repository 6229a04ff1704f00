# Build-time SPIR-V: every GLSL file becomes <name>.spv in HSDF_SHADER_OUTPUT_DIR.
# glslangValidator writes a depfile, so editing any #included header rebuilds exactly
# the shaders that include it. Hot reload = rebuild the `shaders` target while running.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
set(HSDF_SHADER_OUTPUT_DIR ${CMAKE_BINARY_DIR}/shaders CACHE INTERNAL "")

function(hsdf_compile_shaders target)
  set(spirv_files)
  foreach(source IN LISTS ARGN)
    get_filename_component(abs ${source} ABSOLUTE)
    get_filename_component(name ${source} NAME)
    set(spv ${HSDF_SHADER_OUTPUT_DIR}/${name}.spv)
    set(dep ${HSDF_SHADER_OUTPUT_DIR}/${name}.d)
    add_custom_command(
      OUTPUT ${spv}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${HSDF_SHADER_OUTPUT_DIR}
      COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.3 -g
              -I${CMAKE_SOURCE_DIR}/shaders --depfile ${dep} -o ${spv} ${abs}
      MAIN_DEPENDENCY ${abs}
      DEPFILE ${dep}
      COMMENT "GLSL ${name}"
      VERBATIM)
    list(APPEND spirv_files ${spv})
  endforeach()
  add_custom_target(${target} ALL DEPENDS ${spirv_files})
  # SPIR-V whose source is gone (a renamed or deleted shader) would otherwise stay in the folder,
  # where the loader and the prepass SPIR-V check would still find it. The source glob is
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
