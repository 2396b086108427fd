/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/common/io.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/icf/segmentation/voxel_downsample.h>
#include <pcl/icf/segmentation/impl/segmentation_common.hpp>

#include <memory>

template <typename PointT>
pcl::PointCloud<PointT> pcl::icf::segmentation::voxelDownsample(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, const VoxelParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::voxelDownsample");

  pcl::PointCloud<PointT> out;
  auto finite = std::make_shared<pcl::Indices>(detail::finiteSubset(cloud, indices));
  if (params.voxel_size <= 0.0 || finite->empty()) {
    pcl::copyPointCloud(cloud, *finite, out);
  } else {
    pcl::VoxelGrid<PointT> grid;
    grid.setInputCloud(detail::nonOwning(cloud));
    grid.setIndices(finite);
    const auto leaf = static_cast<float>(params.voxel_size);
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
