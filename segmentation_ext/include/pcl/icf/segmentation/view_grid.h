/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief A depth image rebuilt from any cloud: points projected through a pinhole at the
 * camera (optical axis +z, the Kinect frame) into square angular bins, keeping the nearest
 * depth per bin. Lets the localizer ask "what does the camera see along this ray" of organized
 * and unorganized clouds alike (doc/localizer.md). */
class ViewGrid {
 public:
  /** \param points scene points (scene frame) \param camera camera position
   * \param bin_angle angular size of a bin, radians (default about two Kinect pixels) */
  ViewGrid(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& camera,
           float bin_angle = 0.004f);

  /** \brief Bin of \a p, or -1 when it is behind the camera or outside the grid. */
  std::int64_t bin(const Eigen::Vector3f& p) const;
  /** \brief Nearest scene depth (along +z) in bin \a b; +inf when the bin saw nothing. */
  float depth(std::int64_t b) const { return b < 0 ? kEmpty : depth_[static_cast<std::size_t>(b)]; }
  /** \brief Depth of \a p along +z from the camera. */
  float depthOf(const Eigen::Vector3f& p) const { return p.z() - camera_.z(); }
  /** \brief The 8 neighbours of bin \a b (fewer at the border). */
  std::vector<std::int64_t> neighbours(std::int64_t b) const;

  static constexpr float kEmpty = 1e30f;

 private:
  Eigen::Vector3f camera_;
  float inv_bin_ = 0.f;
  int u0_ = 0, v0_ = 0, width_ = 0, height_ = 0;
  std::vector<float> depth_;
};

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
