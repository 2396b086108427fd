/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/global_search.h>
#include <pcl/icf/segmentation/colour_histogram.h>
#include <pcl/icf/segmentation/view_grid.h>
#include <pcl/icf/usable_point.h>
#include <pcl/point_types.h>
#include <pcl/icf/segmentation/impl/object_localizer.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

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
  if (!(gate_distance > 0.f) || !std::isfinite(gate_distance))
    fail("gate_distance", gate_distance, "must be positive and finite");
  if (gate_max_far_points < 0)
    fail("gate_max_far_points", gate_max_far_points, "must be >= 0");
  if (!(min_single_object_inliers >= 0.0 && min_single_object_inliers <= 1.0))
    fail("min_single_object_inliers", min_single_object_inliers, "must lie in [0, 1]");
  if (!(gate_max_far_fraction >= 0.0 && gate_max_far_fraction <= 1.0))
    fail("gate_max_far_fraction", gate_max_far_fraction, "must lie in [0, 1]");
  if (!(free_space_tolerance > 0.f) || !std::isfinite(free_space_tolerance))
    fail("free_space_tolerance", free_space_tolerance, "must be positive and finite");
  if (!(max_free_space_violation >= 0.0 && max_free_space_violation <= 1.0))
    fail("max_free_space_violation", max_free_space_violation, "must lie in [0, 1]");
  if (!(boundary_tolerance > 0.f) || !std::isfinite(boundary_tolerance))
    fail("boundary_tolerance", boundary_tolerance, "must be positive and finite");
  if (!(max_boundary_continuation >= 0.0 && max_boundary_continuation <= 1.0))
    fail("max_boundary_continuation", max_boundary_continuation, "must lie in [0, 1]");
  if (!(view_bin_angle > 1e-5f && view_bin_angle < 0.2f))
    fail("view_bin_angle", view_bin_angle, "must lie in (1e-5, 0.2) radians");
  if (threads < 0 || threads > 1024)
    fail("threads", threads, "must lie in [0, 1024] (0 = all cores)");
}

namespace detail {
namespace {

/** The posed model as the camera sees it: bins of its visible samples with their depth,
 * closed morphologically so that sparse samples make a solid silhouette. */
struct Footprint {
  std::unordered_map<std::int64_t, float> depth;  // bin -> nearest model depth (sampled bins)
  std::unordered_set<std::int64_t> solid;         // sampled bins with their holes closed
};

Footprint modelFootprint(const IcfModel& model, const Eigen::Isometry3f& model_to_scene,
                         const std::vector<std::size_t>& visible, const ViewGrid& grid) {
  Footprint f;
  for (std::size_t s : visible) {
    const Eigen::Vector3f p = model_to_scene * model.samples()[s].point;
    const std::int64_t b = grid.bin(p);
    if (b < 0)
      continue;
    const float d = grid.depthOf(p);
    auto it = f.depth.find(b);
    if (it == f.depth.end())
      f.depth.emplace(b, d);
    else
      it->second = std::min(it->second, d);
  }
  std::unordered_set<std::int64_t> dilated;
  for (const auto& kv : f.depth) {
    dilated.insert(kv.first);
    for (std::int64_t n : grid.neighbours(kv.first))
      dilated.insert(n);
  }
  for (std::int64_t b : dilated) {
    bool interior = true;
    for (std::int64_t n : grid.neighbours(b))
      interior = interior && dilated.count(n) > 0;
    if (interior || f.depth.count(b))
      f.solid.insert(b);
  }
  return f;
}

/** Share of the silhouette's outer ring where the scene surface carries on at the depth of
 * the model's adjacent border. */
double boundaryContinuation(const Footprint& f, const ViewGrid& grid, float tolerance) {
  std::set<std::int64_t> ring;
  for (std::int64_t b : f.solid)
    for (std::int64_t n : grid.neighbours(b))
      if (!f.solid.count(n))
        ring.insert(n);
  std::size_t judged = 0, continuing = 0;
  for (std::int64_t r : ring) {
    float model_depth = ViewGrid::kEmpty;
    for (std::int64_t n : grid.neighbours(r)) {
      const auto it = f.depth.find(n);
      if (it != f.depth.end())
        model_depth = std::min(model_depth, it->second);
    }
    if (model_depth == ViewGrid::kEmpty)
      continue;
    ++judged;
    const float scene_depth = grid.depth(r);
    if (scene_depth < ViewGrid::kEmpty && std::abs(scene_depth - model_depth) < tolerance)
      ++continuing;
  }
  return judged > 0 ? static_cast<double>(continuing) / static_cast<double>(judged) : 0.0;
}

ClusterLocalization judgeCluster(const SceneView& view, const ViewGrid& grid,
                                 const pcl::PointIndices& indices, const IcfModel& model,
                                 const LocalizerParams& params, int icf_threads,
                                 const std::optional<ColourHistogram>& expected,
                                 bool single_object) {
  ClusterLocalization c;
  c.indices = indices;
  std::vector<Eigen::Vector3f> points;
  points.reserve(indices.indices.size());
  for (const auto i : indices.indices)
    if (isUsablePoint(view.points[static_cast<std::size_t>(i)]))
      points.push_back(view.points[static_cast<std::size_t>(i)]);
  IcfParams icf = params.icf;
  icf.threads = icf_threads;
  c.icf = estimatePose(model, points, view.camera, icf);
  if (c.icf.status == IcfStatus::TooFewPoints) {
    c.reason = "too few points (" + std::to_string(c.icf.points) + ")";
    return c;
  }
  const Eigen::Isometry3f model_to_scene(c.icf.object_pose);
  const Eigen::Isometry3f scene_to_model(c.icf.scene_to_model);
  const std::vector<std::size_t> visible =
      visibleSamples(model, model_to_scene, view.camera, params.icf.acceptance.visibility);
  const Footprint footprint = modelFootprint(model, model_to_scene, visible, grid);

  // Free space: visible model samples in front of what the camera saw along their ray.
  std::size_t seen_through = 0;
  for (std::size_t s : visible) {
    const Eigen::Vector3f p = model_to_scene * model.samples()[s].point;
    const float scene_depth = grid.depth(grid.bin(p));
    if (scene_depth < ViewGrid::kEmpty &&
        scene_depth > grid.depthOf(p) + params.free_space_tolerance)
      ++seen_through;
  }
  c.free_space_violation =
      visible.empty() ? 1.0
                      : static_cast<double>(seen_through) / static_cast<double>(visible.size());

  // The thesis's gate. A cluster of one object (compact, or a convexity segment) must be
  // explained whole; in a merged cluster the posed model answers only for the points it
  // claims: inside its silhouette and behind its visible surface.
  for (const auto& x : points) {
    if (!single_object) {
      const std::int64_t b = grid.bin(x);
      const auto it = footprint.depth.find(b);
      if (!footprint.solid.count(b) || it == footprint.depth.end() || grid.depthOf(x) < it->second)
        continue;
    }
    if (model.index().closestFace(scene_to_model * x, params.gate_distance).distance >
        params.gate_distance)
      ++c.gate_far_points;
  }
  const double allowed =
      std::max<double>(params.gate_max_far_points, params.gate_max_far_fraction * points.size());
  c.gate_passed = !params.thesis_gate || c.gate_far_points <= allowed;
  c.boundary_continuation = boundaryContinuation(footprint, grid, params.boundary_tolerance);

  double colour_factor = 1.0;
  if (expected && !view.colours.empty()) {
    ColourHistogram h(params.colour.bins);
    for (const auto i : indices.indices)
      h.add(view.colours[static_cast<std::size_t>(i)]);
    c.colour_similarity = h.intersection(*expected);
    colour_factor = std::pow(std::max(1e-3, *c.colour_similarity), params.colour.weight);
  }
  c.score = c.icf.quality.surface_coverage * std::sqrt(c.icf.quality.inlier_ratio) *
            (1.0 - c.free_space_violation) * colour_factor;

  std::ostringstream why;
  if (!c.icf.accepted())
    why << "pose rejected (coverage " << c.icf.quality.surface_coverage << ", rmse "
        << c.icf.quality.rmse << ") ";
  c.single_object = single_object;
  if (single_object && c.icf.quality.inlier_ratio < params.min_single_object_inliers)
    why << "explains only " << c.icf.quality.inlier_ratio << " of the object's points ";
  if (!c.gate_passed)
    why << "thesis gate (" << c.gate_far_points << " points beyond " << params.gate_distance
        << ") ";
  if (c.free_space_violation > params.max_free_space_violation)
    why << "free space (" << c.free_space_violation << " of the model seen through) ";
  if (c.boundary_continuation > params.max_boundary_continuation)
    why << "surface continues past the model (" << c.boundary_continuation << ") ";
  c.reason = why.str();
  if (!c.reason.empty())
    c.reason.pop_back();
  c.accepted = c.reason.empty();
  return c;
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
  std::vector<bool> is_table(view.points.size(), false);
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
    for (const auto i : segmentation.plane.inliers)
      is_table[static_cast<std::size_t>(i)] = true;
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

  // What the camera saw, without the table (an object standing on it would otherwise seem to
  // carry on into the table at its base).
  std::vector<Eigen::Vector3f> seen;
  seen.reserve(view.points.size());
  for (std::size_t i = 0; i < view.points.size(); ++i)
    if (!is_table[i] && isUsablePoint(view.points[i]))
      seen.push_back(view.points[i]);
  const ViewGrid grid(seen, view.camera, params.view_bin_angle);

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
      out.clusters[k] = judgeCluster(view, grid, clusters[k], model, params, m == 1 ? threads : 1,
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
