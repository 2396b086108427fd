/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): the body of
 * tabletop_segmentation.h's templates, instantiated in src/tabletop_segmentation.cpp for
 * PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/console/print.h>
#include <pcl/icf/segmentation/scene_extent.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include "segmentation_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pcl::icf::segmentation::detail {

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

/** Where segmentTabletop stops early: the status and its one-line explanation. */
struct Stop {
  TabletopStatus status;
  std::string message;
};

/** A SceneUnitsSuspect stop, logged with PCL_WARN (the one stop a caller is warned about: the
 * parameters and the cloud disagree on units). */
inline Stop unitsSuspect(const std::string& message) {
  PCL_WARN("[pcl::icf::segmentation::segmentTabletop] %s\n", message.c_str());
  return Stop{TabletopStatus::SceneUnitsSuspect, message};
}

/** The units checks: the finite points' robust extent (max_scene_extent) and an organized
 * cloud's pixel spacing (max_pixel_spacing_factor) against a scene in metres. */
template <typename PointT>
std::optional<Stop> checkSceneUnits(const pcl::PointCloud<PointT>& cloud,
                                    const pcl::Indices& finite, const TabletopParams& params) {
  if (params.max_scene_extent > 0.0) {
    const double extent = robustExtent(cloud, finite);
    if (extent > params.max_scene_extent) {
      std::ostringstream msg;
      msg << "the scene's extent (bounding box of the 1st-99th percentile per axis) is " << extent
          << " units, more than "
          << "max_scene_extent = " << params.max_scene_extent
          << ": the cloud looks like millimetres while the parameters are in metres; scale the "
             "cloud by 0.001 (or raise max_scene_extent for a large scene in metres)";
      return unitsSuspect(msg.str());
    }
  }
  if (params.max_pixel_spacing_factor > 0.0) {
    const double spacing = medianPixelSpacing(cloud);
    const double limit = params.max_pixel_spacing_factor * params.cluster.tolerance;
    if (spacing > limit) {
      std::ostringstream msg;
      msg << "adjacent pixels are " << spacing << " units apart (median), more than "
          << "max_pixel_spacing_factor * cluster.tolerance = " << limit
          << ": the cloud looks like millimetres while the parameters are in metres; scale the "
             "cloud by 0.001";
      return unitsSuspect(msg.str());
    }
  }
  return std::nullopt;
}

/** Stage 1 on the finite points \a finite: there are some, their units look like metres, and
 * there are enough of them to hold a table. Times the stage into seg.timing.finite_ms. */
template <typename PointT>
std::optional<Stop> checkFinitePoints(const pcl::PointCloud<PointT>& cloud,
                                      const pcl::Indices& finite, const TabletopParams& params,
                                      TabletopSegmentation& seg, Stopwatch& stage) {
  std::ostringstream msg;
  if (finite.empty()) {
    msg << "none of the " << cloud.size() << " points has finite coordinates";
    return Stop{TabletopStatus::NoFinitePoints, msg.str()};
  }
  std::optional<Stop> units = checkSceneUnits(cloud, finite, params);
  seg.timing.finite_ms = stage.lap();
  if (units)
    return units;
  if (finite.size() < params.plane.min_inliers) {
    msg << "only " << finite.size()
        << " finite points, fewer than plane.min_inliers = " << params.plane.min_inliers;
    return Stop{TabletopStatus::TooFewPoints, msg.str()};
  }
  return std::nullopt;
}

/** Stages 2 and 3: the optional voxel grid (the plane is searched among the voxel centroids),
 * the table plane refitted to and with its inliers in the full cloud (seg.plane), and the
 * table's convex \a hull. The hull comes from the inliers where the plane was searched (fewer
 * points; \a searched_inliers of them), projected onto the plane refitted to the full cloud,
 * from which the prism measures heights. */
template <typename PointT>
std::optional<Stop> findTable(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& finite,
                              const TabletopParams& params, TabletopSegmentation& seg,
                              Stopwatch& stage, pcl::PointCloud<PointT>& hull,
                              std::size_t& searched_inliers) {
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

  const TablePlane searched = findTablePlane(search_cloud, search_indices, params.plane);
  seg.plane = downsample ? refineTablePlane(cloud, finite, searched, params.plane) : searched;
  seg.timing.plane_ms = stage.lap();
  if (!seg.plane.found()) {
    std::ostringstream msg;
    msg << "no plane with plane.min_inliers = " << params.plane.min_inliers << " inliers among "
        << search_indices.size() << (downsample ? " voxel centroids" : " points") << " ("
        << toString(seg.plane.status) << ", best had " << searched.inliers.size() << ")";
    return Stop{TabletopStatus::NoPlane, msg.str()};
  }
  hull = tableHull(search_cloud, searched.inliers, seg.plane.coefficients);
  searched_inliers = searched.inliers.size();
  return std::nullopt;
}

/** Stage 4: the finite points in the prism over the table's \a hull (seg.above_table). */
template <typename PointT>
std::optional<Stop> selectAboveTable(const pcl::PointCloud<PointT>& cloud,
                                     const pcl::Indices& finite,
                                     const pcl::PointCloud<PointT>& hull,
                                     std::size_t searched_inliers, const TabletopParams& params,
                                     TabletopSegmentation& seg, Stopwatch& stage) {
  const AboveTable above = aboveTableIndices(cloud, finite, hull, params.above_table);
  seg.above_table = above.indices;
  seg.timing.above_table_ms = stage.lap();
  std::ostringstream msg;
  if (above.status != AboveTableStatus::Ok) {
    msg << "the table's " << searched_inliers << " inliers have no 2D convex hull ("
        << toString(above.status) << ")";
    return Stop{TabletopStatus::NoPlane, msg.str()};
  }
  if (seg.above_table.empty()) {
    msg << "no point between above_table.min_height = " << params.above_table.min_height
        << " and max_height = " << params.above_table.max_height << " over the table";
    return Stop{TabletopStatus::NoCluster, msg.str()};
  }
  return std::nullopt;
}

}  // namespace pcl::icf::segmentation::detail

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
  if (cloud.empty())
    return finish(TabletopStatus::EmptyCloud, "the cloud has no points");
  const pcl::Indices finite = finiteIndices(cloud);
  seg.finite_points = finite.size();
  if (const auto stop = detail::checkFinitePoints(cloud, finite, params, seg, stage))
    return finish(stop->status, stop->message);
  pcl::PointCloud<PointT> hull;
  std::size_t searched_inliers = 0;
  if (const auto stop =
          detail::findTable(cloud, finite, params, seg, stage, hull, searched_inliers))
    return finish(stop->status, stop->message);
  for (const auto& vertex : hull)
    seg.hull.push_back(vertex.getVector3fMap());
  if (const auto stop =
          detail::selectAboveTable(cloud, finite, hull, searched_inliers, params, seg, stage))
    return finish(stop->status, stop->message);

  // 5. Clusters.
  seg.clusters = extractClusters(cloud, seg.above_table, params.cluster);
  seg.timing.cluster_ms = stage.lap();
  if (seg.clusters.empty()) {
    std::ostringstream msg;
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
