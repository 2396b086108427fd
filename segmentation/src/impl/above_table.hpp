/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): the body of above_table.h's
 * templates, instantiated in src/above_table.cpp for PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/PointIndices.h>
#include <pcl/icf/segmentation/above_table.h>
#include <pcl/segmentation/extract_polygonal_prism_data.h>
#include <pcl/surface/convex_hull.h>
#include "segmentation_common.hpp"

#include <memory>
#include <numeric>

template <typename PointT>
pcl::PointCloud<PointT> pcl::icf::segmentation::tableHull(const pcl::PointCloud<PointT>& cloud,
                                                          const pcl::Indices& inliers,
                                                          const Eigen::Vector4f& coefficients) {
  detail::requireIndicesInRange(cloud, inliers, "segmentation::tableHull");
  pcl::PointCloud<PointT> hull;

  // Project the inliers onto the plane (p - (n.p + d) n), as pcl::ProjectInliers would.
  auto projected = std::make_shared<pcl::PointCloud<PointT>>();
  projected->reserve(inliers.size());
  const Eigen::Vector3f n = coefficients.head<3>();
  const float d = coefficients[3];
  for (const pcl::index_t i : inliers) {
    PointT p = cloud[i];
    if (!pcl::isXYZFinite(p))
      continue;
    const float h = n.dot(p.getVector3fMap()) + d;
    p.getVector3fMap() -= h * n;
    projected->push_back(p);
  }
  if (projected->size() < 3)
    return hull;
  pcl::Indices all(projected->size());
  std::iota(all.begin(), all.end(), 0);
  if (!detail::spansPlane(*projected, all))
    return hull;

  pcl::ConvexHull<PointT> chull;
  chull.setInputCloud(projected);
  chull.setDimension(2);
  chull.reconstruct(hull);
  if (hull.size() < 3)
    hull.clear();
  return hull;
}

template <typename PointT>
pcl::icf::segmentation::AboveTable pcl::icf::segmentation::aboveTableIndices(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
    const pcl::PointCloud<PointT>& hull, const AboveTableParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::aboveTableIndices");

  AboveTable result;
  result.hull_size = hull.size();
  if (hull.size() < 3) {
    result.status = AboveTableStatus::DegenerateHull;
    return result;
  }
  result.status = AboveTableStatus::Ok;
  auto candidates = std::make_shared<pcl::Indices>(detail::finiteSubset(cloud, indices));
  if (candidates->empty())
    return result;

  pcl::ExtractPolygonalPrismData<PointT> prism;
  prism.setInputCloud(detail::nonOwning(cloud));
  prism.setIndices(candidates);
  prism.setInputPlanarHull(std::make_shared<const pcl::PointCloud<PointT>>(hull));
  prism.setHeightLimits(params.min_height, params.max_height);
  prism.setViewPoint(cloud.sensor_origin_[0], cloud.sensor_origin_[1], cloud.sensor_origin_[2]);
  pcl::PointIndices inside;
  prism.segment(inside);
  result.indices = std::move(inside.indices);
  return result;
}

template <typename PointT>
pcl::icf::segmentation::AboveTable pcl::icf::segmentation::aboveTableIndices(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, const TablePlane& plane,
    const AboveTableParams& params) {
  params.validate();
  if (!plane.found()) {
    detail::requireIndicesInRange(cloud, indices, "segmentation::aboveTableIndices");
    return AboveTable{};
  }
  const pcl::PointCloud<PointT> hull = tableHull(cloud, plane.inliers, plane.coefficients);
  return aboveTableIndices(cloud, indices, hull, params);
}

#define PCL_INSTANTIATE_IcfTableHull(T)                             \
  template pcl::PointCloud<T> pcl::icf::segmentation::tableHull<T>( \
      const pcl::PointCloud<T>&, const pcl::Indices&, const Eigen::Vector4f&);
#define PCL_INSTANTIATE_IcfAboveTableIndices(T)                                                  \
  template pcl::icf::segmentation::AboveTable pcl::icf::segmentation::aboveTableIndices<T>(      \
      const pcl::PointCloud<T>&, const pcl::Indices&, const pcl::PointCloud<T>&,                 \
      const pcl::icf::segmentation::AboveTableParams&);                                          \
  template pcl::icf::segmentation::AboveTable pcl::icf::segmentation::aboveTableIndices<T>(      \
      const pcl::PointCloud<T>&, const pcl::Indices&, const pcl::icf::segmentation::TablePlane&, \
      const pcl::icf::segmentation::AboveTableParams&);
