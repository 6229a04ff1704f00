# Warnings are high on every first-party target; third-party code (ImGui backends) opts out.
function(hsdf_set_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
    -Wconversion -Wno-sign-conversion -Wimplicit-fallthrough -Wdouble-promotion
    # `VkFooCreateInfo info{VK_STRUCTURE_TYPE_...}` value-initializes the rest on purpose.
    -Wno-missing-field-initializers)
  if(HSDF_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
