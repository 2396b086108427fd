/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/usable_point.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/parameter_check.h>

#include "hypothesis_judging.h"
#include "impl/object_localizer.hpp"
#include "scene_checks.h"
#include "scene_hypotheses.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iterator>
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

IcfParams LocalizerTuning::defaultIcf() {
  IcfParams icf;
  icf.acceptance.gate.max_fraction = FarPointGate::kLocalizerMaxFraction;
  return icf;
}

DepthVerificationParams LocalizerParams::verificationParams() const {
  return tuning_.verification.forSensor(depth_noise, mesh_accuracy);
}

IcfParams LocalizerParams::icfParams() const {
  IcfParams icf = tuning_.icf;
  icf.strategy = strategy;
  icf.fallback = fallback;
  icf.seed = seed;
  icf.threads = threads;
  // One verification: the seen-through check judges the depth with the same tolerances.
  icf.tuning().depth = tuning_.verification;
  icf.mesh_accuracy = mesh_accuracy;
  icf.depth_noise = depth_noise;
  return icf;
}

segmentation::TabletopParams LocalizerParams::segmentationParams() const {
  segmentation::TabletopParams s = tuning_.segmentation;
  s.cluster = cluster;
  return s;
}

void LocalizerTuning::validate() const {
  const internal::ParameterCheck fail("localization::LocalizerTuning");
  verification.validate();
  alternatives.validate();
  hypotheses.validate();
  if (!(refine_min_confidence >= 0.0 && refine_min_confidence <= 1.0))
    fail("refine_min_confidence", refine_min_confidence, "must lie in [0, 1]");
  if (!(promising_share >= 0.0 && promising_share <= 1.0))
    fail("promising_share", promising_share, "must lie in [0, 1]");
  if (!(min_points_in_front >= 0.0 && min_points_in_front <= 1.0))
    fail("min_points_in_front", min_points_in_front, "must lie in [0, 1]");
  if (!(max_shared_points >= 0.0 && max_shared_points < 1.0))
    fail("max_shared_points", max_shared_points, "must lie in [0, 1)");
}

void LocalizerParams::validate() const {
  const internal::ParameterCheck fail("localization::LocalizerParams");
  if (segment)
    segmentationParams().validate();
  icfParams().validate();
  colour.validate();
  tuning_.validate();
  if (intrinsics)
    intrinsics->validate();
  if (!(min_confidence >= 0.0 && min_confidence <= 1.0))
    fail("min_confidence", min_confidence, "must lie in [0, 1]");
  if (threads < 0 || threads > 1024)
    fail("threads", threads, "must lie in [0, 1024] (0 = all cores)");
  if (max_instances < 1 || max_instances > 1000)
    fail("max_instances", max_instances, "must lie in [1, 1000]");
  depth_noise.validate();
  if (!(mesh_accuracy >= 0.f && mesh_accuracy <= 0.05f))
    fail("mesh_accuracy", mesh_accuracy, "must lie in [0, 0.05] metres");
  if (camera_pose)
    validateRigidTransform(camera_pose->matrix().cast<double>(),
                           "[pcl::icf::localization::LocalizerParams::validate] camera_pose");
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
  for (auto& vertex : loc.segmentation.hull)
    vertex = camera_to_scene * vertex;
  loc.camera_pose = camera_to_scene;
}

namespace {

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
  const SceneHypotheses& hp = params.tuning().hypotheses;
  const std::vector<bool> usable = candidatePoints(view, out.segmentation, explained);
  using Clock = std::chrono::steady_clock;
  const auto msSince = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  auto stage = Clock::now();
  const PointPairScene scene = votingScene(view, usable, model, hp, threads);
  std::vector<Candidate> candidates;
  if (hp.point_pairs)
    candidates = votedCandidates(model, scene, image, hp, threads);
  // A model with no point pair worth voting with (a flat plate, a model smaller than a few
  // sampling steps) is searched for in the clusters.
  if (hp.clusters || model.pointPairs().pairs() == 0) {
    std::vector<pcl::PointIndices> rest = clusters;
    if (explained.size() > params.explained_indices.size())
      withoutExplainedPoints(rest, view, explained, params.cluster.min_size);
    const std::vector<Candidate> searched =
        clusterCandidates(view, searchedClusters(view, rest, model, params), model,
                          params.tuning().icf.tuning().global, params.seed, hp, threads);
    candidates.insert(candidates.end(), searched.begin(), searched.end());
  }
  out.hypotheses_ms += msSince(stage);
  stage = Clock::now();
  const std::size_t judged =
      std::max(hp.judged, 2 * static_cast<std::size_t>(params.max_instances));
  const std::vector<RankedHypothesis> ranked =
      rankCandidates(view, usable, model, image, params.verificationParams(), scene, candidates, hp,
                     judged, threads);
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
  withoutExplainedPoints(clusters, view, params.explained_indices, params.cluster.min_size);
  // What the camera saw, the table marked as background (an object standing on it would
  // otherwise seem to carry on into the table at its base).
  // (Without segmentation the plane has no inliers: nothing is background.)
  DepthImage image = sceneDepthImage(view, segmentation, params);
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
        selectInstances(all.objects, caps, names, params.tuning().max_shared_points);
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
