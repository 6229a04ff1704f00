// Fuzz target for the .hsdf loader. Each input is loaded twice: as is (exercises the framing and
// the checksum), then with its checksum recomputed (so mutations reach the header, size and value
// checks behind the checksum). A file that loads must serialize back to the same bytes: the format
// is canonical, so any difference is a reader/writer disagreement.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <vector>

#include "fuzz_check.h"
#include "hermite_sdf/core/hsdf_file.h"

namespace {

// Small enough that no input can make the loader allocate much, large enough for the seeds.
constexpr std::uint64_t kFuzzBudgetBytes = std::uint64_t(16) << 20;

void loadAndCheckRoundTrip(std::span<const std::uint8_t> bytes) {
  hsdf::HsdfLoadOptions options;
  options.memoryBudgetBytes = kFuzzBudgetBytes;
  auto loaded = hsdf::loadHsdfFromMemory(bytes, options);
  if (!loaded.ok()) return;
  // A file the loader accepts must be exactly what the writer would write for its contents.
  auto again = hsdf::serializeHsdf(*loaded);
  FUZZ_CHECK(again.ok());
  FUZZ_CHECK(again->size() == bytes.size());
  FUZZ_CHECK(std::memcmp(again->data(), bytes.data(), bytes.size()) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  loadAndCheckRoundTrip(input);
  if (size < hsdf::kHsdfTrailerBytes) return 0;
  std::vector<std::uint8_t> fixed(data, data + size);
  const std::uint64_t checksum = hsdf::hsdfChecksum(std::span(fixed).first(size - hsdf::kHsdfTrailerBytes));
  for (std::size_t i = 0; i < hsdf::kHsdfTrailerBytes; ++i)
    fixed[size - hsdf::kHsdfTrailerBytes + i] = std::uint8_t(checksum >> (8 * i));
  loadAndCheckRoundTrip(fixed);
  return 0;
}
