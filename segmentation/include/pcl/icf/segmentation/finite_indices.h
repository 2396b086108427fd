/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/usable_point.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief Indices of the points of \a cloud whose x, y and z are all finite and within
 * +-kMaxPointCoordinate (isUsablePoint), in increasing order.
 *
 * Organized Kinect clouds mark missing depth with NaN; PCL's kd-trees and sample consensus
 * models misbehave on such points, and a corrupt return at 1e30 would wreck the voxel grid and
 * the plane fit, so every stage of the table-top segmentation works on an
 * index list of finite points. An empty cloud gives an empty list. O(n), no allocation beyond
 * the result.
 *
 * \code
 * pcl::PointCloud<pcl::PointXYZ> scene;  // e.g. an organized 640x480 Kinect frame
 * const pcl::Indices finite = pcl::icf::segmentation::finiteIndices(scene);
 * \endcode
 */
template <typename PointT>
pcl::Indices finiteIndices(const pcl::PointCloud<PointT>& cloud) {
  pcl::Indices indices;
  indices.reserve(cloud.size());
  const auto n = static_cast<pcl::index_t>(cloud.size());
  for (pcl::index_t i = 0; i < n; ++i) {
    if (isUsablePoint(cloud[i].getVector3fMap()))
      indices.push_back(i);
  }
  return indices;
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
