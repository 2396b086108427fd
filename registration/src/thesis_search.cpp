/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/thesis_search.h>
#include <pcl_icf_internal/parameter_check.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

void ThesisSearchParams::validate() const {
  const internal::ParameterCheck fail("ThesisSearchParams");
  if (outer_iterations < 1 || outer_iterations > 1000000)
    fail("outer_iterations", outer_iterations, "must lie in [1, 1e6]");
  if (orientation_iterations < 1 || orientation_iterations > 1000000)
    fail("orientation_iterations", orientation_iterations, "must lie in [1, 1e6]");
  if (samples_per_kernel < 1 || samples_per_kernel > 1000000)
    fail("samples_per_kernel", samples_per_kernel, "must lie in [1, 1e6]");
  for (float v : {initial_translation_sigma, restart_translation_sigma, min_translation_sigma,
                  initial_rotation_sigma, min_rotation_sigma})
    if (!(v > 0.f) || !std::isfinite(v))
      fail("*_sigma", v, "every sigma must be positive and finite");
  if (!(translation_sigma_step >= 0.f) || !(rotation_sigma_step >= 0.f))
    fail("*_sigma_step", -1, "must be >= 0");
  if (stall_limit < 1)
    fail("stall_limit", stall_limit, "must be at least 1");
}

namespace {

/** A pose of the search: the position of the model's surface centroid in the scene and Euler
 * angles (x, y, z) of the model's rotation, as the thesis parametrises it. */
struct SearchPose {
  Eigen::Vector3f t = Eigen::Vector3f::Zero();
  Eigen::Vector3f angles = Eigen::Vector3f::Zero();
  double score = 0.0;
};

Eigen::Isometry3f sceneToModel(const SearchPose& p, const Eigen::Vector3f& model_centre) {
  const Eigen::Matrix3f R = (Eigen::AngleAxisf(p.angles.z(), Eigen::Vector3f::UnitZ()) *
                             Eigen::AngleAxisf(p.angles.y(), Eigen::Vector3f::UnitY()) *
                             Eigen::AngleAxisf(p.angles.x(), Eigen::Vector3f::UnitX()))
                                .toRotationMatrix();
  Eigen::Isometry3f model_to_scene = Eigen::Isometry3f::Identity();
  model_to_scene.linear() = R;
  model_to_scene.translation() = p.t - R * model_centre;
  return model_to_scene.inverse();
}

class Evaluator {
 public:
  Evaluator(const IcfModel& model, const std::vector<Eigen::Vector3f>& points,
            const ThesisSearchParams& params, const ObjectiveParams& objective)
      : model_(model), points_(points), params_(params), objective_(objective) {}

  double operator()(const SearchPose& pose) const {
    const Eigen::Isometry3f T = sceneToModel(pose, model_.mesh().surfaceCentroid());
    std::vector<Eigen::Vector3f> moved(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i)
      moved[i] = T * points_[i];
    if (params_.use_field)
      return objectiveValue(
          moved, [this](const Eigen::Vector3f& x) { return model_.field().distance(x); },
          objective_);
    const float radius =
        std::max(objective_.cutoff / objective_.far_factor, objective_.early_exit_distance) * 1.01f;
    return objectiveValue(
        moved,
        [this, radius](const Eigen::Vector3f& x) {
          return model_.index().closestFace(x, radius).distance;
        },
        objective_);
  }

 private:
  const IcfModel& model_;
  const std::vector<Eigen::Vector3f>& points_;
  const ThesisSearchParams& params_;
  const ObjectiveParams& objective_;
};

/** The search's random draws, all from one generator in the thesis's order: uniform
 * translations in the cluster's bounding box, uniform Euler angles, Gaussian kernel offsets. */
class Draws {
 public:
  Draws(std::uint64_t seed, const std::vector<Eigen::Vector3f>& points)
      : rng_(seed), angle_(-kPi, kPi), lo_(points.front()), hi_(lo_) {
    for (const auto& p : points) {
      lo_ = lo_.cwiseMin(p);
      hi_ = hi_.cwiseMax(p);
    }
  }

  Eigen::Vector3f translation() {
    Eigen::Vector3f t;
    for (int a = 0; a < 3; ++a)
      t[a] = std::uniform_real_distribution<float>(lo_[a], hi_[a])(rng_);
    return t;
  }
  Eigen::Vector3f angles() { return Eigen::Vector3f(angle_(rng_), angle_(rng_), angle_(rng_)); }
  /** Three standard normal draws: a kernel's offset before its sigma. */
  Eigen::Vector3f gaussian() { return Eigen::Vector3f(gauss_(rng_), gauss_(rng_), gauss_(rng_)); }

 private:
  static constexpr float kPi = 3.14159265f;
  std::mt19937_64 rng_;
  std::normal_distribution<float> gauss_;
  std::uniform_real_distribution<float> angle_;
  Eigen::Vector3f lo_, hi_;
};

SearchPose bestOf(const std::vector<SearchPose>& poses) {
  return *std::max_element(
      poses.begin(), poses.end(),
      [](const SearchPose& a, const SearchPose& b) { return a.score < b.score; });
}

/** The two inner loops of Algorithm 2 at translation \a t: from random Euler angles, a kernel
 * of samples_per_kernel orientations around the best so far, its sigma shrinking each
 * iteration; after stall_limit iterations without a better score the local maximum goes to
 * BestList and the kernel restarts wide around new random angles. Returns BestList's best.
 * \a kernel_samples is the caller's buffer (samples_per_kernel entries), scored in parallel. */
SearchPose searchOrientations(const Eigen::Vector3f& t, const ThesisSearchParams& params,
                              const Evaluator& evaluate, Draws& draws,
                              std::vector<SearchPose>& kernel_samples, int threads) {
  Eigen::Vector3f angles = draws.angles();
  float sigma_r = params.initial_rotation_sigma;
  std::vector<SearchPose> best_list, pose_list;
  double loop_best = -1.0;
  int stalls = 0;
  SearchPose best_pose;
  for (int it2 = 0; it2 < params.orientation_iterations; ++it2) {
    sigma_r = std::max(params.min_rotation_sigma, sigma_r - params.rotation_sigma_step);
    if (stalls >= params.stall_limit) {  // local maximum: save it, restart wide and random
      if (!pose_list.empty())
        best_list.push_back(pose_list.front());
      pose_list.clear();
      sigma_r = params.initial_rotation_sigma;
      angles = draws.angles();
      stalls = 0;
      loop_best = -1.0;
    }
    for (SearchPose& s : kernel_samples) {
      s.t = t;
      s.angles = angles + sigma_r * draws.gaussian();
    }
    const int n = static_cast<int>(kernel_samples.size());
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
    for (int k = 0; k < n; ++k)
      kernel_samples[static_cast<std::size_t>(k)].score =
          evaluate(kernel_samples[static_cast<std::size_t>(k)]);
    best_pose = bestOf(kernel_samples);
    if (!pose_list.empty() && pose_list.front().score >= best_pose.score)
      best_pose = pose_list.front();  // the kernel's mean stays when nothing beats it
    pose_list.assign(1, best_pose);
    angles = best_pose.angles;
    stalls = best_pose.score > loop_best ? 0 : stalls + 1;
    loop_best = std::max(loop_best, best_pose.score);
  }
  best_list.push_back(best_pose);
  return bestOf(best_list);
}

}  // namespace

PoseHypothesis thesisSearch(const IcfModel& model, const std::vector<Eigen::Vector3f>& scene_points,
                            const ThesisSearchParams& params, const ObjectiveParams& objective,
                            std::uint64_t seed, int threads) {
  params.validate();
  objective.validate();
  PoseHypothesis out;
  if (scene_points.empty())
    return out;
  const Evaluator evaluate(model, scene_points, params, objective);
  Draws draws(seed, scene_points);

  SearchPose best;
  Eigen::Vector3f best_xyz = draws.translation();
  float sigma_t = params.initial_translation_sigma;
  bool translation_stuck = false;
  int translation_stalls = 0;
  std::vector<SearchPose> best_transl;
  std::vector<SearchPose> kernel_samples(static_cast<std::size_t>(params.samples_per_kernel));

  for (int it1 = 0; it1 < params.outer_iterations; ++it1) {
    if (!translation_stuck) {
      sigma_t = std::max(params.min_translation_sigma, sigma_t - params.translation_sigma_step);
    } else {
      sigma_t = params.restart_translation_sigma;
      best_xyz = draws.translation();
      best_transl.push_back(best);
      translation_stuck = false;
      translation_stalls = 0;
    }
    SearchPose pose;
    pose.t = best_xyz + sigma_t * draws.gaussian();
    pose.angles = best.angles;
    pose.score = evaluate(pose);
    if (pose.score > best.score)
      best = pose;

    const SearchPose round_best =
        searchOrientations(pose.t, params, evaluate, draws, kernel_samples, threads);
    if (round_best.score >= best.score && round_best.score > 0.0) {
      translation_stalls = round_best.score > best.score ? 0 : translation_stalls + 1;
      best = round_best;
      best_xyz = best.t;
    } else {
      ++translation_stalls;
    }
    translation_stuck = translation_stalls >= params.stall_limit && best.score > 0.0;
    best_transl.push_back(best);
  }
  const SearchPose final_best = bestOf(best_transl);
  out.scene_to_model = sceneToModel(final_best, model.mesh().surfaceCentroid());
  out.score = final_best.score;
  return out;
}

}  // namespace icf
}  // namespace pcl
