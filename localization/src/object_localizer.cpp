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

}  // namespace

std::vector<int> rankInstances(const std::vector<ClusterLocalization>& clusters, int max_instances,
                               double max_shared) {
  std::vector<int> order;
  for (std::size_t k = 0; k < clusters.size(); ++k)
    if (clusters[k].accepted)
      order.push_back(static_cast<int>(k));
  // By score, ties by index: deterministic.
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return clusters[static_cast<std::size_t>(a)].score >
           clusters[static_cast<std::size_t>(b)].score;
  });
  std::vector<int> instances;
  std::vector<std::vector<pcl::index_t>> claimed;
  for (int k : order) {
    if (static_cast<int>(instances.size()) >= max_instances)
      break;
    const std::vector<pcl::index_t> points =
        sortedIndices(clusters[static_cast<std::size_t>(k)].explained);
    // Each scene point explains one instance: a pose that explains the points of a better one
    // (found again in a merged cluster and in its convexity segment) is the same object.
    const double limit = max_shared * static_cast<double>(points.size());
    if (std::any_of(claimed.begin(), claimed.end(), [&](const auto& other) {
          return static_cast<double>(sharedPoints(points, other)) > limit;
        }))
      continue;
    instances.push_back(k);
    claimed.push_back(points);
  }
  return instances;
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

/** True when a judged cluster may hold another object besides its pose's: it was accepted, or
 * its pose leaves at least a third of its points unexplained (one of two touching copies,
 * pulled towards the other). */
bool holdsMore(const ClusterLocalization& judged, const pcl::PointIndices& cluster) {
  if (judged.verification.model_pixels == 0)
    return false;
  return judged.accepted || 3 * judged.explained.size() <= 2 * cluster.indices.size();
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
                                 const PrincipalAxes* axes) {
  ClusterLocalization c;
  c.indices = indices;
  c.single_object = single_object;
  const std::vector<Eigen::Vector3f> points = usablePoints(view, indices);
  IcfParams icf = params.icf;
  icf.threads = icf_threads;
  StartCheck worth_refining;
  // A start worth refining never needs more than an accepted pose.
  const double refine_at = std::min(params.refine_min_confidence, params.min_confidence);
  if (refine_at > 0.0)
    worth_refining = [&, refine_at](const Eigen::Isometry3f& scene_to_model) {
      return explainDepth(model, scene_to_model.inverse(Eigen::Isometry), image,
                          params.verification)
                 .confidence >= refine_at;
    };
  c.icf = estimatePose(model, points, kCameraAtOrigin, icf, nullptr, {}, worth_refining);
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

/** "no cluster passed the acceptance rules; the best, cluster 3 (confidence 0.42): why". */
std::string notFoundMessage(const std::vector<ClusterLocalization>& clusters) {
  const ClusterLocalization* top = nullptr;
  std::size_t index = 0;
  for (std::size_t k = 0; k < clusters.size(); ++k)
    if (!clusters[k].reason.empty() && (!top || clusters[k].score > top->score)) {
      top = &clusters[k];
      index = k;
    }
  std::string text = "no cluster passed the acceptance rules";
  if (!top)
    return text;
  char confidence[32];
  std::snprintf(confidence, sizeof(confidence), "%.2f", top->verification.confidence);
  return text + "; the best, cluster " + std::to_string(index) + " (confidence " + confidence +
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

/** The hypotheses of one scene and their judgement (judgeCluster, each into its own slot, in
 * parallel): the clusters, the convexity segments of merged ones, and the rests that poses
 * leave of their clusters. Hypothesis k's parent is parents_[k] (ClusterLocalization::parent). */
class HypothesisSearch {
 public:
  HypothesisSearch(const SceneView& view, const DepthImage& image, const IcfModel& model,
                   const LocalizerParams& params, std::vector<pcl::PointIndices> clusters)
      : view_(view), image_(image), model_(model), params_(params), clusters_(std::move(clusters)) {
    if (params.colour.expected)
      expected_ = ColourHistogram::ofColour(*params.colour.expected, params.colour.bins);
    parents_.assign(clusters_.size(), -1);
    single_.assign(clusters_.size(), true);
    for (std::size_t k = 0; k < clusters_.size(); ++k)
      single_[k] = !clusterLooksMerged(view, clusters_[k], model, params);
  }

  /** Merged clusters: their convexity segments become clusters of their own too. */
  void addConvexitySegments() {
    pcl::PointCloud<pcl::PointXYZRGBA> coloured;
    const std::size_t base = clusters_.size();
    for (std::size_t k = 0; k < base; ++k) {
      if (single_[k])
        continue;
      if (coloured.empty())
        coloured = colouredCloud(view_);
      for (auto& segment : segmentation::splitByConvexity(coloured, clusters_[k], params_.split))
        if (segment.indices.size() < clusters_[k].indices.size()) {
          clusters_.push_back(std::move(segment));
          parents_.push_back(static_cast<int>(k));
          single_.push_back(true);
        }
    }
  }

  /** Judges every hypothesis so far: compact clusters and convexity segments first; a merged
   * cluster whole only when none of its segments was accepted (searching 100k points of four
   * objects costs seconds). */
  void judgeSegmentsFirst() {
    if (params_.check_turns)
      axes_ = principalAxes(model_);
    threads_ = params_.threads > 0 ? params_.threads : omp_get_num_procs();
    judged_.resize(clusters_.size());
    std::vector<int> first, second;
    for (std::size_t k = 0; k < clusters_.size(); ++k) {
      const bool has_segments =
          std::find(parents_.begin(), parents_.end(), static_cast<int>(k)) != parents_.end();
      (has_segments ? second : first).push_back(static_cast<int>(k));
    }
    judge(first);
    std::vector<int> retry;
    for (int k : second) {
      bool segment_accepted = false, segment_whole = false;
      const double whole =
          params_.whole_segment_share *
          static_cast<double>(clusters_[static_cast<std::size_t>(k)].indices.size());
      for (std::size_t j = 0; j < clusters_.size(); ++j)
        if (parents_[j] == k) {
          segment_accepted = segment_accepted || judged_[j].accepted;
          segment_whole =
              segment_whole || static_cast<double>(clusters_[j].indices.size()) >= whole;
        }
      if (segment_accepted || segment_whole) {
        judged_[static_cast<std::size_t>(k)].indices = clusters_[static_cast<std::size_t>(k)];
        judged_[static_cast<std::size_t>(k)].reason =
            segment_accepted ? "not searched: a segment was accepted"
                             : "not searched: a segment holds nearly all of it";
      } else
        retry.push_back(k);
    }
    judge(retry);
  }

  /** More instances: what an accepted pose leaves of its cluster is searched again, as a
   * cluster of its own (two touching copies of the object share one Euclidean cluster); when
   * that finds one, the first is searched again without the second's points (its pose was
   * pulled by them). rankInstances keeps the better of a cluster and its refit. With one
   * instance asked for, one round when nothing was accepted: a pose pulled between two
   * touching objects is rejected, and each of them alone may be found. */
  void searchFurtherInstances() {
    expanded_.assign(clusters_.size(), false);
    const bool none_accepted = std::none_of(
        judged_.begin(), judged_.end(), [](const ClusterLocalization& c) { return c.accepted; });
    const int rounds = std::max(params_.max_instances, none_accepted ? 2 : 1);
    for (int round = 1; round < rounds; ++round)
      if (!searchRests())
        break;
  }

  /** The judged hypotheses, each with its parent. */
  std::vector<ClusterLocalization> results() {
    for (std::size_t k = 0; k < judged_.size(); ++k)
      judged_[k].parent = parents_[k];
    return std::move(judged_);
  }

 private:
  /** Judges the hypotheses \a which, one per thread (one alone gets every thread), the
   * largest first: a large cluster started last would leave the other threads idle at the end
   * (longest processing time first). Each is judged on one thread into its own slot, so the
   * order does not change a result. */
  void judge(std::vector<int> which) {
    std::stable_sort(which.begin(), which.end(), [&](int a, int b) {
      return clusters_[static_cast<std::size_t>(a)].indices.size() >
             clusters_[static_cast<std::size_t>(b)].indices.size();
    });
    const int m = static_cast<int>(which.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_) if (m > 1)
    for (int j = 0; j < m; ++j) {
      const auto k = static_cast<std::size_t>(which[static_cast<std::size_t>(j)]);
      judged_[k] = judgeCluster(view_, image_, clusters_[k], model_, params_, m == 1 ? threads_ : 1,
                                expected_, single_[k], axes_ ? &*axes_ : nullptr);
    }
  }

  /** Adds \a points as a hypothesis of its own (child of \a parent); -1 when too small. */
  int addCandidate(pcl::PointIndices points, std::size_t parent, bool expand) {
    if (points.indices.size() < params_.segmentation.cluster.min_size)
      return -1;
    clusters_.push_back(std::move(points));
    parents_.push_back(static_cast<int>(parent));
    single_.push_back(true);
    expanded_.push_back(expand);
    return static_cast<int>(clusters_.size()) - 1;
  }

  void judgeAdded(const std::vector<int>& added) {
    judged_.resize(clusters_.size());
    judge(added);
  }

  /** The points of \a from's parent that \a from's pose leaves unexplained, as a hypothesis. */
  int refitWithout(int from) {
    const auto parent = static_cast<std::size_t>(parents_[static_cast<std::size_t>(from)]);
    return addCandidate(
        unexplainedPoints(clusters_[parent], judged_[static_cast<std::size_t>(from)].explained),
        parent, true);
  }

  /** One round of searchFurtherInstances; false when no hypothesis holds more. */
  bool searchRests() {
    std::vector<int> rests;
    const std::size_t judged = clusters_.size();
    for (std::size_t k = 0; k < judged; ++k)
      if (!expanded_[k] && holdsMore(judged_[k], clusters_[k])) {
        expanded_[k] = true;
        const int r = addCandidate(unexplainedPoints(clusters_[k], judged_[k].explained), k, false);
        if (r >= 0)
          rests.push_back(r);
      }
    if (rests.empty())
      return false;
    judgeAdded(rests);
    // A promising rest is refit too, not only an accepted one: the merged pose took some of
    // its points, so its own pose may run into its neighbour. When its refit (the neighbour)
    // is accepted, the rest is searched once more without the neighbour's points.
    std::vector<int> refits, sources, again;
    for (int r : rests)
      if (isPromising(judged_[static_cast<std::size_t>(r)], params_))
        if (const int refit = refitWithout(r); refit >= 0) {
          refits.push_back(refit);
          sources.push_back(r);
        }
    judgeAdded(refits);
    for (std::size_t j = 0; j < refits.size(); ++j)
      if (judged_[static_cast<std::size_t>(refits[j])].accepted &&
          !judged_[static_cast<std::size_t>(sources[j])].accepted)
        if (const int rest_again = refitWithout(refits[j]); rest_again >= 0)
          again.push_back(rest_again);
    judgeAdded(again);
    return true;
  }

  const SceneView& view_;
  const DepthImage& image_;
  const IcfModel& model_;
  const LocalizerParams& params_;
  std::optional<ColourHistogram> expected_;
  std::optional<PrincipalAxes> axes_;
  int threads_ = 1;
  std::vector<pcl::PointIndices> clusters_;
  std::vector<int> parents_;
  std::vector<bool> single_, expanded_;
  std::vector<ClusterLocalization> judged_;
};

}  // namespace

Localization localizeInView(const SceneView& view, segmentation::TabletopSegmentation segmentation,
                            const IcfModel& model, const LocalizerParams& params,
                            double segmentation_ms) {
  const auto start = std::chrono::steady_clock::now();
  if (params.segment && segmentation.status != segmentation::TabletopStatus::Ok)
    return segmentationStopped(view, std::move(segmentation), params, segmentation_ms);
  Localization out;
  out.segmentation_ms = segmentation_ms;
  std::vector<pcl::PointIndices> clusters;
  if (params.segment) {
    clusters = segmentation.clusters;
  } else {
    clusters.push_back(wholeCloud(view));
    if (clusters.front().indices.empty()) {
      out.status = LocalizationStatus::BadScene;
      out.message = "the cloud has no finite point";
      return out;
    }
  }
  out.segmentation = std::move(segmentation);
  withoutExplainedPoints(clusters, view, params.explained_indices,
                         params.segmentation.cluster.min_size);

  // What the camera saw, the table marked as background (an object standing on it would
  // otherwise seem to carry on into the table at its base).
  // (Without segmentation the plane has no inliers: nothing is background.)
  const DepthImage image = sceneDepthImage(view, out.segmentation.plane.inliers, params);
  HypothesisSearch search(view, image, model, params, std::move(clusters));
  if (params.split_merged)
    search.addConvexitySegments();
  search.judgeSegmentsFirst();
  search.searchFurtherInstances();
  out.clusters = search.results();

  out.instances = rankInstances(out.clusters, params.max_instances, params.max_shared_points);
  out.best = out.instances.empty() ? -1 : out.instances.front();
  out.status = out.best >= 0 ? LocalizationStatus::Found : LocalizationStatus::NotFound;
  if (out.best < 0)
    out.message = notFoundMessage(out.clusters);
  out.registration_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  out.total_ms = out.segmentation_ms + out.registration_ms;
  return out;
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

}  // namespace localization
}  // namespace icf
}  // namespace pcl
