#pragma once
// The .hsdf byte layout (docs/hsdf-format.md) and explicit little-endian encoding: every field is
// written and read byte by byte at its documented offset, never by copying a struct, so the file
// does not depend on the compiler's padding or the host's endianness.
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "hermite_sdf/core/hsdf_file.h"

namespace hsdf::io {

inline constexpr std::array<std::uint8_t, 8> kMagic = {'H', 'S', 'D', 'F', 0x0D, 0x0A, 0x1A, 0x0A};

// Header field offsets.
namespace offset {
inline constexpr std::size_t kMagic = 0;
inline constexpr std::size_t kVersion = 8;
inline constexpr std::size_t kHeaderBytes = 12;
inline constexpr std::size_t kResolution = 16;
inline constexpr std::size_t kScalarType = 20;
inline constexpr std::size_t kFlags = 24;
inline constexpr std::size_t kReserved0 = 28;
inline constexpr std::size_t kSpacing = 32;
inline constexpr std::size_t kOrigin = 40;  // three f64
inline constexpr std::size_t kDenseSamples = 64;
inline constexpr std::size_t kCellCount = 72;
inline constexpr std::size_t kPayloadBytes = 80;
inline constexpr std::size_t kReserved1 = 88;
}  // namespace offset

inline constexpr std::uint32_t kFlagDense = 1u << 0;
inline constexpr std::uint32_t kFlagCells = 1u << 1;
// A material section follows the cells (docs/hsdf-format.md, "Materials"): files without it keep
// the bytes of version 1 files from before materials.
inline constexpr std::uint32_t kFlagMaterials = 1u << 2;
inline constexpr std::uint32_t kKnownFlags = kFlagDense | kFlagCells | kFlagMaterials;

// Material section: u32 palette size, u32 reserved, the palette (per entry f32 r, g, b, a,
// roughness, metallic), a u8 slot per dense sample, then 8 u8 slots per cell record.
inline constexpr std::uint64_t kMaterialsHeaderBytes = 8;
inline constexpr std::uint64_t kPaletteEntryBytes = 6 * 4;
inline std::uint64_t materialSectionBytes(std::uint64_t paletteSize, std::uint64_t denseSamples, std::uint64_t cells) {
  return kMaterialsHeaderBytes + paletteSize * kPaletteEntryBytes + denseSamples + 8 * cells;
}

inline std::size_t scalarBytes(HsdfScalarType type) { return type == HsdfScalarType::Float16 ? 2 : 4; }
inline std::uint64_t denseSampleBytes(HsdfScalarType type) { return 4 * scalarBytes(type); }
// Cell record: x, y, z, class as u16, then 8 corners x (f, fx, fy, fz).
inline std::uint64_t cellRecordBytes(HsdfScalarType type) { return 8 + 32 * scalarBytes(type); }

class ByteWriter {
 public:
  explicit ByteWriter(std::size_t capacity) { bytes_.reserve(capacity); }
  void raw(std::span<const std::uint8_t> data) { bytes_.insert(bytes_.end(), data.begin(), data.end()); }
  void u16(std::uint16_t v) { little(v, 2); }
  void u32(std::uint32_t v) { little(v, 4); }
  void u64(std::uint64_t v) { little(v, 8); }
  void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  void little(std::uint64_t v, int count) {
    for (int i = 0; i < count; ++i) bytes_.push_back(std::uint8_t(v >> (8 * i)));
  }
  std::vector<std::uint8_t> bytes_;
};

// Reads at explicit offsets of a buffer whose size the caller has already checked.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t u8(std::size_t at) const { return bytes_[at]; }
  std::uint16_t u16(std::size_t at) const { return std::uint16_t(little(at, 2)); }
  std::uint32_t u32(std::size_t at) const { return std::uint32_t(little(at, 4)); }
  std::uint64_t u64(std::size_t at) const { return little(at, 8); }
  float f32(std::size_t at) const { return std::bit_cast<float>(u32(at)); }
  double f64(std::size_t at) const { return std::bit_cast<double>(u64(at)); }

 private:
  std::uint64_t little(std::size_t at, int count) const {
    std::uint64_t v = 0;
    for (int i = 0; i < count; ++i) v |= std::uint64_t(bytes_[at + std::size_t(i)]) << (8 * i);
    return v;
  }
  std::span<const std::uint8_t> bytes_;
};

}  // namespace hsdf::io
