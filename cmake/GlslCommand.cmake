# hsdf_glsl_command(SPIRV <out.spv> SOURCE <glsl> STAGE <vert|frag|comp|...> GLSLANG <glslangValidator>
#                   [INCLUDE_DIRS <folder>...] [DEFINES <NAME=VALUE>...])
# The one glslang command line of the build (cmake/Shaders.cmake) and of the installed package
# (hermite_sdf-shaders.cmake, for a project's own shaders): Vulkan 1.3, debug info, the stage named
# (a source ending in .glsl has none of its own), each define as -D, and a depfile next to the
# SPIR-V, so that editing any #included file rebuilds exactly the SPIR-V that includes it.
function(hsdf_glsl_command)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "SPIRV;SOURCE;STAGE;GLSLANG" "INCLUDE_DIRS;DEFINES")
  foreach(required SPIRV SOURCE STAGE GLSLANG)
    if(NOT arg_${required})
      message(FATAL_ERROR "hsdf_glsl_command: ${required} is required")
    endif()
  endforeach()
  set(flags)
  foreach(dir IN LISTS arg_INCLUDE_DIRS)
    list(APPEND flags "-I${dir}")
  endforeach()
  foreach(define IN LISTS arg_DEFINES)
    list(APPEND flags "-D${define}")
  endforeach()
  get_filename_component(output_dir ${arg_SPIRV} DIRECTORY)
  get_filename_component(name ${arg_SPIRV} NAME_WLE)
  set(depfile ${output_dir}/${name}.d)
  add_custom_command(
    OUTPUT ${arg_SPIRV}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${output_dir}
    COMMAND ${arg_GLSLANG} --quiet --target-env vulkan1.3 -g -S ${arg_STAGE}
            ${flags} --depfile ${depfile} -o ${arg_SPIRV} ${arg_SOURCE}
    MAIN_DEPENDENCY ${arg_SOURCE}
    DEPFILE ${depfile}
    COMMENT "GLSL ${name}"
    VERBATIM)
endfunction()

# The stage glslang compiles a stage file name as: its extension (cells.vert -> vert), or an error
# naming the file when it has none of glslang's stage extensions.
function(hsdf_glsl_stage file_name out_var)
  set(stages vert tesc tese geom frag comp mesh task rgen rint rahit rchit rmiss rcall)
  string(REGEX MATCH "[^.]*$" extension ${file_name})
  if(NOT extension IN_LIST stages OR extension STREQUAL file_name)
    list(JOIN stages ", ." names)
    message(FATAL_ERROR "shader ${file_name}: the name must end in the stage it is compiled as (.${names})")
  endif()
  set(${out_var} ${extension} PARENT_SCOPE)
endfunction()
