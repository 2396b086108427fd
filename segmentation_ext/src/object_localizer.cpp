/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/global_search.h>
#include <pcl/icf/segmentation/colour_histogram.h>
#include <pcl/icf/usable_point.h>
#include <pcl/point_types.h>
#include <pcl/icf/segmentation/impl/object_localizer.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace segmentation {

const char* toString(LocalizationStatus status) {
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
  if (expected &&
      !(expected->allFinite() && expected->minCoeff() >= 0.f && expected->maxCoeff() <= 1.f))
    throw std::invalid_argument("ColourCue::expected must be an RGB colour in [0, 1]");
  if (!(weight >= 0.0) || !std::isfinite(weight))
    throw std::invalid_argument("ColourCue::weight = " + std::to_string(weight) +
                                ": must be finite and >= 0");
  if (bins < 2 || bins > 360)
    throw std::invalid_argument("ColourCue::bins = " + std::to_string(bins) +
                                ": must lie in [2, 360]");
}

void LocalizerParams::validate() const {
  auto fail = [](const char* field, double value, const char* rule) {
    std::ostringstream msg;
    msg << "LocalizerParams::" << field << " = " << value << ": " << rule;
    throw std::invalid_argument(msg.str());
  };
  if (segment)
    segmentation.validate();
  icf.validate();
  colour.validate();
  verification.validate();
  if (intrinsics)
    intrinsics->validate();
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0))
    fail("min_confidence", min_confidence, "must lie in [0, 1]");
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
  if (camera_pose)
    validateCameraPose(*camera_pose, "LocalizerParams::camera_pose");
}

void validateCameraPose(const Eigen::Isometry3f& camera_to_scene, const std::string& what) {
  const Eigen::Matrix4f& m = camera_to_scene.matrix();
  if (!m.allFinite())
    throw std::invalid_argument(what + " has a NaN or infinite entry");
  const Eigen::Matrix3f r = m.topLeftCorner<3, 3>();
  const float orthonormality =
      (r.transpose() * r - Eigen::Matrix3f::Identity()).cwiseAbs().maxCoeff();
  if (!(orthonormality < 1e-4f) || !(r.determinant() > 0.f))
    throw std::invalid_argument(
        what + " is not a rotation and a translation (R^T R differs from I by " +
        std::to_string(orthonormality) + ", det " + std::to_string(r.determinant()) + ")");
  if (!(m.row(3) - Eigen::RowVector4f(0, 0, 0, 1)).isZero(0.f))
    throw std::invalid_argument(what + ": the bottom row must be 0 0 0 1");
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

/** Why a judged cluster is not accepted ("" when it is). */
std::string rejection(const ClusterLocalization& c, const LocalizerParams& params) {
  std::ostringstream why;
  const DepthExplanation& e = c.verification;
  if (c.verification.confidence < params.min_confidence)
    why << "confidence " << e.confidence << " < " << params.min_confidence << ": explains "
        << std::lround(100.0 * e.visible_support) << "% of the visible model, "
        << std::lround(100.0 * e.seen_through) << "% seen through, "
        << std::lround(100.0 * e.silhouette_continuation) << "% of its silhouette continues, "
        << std::lround(100.0 * e.supported) << "% of it supported ";
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
                                 const std::optional<ColourHistogram>& expected,
                                 bool single_object) {
  ClusterLocalization c;
  c.indices = indices;
  c.single_object = single_object;
  std::vector<Eigen::Vector3f> points;
  points.reserve(indices.indices.size());
  for (const auto i : indices.indices)
    if (isUsablePoint(view.points[static_cast<std::size_t>(i)]))
      points.push_back(view.points[static_cast<std::size_t>(i)]);
  IcfParams icf = params.icf;
  icf.threads = icf_threads;
  c.icf = estimatePose(model, points, kCameraAtOrigin, icf);
  if (c.icf.status == IcfStatus::TooFewPoints) {
    c.reason = "too few points (" + std::to_string(c.icf.points) + ")";
    return c;
  }
  const Eigen::Isometry3f model_to_camera(c.icf.object_pose);
  const ModelDepth rendered = renderModelDepth(model, model_to_camera, image.intrinsics());
  c.verification = explainDepth(rendered, image, 2.f * model.radius(), params.verification);
  if (params.thesis_gate) {
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
  c.reason = rejection(c, params);
  c.accepted = c.reason.empty();
  return c;
}

/** The scene as a depth image in the camera's frame: an organized cloud's own pixel grid when
 * its points fit a pinhole (0.5 pixel), else the points projected through the given
 * intrinsics or a virtual camera at their spacing. The table's pixels are background. */
DepthImage sceneDepthImage(const SceneView& view, const pcl::Indices& table,
                           const LocalizerParams& params) {
  PinholeIntrinsics k;
  double rms = std::numeric_limits<double>::infinity();
  if (params.intrinsics)
    k = *params.intrinsics;
  else if (view.width > 0)
    k = DepthImage::fitIntrinsics(view.points, view.width, view.height, rms);
  if (!params.intrinsics && !(rms < 0.5))
    k = DepthImage::virtualCamera(view.points, DepthImage::angularSpacing(view.points));
  DepthImage image(view.points, k);
  image.markBackground(view.points, table);
  return image;
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

}  // namespace

Localization localizeInView(const SceneView& view, TabletopSegmentation segmentation,
                            const IcfModel& model, const LocalizerParams& params,
                            double segmentation_ms) {
  const auto start = std::chrono::steady_clock::now();
  Localization out;
  out.segmentation_ms = segmentation_ms;
  std::vector<pcl::PointIndices> clusters;
  if (params.segment) {
    const TabletopStatus status = segmentation.status;
    if (status != TabletopStatus::Ok) {
      const bool bad =
          status == TabletopStatus::EmptyCloud || status == TabletopStatus::NoFinitePoints ||
          status == TabletopStatus::TooFewPoints || status == TabletopStatus::SceneUnitsSuspect;
      out.status = bad ? LocalizationStatus::BadScene : LocalizationStatus::NoClusters;
      out.message = std::string(toString(status)) +
                    (segmentation.message.empty() ? "" : ": " + segmentation.message);
      out.segmentation = std::move(segmentation);
      out.total_ms = segmentation_ms;
      return out;
    }
    clusters = segmentation.clusters;
  } else {
    pcl::PointIndices all;
    for (std::size_t i = 0; i < view.points.size(); ++i)
      if (isUsablePoint(view.points[i]))
        all.indices.push_back(static_cast<pcl::index_t>(i));
    if (all.indices.empty()) {
      out.status = LocalizationStatus::BadScene;
      out.message = "the cloud has no finite point";
      return out;
    }
    clusters.push_back(std::move(all));
  }
  out.segmentation = std::move(segmentation);

  // What the camera saw, the table marked as background (an object standing on it would
  // otherwise seem to carry on into the table at its base).
  // (Without segmentation the plane has no inliers: nothing is background.)
  const DepthImage image = sceneDepthImage(view, out.segmentation.plane.inliers, params);

  std::optional<ColourHistogram> expected;
  if (params.colour.expected)
    expected = ColourHistogram::ofColour(*params.colour.expected, params.colour.bins);

  // Merged clusters: their convexity segments become clusters of their own too.
  std::vector<int> parents(clusters.size(), -1);
  std::vector<bool> single(clusters.size(), true);
  for (std::size_t k = 0; k < clusters.size(); ++k)
    single[k] = !clusterLooksMerged(view, clusters[k], model, params);
  if (params.split_merged) {
    pcl::PointCloud<pcl::PointXYZRGBA> coloured;
    const std::size_t base = clusters.size();
    for (std::size_t k = 0; k < base; ++k) {
      if (single[k])
        continue;
      if (coloured.empty())
        coloured = colouredCloud(view);
      for (auto& segment : splitByConvexity(coloured, clusters[k], params.split))
        if (segment.indices.size() < clusters[k].indices.size()) {
          clusters.push_back(std::move(segment));
          parents.push_back(static_cast<int>(k));
          single.push_back(true);
        }
    }
  }

  const int threads = params.threads > 0 ? params.threads : omp_get_num_procs();
  out.clusters.resize(clusters.size());
  // Compact clusters and convexity segments first; a merged cluster whole only when none of
  // its segments was accepted (searching 100k points of four objects costs seconds).
  auto judge = [&](const std::vector<int>& which) {
    const int m = static_cast<int>(which.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (m > 1)
    for (int j = 0; j < m; ++j) {
      const auto k = static_cast<std::size_t>(which[static_cast<std::size_t>(j)]);
      out.clusters[k] = judgeCluster(view, image, clusters[k], model, params, m == 1 ? threads : 1,
                                     expected, single[k]);
    }
  };
  std::vector<int> first, second;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    const bool has_segments =
        std::find(parents.begin(), parents.end(), static_cast<int>(k)) != parents.end();
    (has_segments ? second : first).push_back(static_cast<int>(k));
  }
  judge(first);
  std::vector<int> retry;
  for (int k : second) {
    bool segment_accepted = false;
    for (std::size_t j = 0; j < clusters.size(); ++j)
      segment_accepted = segment_accepted || (parents[j] == k && out.clusters[j].accepted);
    if (segment_accepted) {
      out.clusters[static_cast<std::size_t>(k)].indices = clusters[static_cast<std::size_t>(k)];
      out.clusters[static_cast<std::size_t>(k)].reason = "not searched: a segment was accepted";
    } else
      retry.push_back(k);
  }
  judge(retry);
  for (std::size_t k = 0; k < out.clusters.size(); ++k)
    out.clusters[k].parent = parents[k];

  for (std::size_t k = 0; k < out.clusters.size(); ++k)
    if (out.clusters[k].accepted &&
        (out.best < 0 ||
         out.clusters[k].score > out.clusters[static_cast<std::size_t>(out.best)].score))
      out.best = static_cast<int>(k);
  out.status = out.best >= 0 ? LocalizationStatus::Found : LocalizationStatus::NotFound;
  if (out.best < 0)
    out.message = "no cluster passed the acceptance rules";
  out.registration_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  out.total_ms = out.segmentation_ms + out.registration_ms;
  return out;
}

}  // namespace detail

template Localization localizeObject<pcl::PointXYZ>(const pcl::PointCloud<pcl::PointXYZ>&,
                                                    const IcfModel&, const LocalizerParams&);
template Localization localizeObject<pcl::PointXYZRGB>(const pcl::PointCloud<pcl::PointXYZRGB>&,
                                                       const IcfModel&, const LocalizerParams&);
template Localization localizeObject<pcl::PointXYZRGBA>(const pcl::PointCloud<pcl::PointXYZRGBA>&,
                                                        const IcfModel&, const LocalizerParams&);

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl
