/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/icf/localization/colour_histogram.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>

namespace pcl {
namespace icf {
namespace localization {

namespace {
constexpr float kMinSaturation = 0.25f;  // below: a grey, binned by brightness
}

ColourHistogram::ColourHistogram(int bins)
    : bins_(std::max(2, bins)), counts_(static_cast<std::size_t>(2 * bins_), 0.f) {}

int ColourHistogram::bin(const Eigen::Vector3f& rgb) const {
  const Eigen::Vector3f c = rgb.cwiseMax(0.f).cwiseMin(1.f);
  const float max = c.maxCoeff(), min = c.minCoeff(), chroma = max - min;
  const float saturation = max > 0.f ? chroma / max : 0.f;
  if (saturation < kMinSaturation) {
    const int v = std::min(bins_ - 1, static_cast<int>(max * static_cast<float>(bins_)));
    return bins_ + v;
  }
  float hue;  // [0, 6)
  if (max == c.x())
    hue = std::fmod((c.y() - c.z()) / chroma + 6.f, 6.f);
  else if (max == c.y())
    hue = (c.z() - c.x()) / chroma + 2.f;
  else
    hue = (c.x() - c.y()) / chroma + 4.f;
  return std::min(bins_ - 1, static_cast<int>(hue / 6.f * static_cast<float>(bins_)));
}

void ColourHistogram::add(const Eigen::Vector3f& rgb, float weight) {
  if (!rgb.allFinite())
    return;
  counts_[static_cast<std::size_t>(bin(rgb))] += weight;
  total_ += weight;
}

double ColourHistogram::intersection(const ColourHistogram& other) const {
  if (empty() || other.empty() || other.bins_ != bins_)
    return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < counts_.size(); ++i)
    sum += std::min(counts_[i] / total_, other.counts_[i] / other.total_);
  return sum;
}

ColourHistogram ColourHistogram::ofColour(const Eigen::Vector3f& rgb, int bins) {
  ColourHistogram h(bins);
  const int b = h.bin(rgb);
  h.add(rgb, 2.f);
  if (b < h.bins_) {  // a hue: half weight to each neighbour (hue is circular)
    h.counts_[static_cast<std::size_t>((b + 1) % h.bins_)] += 1.f;
    h.counts_[static_cast<std::size_t>((b + h.bins_ - 1) % h.bins_)] += 1.f;
    h.total_ += 2.f;
  }
  return h;
}

std::optional<Eigen::Vector3f> meshColour(const pcl::PolygonMesh& mesh) {
  if (pcl::getFieldIndex(mesh.cloud, "rgb") < 0 && pcl::getFieldIndex(mesh.cloud, "rgba") < 0 &&
      pcl::getFieldIndex(mesh.cloud, "r") < 0)
    return std::nullopt;
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  pcl::fromPCLPointCloud2(mesh.cloud, cloud);
  if (cloud.empty())
    return std::nullopt;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : cloud)
    sum += Eigen::Vector3d(p.r, p.g, p.b) / 255.0;
  return (sum / static_cast<double>(cloud.size())).cast<float>();
}

}  // namespace localization
}  // namespace icf
}  // namespace pcl
