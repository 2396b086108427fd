/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bench_scene.h"

#include <pcl/common/io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/localization/objects_localizer.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace pcl_icf_tools {
namespace bench {

namespace localization = pcl::icf::localization;
using Clock = std::chrono::steady_clock;

namespace {

/** The accepted cluster, else the best-scoring one (nullptr when none was judged). */
const localization::ClusterLocalization* topCluster(const localization::Localization& loc) {
  if (loc.best >= 0)
    return &loc.clusters[static_cast<std::size_t>(loc.best)];
  const localization::ClusterLocalization* top = nullptr;
  for (const auto& c : loc.clusters)
    if (!top || c.score > top->score)
      top = &c;
  return top;
}

/** The verification's terms of \a c, "supported=0.91 seen_through=0.02 ..." (for the CSV). */
std::string verificationTerms(const localization::ClusterLocalization& c) {
  const auto& e = c.verification;
  char text[896];
  std::snprintf(text, sizeof(text),
                "pixels=%zu supported=%.4f seen_through=%.4f occluded=%.4f below_support=%.4f "
                "isolated=%.4f missing=%.4f out_of_view=%.4f on_background=%.4f "
                "visible_support=%.4f "
                "continuation=%.4f band=%zu occluder_continuation=%.4f occluded_by_support=%.4f "
                "local_misfit=%.2f residual=%.3f "
                "edge_offset=%.3f edges=%zu allowed_offset=%.3f sunk=%.4f support_tolerance=%.4f "
                "turned=%d alternatives=%zu colour=%.4f",
                e.model_pixels, e.supported, e.seen_through, e.occluded, e.below_support,
                e.isolated_conflicts, e.missing, e.out_of_view, e.on_background, e.visible_support,
                e.silhouette_continuation, e.silhouette_pixels, e.occluder_continuation,
                e.occluded_by_support, e.local_misfit, e.residual, e.silhouette_offset,
                e.silhouette_edges, e.allowed_offset, e.sunk_into_support, e.support_tolerance,
                c.turned ? 1 : 0, c.alternatives.size(),
                c.colour_similarity ? *c.colour_similarity : -1.0);
  return text;
}

/** "[segmentation 110 ms, hypotheses 380, ranking 190, judging 280] ". */
std::string stages(const localization::Localization& loc) {
  char text[160];
  std::snprintf(text, sizeof(text),
                "[segmentation %.0f ms, hypotheses %.0f, ranking %.0f, judging %.0f] ",
                loc.segmentation_ms, loc.hypotheses_ms, loc.ranking_ms, loc.judging_ms);
  return text;
}

/** "Found: hypothesis 3 of 19, score 0.71 [stages]" or "NotFound: 19 hypotheses; best score
 * 0.42 [stages]: why". */
std::string describe(const localization::Localization& loc) {
  std::string text = localization::toString(loc.status) + ": ";
  const auto n = std::to_string(loc.clusters.size());
  char score[32];
  if (loc.best >= 0) {
    const auto& best = loc.clusters[static_cast<std::size_t>(loc.best)];
    std::snprintf(score, sizeof(score), "%.2f", best.score);
    return text + "hypothesis " + std::to_string(loc.best) + " of " + n + ", score " + score + " " +
           stages(loc);
  }
  const localization::ClusterLocalization* top = topCluster(loc);
  if (!top)
    return text + stages(loc) + (loc.message.empty() ? "no hypothesis" : loc.message);
  std::snprintf(score, sizeof(score), "%.2f", top->score);
  return text + n + " hypotheses; best score " + score + " " + stages(loc) + ": " + top->reason;
}

/** \a loc's run: converged when Found, the best cluster's pose, the top cluster's terms. */
MethodRun runOf(const localization::Localization& loc, double ms) {
  MethodRun run;
  run.ms = ms;
  run.converged = loc.status == localization::LocalizationStatus::Found && loc.best >= 0;
  if (run.converged)
    run.object_pose = loc.clusters[static_cast<std::size_t>(loc.best)].icf.object_pose;
  run.detail = describe(loc);
  if (const localization::ClusterLocalization* top = topCluster(loc)) {
    run.confidence = top->verification.confidence;
    run.verification = verificationTerms(*top);
    for (const auto& alt : top->alternatives)
      run.alternative_poses.push_back(alt.object_pose.matrix());
  }
  return run;
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

template <typename PointT>
MethodRun localize(const pcl::PointCloud<PointT>& scene, const PreparedModel& model,
                   const localization::LocalizerParams& params) {
  const auto start = Clock::now();
  const localization::Localization loc = localization::localizeObject(scene, *model.icf, params);
  return runOf(loc, msSince(start));
}

template <typename PointT>
MethodRun localizeWithOthers(const pcl::PointCloud<PointT>& scene, const PreparedModel& model,
                             const std::vector<const PreparedModel*>& others,
                             const localization::LocalizerParams& params) {
  std::vector<localization::ObjectQuery> queries(1 + others.size());
  queries[0].model = model.icf;
  for (std::size_t i = 0; i < others.size(); ++i)
    queries[i + 1].model = others[i]->icf;
  const auto start = Clock::now();
  localization::ObjectsLocalization found = localization::localizeObjects(scene, queries, params);
  return runOf(found.objects.front(), msSince(start));
}

}  // namespace

SceneInput loadScene(const CaseSpec& c) {
  pcl::icf::io::SceneFileInfo info;
  pcl::PointCloud<pcl::PointXYZRGBA>::Ptr cloud;
  try {
    cloud = pcl::icf::io::loadSceneCloud(c.scene.string(), &info);
  } catch (const pcl::icf::io::FileError& e) {
    throw BadInput(c.source + ": " + e.what());
  }
  if (c.camera_set)
    cloud->sensor_origin_.head<3>() = c.camera;
  SceneInput scene;
  scene.finite_points = info.finite_points;
  if (info.has_colour) {
    scene.rgba = cloud;
    return scene;
  }
  scene.xyz = pcl::make_shared<CloudXYZ>();
  pcl::copyPointCloud(*cloud, *scene.xyz);
  scene.xyz->sensor_origin_ = cloud->sensor_origin_;
  scene.xyz->sensor_orientation_ = cloud->sensor_orientation_;
  return scene;
}

MethodRun runScene(const SceneInput& scene, const PreparedModel& model,
                   const localization::LocalizerParams& params) {
  return scene.rgba ? localize(*scene.rgba, model, params) : localize(*scene.xyz, model, params);
}

MethodRun runSceneWithOthers(const SceneInput& scene, const PreparedModel& model,
                             const std::vector<const PreparedModel*>& others,
                             const localization::LocalizerParams& params) {
  return scene.rgba ? localizeWithOthers(*scene.rgba, model, others, params)
                    : localizeWithOthers(*scene.xyz, model, others, params);
}

}  // namespace bench
}  // namespace pcl_icf_tools
