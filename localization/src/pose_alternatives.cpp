/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/localization/pose_alternatives.h>
#include <pcl/icf/registration/global_search.h>
#include <pcl_icf_internal/parameter_check.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace localization {

void PoseAlternativeParams::validate() const {
  const internal::ParameterCheck fail("localization::PoseAlternativeParams");
  if (!(confidence_margin >= 0.0 && confidence_margin <= 1.0))
    fail("confidence_margin", confidence_margin, "must lie in [0, 1]");
  if (!(same_translation >= 0.f) || !std::isfinite(same_translation))
    fail("same_translation", same_translation, "must be >= 0 and finite");
  if (!(same_rotation_deg >= 0.f && same_rotation_deg <= 180.f))
    fail("same_rotation_deg", same_rotation_deg, "must lie in [0, 180]");
  if (max_points == 0)
    fail("max_points", 0.0, "must be positive");
  if (!(quarter_turn_extent_ratio >= 1.f) || !std::isfinite(quarter_turn_extent_ratio))
    fail("quarter_turn_extent_ratio", quarter_turn_extent_ratio, "must be >= 1 and finite");
  if (field_points < 10)
    fail("field_points", field_points, "must be >= 10");
  if (!(fine_start_radius > 0.f && std::isfinite(fine_start_radius)))
    fail("fine_start_radius", fine_start_radius, "must be positive and finite");
  if (fine_iterations < 1)
    fail("fine_iterations", fine_iterations, "must be >= 1");
}

PrincipalAxes principalAxes(const IcfModel& model) {
  const FaceMesh& mesh = model.mesh();
  PrincipalAxes out;
  out.centre = mesh.surfaceCentroid();
  // Second moments of the face centroids weighted by area: enough to find the axes of the
  // shape; the exact moments of each polygon would refine the eigenvalues, not the axes.
  Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
  for (std::size_t f = 0; f < mesh.size(); ++f) {
    const Face& face = mesh.faces()[f];
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    for (std::size_t k = 0; k < face.count; ++k)
      c += mesh.faceVertex(f, k);
    const Eigen::Vector3d d = (c / static_cast<float>(face.count) - out.centre).cast<double>();
    moments += static_cast<double>(face.area) * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(moments);
  // Eigen sorts ascending; largest spread first, and a right-handed frame.
  Eigen::Matrix3d axes;
  axes << eig.eigenvectors().col(2), eig.eigenvectors().col(1), eig.eigenvectors().col(0);
  if (axes.determinant() < 0.0)
    axes.col(2) = -axes.col(2);
  out.axes = axes.cast<float>();
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (std::size_t f = 0; f < mesh.size(); ++f)
    for (std::size_t k = 0; k < mesh.faces()[f].count; ++k) {
      const Eigen::Vector3f q = out.axes.transpose() * (mesh.faceVertex(f, k) - out.centre);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  out.extent = mesh.size() > 0 ? Eigen::Vector3f(hi - lo) : Eigen::Vector3f::Zero();
  return out;
}

namespace {

std::vector<Eigen::Vector3f> stridedSubset(const std::vector<Eigen::Vector3f>& points,
                                           std::size_t max_points) {
  if (points.size() <= max_points)
    return points;
  std::vector<Eigen::Vector3f> subset;
  subset.reserve(max_points);
  const double stride = static_cast<double>(points.size()) / static_cast<double>(max_points);
  for (std::size_t i = 0; i < max_points; ++i)
    subset.push_back(points[static_cast<std::size_t>(static_cast<double>(i) * stride)]);
  return subset;
}

/** Translation between the origins and rotation angle (degrees) from \a a to \a b. */
void poseOffset(const Eigen::Isometry3f& a, const Eigen::Isometry3f& b, float& translation,
                float& rotation_deg) {
  translation = (a.translation() - b.translation()).norm();
  const Eigen::AngleAxisf turn(a.linear().transpose() * b.linear());
  rotation_deg = std::abs(turn.angle()) * 180.f / static_cast<float>(M_PI);
}

bool samePose(const Eigen::Isometry3f& a, const Eigen::Isometry3f& b,
              const PoseAlternativeParams& params) {
  float t = 0.f, r = 0.f;
  poseOffset(a, b, t, r);
  return t <= params.same_translation && r <= params.same_rotation_deg;
}

}  // namespace

std::vector<PoseAlternative> turnedAlternatives(
    const IcfModel& model, const PrincipalAxes& principal,
    const std::vector<Eigen::Vector3f>& points, const Eigen::Isometry3f& object_pose,
    const DepthExplanation& found, const DepthImage& image, const PoseAlternativeParams& params,
    const TurnChecks& checks) {
  params.validate();
  checks.refinement.validate();
  checks.verification.validate();
  std::vector<PoseAlternative> out;
  if (points.empty() || image.empty())
    return out;
  const std::vector<Eigen::Vector3f> subset = stridedSubset(points, params.max_points);
  const std::vector<Eigen::Vector3f> field_subset = stridedSubset(points, params.field_points);
  const Eigen::Vector3f pivot = model.mesh().surfaceCentroid();
  const double scale = std::max(1e-3f, model.radius());
  RefinementParams fine = checks.refinement;
  fine.initial_inlier_distance = std::max(fine.final_inlier_distance, params.fine_start_radius);
  fine.max_iterations = std::min(fine.max_iterations, params.fine_iterations);
  const float diameter = 2.f * model.radius();
  for (int a = 0; a < 3; ++a)
    for (const float degrees : {90.f, 180.f, 270.f}) {
      const float e1 = principal.extent[(a + 1) % 3], e2 = principal.extent[(a + 2) % 3];
      if (degrees != 180.f &&
          std::max(e1, e2) > params.quarter_turn_extent_ratio * std::min(e1, e2))
        continue;
      PoseAlternative alt;
      alt.axis = principal.axes.col(a);
      alt.turn_deg = degrees;
      const Eigen::Isometry3f turn =
          Eigen::Translation3f(principal.centre) *
          Eigen::AngleAxisf(degrees * static_cast<float>(M_PI) / 180.f, alt.axis) *
          Eigen::Translation3f(-principal.centre);
      const Eigen::Isometry3f start = object_pose * turn;
      // Coarse to fine: the turn refined on the closest-point field with a few hundred points,
      // then with exact faces from the final Tukey radius (a turned start lies far from where
      // it settles; most of the way costs a field lookup instead of an exact query).
      const Eigen::Isometry3f coarse =
          refinePoseOnField(model.field(), pivot, scale, field_subset, start.inverse(),
                            GlobalSearchParams::defaultFieldRefinement())
              .scene_to_model;
      const RefinementResult refined = refinePose(model.index(), subset, coarse, fine, 1);
      alt.object_pose = refined.scene_to_model.inverse();
      if (samePose(alt.object_pose, object_pose, params))
        continue;
      if (std::any_of(out.begin(), out.end(), [&](const PoseAlternative& other) {
            return samePose(alt.object_pose, other.object_pose, params);
          }))
        continue;
      alt.verification = explainDepth(renderModelDepth(model, alt.object_pose, image.intrinsics()),
                                      image, diameter, checks.verification);
      if (alt.verification.confidence < found.confidence - params.confidence_margin)
        continue;
      poseOffset(object_pose, alt.object_pose, alt.translation_offset, alt.rotation_offset_deg);
      out.push_back(alt);
    }
  std::stable_sort(out.begin(), out.end(), [](const PoseAlternative& x, const PoseAlternative& y) {
    if (x.verification.confidence != y.verification.confidence)
      return x.verification.confidence > y.verification.confidence;
    return x.verification.residual < y.verification.residual;
  });
  return out;
}

}  // namespace localization
}  // namespace icf
}  // namespace pcl
