#pragma once
// Quality and work of one row, accumulated over its views from float read-backs:
//   coverage mismatch: pixels where the GPU and the truth disagree on hit / miss (per view);
//   normal error: angle between the GPU normal (DEBUG_VIEW_NORMALS in a float target) and the
//                 truth normal, over pixels both hit, mean and 95th percentile in degrees;
//   depth error: |distance along the ray (GPU depth) - truth distance| over pixels both hit,
//                mean, relative to the bounding-box diagonal of the source;
//   work: the renderer's per-pixel work counters (root-search evaluations) over covered pixels,
//         the rays that ran out of steps (sphere tracing; drawn as misses), per view, and the tiled
//         cells' list walk per covered pixel.
#include <cstdint>
#include <map>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/camera_view.h"
#include "ground_truth.h"

namespace capture {

// What the capture reads back from the GPU for one view of one row.
struct GpuReadback {
  std::vector<float> depth;            // reverse-Z, 0 = background
  std::vector<glm::vec4> normalColor;  // DEBUG_VIEW_NORMALS: 0.5 n + 0.5
  std::vector<std::uint32_t> work;     // empty when nothing counted
  std::uint32_t raysOutOfSteps = 0;    // WorkTotals::raysOutOfSteps of the frame
  std::uint32_t tileEntriesWalked = 0; // WorkTotals: the tiled cells' list walk (0 without tiles)
  std::uint32_t tileEntriesTested = 0;
  std::uint32_t tileMaskWordsRead = 0;  // the words of their pixels' masks the fragments read
};

struct RowQuality {
  double coverageMismatch = 0.0;  // pixels per view
  double normalErrorMean = 0.0;   // degrees
  double normalErrorP95 = 0.0;
  double depthErrorMean = 0.0;    // fraction of the diagonal
  // Root-search evaluations (sphere-tracing steps, cell evaluations) of every pixel, hits and misses,
  // per covered pixel: the work of the frame per pixel drawn, as the tile columns count it. (It was
  // the mean over the covered pixels of their own counts, leaving out the rays that miss: 39-58 % of
  // a sphere tracer's steps, whose proxy box covers 3-5 times the object's pixels.)
  double evalsMean = 0.0;
  double evalsCoveredMean = 0.0;  // the covered pixels' own counts: mean
  double evalsP95 = 0.0;          // ... and p95
  double raysOutOfSteps = 0.0;    // per view
  // Tiled cells: tile-list entries read / ray-box tested by the prepass fragments, per covered pixel.
  double tileEntriesWalked = 0.0;
  double tileEntriesTested = 0.0;
  double tileMaskWordsRead = 0.0;
  std::uint64_t coveredPixels = 0;
};

// The quality of one object of a scene (TruthImage::part), from the pixels where the truth hits
// it: GPU hits where the truth sees background belong to no object and count only in RowQuality.
struct PartQuality {
  std::int32_t part = -1;          // SceneData::nodes index
  double truthPixels = 0.0;        // per view
  double missedPixels = 0.0;       // per view: the truth hits the object, the GPU draws nothing
  double normalErrorMean = 0.0;    // degrees, over the object's pixels both hit
  double normalErrorP95 = 0.0;
  double depthErrorMean = 0.0;     // fraction of the diagonal
};

class QualityAccumulator {
 public:
  explicit QualityAccumulator(double diagonal) : diagonal_(diagonal) {}
  void add(const TruthImage& truth, const GpuReadback& gpu, const engine::render::CameraView& camera);
  RowQuality result() const;
  // One entry per object the truth hit in some view, by part index.
  std::vector<PartQuality> parts() const;

 private:
  double diagonal_;
  std::uint32_t views_ = 0;
  std::uint64_t mismatches_ = 0;
  std::uint64_t raysOutOfSteps_ = 0;
  std::uint64_t tileEntriesWalked_ = 0, tileEntriesTested_ = 0, tileMaskWordsRead_ = 0;
  double depthErrorSum_ = 0.0;
  std::vector<float> angles_;
  std::vector<std::uint32_t> evals_;  // the covered pixels' counts
  std::uint64_t evalsTotal_ = 0;      // every pixel's
  std::uint64_t covered_ = 0;
  struct PartSums {
    std::uint64_t truth = 0, missed = 0;
    double depthErrorSum = 0.0;
    std::vector<float> angles;
  };
  std::map<std::int32_t, PartSums> parts_;
};

// The value at fraction p (0..1) of the sorted values (nearest rank); 0 for none.
double percentile(std::vector<double> values, double p);

}  // namespace capture
