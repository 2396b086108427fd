/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): the body of
 * voxel_downsample.h's templates, instantiated in src/voxel_downsample.cpp for
 * PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/common/common.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/icf/segmentation/voxel_downsample.h>
#include "segmentation_common.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

namespace pcl::icf::segmentation::detail {

/** True when pcl::VoxelGrid could index the voxels of cloud[indices] with \a leaf: PCL 1.13
 * refuses more than INT32_MAX cells by returning its whole input cloud (NaN and unindexed
 * points included), and computes that cell count in int64 arithmetic that a far stray point
 * overflows; here it is counted in double. */
template <typename PointT>
bool voxelGridFits(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, float leaf) {
  Eigen::Vector4f lo, hi;
  pcl::getMinMax3D(cloud, indices, lo, hi);  // the bounds VoxelGrid itself computes
  double cells = 1.0;
  for (int a = 0; a < 3; ++a)
    cells *= std::floor((static_cast<double>(hi[a]) - lo[a]) / leaf) + 1.0;
  return cells <= static_cast<double>(std::numeric_limits<std::int32_t>::max());
}

}  // namespace pcl::icf::segmentation::detail

template <typename PointT>
pcl::PointCloud<PointT> pcl::icf::segmentation::voxelDownsample(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, const VoxelParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::voxelDownsample");

  pcl::PointCloud<PointT> out;
  auto finite = std::make_shared<pcl::Indices>(detail::finiteSubset(cloud, indices));
  const auto leaf = static_cast<float>(params.voxel_size);
  if (params.voxel_size <= 0.0 || finite->empty()) {
    pcl::copyPointCloud(cloud, *finite, out);
  } else if (!detail::voxelGridFits(cloud, *finite, leaf)) {
    PCL_WARN(
        "[pcl::icf::segmentation::voxelDownsample] the points span more than 2^31 voxels "
        "of %g (a stray point far away?): the finite points are used unchanged\n",
        params.voxel_size);
    pcl::copyPointCloud(cloud, *finite, out);
  } else {
    pcl::VoxelGrid<PointT> grid;
    grid.setInputCloud(detail::nonOwning(cloud));
    grid.setIndices(finite);
    grid.setLeafSize(leaf, leaf, leaf);
    grid.filter(out);
  }
  out.header = cloud.header;
  out.sensor_origin_ = cloud.sensor_origin_;
  out.sensor_orientation_ = cloud.sensor_orientation_;
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = true;
  return out;
}

#define PCL_INSTANTIATE_IcfVoxelDownsample(T)                             \
  template pcl::PointCloud<T> pcl::icf::segmentation::voxelDownsample<T>( \
      const pcl::PointCloud<T>&, const pcl::Indices&, const pcl::icf::segmentation::VoxelParams&);
