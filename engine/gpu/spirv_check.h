#pragma once
// What the loader checks before SPIR-V reaches vkCreateShaderModule, where invalid code is
// undefined behaviour (a crash on some drivers): a hot reload of a broken or half-written file must
// fail with a message naming the problem, and the old pipelines keep drawing.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "engine/core/expected.h"

namespace engine::gpu {

// Checks that `bytes` look like a whole SPIR-V module: whole 32-bit words, the header (magic
// number), instructions (each one's word count in its first word) that end exactly at the end of
// the file, and a last instruction of OpFunctionEnd (functions come last in a module's layout).
// So a text file, a short file and a file cut off anywhere inside or right after an instruction
// are refused; a cut right after an earlier function's OpFunctionEnd is not seen (the driver's own
// checks remain). The message starts with "not SPIR-V" and says what was found.
Status checkSpirv(std::span<const std::uint8_t> bytes);

}  // namespace engine::gpu
