/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/segmentation/view_grid.h>

#include <algorithm>
#include <cmath>

namespace pcl {
namespace icf {
namespace segmentation {

namespace {
constexpr int kMaxSide = 4096;  // bins per side: bounds memory whatever the input
}

ViewGrid::ViewGrid(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& camera,
                   float bin_angle)
    : camera_(camera), inv_bin_(1.f / bin_angle) {
  int umin = kMaxSide, umax = -kMaxSide, vmin = kMaxSide, vmax = -kMaxSide;
  std::vector<std::pair<int, int>> uv(points.size(), {kMaxSide * 4, 0});
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f p = points[i] - camera_;
    if (!(p.z() > 1e-6f))
      continue;
    const float u = std::floor(p.x() / p.z() * inv_bin_), v = std::floor(p.y() / p.z() * inv_bin_);
    if (!(std::abs(u) < kMaxSide && std::abs(v) < kMaxSide))
      continue;
    uv[i] = {static_cast<int>(u), static_cast<int>(v)};
    umin = std::min(umin, uv[i].first);
    umax = std::max(umax, uv[i].first);
    vmin = std::min(vmin, uv[i].second);
    vmax = std::max(vmax, uv[i].second);
  }
  if (umax < umin)
    return;
  // One bin of border so that neighbours of the outermost bins exist.
  u0_ = umin - 1;
  v0_ = vmin - 1;
  width_ = umax - umin + 3;
  height_ = vmax - vmin + 3;
  depth_.assign(static_cast<std::size_t>(width_) * height_, kEmpty);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (uv[i].first == kMaxSide * 4)
      continue;
    const std::size_t b = static_cast<std::size_t>(uv[i].second - v0_) * width_ +
                          static_cast<std::size_t>(uv[i].first - u0_);
    depth_[b] = std::min(depth_[b], depthOf(points[i]));
  }
}

std::int64_t ViewGrid::bin(const Eigen::Vector3f& point) const {
  const Eigen::Vector3f p = point - camera_;
  if (!(p.z() > 1e-6f) || depth_.empty())
    return -1;
  const float u = std::floor(p.x() / p.z() * inv_bin_) - static_cast<float>(u0_);
  const float v = std::floor(p.y() / p.z() * inv_bin_) - static_cast<float>(v0_);
  if (!(u >= 0.f && v >= 0.f && u < static_cast<float>(width_) && v < static_cast<float>(height_)))
    return -1;
  return static_cast<std::int64_t>(v) * width_ + static_cast<std::int64_t>(u);
}

std::vector<std::int64_t> ViewGrid::neighbours(std::int64_t b) const {
  std::vector<std::int64_t> out;
  if (b < 0)
    return out;
  const std::int64_t u = b % width_, v = b / width_;
  for (std::int64_t dv = -1; dv <= 1; ++dv)
    for (std::int64_t du = -1; du <= 1; ++du) {
      if (du == 0 && dv == 0)
        continue;
      const std::int64_t nu = u + du, nv = v + dv;
      if (nu >= 0 && nv >= 0 && nu < width_ && nv < height_)
        out.push_back(nv * width_ + nu);
    }
  return out;
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
