/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief The extent of cloud[indices] without its stray points: the diagonal of the box that
 * holds, on each axis, the coordinates between the 1st and the 99th percentile (as many values
 * cut at each end; at most 20,000 points, evenly strided). 0 for no points.
 *
 * Units checks use it ("a scene in metres spans a few metres, the same scene in millimetres
 * thousands"), so that a few wild returns (a corrupt pixel at 1e5, say) cannot make a scene in
 * metres look like millimetres. The indices should hold finite points (finiteIndices).
 */
template <typename PointT>
double robustExtent(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  if (indices.empty())
    return 0.0;
  const std::size_t stride = (indices.size() + 19999) / 20000;  // at most 20,000 points
  std::vector<float> axis;
  axis.reserve(indices.size() / stride + 1);
  Eigen::Vector3d span;
  for (int a = 0; a < 3; ++a) {
    axis.clear();
    for (std::size_t k = 0; k < indices.size(); k += stride)
      axis.push_back(cloud[indices[k]].getVector3fMap()[a]);
    const std::size_t cut = (axis.size() - 1) / 100;  // the 1st percentile's rank, either side
    const auto valueAt = [&axis](std::size_t rank) {
      const auto at = axis.begin() + static_cast<std::ptrdiff_t>(rank);
      std::nth_element(axis.begin(), at, axis.end());
      return static_cast<double>(*at);
    };
    const double lo = valueAt(cut);
    span[a] = valueAt(axis.size() - 1 - cut) - lo;
  }
  return span.norm();
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
