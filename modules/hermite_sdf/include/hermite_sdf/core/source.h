#pragma once
// SdfSource: anything that can be sampled into a field — analytic shapes, triangle meshes.
// Sources are evaluated from many threads at once while baking, so every query must be thread-safe.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include <glm/glm.hpp>

namespace hsdf {

struct Aabb {
  glm::dvec3 min{0.0};
  glm::dvec3 max{0.0};
  glm::dvec3 size() const { return max - min; }
  glm::dvec3 center() const { return 0.5 * (min + max); }
};

// Signed distance (negative inside) and its gradient in world units.
struct SdfSample {
  double value = 0.0;
  glm::dvec3 gradient{0.0};
  // The material slot (materials.h) of the closest surface, for sources with materialSlots() > 1;
  // 0 otherwise.
  std::uint8_t material = 0;
};

// Answer of a band-limited query (narrow-band baking). When `exact`, `sample` is what sample()
// returns. Otherwise the surface is farther than the requested band: `sample.value` is the sign
// times a lower bound (>= band) on the distance, and `sample.gradient` is zero.
struct SdfBandSample {
  SdfSample sample;
  bool exact = true;
};

class SdfSource {
 public:
  virtual ~SdfSource() = default;
  // Exact (or best available) signed distance and gradient at p.
  virtual SdfSample sample(const glm::dvec3& p) const = 0;
  // Bounds of the surface (not of the grid: grids add padding around these).
  virtual Aabb bounds() const = 0;
  // How many material slots the samples' `material` takes (a mesh of several materials); 0 when
  // the source has one material and the bakes record none.
  virtual std::size_t materialSlots() const { return 0; }

  // Samples the points start + i*step, i = 0..out.size()-1, into out. Same results as calling
  // sample() per point; sources whose queries profit from coherence (meshes) override it, so a
  // baker should prefer it over per-point calls when it walks grid rows.
  virtual void sampleRow(const glm::dvec3& start, const glm::dvec3& step, std::span<SdfSample> out) const {
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = sample(start + double(i) * step);
  }

  // Exact sample where the surface is within `band` of p, otherwise only the sign and a safe
  // distance bound (see SdfBandSample). Far samples are what a narrow-band bake skips, so sources
  // with expensive exact queries (meshes) override this to answer them cheaply.
  virtual SdfBandSample sampleBand(const glm::dvec3& p, double band) const {
    (void)band;
    return {sample(p), true};
  }

  // The exact sample where the surface is within `band` of p (as sampleBand's), else nothing: for
  // callers that skip far points without their sign, which meshes then do not compute.
  virtual std::optional<SdfSample> sampleNear(const glm::dvec3& p, double band) const {
    const SdfBandSample s = sampleBand(p, band);
    return s.exact ? std::optional(s.sample) : std::nullopt;
  }

  // Row version of sampleBand(), with the same coherence benefit as sampleRow().
  virtual void sampleBandRow(const glm::dvec3& start, const glm::dvec3& step, double band,
                             std::span<SdfBandSample> out) const {
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = sampleBand(start + double(i) * step, band);
  }
};

}  // namespace hsdf
