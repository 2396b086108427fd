/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "scene_hypotheses.h"

#include <pcl/icf/registration/refinement.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl_icf_internal/grown_model_box.h>
#include <pcl_icf_internal/parameter_check.h>
#include <pcl_icf_internal/place_quota.h>

#include <omp.h>

#include <algorithm>
#include <numeric>

namespace pcl {
namespace icf {
namespace localization {

PointPairVotingParams SceneHypotheses::defaultVoting() {
  PointPairVotingParams v;
  v.kept = 100;
  v.kept_visible = 40;
  return v;
}

void SceneHypotheses::validate() const {
  voting.validate();
  const internal::ParameterCheck fail("localization::SceneHypotheses");
  if (!point_pairs && !clusters)
    fail("point_pairs", point_pairs,
         "and clusters cannot both be off: no hypothesis would be made");
  if (per_cluster < 1)
    fail("per_cluster", per_cluster, "must be >= 1");
  if (judged < 1)
    fail("judged", judged, "must be >= 1");
  if (per_location < 1)
    fail("per_location", per_location, "must be >= 1");
  if (!(min_prescore >= 0.0 && min_prescore <= 1.0))
    fail("min_prescore", min_prescore, "must lie in [0, 1]");
  if (!(crop_margin >= 0.f && crop_margin <= 2.f))
    fail("crop_margin", crop_margin, "must lie in [0, 2] (a share of the diameter)");
  if (refine_points < 10)
    fail("refine_points", refine_points, "must be >= 10");
  if (final_points < 10)
    fail("final_points", final_points, "must be >= 10");
  if (max_voting_points > 0 && max_voting_points < 100)
    fail("max_voting_points", max_voting_points, "must be 0 (no limit) or >= 100");
  if (!(fine_start_radius > 0.f && std::isfinite(fine_start_radius)))
    fail("fine_start_radius", fine_start_radius, "must be positive and finite");
  if (fine_iterations < 1)
    fail("fine_iterations", fine_iterations, "must be >= 1");
}

namespace detail {

std::vector<bool> candidatePoints(const internal::SceneView& view,
                                  const segmentation::TabletopSegmentation& segmentation,
                                  const std::vector<int>& explained) {
  const bool on_table = segmentation.status == segmentation::TabletopStatus::Ok;
  std::vector<bool> usable(view.points.size(), !on_table);
  if (on_table)
    for (const auto i : segmentation.above_table)
      usable[static_cast<std::size_t>(i)] = true;
  for (const auto i : segmentation.plane.inliers)
    usable[static_cast<std::size_t>(i)] = false;
  for (const int i : explained)
    usable[static_cast<std::size_t>(i)] = false;
  for (std::size_t i = 0; i < view.points.size(); ++i)
    usable[i] = usable[i] && isUsablePoint(view.points[i]);
  return usable;
}

pcl::PointIndices pointsInGrownBox(const internal::SceneView& view, const std::vector<bool>& usable,
                                   const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                                   float margin) {
  const internal::GrownModelBox box(model, model_to_camera, margin);
  pcl::PointIndices inside;
  for (std::size_t i = 0; i < view.points.size(); ++i)
    if (usable[i] && box.contains(view.points[i]))
      inside.indices.push_back(static_cast<pcl::index_t>(i));
  return inside;
}

PointPairScene votingScene(const internal::SceneView& view, const std::vector<bool>& usable,
                           const IcfModel& model, const SceneHypotheses& params, int threads) {
  const PointPairModel& table = model.pointPairs();
  if (table.empty())
    return {};
  std::vector<int> eligible;
  eligible.reserve(view.points.size());
  for (std::size_t i = 0; i < view.points.size(); ++i)
    if (usable[i])
      eligible.push_back(static_cast<int>(i));
  return subsampleForVoting(view.points, eligible, table.step(),
                            params.voting.normal_radius * table.step(), threads,
                            params.max_voting_points);
}

std::vector<Candidate> votedCandidates(const IcfModel& model, const PointPairScene& scene,
                                       const DepthImage& image, const SceneHypotheses& params,
                                       int threads) {
  std::vector<Candidate> out;
  for (const VotedPose& v :
       voteForPoses(model, scene, params.voting, threads, image.empty() ? nullptr : &image)) {
    Candidate c;
    c.model_to_camera = v.model_to_camera;
    c.source.votes = v.votes;
    out.push_back(c);
  }
  return out;
}

std::vector<Candidate> clusterCandidates(const internal::SceneView& view,
                                         const std::vector<pcl::PointIndices>& clusters,
                                         const IcfModel& model, const GlobalSearchParams& search,
                                         std::uint64_t seed, const SceneHypotheses& params,
                                         int threads) {
  std::vector<std::vector<Candidate>> per_cluster(clusters.size());
  const int n = static_cast<int>(clusters.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads)) if (n > 1)
  for (int k = 0; k < n; ++k) {
    std::vector<Eigen::Vector3f> points;
    for (const auto i : clusters[static_cast<std::size_t>(k)].indices)
      if (isUsablePoint(view.points[static_cast<std::size_t>(i)]))
        points.push_back(view.points[static_cast<std::size_t>(i)]);
    if (points.size() < 3)
      continue;
    // One thread each (the clusters run in parallel); a cluster alone gets them all.
    const std::vector<PoseHypothesis> found =
        globalSearch(model, points, Eigen::Vector3f::Zero(), search, seed, n == 1 ? threads : 1);
    for (std::size_t h = 0; h < found.size() && h < params.per_cluster; ++h) {
      Candidate c;
      c.model_to_camera = found[h].scene_to_model.inverse(Eigen::Isometry);
      c.refined = true;
      c.source.cluster = k;
      per_cluster[static_cast<std::size_t>(k)].push_back(c);
    }
  }
  std::vector<Candidate> out;
  for (auto& c : per_cluster)
    out.insert(out.end(), c.begin(), c.end());
  return out;
}

namespace {

/** The points of \a scene inside \a model's box at \a model_to_camera grown by \a margin. */
std::vector<Eigen::Vector3f> votingPointsInGrownBox(const PointPairScene& scene,
                                                    const IcfModel& model,
                                                    const Eigen::Isometry3f& model_to_camera,
                                                    float margin) {
  const internal::GrownModelBox box(model, model_to_camera, margin);
  std::vector<Eigen::Vector3f> inside;
  for (const Eigen::Vector3f& p : scene.points)
    if (box.contains(p))
      inside.push_back(p);
  return inside;
}

/** A candidate through the ranking. */
struct Ranked {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  bool usable = false;
  double confidence = -1.0;
};

}  // namespace

std::vector<RankedHypothesis> rankCandidates(
    const internal::SceneView& view, const std::vector<bool>& usable, const IcfModel& model,
    const DepthImage& image, const DepthVerificationParams& verification,
    const PointPairScene& scene, const std::vector<Candidate>& candidates,
    const SceneHypotheses& params, std::size_t judged, int threads) {
  std::vector<RankedHypothesis> out;
  if (image.empty() || candidates.empty())
    return out;
  const float diameter = 2.f * model.radius();
  const float margin = params.crop_margin * diameter;
  const Eigen::Vector3f pivot = model.mesh().surfaceCentroid();
  const double scale = std::max(1e-3f, model.radius());
  const RefinementParams field = GlobalSearchParams::defaultFieldRefinement();
  // Each candidate refined into its own slot (independent of the thread count).
  std::vector<Ranked> ranked(candidates.size());
  const int n = static_cast<int>(candidates.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads)) if (n > 1)
  for (int k = 0; k < n; ++k) {
    const Candidate& c = candidates[static_cast<std::size_t>(k)];
    Ranked& r = ranked[static_cast<std::size_t>(k)];
    r.pose = c.model_to_camera;
    r.usable = c.refined;
    if (c.refined)
      continue;
    const std::vector<Eigen::Vector3f> near =
        votingPointsInGrownBox(scene, model, c.model_to_camera, margin);
    if (near.size() < 10)
      continue;
    r.pose = refinePoseOnField(model.field(), pivot, scale, near,
                               c.model_to_camera.inverse(Eigen::Isometry), field)
                 .scene_to_model.inverse(Eigen::Isometry);
    r.usable = true;
  }
  // Refined poses often meet: one that puts the model's surface where an earlier one does is
  // that pose, and is not verified again.
  const float tolerance = params.voting.distinct_surface * diameter;
  std::vector<std::size_t> unique;
  for (std::size_t k = 0; k < ranked.size(); ++k)
    if (ranked[k].usable && std::none_of(unique.begin(), unique.end(), [&](std::size_t u) {
          return posesShareSurface(model, ranked[k].pose, ranked[u].pose, tolerance);
        }))
      unique.push_back(k);
  const int m = static_cast<int>(unique.size());
  const DepthVerificationParams rough = verification.forRoughPoses();  // refined on the field only
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads)) if (m > 1)
  for (int j = 0; j < m; ++j) {
    Ranked& r = ranked[unique[static_cast<std::size_t>(j)]];
    r.confidence = explainDepth(model, r.pose, image, rough).confidence;
  }
  std::stable_sort(unique.begin(), unique.end(), [&](std::size_t a, std::size_t b) {
    return ranked[a].confidence > ranked[b].confidence;
  });
  // At most per_location hypotheses of one place (model centres within a quarter of the
  // diameter of a better one's): the rest of the quota goes to other places (a second copy).
  const Eigen::Vector3f centre = 0.5f * (model.mesh().boundsMin() + model.mesh().boundsMax());
  internal::PlaceQuota quota(0.25f * diameter, params.per_location);
  for (const std::size_t k : unique) {
    if (out.size() >= judged || ranked[k].confidence < params.min_prescore)
      break;
    if (!quota.admit(ranked[k].pose * centre))
      continue;
    RankedHypothesis h;
    h.model_to_camera = ranked[k].pose;
    h.prescore = ranked[k].confidence;
    h.source = candidates[k].source;
    h.near = pointsInGrownBox(view, usable, model, ranked[k].pose, margin);
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace detail
}  // namespace localization
}  // namespace icf
}  // namespace pcl
