/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to the libraries' sources (not installed): a scene cloud as the non-template
 * cores of localization and tracking read it (localizeObject's and ObjectTracker::track's
 * template shells build it once per call). */

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>  // pcl::traits::has_color_v
#include <pcl/type_traits.h>

#include <Eigen/Core>

#include <vector>

namespace pcl {
namespace icf {
namespace internal {

/** What the non-template cores need of a scene: its points and colours, and its image size. */
struct SceneView {
  std::vector<Eigen::Vector3f> points;   ///< every point (NaN where the cloud has NaN)
  std::vector<Eigen::Vector3f> colours;  ///< [0, 1] RGB per point, empty without colour
  int width = 0, height = 0;             ///< an organized cloud's image size; 0 when unorganized
};

/** \a scene's view: its x, y, z, its r, g, b / 255 when PointT has colour, and width and height
 * when it is organized with more than one row. */
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
  if (scene.isOrganized() && scene.height > 1) {
    view.width = static_cast<int>(scene.width);
    view.height = static_cast<int>(scene.height);
  }
  return view;
}

}  // namespace internal
}  // namespace icf
}  // namespace pcl
