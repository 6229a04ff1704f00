// Replays a fuzz target without libFuzzer, so every build (gcc, no sanitizer runtime needed) runs
// the fuzz targets as ordinary ctests:
//   <target>_replay CORPUS_DIR [MUTATIONS]
// 1. every regular file in CORPUS_DIR (sorted by name) is fed to LLVMFuzzerTestOneInput;
// 2. then MUTATIONS (default 20000) inputs derived from them by a fixed-seed generator: bit flips,
//    random bytes, truncations, insertions, duplicated chunks and "interesting" integers (0, -1,
//    huge counts) written over random offsets, 1 to 4 edits each.
// The run is deterministic: the same binary replays the same inputs. Exit 0 when every input
// returned (a crash, sanitizer report or hang ends the process), 1 on usage errors or an empty
// corpus (a replay that feeds nothing would pass without testing anything).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

constexpr std::uint64_t kSeed = 0x68736466'5f66757aULL;  // "hsdf_fuz"
constexpr long kDefaultMutations = 20000;
// A safety net, not the normal stop: the mutation count is sized to finish well within it.
constexpr std::chrono::seconds kTimeLimit{55};

std::vector<Bytes> readCorpus(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Bytes> corpus;
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return corpus;
}

void writeInteresting(Bytes& b, std::mt19937_64& rng) {
  static constexpr std::uint64_t kValues[] = {0, 1, 0x7f, 0x80, 0xff, 0x7fff, 0xffff, 0x7fffffff, 0xffffffff,
                                              0x80000000, 0x7ff0000000000000ULL /* +inf as double */,
                                              0x7fc00000 /* NaN as float */, 0xffffffffffffffffULL};
  if (b.empty()) return;
  const std::uint64_t value = kValues[rng() % std::size(kValues)];
  const std::size_t width = std::size_t(1) << (rng() % 4);  // 1, 2, 4 or 8 bytes, little endian
  const std::size_t at = rng() % b.size();
  for (std::size_t i = 0; i < width && at + i < b.size(); ++i) b[at + i] = std::uint8_t(value >> (8 * i));
}

void mutateOnce(Bytes& b, std::mt19937_64& rng) {
  switch (rng() % 6) {
    case 0:  // bit flip
      if (!b.empty()) b[rng() % b.size()] ^= std::uint8_t(1u << (rng() % 8));
      break;
    case 1:  // random byte
      if (!b.empty()) b[rng() % b.size()] = std::uint8_t(rng());
      break;
    case 2:  // truncation
      b.resize(b.empty() ? 0 : rng() % b.size());
      break;
    case 3: {  // insert random bytes
      const std::size_t at = b.empty() ? 0 : rng() % (b.size() + 1);
      Bytes extra(1 + rng() % 16);
      for (auto& x : extra) x = std::uint8_t(rng());
      b.insert(b.begin() + std::ptrdiff_t(at), extra.begin(), extra.end());
      break;
    }
    case 4: {  // duplicate a chunk at the end
      if (b.empty()) break;
      const std::size_t from = rng() % b.size();
      const std::size_t len = std::min<std::size_t>(1 + rng() % 64, b.size() - from);
      const Bytes chunk(b.begin() + std::ptrdiff_t(from), b.begin() + std::ptrdiff_t(from + len));
      b.insert(b.end(), chunk.begin(), chunk.end());
      break;
    }
    default:
      writeInteresting(b, rng);
      break;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [MUTATIONS]\n", argv[0]);
    return 1;
  }
  const std::vector<Bytes> corpus = readCorpus(argv[1]);
  if (corpus.empty()) {
    std::fprintf(stderr, "no seed inputs in %s\n", argv[1]);
    return 1;
  }
  const long mutations = argc == 3 ? std::strtol(argv[2], nullptr, 10) : kDefaultMutations;
  for (const Bytes& input : corpus) LLVMFuzzerTestOneInput(input.data(), input.size());

  std::mt19937_64 rng(kSeed);
  const auto deadline = std::chrono::steady_clock::now() + kTimeLimit;
  long done = 0;
  for (; done < mutations; ++done) {
    Bytes input = corpus[std::size_t(done) % corpus.size()];
    const int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) mutateOnce(input, rng);
    LLVMFuzzerTestOneInput(input.data(), input.size());
    if ((done & 255) == 0 && std::chrono::steady_clock::now() > deadline) {
      std::fprintf(stderr, "warning: time limit reached after %ld of %ld mutations\n", done, mutations);
      break;
    }
  }
  std::printf("replayed %zu seed inputs and %ld mutations without a crash\n", corpus.size(), done);
  return 0;
}
