#include "metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "engine/core/math.h"

namespace capture {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// The nearest-rank percentile: the smallest value with at least p of the values at or below it
// (rank ceil(p n)). It took rank floor(p n) + 1, one too high whenever p n is whole: the median of
// 4 frames was the 3rd, and with 2 frames the median was the p95 and the largest.
template <class T>
double nearestRank(std::vector<T>& values, double p) {
  if (values.empty()) return 0.0;
  const double rank = std::ceil(p * double(values.size()) - 1e-9);
  const auto k = std::size_t(std::clamp(rank, 1.0, double(values.size()))) - 1;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
  return double(values[k]);
}

}  // namespace

double percentile(std::vector<double> values, double p) { return nearestRank(values, p); }

void QualityAccumulator::add(const TruthImage& truth, const GpuReadback& gpu, const engine::render::CameraView& camera) {
  ++views_;
  raysOutOfSteps_ += gpu.raysOutOfSteps;
  tileEntriesWalked_ += gpu.tileEntriesWalked;
  tileEntriesTested_ += gpu.tileEntriesTested;
  tileMaskWordsRead_ += gpu.tileMaskWordsRead;
  const glm::dvec3 forward = glm::normalize(glm::dvec3(glm::inverse(camera.view) * glm::vec4(0, 0, -1, 0)));
  for (int y = 0; y < truth.height; ++y) {
    for (int x = 0; x < truth.width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(truth.width) + std::size_t(x);
      const bool gpuHit = gpu.depth[i] > 0.0f;
      if (!gpu.work.empty()) evalsTotal_ += gpu.work[i];  // misses too: their search is work done
      if (gpuHit) {
        ++covered_;
        if (!gpu.work.empty()) evals_.push_back(gpu.work[i]);
      }
      if (gpuHit != truth.hit(i)) ++mismatches_;
      PartSums* part = truth.hit(i) && i < truth.part.size() && truth.part[i] >= 0 ? &parts_[truth.part[i]] : nullptr;
      if (part) ++part->truth, part->missed += !gpuHit;
      if (!gpuHit || !truth.hit(i)) continue;
      const engine::math::Ray ray =
          engine::math::pixelRay(camera.view, camera.proj, {float(x) + 0.5f, float(y) + 0.5f}, {truth.width, truth.height});
      const double viewDistance = engine::math::depthToViewDistance(camera.proj, gpu.depth[i]);
      const double distance = viewDistance / glm::dot(ray.direction, forward);
      const double depthError = std::abs(distance - double(truth.distance[i])) / diagonal_;
      depthErrorSum_ += depthError;
      const glm::dvec3 n = glm::dvec3(glm::vec3(gpu.normalColor[i])) * 2.0 - 1.0;
      const double length = glm::length(n);
      const double c = length > 0.0 ? glm::dot(n / length, glm::dvec3(truth.normal[i])) : -1.0;
      angles_.push_back(float(std::acos(std::clamp(c, -1.0, 1.0)) * kDegrees));
      if (part) part->depthErrorSum += depthError, part->angles.push_back(angles_.back());
    }
  }
}

RowQuality QualityAccumulator::result() const {
  RowQuality q;
  q.coverageMismatch = views_ ? double(mismatches_) / double(views_) : 0.0;
  q.coveredPixels = covered_;
  q.raysOutOfSteps = views_ ? double(raysOutOfSteps_) / double(views_) : 0.0;
  if (covered_ > 0) {
    q.tileEntriesWalked = double(tileEntriesWalked_) / double(covered_);
    q.tileEntriesTested = double(tileEntriesTested_) / double(covered_);
    q.tileMaskWordsRead = double(tileMaskWordsRead_) / double(covered_);
  }
  if (!angles_.empty()) {
    q.normalErrorMean = std::accumulate(angles_.begin(), angles_.end(), 0.0) / double(angles_.size());
    std::vector<float> angles = angles_;
    q.normalErrorP95 = nearestRank(angles, 0.95);
    q.depthErrorMean = depthErrorSum_ / double(angles_.size());
  }
  if (!evals_.empty()) {
    q.evalsMean = double(evalsTotal_) / double(covered_);
    q.evalsCoveredMean = std::accumulate(evals_.begin(), evals_.end(), 0.0) / double(evals_.size());
    std::vector<std::uint32_t> evals = evals_;
    q.evalsP95 = nearestRank(evals, 0.95);
  }
  return q;
}

std::vector<PartQuality> QualityAccumulator::parts() const {
  std::vector<PartQuality> out;
  const double views = std::max(1.0, double(views_));
  for (const auto& [index, sums] : parts_) {
    PartQuality q;
    q.part = index;
    q.truthPixels = double(sums.truth) / views;
    q.missedPixels = double(sums.missed) / views;
    if (!sums.angles.empty()) {
      q.normalErrorMean = std::accumulate(sums.angles.begin(), sums.angles.end(), 0.0) / double(sums.angles.size());
      std::vector<float> angles = sums.angles;
      q.normalErrorP95 = nearestRank(angles, 0.95);
      q.depthErrorMean = sums.depthErrorSum / double(sums.angles.size());
    }
    out.push_back(q);
  }
  return out;
}

}  // namespace capture
