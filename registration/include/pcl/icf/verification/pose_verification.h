/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/objective.h>

#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {

/** \brief Which parts of a posed model the camera should see (doc/icf.md section 6).
 * Lengths in scene units. */
struct VisibilityParams {
  /** Angular size of the z-buffer bins used for self-occlusion, radians (2 mrad: about 1 mm at
   * 50 cm, coarser than a Kinect pixel so sparse samples still fill it). */
  float bin_angle = 0.004f;
  /** A sample within this depth behind the nearest sample of its bin is still visible. */
  float depth_tolerance = 0.01f;
  /** Faces seen at a grazing angle (cosine below this) are not counted as visible: a depth
   * camera returns few points there. */
  float min_view_cosine = 0.2f;

  void validate() const;
};

/** \brief Indices of the model's surface samples that a camera at \a camera (scene frame)
 * would see with the model at \a model_to_scene: facing the camera and not hidden behind
 * another part of the model. */
std::vector<std::size_t> visibleSamples(const IcfModel& model,
                                        const Eigen::Isometry3f& model_to_scene,
                                        const Eigen::Vector3f& camera,
                                        const VisibilityParams& params = {});

/** \brief How well a pose explains a cluster, all measured at the final pose. */
struct PoseQuality {
  double thesis_score = 0.0;  ///< F(P, S) of the thesis (eq. 1), exact distances, no early exit
  double inlier_ratio = 0.0;  ///< share of scene points within inlier_distance of the model
  double rmse = 0.0;          ///< RMS point-to-face distance of those inliers, scene units
  /** Share of the visible model surface (visibleSamples) with a scene point within
   * inlier_distance: how much of what the camera should see of the model is there. */
  double surface_coverage = 0.0;
  int far_points = 0;      ///< scene points farther than the thesis gate distance
  std::size_t points = 0;  ///< scene points measured
  std::size_t inliers = 0;
  std::size_t visible_samples = 0;
  /** Share of the posed model's pixels, where the camera could have seen it, that the camera
   * saw through (measured depth behind the model, or the table in front of it; explainDepth).
   * Measured by estimatePose, not by measurePoseQuality: 0 when not measured. */
  double seen_through = 0.0;
};

/** \brief Measure PoseQuality with exact distances.
 * \param scene_points finite scene points
 * \param scene_to_model the registration transform (its inverse poses the model)
 * \param inlier_distance radius for inliers and coverage
 * \param gate_distance distance beyond which a point counts in far_points (thesis: 27 mm) */
PoseQuality measurePoseQuality(const IcfModel& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Isometry3f& scene_to_model,
                               const Eigen::Vector3f& camera, float inlier_distance,
                               float gate_distance, const ObjectiveParams& objective,
                               const VisibilityParams& visibility, int threads = 1);

}  // namespace icf
}  // namespace pcl
