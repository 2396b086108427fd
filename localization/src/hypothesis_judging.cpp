/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "hypothesis_judging.h"

#include <pcl/icf/localization/colour_histogram.h>
#include <pcl/icf/localization/pose_alternatives.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl/icf/verification/pose_verification.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace pcl::icf::localization::detail {

using internal::SceneView;

namespace {

/** The localizer works in the camera's frame (localizeObject moves the scene there). */
const Eigen::Vector3f kCameraAtOrigin = Eigen::Vector3f::Zero();

/** The thesis's gate on one cluster: points farther than the gate's distance from the posed
 * model.
 * A cluster of one object is counted whole; in a merged cluster only the points the model
 * claims: on its rendered silhouette and not in front of its surface. */
int gateFarPoints(const std::vector<Eigen::Vector3f>& points, const IcfModel& model,
                  const Eigen::Isometry3f& scene_to_model, const ModelDepth& rendered,
                  const DepthImage& image, const FarPointGate& gate, bool single_object) {
  int far = 0;
  for (const auto& x : points) {
    if (!single_object) {
      int u = 0, v = 0;
      if (!image.pixelOf(x, u, v) || !rendered.covers(u, v) ||
          x.z() < rendered.depthAt(u, v) - gate.distance)
        continue;
    }
    if (model.index().closestFace(scene_to_model * x, gate.distance).distance > gate.distance)
      ++far;
  }
  return far;
}

/** The points of \a indices within the verification's depth tolerance of the posed model's
 * surface (noise_sigmas x sigma(z) + size_tolerance x diameter). */
pcl::Indices explainedPoints(const SceneView& view, const pcl::PointIndices& indices,
                             const IcfModel& model, const Eigen::Isometry3f& scene_to_model,
                             const DepthVerificationParams& v) {
  const float diameter = 2.f * model.radius();
  pcl::Indices explained;
  for (const auto i : indices.indices) {
    const Eigen::Vector3f& p = view.points[static_cast<std::size_t>(i)];
    if (!isUsablePoint(p))
      continue;
    const float tolerance = v.supportTolerance(p.z(), diameter);
    if (model.index().closestFace(scene_to_model * p, tolerance).distance <= tolerance)
      explained.push_back(i);
  }
  return explained;
}

/** True when \a judged's pose is worth more work (its turns, a last refinement on its crop):
 * at least promising_share of the confidence an acceptance needs. */
bool isPromising(const ClusterLocalization& judged, const LocalizerParams& params) {
  return judged.verification.confidence >= params.tuning().promising_share * params.min_confidence;
}

/** The factor the colour cue gives \a c's score: 1 without the cue. */
double colourFactor(const ClusterLocalization& c, const LocalizerParams& params) {
  if (!c.colour_similarity)
    return 1.0;
  return std::pow(std::max(1e-3, *c.colour_similarity), params.colour.weight);
}

/** The usable points of \a indices. */
std::vector<Eigen::Vector3f> usablePoints(const SceneView& view, const pcl::PointIndices& indices) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(indices.indices.size());
  for (const auto i : indices.indices)
    if (isUsablePoint(view.points[static_cast<std::size_t>(i)]))
      points.push_back(view.points[static_cast<std::size_t>(i)]);
  return points;
}

/** \a alt's turn from \a from, in \a from's model frame: axis, angle and offsets. */
void describeTurn(const Eigen::Isometry3f& from, PoseAlternative& alt) {
  const Eigen::AngleAxisf turn(from.linear().transpose() * alt.object_pose.linear());
  alt.axis = turn.axis();
  alt.turn_deg = std::abs(turn.angle()) * 180.f / static_cast<float>(M_PI);
  alt.rotation_offset_deg = alt.turn_deg;
  alt.translation_offset = (alt.object_pose.translation() - from.translation()).norm();
}

/** \a c's pose becomes \a pose (model -> camera), verified as \a verification: its quality on
 * \a points, its score (the colour factor kept) and the points it explains follow. */
void adoptPose(ClusterLocalization& c, const Eigen::Isometry3f& pose,
               const DepthExplanation& verification, const SceneView& view,
               const std::vector<Eigen::Vector3f>& points, const IcfModel& model,
               const LocalizerParams& params) {
  const Eigen::Isometry3f scene_to_model = pose.inverse();
  c.icf.object_pose = pose.matrix();
  c.icf.scene_to_model = scene_to_model.matrix();
  c.icf.quality = measurePoseQuality(
      model, points, scene_to_model, kCameraAtOrigin,
      params.tuning().icf.acceptance.inlier_distance, params.tuning().icf.acceptance.gate.distance,
      params.tuning().icf.tuning().objective, params.tuning().icf.tuning().visibility);
  c.verification = verification;
  c.score = c.verification.confidence * colourFactor(c, params);
  c.explained =
      explainedPoints(view, c.indices, model, scene_to_model, params.verificationParams());
}

/** \a base as a hypothesis's exact refinement runs it: on \a max_points of its crop (the
 * refinement's stride), from the Tukey radius fine_start_radius, for at most fine_iterations
 * (SceneHypotheses). */
RefinementParams hypothesisRefinement(RefinementParams base, const SceneHypotheses& hp,
                                      std::size_t max_points) {
  base.max_points = max_points;
  base.initial_inlier_distance = std::max(base.final_inlier_distance, hp.fine_start_radius);
  base.max_iterations = std::min(base.max_iterations, hp.fine_iterations);
  return base;
}

/** The judged pose refined once more with exact faces on \a points, its crop's usable points
 * (strided to final_points: SceneHypotheses::final_points), from the fine start radius, and
 * verified again; it replaces the judged pose when it explains the depth better. The hypotheses
 * and their turns are refined on small subsets so that many are cheap, and the subset's optimum
 * can sit far enough from the crop's to cost a right pose its fit. */
void refineOnTheCrop(ClusterLocalization& c, const std::vector<Eigen::Vector3f>& points,
                     const SceneView& view, const DepthImage& image, const IcfModel& model,
                     const LocalizerParams& params, int threads) {
  if (points.empty())
    return;
  const SceneHypotheses& hp = params.tuning().hypotheses;
  const RefinementParams fine =
      hypothesisRefinement(params.tuning().icf.tuning().refinement, hp, hp.final_points);
  const RefinementResult refined =
      refinePose(model.index(), points, Eigen::Isometry3f(c.icf.scene_to_model), fine, threads);
  const Eigen::Isometry3f pose = refined.scene_to_model.inverse();
  const DepthExplanation verification =
      explainDepth(model, pose, image, params.verificationParams());
  if (!(verification.confidence > c.verification.confidence))
    return;
  adoptPose(c, pose, verification, view, points, model, params);
  c.icf.refinement_iterations = refined.iterations;
  c.icf.refinement_converged = refined.converged;
}

/** A pose against its turns about the model's principal axes (turnedAlternatives): a turn
 * that explains the depth clearly better (by more than the margin) replaces it. Returns the
 * poses not chosen: the search's own first when a turn replaced it, then the turns best first. */
std::vector<PoseAlternative> resolveTurns(ClusterLocalization& c,
                                          const std::vector<Eigen::Vector3f>& points,
                                          const SceneView& view, const DepthImage& image,
                                          const IcfModel& model, const PrincipalAxes& axes,
                                          const LocalizerParams& params) {
  const PoseAlternativeParams& ap = params.tuning().alternatives;
  const TurnChecks checks{params.tuning().icf.tuning().refinement, params.verificationParams()};
  const Eigen::Isometry3f found(c.icf.object_pose);
  std::vector<PoseAlternative> candidates =
      turnedAlternatives(model, axes, points, found, c.verification, image, ap, checks);
  if (candidates.empty())
    return {};
  PoseAlternative self;
  self.object_pose = found;
  self.verification = c.verification;
  candidates.insert(candidates.begin(), self);
  // A turn replaces the search's pose only when it explains the depth clearly better (its
  // confidence higher by more than the margin): within the margin the difference is noise
  // (a flat box's flip and the truth differ by 0.001-0.006 on the YCB-Video frames, either
  // way), and the turns are reported as alternatives instead.
  std::size_t chosen = 0;
  for (std::size_t k = 1; k < candidates.size(); ++k)
    if (candidates[k].verification.confidence >
        candidates[chosen].verification.confidence + (chosen == 0 ? ap.confidence_margin : 0.0))
      chosen = k;
  if (chosen != 0) {
    adoptPose(c, candidates[chosen].object_pose, candidates[chosen].verification, view, points,
              model, params);
    c.turned = true;
  }
  candidates.erase(candidates.begin() + static_cast<std::ptrdiff_t>(chosen));
  return candidates;
}

/** \a c's alternatives: the poses of \a others (resolveTurns) within the margin of its
 * confidence, each described as a turn from its final pose. */
void recordAlternatives(ClusterLocalization& c, const std::vector<PoseAlternative>& others,
                        const LocalizerParams& params) {
  const double margin = params.tuning().alternatives.confidence_margin;
  const Eigen::Isometry3f pose(c.icf.object_pose);
  c.alternatives.clear();
  for (PoseAlternative alt : others)
    if (alt.verification.confidence >= c.verification.confidence - margin) {
      describeTurn(pose, alt);
      c.alternatives.push_back(alt);
    }
}

/** Why a judged cluster is not accepted ("" when it is). */
std::string rejection(const ClusterLocalization& c, const LocalizerParams& params) {
  std::string reason;
  if (c.verification.confidence < params.min_confidence)
    reason = describeRefusal(c.verification, params.min_confidence, params.verificationParams());
  if (!c.gate_passed) {
    std::ostringstream gate;
    gate << (reason.empty() ? "" : " ") << "thesis gate (" << c.gate_far_points << " points beyond "
         << params.tuning().icf.acceptance.gate.distance << ")";
    reason += gate.str();
  }
  return reason;
}

/** A hypothesis at \a start (model -> camera) judged on the points \a indices near it: refined
 * from there with exact faces on a strided subset, verified against \a image, its turns tried
 * and refined once more when it is promising, then accepted or refused with the reason. */
ClusterLocalization judgeHypothesis(const SceneView& view, const DepthImage& image,
                                    const pcl::PointIndices& indices, const IcfModel& model,
                                    const LocalizerParams& params, int icf_threads,
                                    const std::optional<ColourHistogram>& expected,
                                    bool single_object, const PrincipalAxes* axes,
                                    const Eigen::Isometry3f& start) {
  ClusterLocalization c;
  c.indices = indices;
  c.single_object = single_object;

  const std::vector<Eigen::Vector3f> points = usablePoints(view, indices);
  IcfParams icf = params.icfParams();
  icf.threads = icf_threads;
  // The gate is applied below, to the points the posed model claims (a merged cluster's other
  // objects are not its far points), not by estimatePose to the whole crop.
  icf.acceptance.gate.enabled = false;
  // A hypothesis is refined from its pose (scene -> model), on a strided subset of the points
  // near it.
  const SceneHypotheses& hp = params.tuning().hypotheses;
  icf.tuning().refinement = hypothesisRefinement(icf.tuning().refinement, hp, hp.refine_points);
  PoseEstimateOptions options;
  options.guess = start.inverse(Eigen::Isometry);
  // A start worth refining never needs more than an accepted pose.
  const double refine_at = std::min(params.tuning().refine_min_confidence, params.min_confidence);
  const DepthVerificationParams rough = params.verificationParams().forRoughPoses();
  if (refine_at > 0.0)
    options.worth_refining = [&, refine_at](const Eigen::Isometry3f& scene_to_model) {
      return explainDepth(model, scene_to_model.inverse(Eigen::Isometry), image, rough)
                 .confidence >= refine_at;
    };
  c.icf = estimatePose(model, points, kCameraAtOrigin, icf, options);
  if (c.icf.status == IcfStatus::TooFewPoints) {
    c.reason = "too few points (" + std::to_string(c.icf.points) + ")";
    return c;
  }
  c.verification =
      explainDepth(model, Eigen::Isometry3f(c.icf.object_pose), image, params.verificationParams());
  c.explained = explainedPoints(view, indices, model, Eigen::Isometry3f(c.icf.scene_to_model),
                                params.verificationParams());
  if (expected && !view.colours.empty()) {
    ColourHistogram h(params.colour.bins);
    for (const auto i : indices.indices)
      h.add(view.colours[static_cast<std::size_t>(i)]);
    c.colour_similarity = h.intersection(*expected);
  }
  c.score = c.verification.confidence * colourFactor(c, params);
  // A promising pose is checked against its turns before it is judged (the search may have
  // landed on a near-symmetric flip that explains the depth a little worse), then refined on
  // more of its crop.
  if (isPromising(c, params)) {
    const std::vector<PoseAlternative> others =
        axes ? resolveTurns(c, points, view, image, model, *axes, params)
             : std::vector<PoseAlternative>{};
    refineOnTheCrop(c, points, view, image, model, params, icf_threads);
    recordAlternatives(c, others, params);
  }
  const FarPointGate& gate = params.tuning().icf.acceptance.gate;
  if (gate.enabled) {
    const Eigen::Isometry3f model_to_camera(c.icf.object_pose);
    c.gate_far_points = gateFarPoints(points, model, model_to_camera.inverse(),
                                      renderModelDepth(model, model_to_camera, image.intrinsics()),
                                      image, gate, single_object);
    c.gate_passed = c.gate_far_points <= gate.allowed(points.size());
  }
  c.reason = rejection(c, params);
  c.accepted = c.reason.empty();
  return c;
}

}  // namespace

std::vector<ClusterLocalization> judgeHypotheses(const SceneView& view, const DepthImage& image,
                                                 const IcfModel& model,
                                                 const LocalizerParams& params,
                                                 const std::vector<RankedHypothesis>& ranked,
                                                 int threads) {
  std::optional<ColourHistogram> expected;
  if (params.colour.expected)
    expected = ColourHistogram::ofColour(*params.colour.expected, params.colour.bins);
  std::optional<PrincipalAxes> axes;
  if (params.check_turns)
    axes = principalAxes(model);
  std::vector<ClusterLocalization> judged(ranked.size());
  const int n = static_cast<int>(ranked.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (n > 1)
  for (int k = 0; k < n; ++k) {
    const RankedHypothesis& h = ranked[static_cast<std::size_t>(k)];
    ClusterLocalization& c = judged[static_cast<std::size_t>(k)];
    c = judgeHypothesis(view, image, h.near, model, params, n == 1 ? threads : 1, expected, true,
                        axes ? &*axes : nullptr, h.model_to_camera);
    c.source_cluster = h.source.cluster;
    c.prescore = h.prescore;
  }
  return judged;
}

}  // namespace pcl::icf::localization::detail
