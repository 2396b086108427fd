/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/console/print.h>
#include <pcl/icf/segmentation/scene_extent.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/icf/segmentation/impl/segmentation_common.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {
namespace detail {

/** Median distance between horizontally adjacent finite pixels of an organized cloud, over every
 * fourth row; 0 when the cloud is not organized or has no such pair. */
template <typename PointT>
double medianPixelSpacing(const pcl::PointCloud<PointT>& cloud) {
  if (!cloud.isOrganized() || cloud.width < 2)
    return 0.0;
  std::vector<float> gaps;
  for (std::uint32_t r = 0; r < cloud.height; r += 4) {
    for (std::uint32_t c = 0; c + 1 < cloud.width; ++c) {
      const PointT& a = cloud.at(c, r);
      const PointT& b = cloud.at(c + 1, r);
      if (pcl::isXYZFinite(a) && pcl::isXYZFinite(b))
        gaps.push_back((a.getVector3fMap() - b.getVector3fMap()).norm());
    }
  }
  if (gaps.empty())
    return 0.0;
  auto mid = gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2);
  std::nth_element(gaps.begin(), mid, gaps.end());
  return static_cast<double>(*mid);
}

}  // namespace detail
}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

template <typename PointT>
pcl::icf::segmentation::TabletopSegmentation pcl::icf::segmentation::segmentTabletop(
    const pcl::PointCloud<PointT>& cloud, const TabletopParams& params) {
  detail::Stopwatch total;
  detail::Stopwatch stage;
  params.validate();

  TabletopSegmentation seg;
  const auto finish = [&](TabletopStatus status, const std::string& message) {
    seg.status = status;
    seg.message = message;
    seg.timing.total_ms = total.lap();
    return std::move(seg);
  };
  std::ostringstream msg;

  // 1. Finite points and the units checks.
  if (cloud.empty())
    return finish(TabletopStatus::EmptyCloud, "the cloud has no points");
  const pcl::Indices finite = finiteIndices(cloud);
  seg.finite_points = finite.size();
  if (finite.empty()) {
    msg << "none of the " << cloud.size() << " points has finite coordinates";
    return finish(TabletopStatus::NoFinitePoints, msg.str());
  }
  if (params.max_scene_extent > 0.0) {
    const double extent = robustExtent(cloud, finite);
    if (extent > params.max_scene_extent) {
      msg << "the scene's extent (bounding box of the 1st-99th percentile per axis) is " << extent
          << " units, more than "
          << "max_scene_extent = " << params.max_scene_extent
          << ": the cloud looks like millimetres while the parameters are in metres; scale the "
             "cloud by 0.001 (or raise max_scene_extent for a large scene in metres)";
      PCL_WARN("[pcl::icf::segmentation::segmentTabletop] %s\n", msg.str().c_str());
      seg.timing.finite_ms = stage.lap();
      return finish(TabletopStatus::SceneUnitsSuspect, msg.str());
    }
  }
  if (params.max_pixel_spacing_factor > 0.0) {
    const double spacing = detail::medianPixelSpacing(cloud);
    const double limit = params.max_pixel_spacing_factor * params.cluster.tolerance;
    if (spacing > limit) {
      msg << "adjacent pixels are " << spacing << " units apart (median), more than "
          << "max_pixel_spacing_factor * cluster.tolerance = " << limit
          << ": the cloud looks like millimetres while the parameters are in metres; scale the "
             "cloud by 0.001";
      PCL_WARN("[pcl::icf::segmentation::segmentTabletop] %s\n", msg.str().c_str());
      seg.timing.finite_ms = stage.lap();
      return finish(TabletopStatus::SceneUnitsSuspect, msg.str());
    }
  }
  seg.timing.finite_ms = stage.lap();
  if (finite.size() < params.plane.min_inliers) {
    msg << "only " << finite.size()
        << " finite points, fewer than plane.min_inliers = " << params.plane.min_inliers;
    return finish(TabletopStatus::TooFewPoints, msg.str());
  }

  // 2. Optional voxel grid: the plane is searched among the voxel centroids.
  const bool downsample = params.voxel.voxel_size > 0.0;
  pcl::PointCloud<PointT> reduced;
  pcl::Indices reduced_all;
  if (downsample) {
    reduced = voxelDownsample(cloud, finite, params.voxel);
    reduced_all.resize(reduced.size());
    std::iota(reduced_all.begin(), reduced_all.end(), 0);
  }
  const pcl::PointCloud<PointT>& search_cloud = downsample ? reduced : cloud;
  const pcl::Indices& search_indices = downsample ? reduced_all : finite;
  seg.plane_search_points = search_indices.size();
  seg.timing.voxel_ms = stage.lap();

  // 3. Table plane, refitted to and with its inliers in the full cloud.
  const TablePlane searched = findTablePlane(search_cloud, search_indices, params.plane);
  seg.plane = downsample ? refineTablePlane(cloud, finite, searched, params.plane) : searched;
  seg.timing.plane_ms = stage.lap();
  if (!seg.plane.found()) {
    msg << "no plane with plane.min_inliers = " << params.plane.min_inliers << " inliers among "
        << search_indices.size() << (downsample ? " voxel centroids" : " points") << " ("
        << toString(seg.plane.status) << ", best had " << searched.inliers.size() << ")";
    return finish(TabletopStatus::NoPlane, msg.str());
  }

  // 4. Points in the prism over the table's convex hull. The hull comes from the inliers where
  // the plane was searched (fewer points), projected onto the plane refitted to the full cloud,
  // from which the prism measures heights.
  const pcl::PointCloud<PointT> hull =
      tableHull(search_cloud, searched.inliers, seg.plane.coefficients);
  const AboveTable above = aboveTableIndices(cloud, finite, hull, params.above_table);
  seg.above_table = above.indices;
  seg.timing.above_table_ms = stage.lap();
  if (above.status != AboveTableStatus::Ok) {
    msg << "the table's " << searched.inliers.size() << " inliers have no 2D convex hull ("
        << toString(above.status) << ")";
    return finish(TabletopStatus::NoPlane, msg.str());
  }
  if (seg.above_table.empty()) {
    msg << "no point between above_table.min_height = " << params.above_table.min_height
        << " and max_height = " << params.above_table.max_height << " over the table";
    return finish(TabletopStatus::NoCluster, msg.str());
  }

  // 5. Clusters.
  seg.clusters = extractClusters(cloud, seg.above_table, params.cluster);
  seg.timing.cluster_ms = stage.lap();
  if (seg.clusters.empty()) {
    msg << "the " << seg.above_table.size() << " points above the table form no cluster of "
        << params.cluster.min_size << " to " << params.cluster.max_size << " points";
    return finish(TabletopStatus::NoCluster, msg.str());
  }
  return finish(TabletopStatus::Ok, "");
}

#define PCL_INSTANTIATE_IcfSegmentTabletop(T)                           \
  template pcl::icf::segmentation::TabletopSegmentation                 \
  pcl::icf::segmentation::segmentTabletop<T>(const pcl::PointCloud<T>&, \
                                             const pcl::icf::segmentation::TabletopParams&);
