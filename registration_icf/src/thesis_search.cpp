/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/thesis_search.h>
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
            const ThesisSearchParams& params, const ThesisObjectiveParams& objective)
      : model_(model), points_(points), params_(params), objective_(objective) {}

  double operator()(const SearchPose& pose) const {
    const Eigen::Isometry3f T = sceneToModel(pose, model_.mesh().surfaceCentroid());
    std::vector<Eigen::Vector3f> moved(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i)
      moved[i] = T * points_[i];
    if (params_.use_field)
      return thesisObjective(
          moved, [this](const Eigen::Vector3f& x) { return model_.field().distance(x); },
          objective_);
    const float radius =
        std::max(objective_.cutoff / objective_.far_factor, objective_.early_exit_distance) * 1.01f;
    return thesisObjective(
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
  const ThesisObjectiveParams& objective_;
};

}  // namespace

PoseHypothesis thesisSearch(const IcfModel& model, const std::vector<Eigen::Vector3f>& scene_points,
                            const ThesisSearchParams& params,
                            const ThesisObjectiveParams& objective, std::uint64_t seed,
                            int threads) {
  params.validate();
  objective.validate();
  PoseHypothesis out;
  if (scene_points.empty())
    return out;
  const Evaluator evaluate(model, scene_points, params, objective);
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> gauss;
  constexpr float kPi = 3.14159265f;
  std::uniform_real_distribution<float> angle(-kPi, kPi);
  Eigen::Vector3f lo = scene_points.front(), hi = lo;
  for (const auto& p : scene_points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  auto randomTranslation = [&] {
    Eigen::Vector3f t;
    for (int a = 0; a < 3; ++a)
      t[a] = std::uniform_real_distribution<float>(lo[a], hi[a])(rng);
    return t;
  };
  auto randomAngles = [&] { return Eigen::Vector3f(angle(rng), angle(rng), angle(rng)); };

  SearchPose best;
  Eigen::Vector3f best_xyz = randomTranslation();
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
      best_xyz = randomTranslation();
      best_transl.push_back(best);
      translation_stuck = false;
      translation_stalls = 0;
    }
    SearchPose pose;
    pose.t = best_xyz + sigma_t * Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng));
    pose.angles = best.angles;
    pose.score = evaluate(pose);
    if (pose.score > best.score)
      best = pose;

    // Orientation search for this translation (the two inner loops).
    Eigen::Vector3f angles = randomAngles();
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
        angles = randomAngles();
        stalls = 0;
        loop_best = -1.0;
      }
      for (SearchPose& s : kernel_samples) {
        s.t = pose.t;
        s.angles = angles + sigma_r * Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng));
      }
      const int n = static_cast<int>(kernel_samples.size());
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
      for (int k = 0; k < n; ++k)
        kernel_samples[static_cast<std::size_t>(k)].score =
            evaluate(kernel_samples[static_cast<std::size_t>(k)]);
      best_pose = *std::max_element(
          kernel_samples.begin(), kernel_samples.end(),
          [](const SearchPose& a, const SearchPose& b) { return a.score < b.score; });
      if (!pose_list.empty() && pose_list.front().score >= best_pose.score)
        best_pose = pose_list.front();  // the kernel's mean stays when nothing beats it
      pose_list.assign(1, best_pose);
      angles = best_pose.angles;
      stalls = best_pose.score > loop_best ? 0 : stalls + 1;
      loop_best = std::max(loop_best, best_pose.score);
    }
    best_list.push_back(best_pose);
    const SearchPose round_best = *std::max_element(
        best_list.begin(), best_list.end(),
        [](const SearchPose& a, const SearchPose& b) { return a.score < b.score; });
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
  const SearchPose final_best =
      *std::max_element(best_transl.begin(), best_transl.end(),
                        [](const SearchPose& a, const SearchPose& b) { return a.score < b.score; });
  out.scene_to_model = sceneToModel(final_best, model.mesh().surfaceCentroid());
  out.score = final_best.score;
  return out;
}

}  // namespace icf
}  // namespace pcl
