/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/objective.h>
#include <pcl/icf/registration/rotation_sampling.h>
#include <pcl_icf_internal/parameter_check.h>
#include <pcl_icf_internal/search_anchors.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

RefinementParams GlobalSearchParams::defaultFieldRefinement() {
  RefinementParams p;
  p.max_iterations = 12;
  p.initial_inlier_distance = 0.03f;
  p.inlier_shrink = 0.75f;
  p.final_inlier_distance = 0.008f;
  return p;
}

void GlobalSearchParams::validate() const {
  const internal::ParameterCheck fail("GlobalSearchParams");
  if (rotations < 1 || rotations > 10000000)
    fail("rotations", static_cast<double>(rotations), "must lie in [1, 1e7]");
  if (subsample < 3)
    fail("subsample", static_cast<double>(subsample), "must be at least 3");
  if (centroid_samples < 1)
    fail("centroid_samples", static_cast<double>(centroid_samples), "must be at least 1");
  if (!(coarse_kernel > 0.f) || !std::isfinite(coarse_kernel))
    fail("coarse_kernel", coarse_kernel, "must be positive and finite");
  if (!(fine_kernel > 0.f) || !std::isfinite(fine_kernel))
    fail("fine_kernel", fine_kernel, "must be positive and finite");
  if (keep < 1)
    fail("keep", static_cast<double>(keep), "must be at least 1");
  if (!(prescreen_share >= 0.f && prescreen_share <= 1.f))
    fail("prescreen_share", prescreen_share, "must lie in [0, 1]");
  if (!(merged_cluster_ratio > 0.f) || !std::isfinite(merged_cluster_ratio))
    fail("merged_cluster_ratio", merged_cluster_ratio, "must be positive and finite");
  if (!(anchor_spacing > 0.01f) || !std::isfinite(anchor_spacing))
    fail("anchor_spacing", anchor_spacing, "must be finite and > 0.01");
  if (max_anchors < 1 || max_anchors > 100000)
    fail("max_anchors", static_cast<double>(max_anchors), "must lie in [1, 1e5]");
  if (!(distinct_rotation >= 0.f) || !(distinct_translation >= 0.f))
    fail("distinct_*", -1, "must be >= 0");
  if (!(distinct_surface >= 0.f && distinct_surface <= 1.f))
    fail("distinct_surface", distinct_surface, "must lie in [0, 1]");
  field_refinement.validate();
}

namespace internal {

std::vector<Eigen::Vector3f> randomSubset(const std::vector<Eigen::Vector3f>& points,
                                          std::size_t count, std::uint64_t seed) {
  if (points.size() <= count)
    return points;
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(seed);
  // Partial Fisher-Yates with our own draws: the same subset on every standard library.
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = i + static_cast<std::size_t>(rng() % (points.size() - i));
    std::swap(order[i], order[j]);
  }
  order.resize(count);
  std::sort(order.begin(), order.end());
  std::vector<Eigen::Vector3f> subset;
  subset.reserve(count);
  for (std::size_t i : order)
    subset.push_back(points[i]);
  return subset;
}

double fieldKernelScore(const ClosestPointField& field,
                        const std::vector<Eigen::Vector3f>& scene_points,
                        const Eigen::Isometry3f& scene_to_model, float kernel) {
  double score = 0.0;
  for (const Eigen::Vector3f& x : scene_points)
    score += kernelScore(field.distance(scene_to_model * x), kernel);
  return score;
}

Eigen::Vector3f robustCentroid(const std::vector<Eigen::Vector3f>& points) {
  // The coordinate-wise median, then the mean of the points within 1.5 x the 90th-percentile
  // distance (+1 cm) of it: the centroid of the object's points without the pull of a few
  // stray points far away (a 1e5 m point among 2000 moves a plain mean by 50 m).
  Eigen::Vector3f median;
  std::vector<float> axis(points.size());
  for (int a = 0; a < 3; ++a) {
    for (std::size_t i = 0; i < points.size(); ++i)
      axis[i] = points[i][a];
    std::nth_element(axis.begin(), axis.begin() + static_cast<std::ptrdiff_t>(axis.size() / 2),
                     axis.end());
    median[a] = axis[axis.size() / 2];
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    axis[i] = (points[i] - median).norm();
  const std::size_t q = axis.size() * 9 / 10;
  std::nth_element(axis.begin(), axis.begin() + static_cast<std::ptrdiff_t>(q), axis.end());
  const float keep = 1.5f * axis[q] + 0.01f;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (const auto& p : points)
    if ((p - median).norm() <= keep) {
      sum += p.cast<double>();
      ++count;
    }
  return count > 0 ? Eigen::Vector3f((sum / static_cast<double>(count)).cast<float>()) : median;
}

float clusterSpread(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& centroid) {
  if (points.empty())
    return 0.f;
  std::vector<float> spread(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    spread[i] = (points[i] - centroid).norm();
  const std::size_t q = spread.size() * 9 / 10;
  std::nth_element(spread.begin(), spread.begin() + static_cast<std::ptrdiff_t>(q), spread.end());
  return spread[q];
}

std::vector<SearchAnchor> translationAnchors(const std::vector<Eigen::Vector3f>& points,
                                             float model_radius, const GlobalSearchParams& params,
                                             std::uint64_t seed) {
  const Eigen::Vector3f centroid = robustCentroid(points);
  if (clusterSpread(points, centroid) <= params.merged_cluster_ratio * model_radius)
    return {SearchAnchor{centroid, randomSubset(points, params.subsample, seed)}};

  // A merged cluster: windows on a grid of pitch anchor_spacing x model radius, each holding
  // the points within the model's radius of its points' mean.
  const float pitch = std::max(1e-4f, params.anchor_spacing * model_radius);
  std::map<std::array<long, 3>, std::pair<Eigen::Vector3f, int>> cells;
  for (const auto& p : points) {
    // Clamped before the cast: a float beyond long's range (a point at 1e30, NaN) is UB.
    auto cell = [pitch](float v) {
      const float x = v / pitch;
      return static_cast<long>(std::floor(x > -1e15f ? (x < 1e15f ? x : 1e15f) : -1e15f));
    };
    const std::array<long, 3> key{cell(p.x()), cell(p.y()), cell(p.z())};
    // Not cells[key]: that value-initializes the pair, and Eigen's Vector3f() leaves its
    // coordinates uninitialized (the anchors, and so the poses, changed from run to run).
    auto& slot = cells.try_emplace(key, Eigen::Vector3f::Zero(), 0).first->second;
    slot.first += p;
    ++slot.second;
  }
  std::vector<SearchAnchor> anchors;
  std::uint64_t k = 0;
  for (const auto& kv : cells) {
    if (kv.second.second < static_cast<int>(params.min_anchor_points))
      continue;
    SearchAnchor a;
    a.centre = kv.second.first / static_cast<float>(kv.second.second);
    std::vector<Eigen::Vector3f> local;
    for (const auto& p : points)
      if ((p - a.centre).norm() < model_radius)
        local.push_back(p);
    a.subset = randomSubset(local, params.subsample, seed + ++k);
    // The model is placed on the centroid of what it would explain here.
    a.centre = Eigen::Vector3f::Zero();
    for (const auto& p : a.subset)
      a.centre += p;
    a.centre /= static_cast<float>(a.subset.size());
    anchors.push_back(std::move(a));
  }
  if (anchors.size() > params.max_anchors) {  // keep the densest windows
    std::stable_sort(anchors.begin(), anchors.end(),
                     [](const SearchAnchor& a, const SearchAnchor& b) {
                       return a.subset.size() > b.subset.size();
                     });
    anchors.resize(params.max_anchors);
  }
  if (anchors.empty())
    anchors.push_back(SearchAnchor{centroid, randomSubset(points, params.subsample, seed)});
  return anchors;
}

}  // namespace internal

bool spreadsWiderThanModel(const std::vector<Eigen::Vector3f>& points, float model_radius,
                           const GlobalSearchParams& params) {
  return !points.empty() && internal::clusterSpread(points, internal::robustCentroid(points)) >
                                params.merged_cluster_ratio * model_radius;
}

namespace {

using internal::fieldKernelScore;
using internal::SearchAnchor;

/** Model-frame centroids of the surface the camera sees along each of \a views (model frame),
 * weighted by projected area; the surface centroid where nothing faces the camera. Per view two
 * matrix-vector products on the first \a samples surface samples (weights w = max(0, -N v),
 * sums P w), the views shared among \a threads: a loop over samples per view on one thread was
 * a quarter of a small cluster's search. Each view's sums are one thread's, in one order: the
 * same for any thread count (a matrix-matrix product would not be: Eigen blocks it by its own
 * thread count). */
std::vector<Eigen::Vector3f> visibleCentroids(const IcfModel& model, std::size_t samples,
                                              const std::vector<Eigen::Vector3f>& views,
                                              int threads) {
  const std::size_t n = std::min(samples, model.samples().size());
  Eigen::MatrixXf normals(n, 3), points(4, n);  // points' 4th row sums the weights
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    normals.row(row) = -model.samples()[i].normal.transpose();
    points.col(row) << model.samples()[i].point, 1.f;
  }
  std::vector<Eigen::Vector3f> centroids(views.size(), model.mesh().surfaceCentroid());
  const int count = static_cast<int>(views.size());
#pragma omp parallel num_threads(std::max(1, threads))
  {
    Eigen::VectorXf weights(static_cast<Eigen::Index>(n));
    Eigen::Vector4f sums;
#pragma omp for schedule(static)
    for (int v = 0; v < count; ++v) {
      weights.noalias() = normals * views[static_cast<std::size_t>(v)];
      weights = weights.cwiseMax(0.f);
      sums.noalias() = points * weights;
      if (sums[3] > 0.f)
        centroids[static_cast<std::size_t>(v)] = sums.head<3>() / sums[3];
    }
  }
  return centroids;
}

bool isDistinct(const PoseHypothesis& h, const std::vector<PoseHypothesis>& kept, float rotation,
                float translation) {
  for (const PoseHypothesis& k : kept) {
    const Eigen::Isometry3f delta = h.scene_to_model * k.scene_to_model.inverse();
    const float angle = Eigen::AngleAxisf(delta.linear()).angle();
    const Eigen::Isometry3f a = h.scene_to_model.inverse(), b = k.scene_to_model.inverse();
    if (angle < rotation && (a.translation() - b.translation()).norm() < translation)
      return false;
  }
  return true;
}

/** True when \a h puts the model's surface where one of \a kept does: each of the model's
 * first (up to) 64 surface samples, moved from its place at pose h to where pose k puts the
 * same model point, lies within \a distance of the model's surface (the closest-point field).
 * Model point p is at scene point h^-1 p, which k maps to k h^-1 p. Unlike isDistinct, this
 * sees a symmetric model's turns as the pose they are. Every sample, not their mean: a flat
 * box turned 45 degrees about its short axis keeps most of its samples on its large faces
 * (mean 8 mm for Box5) while its corners move 36 mm off. */
bool coversTheSameSurface(const IcfModel& model, const PoseHypothesis& h,
                          const std::vector<PoseHypothesis>& kept, float distance) {
  const std::vector<SurfaceSample>& samples = model.samples();
  const std::size_t n = std::min<std::size_t>(64, samples.size());
  if (n == 0 || distance <= 0.f)
    return false;
  for (const PoseHypothesis& k : kept) {
    const Eigen::Isometry3f moved = k.scene_to_model * h.scene_to_model.inverse();
    std::size_t i = 0;
    while (i < n &&
           model.field().distance(moved * samples[i * samples.size() / n].point) < distance)
      ++i;
    if (i == n)
      return true;
  }
  return false;
}

/** The cascade's second stage: the best prescreen_share of \a coarse by their prescreen
 * score (at least 20 x keep; ties by index) scored again on their anchor's whole subsample;
 * the rest drop below every one of them. */
void scoreTheBestOnTheirSubsets(std::vector<PoseHypothesis>& coarse,
                                const std::vector<std::size_t>& anchor_of,
                                const std::vector<SearchAnchor>& anchors, const IcfModel& model,
                                const GlobalSearchParams& params, int threads) {
  const std::size_t chosen =
      std::min(coarse.size(),
               std::max<std::size_t>(
                   20 * params.keep,
                   static_cast<std::size_t>(std::ceil(params.prescreen_share * coarse.size()))));
  std::vector<std::size_t> order(coarse.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return coarse[a].score > coarse[b].score; });
  for (std::size_t i = chosen; i < order.size(); ++i)
    coarse[order[i]].score = -1.0;  // kernel scores are >= 0
  const int n = static_cast<int>(chosen);
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
  for (int k = 0; k < n; ++k) {
    PoseHypothesis& h = coarse[order[static_cast<std::size_t>(k)]];
    h.score = fieldKernelScore(model.field(),
                               anchors[anchor_of[order[static_cast<std::size_t>(k)]]].subset,
                               h.scene_to_model, params.coarse_kernel);
  }
}

/** The coarse pass: every rotation of a uniform set at every anchor, the model placed by the
 * centroid of its surface visible along \a view (scene frame), scored through the field on the
 * anchor's points (with the cascade: first on the prescreen points, then the best on all of
 * them). \a anchor_of receives each hypothesis's anchor. */
std::vector<PoseHypothesis> coarsePass(const IcfModel& model,
                                       const std::vector<SearchAnchor>& anchors,
                                       const Eigen::Vector3f& view,
                                       const GlobalSearchParams& params, std::uint64_t seed,
                                       int threads, std::vector<std::size_t>& anchor_of) {
  const std::size_t rotation_count =
      anchors.size() > 1 ? std::max<std::size_t>(1, params.rotations / 2) : params.rotations;
  const std::vector<Eigen::Quaternionf> rotations =
      uniformRotations(rotation_count, seed ^ 0x9e3779b97f4a7c15ULL);
  std::vector<Eigen::Vector3f> views(rotations.size());
  for (std::size_t r = 0; r < rotations.size(); ++r)
    views[r] = rotations[r].toRotationMatrix().transpose() * view;
  const std::vector<Eigen::Vector3f> visible_centroids =
      visibleCentroids(model, params.centroid_samples, views, threads);
  // The cascade's first stage: the first prescreen_points of each anchor's random subset.
  std::vector<std::vector<Eigen::Vector3f>> prescreen;
  const bool prescreened =
      params.prescreen_points > 0 && params.prescreen_share > 0.f && params.prescreen_share < 1.f;
  if (prescreened)
    for (const SearchAnchor& a : anchors)
      prescreen.emplace_back(a.subset.begin(),
                             a.subset.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                    params.prescreen_points, a.subset.size())));
  std::vector<PoseHypothesis> coarse(rotations.size() * anchors.size());
  anchor_of.assign(coarse.size(), 0);
  const int count = static_cast<int>(coarse.size());
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
  for (int k = 0; k < count; ++k) {
    const std::size_t r = static_cast<std::size_t>(k) % rotations.size();
    const std::size_t a = static_cast<std::size_t>(k) / rotations.size();
    const Eigen::Matrix3f R = rotations[r].toRotationMatrix();
    Eigen::Isometry3f model_to_scene = Eigen::Isometry3f::Identity();
    model_to_scene.linear() = R;
    model_to_scene.translation() = anchors[a].centre - R * visible_centroids[r];
    PoseHypothesis& h = coarse[static_cast<std::size_t>(k)];
    h.scene_to_model = model_to_scene.inverse();
    h.score = fieldKernelScore(model.field(), prescreened ? prescreen[a] : anchors[a].subset,
                               h.scene_to_model, params.coarse_kernel);
    anchor_of[static_cast<std::size_t>(k)] = a;
  }
  if (prescreened)
    scoreTheBestOnTheirSubsets(coarse, anchor_of, anchors, model, params, threads);
  return coarse;
}

/** The best params.keep of \a coarse, best first (ties by index), each distinct from those kept
 * before it; \a kept_anchor receives their anchors. */
std::vector<PoseHypothesis> bestDistinct(const IcfModel& model,
                                         const std::vector<PoseHypothesis>& coarse,
                                         const std::vector<std::size_t>& anchor_of,
                                         const GlobalSearchParams& params,
                                         std::vector<std::size_t>& kept_anchor) {
  const float surface = params.distinct_surface * model.radius();
  std::vector<std::size_t> order(coarse.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return coarse[a].score > coarse[b].score; });
  std::vector<PoseHypothesis> kept;
  for (std::size_t i : order) {
    if (kept.size() >= params.keep)
      break;
    if (isDistinct(coarse[i], kept, params.distinct_rotation, params.distinct_translation) &&
        !coversTheSameSurface(model, coarse[i], kept, surface)) {
      kept.push_back(coarse[i]);
      kept_anchor.push_back(anchor_of[i]);
    }
  }
  return kept;
}

/** The fine pass: each kept hypothesis refined on the field on its anchor's points and
 * re-scored with the fine kernel; sorted best first. */
void refineOnField(const IcfModel& model, const std::vector<SearchAnchor>& anchors,
                   const std::vector<std::size_t>& kept_anchor, const GlobalSearchParams& params,
                   int threads, std::vector<PoseHypothesis>& kept) {
  const Eigen::Vector3f pivot = model.mesh().surfaceCentroid();
  const double scale = std::max(1e-3f, model.radius());
  const int n = static_cast<int>(kept.size());
#pragma omp parallel for schedule(dynamic) num_threads(std::max(1, threads))
  for (int k = 0; k < n; ++k) {
    PoseHypothesis& h = kept[static_cast<std::size_t>(k)];
    const auto& subset = anchors[kept_anchor[static_cast<std::size_t>(k)]].subset;
    h.scene_to_model = refinePoseOnField(model.field(), pivot, scale, subset, h.scene_to_model,
                                         params.field_refinement)
                           .scene_to_model;
    h.score = fieldKernelScore(model.field(), subset, h.scene_to_model, params.fine_kernel);
  }
  std::stable_sort(kept.begin(), kept.end(), [](const PoseHypothesis& a, const PoseHypothesis& b) {
    return a.score > b.score;
  });
}

}  // namespace

std::vector<PoseHypothesis> globalSearch(const IcfModel& model,
                                         const std::vector<Eigen::Vector3f>& scene_points,
                                         const Eigen::Vector3f& camera,
                                         const GlobalSearchParams& params, std::uint64_t seed,
                                         int threads) {
  params.validate();
  if (scene_points.empty())
    return {};
  const std::vector<SearchAnchor> anchors =
      internal::translationAnchors(scene_points, model.radius(), params, seed);
  const Eigen::Vector3f centroid = internal::robustCentroid(scene_points);
  Eigen::Vector3f view = centroid - camera;
  view = view.norm() > 1e-9f ? Eigen::Vector3f(view.normalized()) : Eigen::Vector3f::UnitZ();
  std::vector<std::size_t> anchor_of, kept_anchor;
  const std::vector<PoseHypothesis> coarse =
      coarsePass(model, anchors, view, params, seed, threads, anchor_of);
  std::vector<PoseHypothesis> kept = bestDistinct(model, coarse, anchor_of, params, kept_anchor);
  refineOnField(model, anchors, kept_anchor, params, threads, kept);
  return kept;
}

}  // namespace icf
}  // namespace pcl
