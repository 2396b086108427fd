/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/global_search.h>
#include <pcl/icf/localization/colour_histogram.h>
#include <pcl/icf/pose_verification.h>
#include <pcl/icf/usable_point.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/parameter_check.h>

#include "impl/object_localizer.hpp"
#include "scene_hypotheses.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace localization {

std::string toString(LocalizationStatus status) {
  switch (status) {
    case LocalizationStatus::Found:
      return "Found";
    case LocalizationStatus::NotFound:
      return "NotFound";
    case LocalizationStatus::NoClusters:
      return "NoClusters";
    case LocalizationStatus::BadScene:
      return "BadScene";
  }
  return "Unknown";
}

void ColourCue::validate() const {
  const internal::ParameterCheck fail("localization::ColourCue");
  if (expected &&
      !(expected->allFinite() && expected->minCoeff() >= 0.f && expected->maxCoeff() <= 1.f))
    fail("expected", expected->transpose(), "must be an RGB colour in [0, 1]");
  if (!(weight >= 0.0) || !std::isfinite(weight))
    fail("weight", weight, "must be finite and >= 0");
  if (bins < 2 || bins > 360)
    fail("bins", bins, "must lie in [2, 360]");
}

void LocalizerParams::useExactMeshSettings() {
  const DepthVerificationParams exact = DepthVerificationParams::forExactMesh();
  verification.fit_residual = exact.fit_residual;
  verification.max_residual = exact.max_residual;
  icf.global.keep = kExactMeshKeep;
}

void LocalizerParams::validate() const {
  const internal::ParameterCheck fail("localization::LocalizerParams");
  if (segment)
    segmentation.validate();
  icf.validate();
  colour.validate();
  verification.validate();
  tuning.validate();
  if (intrinsics)
    intrinsics->validate();
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0))
    fail("min_confidence", min_confidence, "must lie in [0, 1]");
  if (!(refine_min_confidence >= 0.0 && refine_min_confidence <= 1.0))
    fail("refine_min_confidence", refine_min_confidence, "must lie in [0, 1]");
  if (!(gate_distance > 0.f) || !std::isfinite(gate_distance))
    fail("gate_distance", gate_distance, "must be positive and finite");
  if (gate_max_far_points < 0)
    fail("gate_max_far_points", gate_max_far_points, "must be >= 0");
  if (!(gate_max_far_fraction >= 0.0 && gate_max_far_fraction <= 1.0))
    fail("gate_max_far_fraction", gate_max_far_fraction, "must lie in [0, 1]");
  if (threads < 0 || threads > 1024)
    fail("threads", threads, "must lie in [0, 1024] (0 = all cores)");
  if (!(min_points_in_front >= 0.0 && min_points_in_front <= 1.0))
    fail("min_points_in_front", min_points_in_front, "must lie in [0, 1]");
  if (max_instances < 1 || max_instances > 1000)
    fail("max_instances", max_instances, "must lie in [1, 1000]");
  if (!(max_shared_points >= 0.0 && max_shared_points < 1.0))
    fail("max_shared_points", max_shared_points, "must lie in [0, 1)");
  if (!(whole_segment_share > 0.0 && whole_segment_share <= 1.0))
    fail("whole_segment_share", whole_segment_share, "must lie in (0, 1]");
  alternatives.validate();
  if (camera_pose)
    validateRigidTransform(camera_pose->matrix().cast<double>(),
                           "[pcl::icf::localization::LocalizerParams::validate] camera_pose");
}

namespace {

/** How many points the sorted index lists \a a and \a b have in common. */
std::size_t sharedPoints(const std::vector<pcl::index_t>& a, const std::vector<pcl::index_t>& b) {
  std::size_t shared = 0;
  for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();)
    if (*i < *j)
      ++i;
    else if (*j < *i)
      ++j;
    else {
      ++shared;
      ++i;
      ++j;
    }
  return shared;
}

std::vector<pcl::index_t> sortedIndices(pcl::Indices s) {
  std::sort(s.begin(), s.end());
  return s;
}

/** An accepted hypothesis: objects[object].clusters[index]. */
struct Claimant {
  int object = 0;
  int index = 0;
  double score = 0.0;
};

/** The greedy choice of rankInstances and selectInstances: \a claimants by score (ties: the
 * lower object, then the lower index), each kept unless more than \a max_shared of its
 * \a explained points are claimed by a kept one, or its object has \a caps of them already.
 * \a lost(claimant, winner object, winner's rank in its object) is told of a claimant whose
 * points another object's instance holds. */
template <typename Explained, typename Lost>
std::vector<std::vector<int>> chooseInstances(std::vector<Claimant> claimants,
                                              const std::vector<int>& caps, double max_shared,
                                              Explained explained, Lost lost) {
  std::stable_sort(claimants.begin(), claimants.end(), [](const Claimant& a, const Claimant& b) {
    if (a.score != b.score)
      return a.score > b.score;
    return a.object != b.object ? a.object < b.object : a.index < b.index;
  });
  std::vector<std::vector<int>> kept(caps.size());
  struct Claim {
    std::vector<pcl::index_t> points;
    int object, rank;
  };
  std::vector<Claim> claims;
  for (const Claimant& c : claimants) {
    auto& mine = kept[static_cast<std::size_t>(c.object)];
    if (static_cast<int>(mine.size()) >= caps[static_cast<std::size_t>(c.object)])
      continue;
    std::vector<pcl::index_t> points = sortedIndices(explained(c));
    // Each scene point explains one instance: a pose that explains the points of a better one
    // is the same object found again (in a merged cluster and in its convexity segment) or,
    // for another model, a worse explanation of that object.
    const double limit = max_shared * static_cast<double>(points.size());
    const auto holder = std::find_if(claims.begin(), claims.end(), [&](const Claim& other) {
      return static_cast<double>(sharedPoints(points, other.points)) > limit;
    });
    if (holder != claims.end()) {
      if (holder->object != c.object)
        lost(c, holder->object, holder->rank);
      continue;
    }
    claims.push_back({std::move(points), c.object, static_cast<int>(mine.size())});
    mine.push_back(c.index);
  }
  return kept;
}

}  // namespace

std::vector<int> rankInstances(const std::vector<ClusterLocalization>& clusters, int max_instances,
                               double max_shared) {
  std::vector<Claimant> claimants;
  for (std::size_t k = 0; k < clusters.size(); ++k)
    if (clusters[k].accepted)
      claimants.push_back({0, static_cast<int>(k), clusters[k].score});
  const auto explained = [&](const Claimant& c) {
    return clusters[static_cast<std::size_t>(c.index)].explained;
  };
  return chooseInstances(std::move(claimants), {max_instances}, max_shared, explained,
                         [](const Claimant&, int, int) {})
      .front();
}

std::vector<std::vector<int>> selectInstances(std::vector<Localization>& objects,
                                              const std::vector<int>& max_instances,
                                              const std::vector<std::string>& names,
                                              double max_shared) {
  if (max_instances.size() != objects.size() || names.size() != objects.size())
    throw std::invalid_argument(
        "[pcl::icf::localization::selectInstances] one instance count and one name per object");
  std::vector<Claimant> claimants;
  for (std::size_t o = 0; o < objects.size(); ++o)
    for (std::size_t k = 0; k < objects[o].clusters.size(); ++k)
      if (objects[o].clusters[k].accepted)
        claimants.push_back(
            {static_cast<int>(o), static_cast<int>(k), objects[o].clusters[k].score});
  const auto cluster = [&](const Claimant& c) -> ClusterLocalization& {
    return objects[static_cast<std::size_t>(c.object)].clusters[static_cast<std::size_t>(c.index)];
  };
  const auto explained = [&](const Claimant& c) { return cluster(c).explained; };
  const auto lost = [&](const Claimant& c, int winner, int rank) {
    ClusterLocalization& loser = cluster(c);
    loser.accepted = false;
    loser.reason = "explained better by " + names[static_cast<std::size_t>(winner)] + " instance " +
                   std::to_string(rank);
  };
  return chooseInstances(std::move(claimants), max_instances, max_shared, explained, lost);
}

namespace detail {

double shareInFront(const std::vector<Eigen::Vector3f>& points) {
  std::size_t finite = 0, in_front = 0;
  for (const auto& p : points)
    if (isUsablePoint(p)) {
      ++finite;
      in_front += p.z() > 0.f ? 1 : 0;
    }
  return finite > 0 ? static_cast<double>(in_front) / static_cast<double>(finite) : 1.0;
}

void validateQueries(const std::vector<ObjectQuery>& objects, const LocalizerParams& params) {
  const std::string where = "[pcl::icf::localization::localizeObjects] ";
  if (objects.empty())
    throw std::invalid_argument(where + "no object to find");
  for (std::size_t k = 0; k < objects.size(); ++k) {
    if (!objects[k].model)
      throw std::invalid_argument(where + "object " + std::to_string(k) + " has no model");
    if (objects[k].max_instances < 1)
      throw std::invalid_argument(where + "object " + std::to_string(k) +
                                  ": max_instances must be at least 1");
  }
  if (objects.size() > 1 && params.colour.expected)
    throw std::invalid_argument(where +
                                "the colour cue describes one object: unset colour.expected "
                                "when several are asked for");
}

void toSceneFrame(Localization& loc, const Eigen::Isometry3f& camera_to_scene) {
  const Eigen::Matrix4f to_scene = camera_to_scene.matrix();
  const Eigen::Matrix4f to_camera = camera_to_scene.inverse(Eigen::Isometry).matrix();
  for (auto& c : loc.clusters) {
    c.icf.object_pose = to_scene * c.icf.object_pose;
    c.icf.scene_to_model = c.icf.scene_to_model * to_camera;
    for (auto& alt : c.alternatives)
      alt.object_pose = camera_to_scene * alt.object_pose;
  }
  // A plane n.x + d = 0 in the camera's frame is (R n).y + d - (R n).t = 0 in the scene's.
  auto& plane = loc.segmentation.plane.coefficients;
  if (!plane.isZero(0.f)) {
    const Eigen::Vector3f n = camera_to_scene.linear() * plane.head<3>();
    plane = Eigen::Vector4f(n.x(), n.y(), n.z(), plane[3] - n.dot(camera_to_scene.translation()));
  }
  loc.camera_pose = camera_to_scene;
}

namespace {

/** The localizer works in the camera's frame (localizeObject moves the scene there). */
const Eigen::Vector3f kCameraAtOrigin = Eigen::Vector3f::Zero();

/** The thesis's gate on one cluster: points farther than gate_distance from the posed model.
 * A cluster of one object is counted whole; in a merged cluster only the points the model
 * claims: on its rendered silhouette and not in front of its surface. */
int gateFarPoints(const std::vector<Eigen::Vector3f>& points, const IcfModel& model,
                  const Eigen::Isometry3f& scene_to_model, const ModelDepth& rendered,
                  const DepthImage& image, const LocalizerParams& params, bool single_object) {
  int far = 0;
  for (const auto& x : points) {
    if (!single_object) {
      int u = 0, v = 0;
      if (!image.pixelOf(x, u, v) || !rendered.covers(u, v) ||
          x.z() < rendered.depth[static_cast<std::size_t>(v) * rendered.width + u] -
                      params.gate_distance)
        continue;
    }
    if (model.index().closestFace(scene_to_model * x, params.gate_distance).distance >
        params.gate_distance)
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

/** True when \a judged's pose is worth more work (its turns, a refit of its cluster's rest):
 * accepted, or at least half the confidence an acceptance needs. */
bool isPromising(const ClusterLocalization& judged, const LocalizerParams& params) {
  return judged.accepted || judged.verification.confidence >= 0.5 * params.min_confidence;
}

/** The points of \a cluster not in \a explained, sorted. */
pcl::PointIndices unexplainedPoints(const pcl::PointIndices& cluster,
                                    const pcl::Indices& explained) {
  const pcl::Indices all = sortedIndices(cluster.indices), some = sortedIndices(explained);
  pcl::PointIndices rest;
  std::set_difference(all.begin(), all.end(), some.begin(), some.end(),
                      std::back_inserter(rest.indices));
  return rest;
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

/** A pose against its turns about the model's principal axes (turnedAlternatives): a turn
 * that explains the depth clearly better (by more than the margin) replaces it; the others as
 * good (within the margin) are recorded as its alternatives. */
void resolveTurns(ClusterLocalization& c, const SceneView& view, const DepthImage& image,
                  const IcfModel& model, const PrincipalAxes& axes, const LocalizerParams& params) {
  const std::vector<Eigen::Vector3f> points = usablePoints(view, c.indices);
  PoseAlternativeParams ap = params.alternatives;
  ap.refinement = params.icf.refinement;
  ap.verification = params.verification;
  const Eigen::Isometry3f found(c.icf.object_pose);
  std::vector<PoseAlternative> candidates =
      turnedAlternatives(model, axes, points, found, c.verification, image, ap);
  if (candidates.empty())
    return;
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
  const PoseAlternative winner = candidates[chosen];
  if (chosen != 0) {
    const double colour_factor =
        c.verification.confidence > 0.0 ? c.score / c.verification.confidence : 1.0;
    const Eigen::Isometry3f scene_to_model = winner.object_pose.inverse();
    c.icf.object_pose = winner.object_pose.matrix();
    c.icf.scene_to_model = scene_to_model.matrix();
    c.icf.quality = measurePoseQuality(model, points, scene_to_model, kCameraAtOrigin,
                                       params.icf.acceptance.inlier_distance,
                                       params.icf.acceptance.gate_distance, params.icf.objective,
                                       params.icf.acceptance.visibility);
    c.verification = winner.verification;
    c.score = c.verification.confidence * colour_factor;
    c.explained = explainedPoints(view, c.indices, model, scene_to_model, params.verification);
    c.turned = true;
  }
  c.alternatives.clear();
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (k != chosen && candidates[k].verification.confidence >=
                           winner.verification.confidence - ap.confidence_margin) {
      PoseAlternative alt = candidates[k];
      describeTurn(winner.object_pose, alt);
      c.alternatives.push_back(alt);
    }
}

/** Why a judged cluster is not accepted ("" when it is). */
std::string rejection(const ClusterLocalization& c, const LocalizerParams& params) {
  std::ostringstream why;
  const DepthExplanation& e = c.verification;
  if (c.verification.confidence < params.min_confidence) {
    why << "confidence " << e.confidence << " < " << params.min_confidence << ": explains "
        << std::lround(100.0 * e.visible_support) << "% of the visible model, "
        << std::lround(100.0 * e.seen_through) << "% seen through, "
        << std::lround(100.0 * e.below_support) << "% beneath the table, "
        << std::lround(100.0 * e.silhouette_continuation) << "% of its silhouette continues, "
        << std::lround(100.0 * e.supported) << "% of it supported ";
    if (e.out_of_view > 0.0)
      why << "(" << std::lround(100.0 * e.out_of_view) << "% beyond the image's border) ";
    // The fit, when it is one of the factors (a scanned mesh under exact-mesh limits is refused
    // by it alone).
    if (const std::string fit = describeFit(e, params.verification); !fit.empty())
      why << "and " << fit << " ";
  }
  if (!c.gate_passed)
    why << "thesis gate (" << c.gate_far_points << " points beyond " << params.gate_distance
        << ") ";
  std::string reason = why.str();
  if (!reason.empty())
    reason.pop_back();
  return reason;
}

ClusterLocalization judgeCluster(const SceneView& view, const DepthImage& image,
                                 const pcl::PointIndices& indices, const IcfModel& model,
                                 const LocalizerParams& params, int icf_threads,
                                 const std::optional<ColourHistogram>& expected, bool single_object,
                                 const PrincipalAxes* axes, const Eigen::Isometry3f* start) {
  ClusterLocalization c;
  c.indices = indices;
  c.single_object = single_object;

  const std::vector<Eigen::Vector3f> points = usablePoints(view, indices);
  IcfParams icf = params.icf;
  icf.threads = icf_threads;
  // A hypothesis is refined from its pose, on a strided subset of the points near it.
  if (start) {
    const SceneHypotheses& hp = params.tuning.hypotheses;
    icf.refinement.max_points = hp.refine_points;
    icf.refinement.initial_inlier_distance =
        std::max(icf.refinement.final_inlier_distance, hp.fine_start_radius);
    icf.refinement.max_iterations = std::min(icf.refinement.max_iterations, hp.fine_iterations);
  }
  const Eigen::Isometry3f guess =
      start ? start->inverse(Eigen::Isometry) : Eigen::Isometry3f::Identity();
  StartCheck worth_refining;
  // A start worth refining never needs more than an accepted pose.
  const double refine_at = std::min(params.refine_min_confidence, params.min_confidence);
  if (refine_at > 0.0)
    worth_refining = [&, refine_at](const Eigen::Isometry3f& scene_to_model) {
      return explainDepth(model, scene_to_model.inverse(Eigen::Isometry), image,
                          params.verification)
                 .confidence >= refine_at;
    };
  c.icf = estimatePose(model, points, kCameraAtOrigin, icf, start ? &guess : nullptr, {},
                       worth_refining);
  if (c.icf.status == IcfStatus::TooFewPoints) {
    c.reason = "too few points (" + std::to_string(c.icf.points) + ")";
    return c;
  }
  const Eigen::Isometry3f model_to_camera(c.icf.object_pose);
  const ModelDepth rendered = renderModelDepth(model, model_to_camera, image.intrinsics());
  c.verification = explainDepth(rendered, image, 2.f * model.radius(), params.verification);
  c.explained = explainedPoints(view, indices, model, Eigen::Isometry3f(c.icf.scene_to_model),
                                params.verification);
  if (params.far_point_gate) {
    c.gate_far_points = gateFarPoints(points, model, Eigen::Isometry3f(c.icf.scene_to_model),
                                      rendered, image, params, single_object);
    const double allowed =
        std::max<double>(params.gate_max_far_points, params.gate_max_far_fraction * points.size());
    c.gate_passed = c.gate_far_points <= allowed;
  }
  double colour_factor = 1.0;
  if (expected && !view.colours.empty()) {
    ColourHistogram h(params.colour.bins);
    for (const auto i : indices.indices)
      h.add(view.colours[static_cast<std::size_t>(i)]);
    c.colour_similarity = h.intersection(*expected);
    colour_factor = std::pow(std::max(1e-3, *c.colour_similarity), params.colour.weight);
  }
  c.score = c.verification.confidence * colour_factor;
  // A promising pose is checked against its turns before it is judged: the search may have
  // landed on a near-symmetric flip that explains the depth a little worse.
  if (axes && isPromising(c, params))
    resolveTurns(c, view, image, model, *axes, params);
  c.reason = rejection(c, params);
  c.accepted = c.reason.empty();
  return c;
}

/** The scene as a depth image in the camera's frame: an organized cloud's own pixel grid when
 * its points fit a pinhole (0.5 pixel), else the points projected through the given
 * intrinsics or a virtual camera (DepthImage::sceneCamera). The table's pixels are background. */
DepthImage sceneDepthImage(const SceneView& view, const pcl::Indices& table,
                           const LocalizerParams& params) {
  DepthImage image(view.points, DepthImage::sceneCamera(view.points, view.width, view.height,
                                                        params.intrinsics));
  image.markBackground(view.points, table);
  image.markExplained(view.points, params.explained_indices);
  if (!view.colours.empty())
    image.setColours(view.points, view.colours);
  return image;
}

/** Points at object heights (above_table.min_height to max_height) on the table's far side
 * from the camera and over the table (inside its inliers' extent on the plane, shrunk by a
 * tenth): an opaque table top hides them from a camera above it, so many of them, and nothing
 * on the camera's side, is a camera placed below the table. */
std::size_t pointsBeyondTheTable(const SceneView& view,
                                 const segmentation::TabletopSegmentation& segmentation,
                                 const LocalizerParams& params) {
  const Eigen::Vector4f& plane = segmentation.plane.coefficients;
  const Eigen::Vector3f n = plane.head<3>();
  if (n.isZero(0.f) || segmentation.plane.inliers.empty())
    return 0;
  const Eigen::Vector3f e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  Eigen::Vector2f lo = Eigen::Vector2f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const auto i : segmentation.plane.inliers) {
    const Eigen::Vector3f& p = view.points[static_cast<std::size_t>(i)];
    const Eigen::Vector2f q(e1.dot(p), e2.dot(p));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector2f margin = 0.1f * (hi - lo);
  lo += margin;
  hi -= margin;
  const auto& heights = params.segmentation.above_table;
  std::size_t beyond = 0;
  for (const auto& p : view.points) {
    if (!isUsablePoint(p))
      continue;
    const double depth = -(n.dot(p) + plane[3]);
    const Eigen::Vector2f q(e1.dot(p), e2.dot(p));
    beyond += depth > heights.min_height && depth < heights.max_height &&
              (q.array() >= lo.array()).all() && (q.array() <= hi.array()).all();
  }
  return beyond;
}

/** The global search's merged-cluster test (spreadsWiderThanModel) on one cluster; clusters
 * of fewer than 10 points count as single. */
bool clusterLooksMerged(const SceneView& view, const pcl::PointIndices& cluster,
                        const IcfModel& model, const LocalizerParams& params) {
  if (cluster.indices.size() < 10)
    return false;
  std::vector<Eigen::Vector3f> points;
  points.reserve(cluster.indices.size());
  for (const auto i : cluster.indices)
    points.push_back(view.points[static_cast<std::size_t>(i)]);
  return spreadsWiderThanModel(points, model.radius(), params.icf.global);
}

/** "no hypothesis passed the acceptance rules; the best, hypothesis 3 (confidence 0.42): why". */
std::string notFoundMessage(const std::vector<ClusterLocalization>& clusters) {
  const ClusterLocalization* top = nullptr;
  std::size_t index = 0;
  for (std::size_t k = 0; k < clusters.size(); ++k)
    if (!clusters[k].reason.empty() && (!top || clusters[k].score > top->score)) {
      top = &clusters[k];
      index = k;
    }
  std::string text = "no hypothesis passed the acceptance rules";
  if (!top)
    return text;
  char confidence[32];
  std::snprintf(confidence, sizeof(confidence), "%.2f", top->verification.confidence);
  return text + "; the best, hypothesis " + std::to_string(index) + " (confidence " + confidence +
         "): " + top->reason;
}

pcl::PointCloud<pcl::PointXYZRGBA> colouredCloud(const SceneView& view) {
  pcl::PointCloud<pcl::PointXYZRGBA> cloud;
  cloud.resize(view.points.size());
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    cloud[i].getVector3fMap() = view.points[i];
    if (!view.colours.empty()) {
      const Eigen::Vector3f c = 255.f * view.colours[i];
      cloud[i].r = static_cast<std::uint8_t>(c.x());
      cloud[i].g = static_cast<std::uint8_t>(c.y());
      cloud[i].b = static_cast<std::uint8_t>(c.z());
    }
  }
  return cloud;
}

/** Takes the points another pose has explained (LocalizerParams::explained_indices, each an
 * index of \a view) out of every cluster; a cluster left with fewer than \a min_size points
 * is dropped. A target touching an explained neighbour is then searched on its own points,
 * not on both objects'. \throws std::invalid_argument for an index outside the scene. */
void withoutExplainedPoints(std::vector<pcl::PointIndices>& clusters, const SceneView& view,
                            const pcl::Indices& explained, std::size_t min_size) {
  for (const int i : explained)
    if (i < 0 || static_cast<std::size_t>(i) >= view.points.size())
      throw std::invalid_argument(
          "[pcl::icf::localization::localizeObject] LocalizerParams::explained_indices: index " +
          std::to_string(i) + " is outside the scene's " + std::to_string(view.points.size()) +
          " points");
  if (explained.empty())
    return;
  std::vector<pcl::PointIndices> kept;
  for (const auto& cluster : clusters) {
    pcl::PointIndices rest = unexplainedPoints(cluster, explained);
    if (rest.indices.size() >= min_size)
      kept.push_back(std::move(rest));
  }
  clusters = std::move(kept);
}

/** localizeInView's outcome when the segmentation stopped (status not Ok): BadScene when the
 * data cannot be a table-top scene (empty, all NaN, too few points, millimetres) or when the
 * objects stand on the table's far side (a camera below the table), else NoClusters. */
Localization segmentationStopped(const SceneView& view,
                                 segmentation::TabletopSegmentation segmentation,
                                 const LocalizerParams& params, double segmentation_ms) {
  Localization out;
  out.segmentation_ms = segmentation_ms;
  const segmentation::TabletopStatus status = segmentation.status;
  const bool bad = status == segmentation::TabletopStatus::EmptyCloud ||
                   status == segmentation::TabletopStatus::NoFinitePoints ||
                   status == segmentation::TabletopStatus::TooFewPoints ||
                   status == segmentation::TabletopStatus::SceneUnitsSuspect;
  out.status = bad ? LocalizationStatus::BadScene : LocalizationStatus::NoClusters;
  out.message =
      toString(status) + (segmentation.message.empty() ? "" : ": " + segmentation.message);
  if (status == segmentation::TabletopStatus::NoCluster) {
    const std::size_t beyond = pointsBeyondTheTable(view, segmentation, params);
    if (beyond >= params.segmentation.cluster.min_size) {
      out.status = LocalizationStatus::BadScene;
      out.message =
          "the camera is on the wrong side of the table: nothing stands on its "
          "side, " +
          std::to_string(beyond) +
          " points stand on the other (check the camera pose: --camera, or the "
          "cloud's VIEWPOINT)";
    }
  }
  out.segmentation = std::move(segmentation);
  out.total_ms = segmentation_ms;
  return out;
}

/** The usable points of \a view as one cluster (LocalizerParams::segment false). */
pcl::PointIndices wholeCloud(const SceneView& view) {
  pcl::PointIndices all;
  for (std::size_t i = 0; i < view.points.size(); ++i)
    if (isUsablePoint(view.points[i]))
      all.indices.push_back(static_cast<pcl::index_t>(i));
  return all;
}

/** What the clusters' searches run on: the clusters that look like one object, and the
 * convexity segments of those that spread wider than the model (touching objects merge into one
 * Euclidean cluster; LocalizerParams::split_merged), which are not searched whole: the votes
 * hypothesise what they hold. */
std::vector<pcl::PointIndices> searchedClusters(const SceneView& view,
                                                const std::vector<pcl::PointIndices>& clusters,
                                                const IcfModel& model,
                                                const LocalizerParams& params) {
  std::vector<pcl::PointIndices> searched, segments;
  pcl::PointCloud<pcl::PointXYZRGBA> coloured;
  for (const auto& cluster : clusters) {
    if (!clusterLooksMerged(view, cluster, model, params)) {
      searched.push_back(cluster);
      continue;
    }
    if (!params.split_merged)
      continue;
    if (coloured.empty())
      coloured = colouredCloud(view);
    for (auto& segment : segmentation::splitByConvexity(coloured, cluster, params.split))
      if (segment.indices.size() < cluster.indices.size())
        segments.push_back(std::move(segment));
  }
  searched.insert(searched.end(), segments.begin(), segments.end());
  return searched;
}

/** Every ranked hypothesis judged (judgeCluster from its pose, on the points near it), in
 * parallel, each into its own slot. */
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
    c = judgeCluster(view, image, h.near, model, params, n == 1 ? threads : 1, expected, true,
                     axes ? &*axes : nullptr, &h.model_to_camera);
    c.source_cluster = h.source.cluster;
    c.prescore = h.prescore;
  }
  return judged;
}

std::size_t acceptedCount(const std::vector<ClusterLocalization>& clusters) {
  return static_cast<std::size_t>(std::count_if(
      clusters.begin(), clusters.end(), [](const ClusterLocalization& c) { return c.accepted; }));
}

/** Why a search gave no hypothesis at all: the model, the scene or the voting. */
std::string noHypothesisMessage(const IcfModel& model, std::size_t candidates,
                                std::size_t voting_points) {
  if (model.pointPairs().pairs() == 0 && candidates == 0)
    return "no hypothesis: the model is too small or flat for point pairs at its sampling step, "
           "and the clusters' search found no pose";
  const std::string voted = std::to_string(voting_points) + " scene points";
  if (voting_points < 2)
    return "no hypothesis: only " + voted + " with a surface normal to vote from";
  if (candidates == 0)
    return "no hypothesis: " + voted + " voted and no pose gathered their votes";
  return "no hypothesis: " + voted +
         " voted, and no pose explains the depth where they put the model";
}

/** One round: the hypotheses of every source on the points not yet \a explained, one ranking,
 * the best judged and appended to \a out.clusters (their times added to \a out's). Returns
 * noHypothesisMessage when nothing was judged, else "". */
std::string searchRound(const SceneView& view, const std::vector<pcl::PointIndices>& clusters,
                        const DepthImage& image, const IcfModel& model,
                        const LocalizerParams& params, const std::vector<int>& explained,
                        int threads, Localization& out) {
  const SceneHypotheses& hp = params.tuning.hypotheses;
  const std::vector<bool> usable = candidatePoints(view, out.segmentation, explained);
  using Clock = std::chrono::steady_clock;
  const auto msSince = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  auto stage = Clock::now();
  const PointPairScene scene = votingScene(view, usable, model, hp, threads);
  std::vector<Candidate> candidates;
  if (hp.point_pairs)
    candidates = votedCandidates(model, scene, hp, threads);
  // A model with no point pair worth voting with (a flat plate, a model smaller than a few
  // sampling steps) is searched for in the clusters.
  if (hp.clusters || model.pointPairs().pairs() == 0) {
    std::vector<pcl::PointIndices> rest = clusters;
    if (explained.size() > params.explained_indices.size())
      withoutExplainedPoints(rest, view, explained, params.segmentation.cluster.min_size);
    const std::vector<Candidate> searched =
        clusterCandidates(view, searchedClusters(view, rest, model, params), model,
                          params.icf.global, params.icf.seed, hp, threads);
    candidates.insert(candidates.end(), searched.begin(), searched.end());
  }
  out.hypotheses_ms += msSince(stage);
  stage = Clock::now();
  const std::size_t judged =
      std::max(hp.judged, 2 * static_cast<std::size_t>(params.max_instances));
  const std::vector<RankedHypothesis> ranked = rankCandidates(
      view, usable, model, image, params.verification, scene, candidates, hp, judged, threads);
  out.ranking_ms += msSince(stage);
  stage = Clock::now();
  std::vector<ClusterLocalization> found =
      judgeHypotheses(view, image, model, params, ranked, threads);
  out.clusters.insert(out.clusters.end(), std::make_move_iterator(found.begin()),
                      std::make_move_iterator(found.end()));
  out.judging_ms += msSince(stage);
  return ranked.empty() ? noHypothesisMessage(model, candidates.size(), scene.points.size()) : "";
}

/** The name refusals give object \a k of \a objects. */
std::string objectName(const std::vector<ObjectQuery>& objects, std::size_t k) {
  return objects[k].name.empty() ? "object " + std::to_string(k) : objects[k].name;
}

/** \a out's instances, best, status and message from its judged hypotheses and \a kept. */
void conclude(Localization& out, std::vector<int> kept, const std::string& no_hypothesis) {
  out.instances = std::move(kept);
  out.best = out.instances.empty() ? -1 : out.instances.front();
  out.status = out.best >= 0 ? LocalizationStatus::Found : LocalizationStatus::NotFound;
  if (out.best < 0)
    out.message = out.clusters.empty() ? no_hypothesis : notFoundMessage(out.clusters);
}

}  // namespace

ObjectsLocalization localizeObjectsInView(const SceneView& view,
                                          segmentation::TabletopSegmentation segmentation,
                                          const std::vector<ObjectQuery>& objects,
                                          const LocalizerParams& params, double segmentation_ms) {
  using Clock = std::chrono::steady_clock;
  const auto msSince = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  const auto start = Clock::now();
  const std::size_t n = objects.size();
  ObjectsLocalization all;
  const auto stopped = [&](Localization one) {
    all.status = one.status;
    all.message = one.message;
    all.objects.assign(n, one);
    all.segmentation = std::move(one.segmentation);
    all.scene_ms = all.total_ms = one.total_ms;
    return all;
  };
  if (params.segment && segmentation.status != segmentation::TabletopStatus::Ok)
    return stopped(segmentationStopped(view, std::move(segmentation), params, segmentation_ms));
  std::vector<pcl::PointIndices> clusters;
  if (params.segment) {
    clusters = segmentation.clusters;
  } else {
    clusters.push_back(wholeCloud(view));
    if (clusters.front().indices.empty()) {
      Localization bad;
      bad.status = LocalizationStatus::BadScene;
      bad.message = "the cloud has no finite point";
      bad.total_ms = segmentation_ms;
      return stopped(std::move(bad));
    }
  }
  withoutExplainedPoints(clusters, view, params.explained_indices,
                         params.segmentation.cluster.min_size);
  // What the camera saw, the table marked as background (an object standing on it would
  // otherwise seem to carry on into the table at its base).
  // (Without segmentation the plane has no inliers: nothing is background.)
  DepthImage image = sceneDepthImage(view, segmentation.plane.inliers, params);
  const int threads = params.threads > 0 ? params.threads : omp_get_num_procs();
  all.scene_ms = segmentation_ms + msSince(start);

  std::vector<LocalizerParams> own(n, params);
  std::vector<int> caps(n);
  std::vector<std::string> names(n);
  int rounds = 0;
  all.objects.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    own[k].max_instances = caps[k] = objects[k].max_instances;
    names[k] = objectName(objects, k);
    rounds = std::max(rounds, caps[k]);
    all.objects[k].segmentation = segmentation;
    all.objects[k].segmentation_ms = segmentation_ms;
  }
  // Rounds of hypotheses, ranking and judging for every object still searching; then one
  // selection over all objects' accepted poses. After a round that keeps new instances, the
  // points they explain are left out and the rest is searched again; an object stops when it
  // has its instances or its round accepts nothing new.
  std::vector<int> explained = params.explained_indices;
  std::vector<std::string> no_hypothesis(n);
  std::vector<bool> searching(n, true);
  std::vector<double> own_ms(n, 0.0);
  std::vector<std::vector<int>> kept(n);
  for (int round = 0; round < rounds; ++round) {
    std::vector<bool> accepted_new(n, false);
    for (std::size_t k = 0; k < n; ++k) {
      if (!searching[k] || round >= caps[k])
        continue;
      const auto began = Clock::now();
      Localization& out = all.objects[k];
      const std::size_t accepted_before = acceptedCount(out.clusters);
      const std::string nothing =
          searchRound(view, clusters, image, *objects[k].model, own[k], explained, threads, out);
      if (round == 0)
        no_hypothesis[k] = nothing;
      accepted_new[k] = acceptedCount(out.clusters) > accepted_before;
      own_ms[k] += msSince(began);
    }
    const auto selection = Clock::now();
    std::vector<std::vector<int>> now =
        selectInstances(all.objects, caps, names, params.max_shared_points);
    bool more = false;
    for (std::size_t k = 0; k < n; ++k) {
      searching[k] = searching[k] && accepted_new[k] && static_cast<int>(now[k].size()) < caps[k];
      more = more || (searching[k] && round + 1 < caps[k]);
    }
    kept = std::move(now);
    all.selection_ms += msSince(selection);
    if (!more)
      break;
    for (std::size_t k = 0; k < n; ++k)
      for (const int h : kept[k])
        for (const auto i : all.objects[k].clusters[static_cast<std::size_t>(h)].explained)
          explained.push_back(static_cast<int>(i));
    std::sort(explained.begin(), explained.end());
    explained.erase(std::unique(explained.begin(), explained.end()), explained.end());
    image.markExplained(view.points, explained);
  }

  for (std::size_t k = 0; k < n; ++k) {
    Localization& out = all.objects[k];
    conclude(out, kept[k], no_hypothesis[k]);
    out.registration_ms = all.scene_ms - segmentation_ms + own_ms[k] + all.selection_ms;
    out.total_ms = out.segmentation_ms + out.registration_ms;
    for (const int h : out.instances)
      all.instances.push_back({static_cast<int>(k), h});
  }
  std::stable_sort(all.instances.begin(), all.instances.end(),
                   [&](const ObjectInstance& a, const ObjectInstance& b) {
                     const auto score = [&](const ObjectInstance& i) {
                       return all.objects[static_cast<std::size_t>(i.object)]
                           .clusters[static_cast<std::size_t>(i.hypothesis)]
                           .score;
                     };
                     return score(a) > score(b);
                   });
  all.status = all.instances.empty() ? LocalizationStatus::NotFound : LocalizationStatus::Found;
  all.segmentation = std::move(segmentation);
  all.total_ms = segmentation_ms + msSince(start);
  return all;
}

}  // namespace detail

template Eigen::Isometry3f cameraPoseOf<pcl::PointXYZ>(const pcl::PointCloud<pcl::PointXYZ>&,
                                                       const LocalizerParams&);
template Eigen::Isometry3f cameraPoseOf<pcl::PointXYZRGB>(const pcl::PointCloud<pcl::PointXYZRGB>&,
                                                          const LocalizerParams&);
template Eigen::Isometry3f cameraPoseOf<pcl::PointXYZRGBA>(
    const pcl::PointCloud<pcl::PointXYZRGBA>&, const LocalizerParams&);
template Localization localizeObject<pcl::PointXYZ>(const pcl::PointCloud<pcl::PointXYZ>&,
                                                    const IcfModel&, const LocalizerParams&);
template Localization localizeObject<pcl::PointXYZRGB>(const pcl::PointCloud<pcl::PointXYZRGB>&,
                                                       const IcfModel&, const LocalizerParams&);
template Localization localizeObject<pcl::PointXYZRGBA>(const pcl::PointCloud<pcl::PointXYZRGBA>&,
                                                        const IcfModel&, const LocalizerParams&);
template ObjectsLocalization localizeObjects<pcl::PointXYZ>(const pcl::PointCloud<pcl::PointXYZ>&,
                                                            const std::vector<ObjectQuery>&,
                                                            const LocalizerParams&);
template ObjectsLocalization localizeObjects<pcl::PointXYZRGB>(
    const pcl::PointCloud<pcl::PointXYZRGB>&, const std::vector<ObjectQuery>&,
    const LocalizerParams&);
template ObjectsLocalization localizeObjects<pcl::PointXYZRGBA>(
    const pcl::PointCloud<pcl::PointXYZRGBA>&, const std::vector<ObjectQuery>&,
    const LocalizerParams&);

}  // namespace localization
}  // namespace icf
}  // namespace pcl
