// The depth prepass's fragment shaders, as this build compiled them, keep early depth rejection on
// GPUs: none may contain `discard` (OpKill, OpTerminateInvocation,
// OpDemoteToHelperInvocation), an atomic, a store or memory copy into a storage buffer (StorageBuffer,
// PhysicalStorageBuffer, or an old-style Uniform buffer block) or an image write. On an NVIDIA H100
// a fragment shader that merely contains a buffer write lost early and hierarchical depth
// rejection even where the write never ran, and removing it halved the cells' prepass
// (../shared/gpu/h100-b505968/README.md §3b). Such code belongs in separate pipeline variants:
// - *_counted: the work counters, bound only in frames that count work;
// - *_early (and the early stage's fix-up): the cells' early depth stage, which needs its atomicMax
//   and discard by design and is chosen only on software rasterizers (lavapipe shades in order,
//   where it saves 40-60 %; on a GPU it is off by default: HermiteCellFeature::EarlyDepth::Auto);
// - debug views (*_wire, *_debug).
// Reads the SPIR-V with its own walk of the instruction stream; no device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "prepass_shaders.h"

#ifndef HSDF_SHADER_OUTPUT_DIR
#error "HSDF_SHADER_OUTPUT_DIR must be defined by the build"
#endif

namespace {

// SPIR-V opcodes and storage classes (SPIR-V specification, sections 3.7 and 3.52).
enum Op : std::uint32_t {
  kOpUndef = 1,
  kOpTypeForwardPointer = 39,
  kOpTypePointer = 32,
  kOpFunctionParameter = 55,
  kOpFunctionCall = 57,
  kOpVariable = 59,
  kOpImageTexelPointer = 60,
  kOpLoad = 61,
  kOpStore = 62,
  kOpCopyMemory = 63,
  kOpCopyMemorySized = 64,
  kOpAccessChain = 65,
  kOpInBoundsAccessChain = 66,
  kOpPtrAccessChain = 67,
  kOpInBoundsPtrAccessChain = 70,
  kOpCompositeExtract = 81,
  kOpCopyObject = 83,
  kOpImageWrite = 99,
  kOpConvertUToPtr = 120,
  kOpPtrCastToGeneric = 121,
  kOpGenericCastToPtr = 122,
  kOpGenericCastToPtrExplicit = 123,
  kOpBitcast = 124,
  kOpSelect = 169,
  kOpAtomicFirst = 227,  // OpAtomicLoad ..
  kOpAtomicLast = 242,   // .. OpAtomicXor
  kOpPhi = 245,
  kOpKill = 252,
  kOpAtomicFlagTestAndSet = 318,
  kOpAtomicFlagClear = 319,
  kOpCopyLogical = 400,
  kOpTerminateInvocation = 4416,
  kOpDemoteToHelperInvocation = 5380,
  kOpAtomicFMinEXT = 5614,
  kOpAtomicFMaxEXT = 5615,
  kOpAtomicFAddEXT = 6035,
};
enum StorageClass : std::uint32_t {
  kFunction = 7,
  kUniform = 2,  // with BufferBlock: an old-style storage buffer (a uniform block cannot be written)
  kStorageBuffer = 12,
  kPhysicalStorageBuffer = 5349,
};
constexpr std::uint32_t kMagic = 0x07230203u;
constexpr std::uint32_t kUnknown = ~0u;

bool isWritableBufferClass(std::uint32_t storageClass) {
  return storageClass == kStorageBuffer || storageClass == kPhysicalStorageBuffer || storageClass == kUniform;
}

// Instructions that yield a value of a pointer type (result type in word 1, result id in word 2):
// every way a shader can reach a pointer it then stores through.
bool yieldsTypedResult(std::uint32_t op) {
  switch (op) {
    case kOpUndef: case kOpFunctionParameter: case kOpFunctionCall: case kOpVariable: case kOpImageTexelPointer:
    case kOpLoad: case kOpAccessChain: case kOpInBoundsAccessChain: case kOpPtrAccessChain:
    case kOpInBoundsPtrAccessChain: case kOpCompositeExtract: case kOpCopyObject: case kOpConvertUToPtr:
    case kOpPtrCastToGeneric: case kOpGenericCastToPtr: case kOpGenericCastToPtrExplicit: case kOpBitcast:
    case kOpSelect: case kOpPhi: case kOpCopyLogical:
      return true;
    default:
      return false;
  }
}

std::string atomicName(std::uint32_t op) {
  static constexpr const char* kNames[] = {"Load", "Store", "Exchange", "CompareExchange", "CompareExchangeWeak",
                                           "IIncrement", "IDecrement", "IAdd", "ISub", "SMin", "UMin", "SMax",
                                           "UMax", "And", "Or", "Xor"};
  if (op >= kOpAtomicFirst && op <= kOpAtomicLast) return std::string("OpAtomic") + kNames[op - kOpAtomicFirst];
  return "atomic (opcode " + std::to_string(op) + ")";
}

std::string storageClassName(std::uint32_t storageClass) {
  switch (storageClass) {
    case kStorageBuffer: return "StorageBuffer";
    case kPhysicalStorageBuffer: return "PhysicalStorageBuffer";
    case kUniform: return "Uniform (buffer block)";
    case kUnknown: return "a pointer of unknown storage class";
    default: return "storage class " + std::to_string(storageClass);
  }
}

// What in `words` costs a GPU its early depth rejection, as "instruction (count)" entries; empty
// when nothing does. A malformed module is reported too (it proves nothing).
std::vector<std::string> earlyDepthBreakers(const std::vector<std::uint32_t>& words) {
  if (words.size() < 5 || words[0] != kMagic) return {"not a SPIR-V module"};
  std::map<std::uint32_t, std::uint32_t> pointerTypeClass;  // OpTypePointer id -> storage class
  std::map<std::uint32_t, std::uint32_t> valueType;         // result id -> its type id
  std::map<std::string, int> found;
  const auto storageClassOf = [&](std::uint32_t pointerId) {
    const auto type = valueType.find(pointerId);
    if (type == valueType.end()) return kUnknown;
    const auto storage = pointerTypeClass.find(type->second);
    return storage == pointerTypeClass.end() ? kUnknown : storage->second;
  };
  // The header is 5 words; then each instruction's first word holds its word count (high 16 bits)
  // and opcode (low 16 bits). Types and global variables precede the functions, and within a
  // function a value is defined before the instructions it dominates, so one pass suffices.
  for (std::size_t at = 5; at < words.size();) {
    const std::uint32_t count = words[at] >> 16, op = words[at] & 0xffffu;
    if (count == 0 || at + count > words.size()) return {"malformed instruction at word " + std::to_string(at)};
    const std::uint32_t* w = &words[at];
    if ((op == kOpTypePointer || op == kOpTypeForwardPointer) && count >= 3) pointerTypeClass[w[1]] = w[2];
    if (yieldsTypedResult(op) && count >= 3) valueType[w[2]] = w[1];
    if (op == kOpKill) ++found["OpKill (discard)"];
    if (op == kOpTerminateInvocation) ++found["OpTerminateInvocation (discard)"];
    if (op == kOpDemoteToHelperInvocation) ++found["OpDemoteToHelperInvocation"];
    if ((op >= kOpAtomicFirst && op <= kOpAtomicLast) || op == kOpAtomicFlagTestAndSet || op == kOpAtomicFlagClear ||
        op == kOpAtomicFMinEXT || op == kOpAtomicFMaxEXT || op == kOpAtomicFAddEXT)
      ++found[atomicName(op)];
    if (op == kOpImageWrite) ++found["OpImageWrite"];
    if ((op == kOpStore || op == kOpCopyMemory || op == kOpCopyMemorySized) && count >= 2) {
      const std::uint32_t storageClass = storageClassOf(w[1]);
      if (isWritableBufferClass(storageClass) || storageClass == kUnknown)
        ++found[std::string(op == kOpStore ? "OpStore" : "OpCopyMemory") + " into " + storageClassName(storageClass)];
    }
    at += count;
  }
  std::vector<std::string> list;
  for (const auto& [what, n] : found) list.push_back(what + " x" + std::to_string(n));
  return list;
}

std::string joined(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : "; ") + part;
  return text;
}

// The folder of this build's SPIR-V; HSDF_PREPASS_SPIRV_DIR points the test at another (e.g. the
// SPIR-V of an older commit, to see that the test fails on it).
std::filesystem::path shaderDir() {
  if (const char* dir = std::getenv("HSDF_PREPASS_SPIRV_DIR")) return dir;
  return HSDF_SHADER_OUTPUT_DIR;
}

std::vector<std::uint32_t> readWords(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::uint32_t> words(bytes.size() / 4);
  for (std::size_t i = 0; i < words.size(); ++i)
    for (int b = 0; b < 4; ++b) words[i] |= std::uint32_t(std::uint8_t(bytes[4 * i + b])) << (8 * b);
  return words;
}

using hsdftest::isPrepassFragmentShader;
bool contains(const std::string& text, const char* part) { return hsdftest::nameContains(text, part); }
bool isExempt(const std::string& name) { return hsdftest::isExemptPrepassVariant(name); }

std::set<std::string> prepassShaders() {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(shaderDir(), ec))
    if (entry.is_regular_file() && isPrepassFragmentShader(entry.path().filename().string()))
      names.insert(entry.path().filename().string());
  return names;
}

// Tricky: a rule that matched nothing (a renamed folder, a changed extension) would pass every
// shader vacuously: the known production shaders and the exempt variants must all be found.
TEST(PrepassSpirv, TheRuleFindsTheKnownPrepassShaders) {
  const std::set<std::string> names = prepassShaders();
  ASSERT_FALSE(names.empty()) << "no prepass fragment shader in " << shaderDir();
  for (const char* known : {"cells_depth.frag.spv", "cells_depth_near.frag.spv", "runs_depth.frag.spv",
                            "runs_depth_near.frag.spv", "cells_depth_counted.frag.spv",
                            "cells_depth_near_counted.frag.spv", "runs_depth_counted.frag.spv",
                            "runs_depth_near_counted.frag.spv", "cells_depth_early.frag.spv",
                            "cells_depth_near_early.frag.spv", "runs_depth_early.frag.spv",
                            "runs_depth_near_early.frag.spv", "cells_depth_early_fixup.frag.spv",
                            "bricks_depth.frag.spv", "bricks_depth_near.frag.spv", "bricks_depth_counted.frag.spv",
                            "bricks_depth_near_counted.frag.spv", "cells_thin_depth.frag.spv",
                            "cells_thin_depth_near.frag.spv", "cells_thin_depth_counted.frag.spv",
                            "cells_thin_depth_near_counted.frag.spv", "cell_tiles_depth.frag.spv",
                            "cell_tiles_depth_counted.frag.spv"})
    EXPECT_TRUE(names.contains(known)) << known << " not found by the rule in " << shaderDir();
  EXPECT_TRUE(std::any_of(names.begin(), names.end(), [](const std::string& n) {
    return n.starts_with("sphere_trace_") && !isExempt(n);
  })) << "the sphere tracers' depth prepass shaders";
  EXPECT_FALSE(isPrepassFragmentShader("cells_resolve.frag.spv")) << "the shading pass is not a prepass";
  EXPECT_FALSE(isPrepassFragmentShader("cells.vert.spv"));
}

// The point of the test: every production prepass fragment shader may be rejected early by depth.
TEST(PrepassSpirv, ProductionPrepassShadersHoldNoDiscardAtomicOrBufferWrite) {
  int checked = 0;
  for (const std::string& name : prepassShaders()) {
    if (isExempt(name)) continue;
    const std::vector<std::uint32_t> words = readWords(shaderDir() / name);
    const std::vector<std::string> breakers = earlyDepthBreakers(words);
    EXPECT_TRUE(breakers.empty()) << name << " (" << words.size() << " words) would lose early depth rejection: "
                                  << joined(breakers);
    ++checked;
  }
  EXPECT_GE(checked, 9) << "cells_depth, cells_thin_depth, runs_depth, bricks_depth, their _near variants and cell_tiles_depth at least";
}

// The execution modes a fragment shader declares (OpExecutionMode, opcode 16: entry point, mode).
constexpr std::uint32_t kOpExecutionMode = 16;
constexpr std::uint32_t kModeDepthReplacing = 12, kModeDepthGreater = 14, kModeDepthLess = 15;

std::set<std::uint32_t> executionModes(const std::vector<std::uint32_t>& words) {
  std::set<std::uint32_t> modes;
  for (std::size_t at = 5; at < words.size();) {
    const std::uint32_t count = words[at] >> 16, op = words[at] & 0xffffu;
    if (count == 0 || at + count > words.size()) break;
    if (op == kOpExecutionMode && count >= 3) modes.insert(words[at + 2]);
    at += count;
  }
  return modes;
}

// Tricky: a prepass shader that writes its depth keeps early and hierarchical depth rejection on
// GPUs only if it declares the depth it writes conservative: under reverse-Z, `depth_less` (never
// nearer than the box face it was drawn on). The declaration is a macro in each variant's file;
// forgetting it in a new variant lost the rejection without a word, and the test above saw nothing
// (no discard, no store). The near variants draw a box's back faces (the eye is inside it), where
// the hit lies in front of the face: declaring it there would be wrong, and must not happen either.
TEST(PrepassSpirv, DepthWritingPrepassShadersDeclareItConservativeExceptNearVariants) {
  int conservative = 0, near = 0;
  for (const std::string& name : prepassShaders()) {
    if (contains(name, "_early") || contains(name, "_wire") || contains(name, "_debug")) continue;
    const std::set<std::uint32_t> modes = executionModes(readWords(shaderDir() / name));
    if (!modes.contains(kModeDepthReplacing)) continue;
    if (contains(name, "_near")) {
      EXPECT_FALSE(modes.contains(kModeDepthLess) || modes.contains(kModeDepthGreater))
          << name << " draws back faces: its hits lie in front of them, no conservative depth may be declared";
      ++near;
    } else {
      EXPECT_TRUE(modes.contains(kModeDepthLess)) << name << " writes its depth without declaring it depth_less";
      ++conservative;
    }
  }
  EXPECT_GE(conservative, 12) << "cells, thin cells, runs, bricks, tiles, both tracers (each with its counted variant)";
  EXPECT_GE(near, 10);
}

// Tricky: the walker must see what it is meant to see in real modules, or the test above passes
// vacuously: the counted variants hold the counters' atomicAdd, the early ones the hit depths'
// atomicMax and a discard, the fix-up a discard and a store into a buffer by address.
TEST(PrepassSpirv, TheWalkerFindsWhatTheExemptVariantsAreExemptFor) {
  const auto breakers = [](const char* name) { return joined(earlyDepthBreakers(readWords(shaderDir() / name))); };
  for (const char* counted : {"cells_depth_counted.frag.spv", "cells_depth_near_counted.frag.spv",
                              "runs_depth_counted.frag.spv", "runs_depth_near_counted.frag.spv",
                              "bricks_depth_counted.frag.spv", "bricks_depth_near_counted.frag.spv",
                              "cells_thin_depth_counted.frag.spv", "cells_thin_depth_near_counted.frag.spv",
                              "cell_tiles_depth_counted.frag.spv"}) {
    const std::string found = breakers(counted);
    EXPECT_TRUE(contains(found, "OpAtomicIAdd")) << counted << ": " << found;
    EXPECT_FALSE(contains(found, "discard")) << counted << ": counting must not change the depth test: " << found;
  }
  for (const char* early : {"cells_depth_early.frag.spv", "runs_depth_early.frag.spv"}) {
    const std::string found = breakers(early);
    EXPECT_TRUE(contains(found, "OpAtomicUMax")) << early << ": " << found;
    EXPECT_TRUE(contains(found, "discard")) << early << ": " << found;
  }
  for (const char* nearEarly : {"cells_depth_near_early.frag.spv", "runs_depth_near_early.frag.spv"})
    EXPECT_TRUE(contains(breakers(nearEarly), "OpAtomicUMax")) << nearEarly << ": " << breakers(nearEarly);
  const std::string fixup = breakers("cells_depth_early_fixup.frag.spv");
  EXPECT_TRUE(contains(fixup, "discard")) << fixup;
  EXPECT_TRUE(contains(fixup, "OpStore into PhysicalStorageBuffer")) << fixup;
}

// A hand-built module: the walk must tell a store into a function-local variable (harmless) from
// one into a storage buffer, and follow a pointer made from an address (buffer_reference).
TEST(PrepassSpirv, TheWalkerTellsStorageClassesApart) {
  const auto inst = [](std::uint32_t op, std::vector<std::uint32_t> operands) {
    std::vector<std::uint32_t> w{(std::uint32_t(operands.size() + 1) << 16) | op};
    w.insert(w.end(), operands.begin(), operands.end());
    return w;
  };
  const auto module = [&](const std::vector<std::vector<std::uint32_t>>& body) {
    std::vector<std::uint32_t> words{kMagic, 0x00010600u, 0u, 100u, 0u};
    for (const auto& i : body) words.insert(words.end(), i.begin(), i.end());
    return words;
  };
  constexpr std::uint32_t kOpTypeInt = 21;
  const auto uint32 = inst(kOpTypeInt, {1, 32, 0});
  // %2 = pointer to Function uint, %3 = pointer to StorageBuffer uint, %4 = PhysicalStorageBuffer.
  const auto types = std::vector<std::vector<std::uint32_t>>{
      uint32, inst(kOpTypePointer, {2, kFunction, 1}), inst(kOpTypePointer, {3, kStorageBuffer, 1}),
      inst(kOpTypePointer, {4, kPhysicalStorageBuffer, 1})};
  auto local = types;
  local.push_back(inst(kOpVariable, {2, 10, kFunction}));
  local.push_back(inst(kOpStore, {10, 11}));
  EXPECT_TRUE(earlyDepthBreakers(module(local)).empty()) << joined(earlyDepthBreakers(module(local)));

  auto storage = types;
  storage.push_back(inst(kOpVariable, {3, 10, kStorageBuffer}));
  storage.push_back(inst(kOpAccessChain, {3, 12, 10, 13}));
  storage.push_back(inst(kOpStore, {12, 11}));
  EXPECT_EQ(joined(earlyDepthBreakers(module(storage))), "OpStore into StorageBuffer x1");

  auto address = types;
  address.push_back(inst(kOpConvertUToPtr, {4, 14, 15}));
  address.push_back(inst(kOpCopyMemory, {14, 16}));
  address.push_back(inst(kOpKill, {}));
  EXPECT_EQ(joined(earlyDepthBreakers(module(address))),
            "OpCopyMemory into PhysicalStorageBuffer x1; OpKill (discard) x1");

  auto unknown = types;
  unknown.push_back(inst(kOpStore, {99, 11}));  // a pointer the walk cannot place is not let through
  EXPECT_EQ(joined(earlyDepthBreakers(module(unknown))), "OpStore into a pointer of unknown storage class x1");

  auto truncated = module(storage);
  truncated.pop_back();
  EXPECT_EQ(joined(earlyDepthBreakers(truncated)).rfind("malformed instruction", 0), 0u);
}

}  // namespace
