/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/objective.h>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Parameters of the thesis's stochastic kernel search (section 4.3.2, Algorithm 2).
 * Defaults are the thesis's values (threshold1..3 = 50, 100, 20; kernels shrinking by 10 mm
 * and 10 degrees; restart after 3 stalls), lengths in scene units. The minimum sigmas are
 * ours: the thesis's decrements would otherwise drive them below zero. */
struct ThesisSearchParams {
  int outer_iterations = 50;                 ///< threshold1: translation kernels
  int orientation_iterations = 100;          ///< threshold2: orientation kernels per translation
  int samples_per_kernel = 20;               ///< threshold3: samples drawn from each kernel
  float initial_translation_sigma = 0.050f;  ///< k.loch = 50 mm
  float translation_sigma_step = 0.010f;     ///< decreased by 10 mm per outer iteration
  float restart_translation_sigma = 0.020f;  ///< "carried up to 20 mm" at a local maximum
  float min_translation_sigma = 0.002f;
  float initial_rotation_sigma = 3.14159265f;  ///< k.orih = 180 degrees
  float rotation_sigma_step = 0.17453293f;     ///< decreased by 10 degrees
  float min_rotation_sigma = 0.017453293f;     ///< 1 degree
  int stall_limit = 3;                         ///< "does not change for more than 3 iterations"
  /** Score through the closest-point field (our speed-up) instead of exact distances. */
  bool use_field = true;

  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;
};

/** \brief The thesis's search, faithful (doc/icf.md section 7): a random translation inside
 * the cluster's bounding box, Gaussian kernels around the best translation and the best Euler
 * angles, shrinking each iteration and re-randomised and widened at a local maximum; BestList
 * and BestTransl kept as described. Scores with the thesis objective F (with its early exit).
 * Returns the best pose found; deterministic for a seed and any thread count. */
PoseHypothesis thesisSearch(const IcfModel& model, const std::vector<Eigen::Vector3f>& scene_points,
                            const ThesisSearchParams& params, const ObjectiveParams& objective,
                            std::uint64_t seed, int threads = 1);

}  // namespace icf
}  // namespace pcl
