/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief When the depth cannot decide: poses that differ from a found one by a turn and
 * explain the depth image as well (a box-like object's 180-degree flip, a can's spin about its
 * axis). The thesis's objects were chosen so that the pose was unique up to their symmetries;
 * a grasp planner given a near-symmetric object needs the alternatives with their scores. */

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/refinement.h>
#include <pcl/icf/verification/depth_verification.h>

#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {
namespace localization {

/** \brief The model's principal axes: the eigenvectors (columns, largest spread first) of its
 * surface's area-weighted second moments about the surface centroid, in the model frame. */
struct PrincipalAxes {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();
  Eigen::Vector3f extent = Eigen::Vector3f::Zero();  ///< the vertices' spread along each axis
};
PrincipalAxes principalAxes(const IcfModel& model);

/** \brief Parameters of turnedAlternatives. */
struct PoseAlternativeParams {
  /** An alternative within this much confidence of the best is as good: the pose is
   * ambiguous. */
  double confidence_margin = 0.05;
  /** A refined turn that lands within these of the found pose is the same pose. */
  float same_translation = 0.005f;  ///< metres, between the model origins
  float same_rotation_deg = 5.f;
  /** A quarter turn about an axis is tried only when the extents along the other two axes
   * differ by at most this factor (a quarter turn of a 14 x 9 cm face cannot cover it). */
  float quarter_turn_extent_ratio = 1.15f;
  /** Points used by each turn's refinement (an evenly strided subset). */
  std::size_t max_points = 3000;
  /** Each turn is refined coarse to fine: on the closest-point field with field_points points
   * first, then with exact faces from the Tukey radius fine_start_radius (metres) for at most
   * fine_iterations (the field stage leaves it within a few millimetres of where the exact
   * faces settle it). */
  std::size_t field_points = 500;
  float fine_start_radius = 0.01f;
  int fine_iterations = 15;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief A pose that differs from the found one by a turn of the model about one of its
 * principal axes (through its surface centroid), refined and verified like the found one. */
struct PoseAlternative {
  Eigen::Isometry3f object_pose = Eigen::Isometry3f::Identity();  ///< model -> camera
  Eigen::Vector3f axis = Eigen::Vector3f::UnitZ();                ///< the turn's axis, model frame
  float turn_deg = 180.f;                                         ///< 90, 180 or 270
  DepthExplanation verification;
  float translation_offset = 0.f;  ///< metres between this pose's and the found one's origins
  float rotation_offset_deg = 0.f;
};

/** \brief How a turn is refined and judged: as the found pose was (the localizer passes its
 * own refinement and verification), so a turn and the found pose are compared alike. */
struct TurnChecks {
  RefinementParams refinement;
  DepthVerificationParams verification;
};

/** \brief Turns the model found at \a object_pose (model -> camera) by 180 degrees about each
 * principal axis, and by 90 and 270 where the other two extents nearly agree, refines each turn on
 * \a points (camera frame) and verifies it on \a image, both as \a checks say. Returns the distinct
 * refined poses (not within same_translation / same_rotation of the found one or of each other)
 * whose confidence reaches the found pose's minus confidence_margin, best first (confidence, then
 * the lower residual). Deterministic. */
std::vector<PoseAlternative> turnedAlternatives(
    const IcfModel& model, const PrincipalAxes& principal,
    const std::vector<Eigen::Vector3f>& points, const Eigen::Isometry3f& object_pose,
    const DepthExplanation& found, const DepthImage& image,
    const PoseAlternativeParams& params = {}, const TurnChecks& checks = {});

}  // namespace localization
}  // namespace icf
}  // namespace pcl
