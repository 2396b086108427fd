/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/segmentation/object_localizer.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/type_traits.h>

#include <chrono>
#include <cmath>

namespace pcl {
namespace icf {
namespace segmentation {
namespace detail {

/** What the non-template core needs of the scene. */
struct SceneView {
  std::vector<Eigen::Vector3f> points;   ///< every point (NaN where the cloud has NaN)
  std::vector<Eigen::Vector3f> colours;  ///< [0, 1] RGB per point, empty without colour
  Eigen::Vector3f camera = Eigen::Vector3f::Zero();
};

Localization localizeInView(const SceneView& view, TabletopSegmentation segmentation,
                            const IcfModel& model, const LocalizerParams& params,
                            double segmentation_ms);

template <typename PointT>
SceneView makeSceneView(const pcl::PointCloud<PointT>& scene) {
  SceneView view;
  view.points.reserve(scene.size());
  for (const auto& p : scene)
    view.points.emplace_back(p.x, p.y, p.z);
  if constexpr (pcl::traits::has_color_v<PointT>) {
    view.colours.reserve(scene.size());
    for (const auto& p : scene)
      view.colours.emplace_back(p.r / 255.f, p.g / 255.f, p.b / 255.f);
  }
  view.camera = scene.sensor_origin_.template head<3>();
  return view;
}

}  // namespace detail

template <typename PointT>
Localization localizeObject(const pcl::PointCloud<PointT>& scene, const IcfModel& model,
                            const LocalizerParams& params) {
  params.validate();
  const auto start = std::chrono::steady_clock::now();
  TabletopSegmentation segmentation;
  if (params.segment)
    segmentation = segmentTabletop(scene, params.segmentation);
  const double segmentation_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return detail::localizeInView(detail::makeSceneView(scene), std::move(segmentation), model,
                                params, segmentation_ms);
}

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
