/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl_icf_internal/parameter_check.h>
#include <pcl_icf_internal/search_anchors.h>

#include <omp.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

SearchStrategy parseSearchStrategy(const std::string& name) {
  if (name == "fast")
    return SearchStrategy::Fast;
  if (name == "thesis")
    return SearchStrategy::Thesis;
  throw std::invalid_argument("unknown search strategy '" + name + "' (expected fast or thesis)");
}

std::string toString(SearchStrategy strategy) {
  return strategy == SearchStrategy::Fast ? "fast" : "thesis";
}

FallbackPolicy parseFallbackPolicy(const std::string& name) {
  if (name == "off")
    return FallbackPolicy::Off;
  if (name == "auto")
    return FallbackPolicy::Auto;
  if (name == "always")
    return FallbackPolicy::Always;
  throw std::invalid_argument("unknown fallback policy '" + name +
                              "' (expected off, auto or always)");
}

std::string toString(FallbackPolicy policy) {
  switch (policy) {
    case FallbackPolicy::Off:
      return "off";
    case FallbackPolicy::Auto:
      return "auto";
    case FallbackPolicy::Always:
      return "always";
  }
  return "unknown";
}

std::string toString(IcfStatus status) {
  switch (status) {
    case IcfStatus::NotRun:
      return "not run";
    case IcfStatus::Accepted:
      return "accepted";
    case IcfStatus::Rejected:
      return "rejected";
    case IcfStatus::TooFewPoints:
      return "too few points";
    case IcfStatus::NoModel:
      return "no model";
  }
  return "unknown";
}

void ObjectiveParams::validate() const {
  const internal::ParameterCheck fail("ObjectiveParams");
  if (!(near_distance > 0.f) || !std::isfinite(near_distance))
    fail("near_distance", near_distance, "must be positive and finite");
  if (!(far_factor >= 1.f) || !std::isfinite(far_factor))
    fail("far_factor", far_factor, "must be finite and >= 1");
  if (!(cutoff > 0.f) || !std::isfinite(cutoff))
    fail("cutoff", cutoff, "must be positive and finite");
  if (!(early_exit_distance > 0.f) || !std::isfinite(early_exit_distance))
    fail("early_exit_distance", early_exit_distance, "must be positive and finite");
  if (early_exit_count < 0)
    fail("early_exit_count", early_exit_count, "must be >= 0");
}

void FarPointGate::validate() const {
  const internal::ParameterCheck fail("FarPointGate");
  if (!(distance > 0.f) || !std::isfinite(distance))
    fail("distance", distance, "must be positive and finite");
  if (max_points < 0)
    fail("max_points", max_points, "must be >= 0");
  if (!(max_fraction >= 0.0 && max_fraction <= 1.0))
    fail("max_fraction", max_fraction, "must lie in [0, 1]");
}

void AcceptanceParams::validate() const {
  const internal::ParameterCheck fail("AcceptanceParams");
  if (!(inlier_distance > 0.f) || !std::isfinite(inlier_distance))
    fail("inlier_distance", inlier_distance, "must be positive and finite");
  if (!(min_surface_coverage >= 0.0 && min_surface_coverage <= 1.0))
    fail("min_surface_coverage", min_surface_coverage, "must lie in [0, 1]");
  if (!(max_rmse > 0.0) || !std::isfinite(max_rmse))
    fail("max_rmse", max_rmse, "must be positive and finite");
  gate.validate();
  if (!(max_seen_through >= 0.0 && max_seen_through <= 1.0))
    fail("max_seen_through", max_seen_through, "must lie in [0, 1]");
}

void IcfTuning::validate(bool with_sac) const {
  global.validate();
  thesis.validate();
  objective.validate();
  refinement.validate();
  visibility.validate();
  depth.validate();
  if (with_sac)
    sac.validate();
  const internal::ParameterCheck fail("IcfTuning");
  if (exact_candidates < 1)
    fail("exact_candidates", exact_candidates, "must be at least 1");
  if (candidate_points < 3)
    fail("candidate_points", candidate_points, "must be at least 3 (a refinement needs points)");
  if (fine_iterations < 1 || fine_iterations > 100000)
    fail("fine_iterations", fine_iterations, "must lie in [1, 100000]");
}

DepthVerificationParams IcfParams::depthParams() const {
  return tuning_.depth.forSensor(depth_noise, mesh_accuracy);
}

void IcfParams::validate() const {
  acceptance.validate();
  tuning_.validate(fallback != FallbackPolicy::Off);
  depthParams().validate();
  const internal::ParameterCheck fail("IcfParams");
  if (threads < 0 || threads > 1024)
    fail("threads", threads, "must lie in [0, 1024] (0 = all cores)");
}

bool isAcceptable(const PoseQuality& q, const AcceptanceParams& p) {
  if (q.inliers < p.min_inliers || q.surface_coverage < p.min_surface_coverage ||
      q.rmse > p.max_rmse || q.seen_through > p.max_seen_through)
    return false;
  return !p.gate.enabled || q.far_points <= p.gate.allowed(q.points);
}

namespace {

double exactKernelScore(const ClosestFaceQuery& index, const std::vector<Eigen::Vector3f>& points,
                        const Eigen::Isometry3f& scene_to_model, float kernel, int threads) {
  std::vector<float> scores(points.size());
  const int n = static_cast<int>(points.size());
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    scores[k] = kernelScore(index.closestFace(scene_to_model * points[k], kernel).distance, kernel);
  }
  double score = 0.0;  // summed in order: the same for any thread count
  for (float s : scores)
    score += s;
  return score;
}

/** The points that can belong to the model at a pose: within its radius plus \a margin of its
 * surface centroid. In a merged cluster the rest belongs to other objects and only costs
 * closest-face queries. */
std::vector<Eigen::Vector3f> pointsNearModel(const IcfModel& model,
                                             const std::vector<Eigen::Vector3f>& points,
                                             const Eigen::Isometry3f& scene_to_model,
                                             float margin) {
  const float r = model.radius() + margin;
  const Eigen::Vector3f& c = model.mesh().surfaceCentroid();
  std::vector<Eigen::Vector3f> near;
  near.reserve(points.size());
  for (const auto& p : points)
    if ((scene_to_model * p - c).squaredNorm() < r * r)
      near.push_back(p);
  return near;
}

/** The fast strategy's start for the final refinement: the global search's best hypotheses,
 * each refined with exact faces on a subset, the best by the fine kernel. */
PoseHypothesis fastSearch(const IcfModel& model, const std::vector<Eigen::Vector3f>& points,
                          const Eigen::Vector3f& camera, const IcfParams& params, int threads,
                          const StartCheck& worth_refining) {
  const IcfTuning& tuning = params.tuning();
  const std::vector<PoseHypothesis> hypotheses =
      globalSearch(model, points, camera, tuning.global, params.seed, threads);
  const std::size_t n = std::min(tuning.exact_candidates, hypotheses.size());
  // No candidate the caller's check gives a chance: the search's best as it is, unrefined.
  if (tuning.check_candidates && worth_refining && n > 0 &&
      std::none_of(hypotheses.begin(), hypotheses.begin() + static_cast<std::ptrdiff_t>(n),
                   [&](const PoseHypothesis& h) { return worth_refining(h.scene_to_model); }))
    return hypotheses.front();
  // One candidate after the other, each on every thread: three candidates on two cores would
  // otherwise take two rounds with one core idle in the second.
  PoseHypothesis best;
  best.score = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::vector<Eigen::Vector3f> subset =
        internal::randomSubset(pointsNearModel(model, points, hypotheses[i].scene_to_model,
                                               tuning.refinement.initial_inlier_distance),
                               tuning.candidate_points, params.seed + 1);
    const RefinementResult refined =
        refinePose(model.index(), subset, hypotheses[i].scene_to_model, tuning.refinement, threads);
    const double score = exactKernelScore(model.index(), subset, refined.scene_to_model,
                                          tuning.global.fine_kernel, threads);
    if (score > best.score)
      best = PoseHypothesis{refined.scene_to_model, score};
  }
  return best;
}

/** refinePose on at most \a coarse_points points (from params.initial_inlier_distance down the
 * schedule), then on all of \a params' from the final Tukey radius for at most
 * \a fine_iterations (the coarse stage has reached it). The callback sees the iterations of
 * both stages numbered on. */
RefinementResult refineCoarseToFine(const ClosestFaceQuery& index,
                                    const std::vector<Eigen::Vector3f>& points,
                                    const Eigen::Isometry3f& from, const RefinementParams& params,
                                    std::size_t coarse_points, int fine_iterations, int threads,
                                    const IterationCallback& callback) {
  const std::size_t fine_points = params.max_points > 0 ? params.max_points : points.size();
  if (coarse_points == 0 || fine_points <= 2 * coarse_points)
    return refinePose(index, points, from, params, threads, callback);
  RefinementParams coarse = params;
  coarse.max_points = coarse_points;
  const RefinementResult first = refinePose(index, points, from, coarse, threads, callback);
  RefinementParams fine = params;
  fine.initial_inlier_distance = params.final_inlier_distance;
  fine.max_iterations = std::min(params.max_iterations, fine_iterations);
  IterationCallback numbered;
  if (callback)
    numbered = [&](const Eigen::Isometry3f& t, int k) { callback(t, first.iterations + k); };
  RefinementResult out = refinePose(index, points, first.scene_to_model, fine, threads, numbered);
  out.iterations += first.iterations;
  return out;
}

/** The depth image the seen-through check compares poses with, and the scene frame's transform
 * into that image's camera frame. */
struct CheckImage {
  DepthImage image;
  Eigen::Isometry3f scene_to_camera = Eigen::Isometry3f::Identity();
};

/** \a points (scene frame) as a virtual camera at \a camera looking at their centroid sees them,
 * in pixels of DepthImage::virtualPixelAngle: a cluster's own depth image, as the
 * localizer makes one for an unorganized scene. Looking along the scene's z axis the camera's
 * axes are the scene's. */
CheckImage clusterDepthImage(const std::vector<Eigen::Vector3f>& points,
                             const Eigen::Vector3f& camera) {
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : points)
    centroid += p;
  centroid /= static_cast<float>(points.size());
  Eigen::Vector3f z = centroid - camera;
  z = z.norm() > 0.f ? Eigen::Vector3f(z.normalized()) : Eigen::Vector3f::UnitZ();
  Eigen::Vector3f x = Eigen::Vector3f::UnitY().cross(z);
  if (x.norm() < 1e-3f)
    x = z.unitOrthogonal();
  x.normalize();
  CheckImage out;
  out.scene_to_camera.linear().row(0) = x;
  out.scene_to_camera.linear().row(1) = z.cross(x);
  out.scene_to_camera.linear().row(2) = z;
  out.scene_to_camera.translation() = -(out.scene_to_camera.linear() * camera);
  std::vector<Eigen::Vector3f> seen(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    seen[i] = out.scene_to_camera * points[i];
  out.image =
      DepthImage(seen, DepthImage::virtualCamera(seen, DepthImage::virtualPixelAngle(seen, 200)));
  return out;
}

/** PoseQuality::seen_through of the model at \a scene_to_model against \a image, whose camera
 * frame the scene's maps into by \a scene_to_camera. */
double seenThrough(const IcfModel& model, const Eigen::Isometry3f& scene_to_model,
                   const DepthImage& image, const Eigen::Isometry3f& scene_to_camera,
                   const DepthVerificationParams& params) {
  // The model beyond the image is not drawn: the share computed here leaves it out anyway.
  const ModelDepth rendered = renderModelDepth(
      model, scene_to_camera * scene_to_model.inverse(Eigen::Isometry), image.intrinsics(), false);
  const DepthExplanation e = explainDepth(rendered, image, 2.f * model.radius(), params);
  const double conflicts = e.seen_through + e.below_support;
  return conflicts > 0.0 ? conflicts / (e.supported + conflicts) : 0.0;
}

/** What refining one start gave: the refinement, the quality measured at its end and the
 * decision. */
struct Outcome {
  RefinementResult refined;
  PoseQuality quality;
  bool accepted = false;
  bool skipped = false;  ///< worth_refining said no: the start as it is
};

/** The points of \a scene_points estimatePose works on (isUsablePoint), in their order. */
std::vector<Eigen::Vector3f> usablePoints(const std::vector<Eigen::Vector3f>& scene_points) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(scene_points.size());
  for (const auto& p : scene_points)
    if (isUsablePoint(p))
      points.push_back(p);
  return points;
}

/** One estimatePose call on its usable points: where it starts (a guess, a search, SAC) and
 * how every start is refined, measured and judged, the same way for each. */
class PoseEstimation {
 public:
  PoseEstimation(const IcfModel& model, const std::vector<Eigen::Vector3f>& points,
                 const Eigen::Vector3f& camera, const IcfParams& params,
                 const Eigen::Isometry3f* guess, const StartCheck& worth_refining,
                 const DepthImage* camera_image)
      : model_(model),
        points_(points),
        camera_(camera),
        params_(params),
        tuning_(params.tuning()),
        depth_(params.depthParams()),
        guess_(guess),
        worth_refining_(worth_refining),
        threads_(params.threads > 0 ? params.threads : omp_get_num_procs()) {
    // The seen-through check's image: the caller's, else the cluster's own.
    if (params.acceptance.max_seen_through < 1.0) {
      if (!camera_image) {
        own_image_ = clusterDepthImage(points, camera);
        scene_to_camera_ = own_image_->scene_to_camera;
      }
      check_image_ = camera_image ? camera_image : &own_image_->image;
    }
  }
  PoseEstimation(const PoseEstimation&) = delete;  // check_image_ may point into own_image_
  PoseEstimation& operator=(const PoseEstimation&) = delete;

  /** The first start: the guess, SAC's (policy Always) or the search's (params.strategy);
   * IcfResult::method, search_score and the SAC fields filled in. */
  Eigen::Isometry3f firstStart(IcfResult& result) const {
    if (guess_) {
      result.method = "guess+icf";
      return *guess_;
    }
    if (params_.fallback == FallbackPolicy::Always) {
      result.method = "sac+icf";
      return sacStart(result);
    }
    const PoseHypothesis h =
        params_.strategy == SearchStrategy::Thesis
            ? thesisSearch(model_, points_, tuning_.thesis, tuning_.objective, params_.seed,
                           threads_)
            : fastSearch(model_, points_, camera_, params_, threads_, worth_refining_);
    result.search_score = h.score;
    result.method = params_.strategy == SearchStrategy::Thesis ? "thesis+icf" : "fast+icf";
    return h.scene_to_model;
  }

  /** Refine from \a from (ICP's one stage with a guess, else coarse to fine), measure with
   * exact distances and the seen-through check, accept or reject. A start worth_refining
   * refuses is returned as it is, skipped. */
  Outcome refineAndMeasure(const Eigen::Isometry3f& from, const IterationCallback& cb) const {
    Outcome o;
    if (!guess_ && worth_refining_ && !worth_refining_(from)) {
      o.refined.scene_to_model = from;
      o.skipped = true;
      return o;
    }
    // Every start runs the whole Tukey schedule. Starting a converged fast-search candidate at
    // the smallest radius was measured a quarter faster on real crops with the same successes,
    // but under clang's rounding it left the second of two touching copies unfound
    // (Localizer/TwoCopies.GiveTwoInstances/1; doc/BENCHMARKS.md): not the default until that
    // is understood.
    o.refined =
        guess_ ? refinePose(model_.index(), points_, from, tuning_.refinement, threads_, cb)
               : refineCoarseToFine(model_.index(), points_, from, tuning_.refinement,
                                    tuning_.coarse_points, tuning_.fine_iterations, threads_, cb);
    o.quality = measurePoseQuality(
        model_, points_, o.refined.scene_to_model, camera_, params_.acceptance.inlier_distance,
        params_.acceptance.gate.distance, tuning_.objective, tuning_.visibility, threads_);
    if (check_image_)
      o.quality.seen_through =
          seenThrough(model_, o.refined.scene_to_model, *check_image_, scene_to_camera_, depth_);
    o.accepted = isAcceptable(o.quality, params_.acceptance);
    return o;
  }

  /** The Auto fallback after a rejected search pose: SAC's start, when SAC finds one, refined
   * and measured; it replaces \a best when accepted or when it covers more of the model's
   * visible surface (accepted beats rejected; between two rejected poses, more coverage). */
  void tryFallback(Outcome& best, IcfResult& result, const IterationCallback& cb) const {
    const Eigen::Isometry3f sac_pose = sacStart(result);
    if (result.sac_status != SacStatus::Found)
      return;
    Outcome fallback = refineAndMeasure(sac_pose, cb);
    if (fallback.accepted || fallback.quality.surface_coverage > best.quality.surface_coverage) {
      best = fallback;
      result.method = "sac+icf";
    }
  }

 private:
  /** The SampleConsensus start: SAC's transform, or the centroid start (the model's surface
   * centroid on the points' centroid, no rotation) when it finds nothing. */
  Eigen::Isometry3f sacStart(IcfResult& result) const {
    const SacResult sac = sampleConsensusAlign(model_, points_, camera_, tuning_.sac, threads_);
    result.fallback_ran = true;
    result.sac_status = sac.status;
    if (sac.found())
      return Eigen::Isometry3f(sac.scene_to_model);
    Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
    for (const auto& p : points_)
      centroid += p;
    centroid /= static_cast<float>(points_.size());
    Eigen::Isometry3f start = Eigen::Isometry3f::Identity();
    start.translation() = model_.mesh().surfaceCentroid() - centroid;
    return start;
  }

  const IcfModel& model_;
  const std::vector<Eigen::Vector3f>& points_;
  const Eigen::Vector3f& camera_;
  const IcfParams& params_;
  const IcfTuning& tuning_;
  const DepthVerificationParams depth_;  ///< params_.depthParams(), made once
  const Eigen::Isometry3f* guess_;
  const StartCheck& worth_refining_;
  const int threads_;
  std::optional<CheckImage> own_image_;
  const DepthImage* check_image_ = nullptr;
  Eigen::Isometry3f scene_to_camera_ = Eigen::Isometry3f::Identity();
};

/** The chosen outcome into \a result: the pose both ways, the refinement's facts, the quality
 * and the status. */
void report(const Outcome& best, IcfResult& result) {
  result.refinement_skipped = best.skipped;
  result.refinement_iterations = best.refined.iterations;
  result.refinement_converged = best.refined.converged;
  result.scene_to_model = best.refined.scene_to_model.matrix();
  result.object_pose = best.refined.scene_to_model.inverse().matrix();
  result.quality = best.quality;
  result.status = best.accepted ? IcfStatus::Accepted : IcfStatus::Rejected;
}

}  // namespace

IcfResult estimatePose(const IcfModel& model, const std::vector<Eigen::Vector3f>& scene_points,
                       const Eigen::Vector3f& camera, const IcfParams& params,
                       const PoseEstimateOptions& options) {
  params.validate();
  const Eigen::Isometry3f* guess = options.guess ? &*options.guess : nullptr;
  const IterationCallback& callback = options.callback;
  const auto start = std::chrono::steady_clock::now();
  IcfResult result;
  const std::vector<Eigen::Vector3f> points = usablePoints(scene_points);
  result.points = points.size();
  if (points.size() < std::max<std::size_t>(params.acceptance.min_inliers, 6)) {
    result.status = IcfStatus::TooFewPoints;
    return result;
  }
  if (guess && !guess->matrix().allFinite())
    throw std::invalid_argument("estimatePose: the initial guess has a non-finite entry");
  const PoseEstimation estimation(model, points, camera, params, guess, options.worth_refining,
                                  options.camera_image);
  Outcome best = estimation.refineAndMeasure(estimation.firstStart(result), callback);
  // A start the caller refused (worth_refining) ends the search here: the caller's check says
  // the cluster holds nothing it could accept near the search's best.
  if (!guess && params.fallback == FallbackPolicy::Auto && !best.accepted && !best.skipped)
    estimation.tryFallback(best, result, callback);
  report(best, result);
  result.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace icf
}  // namespace pcl
