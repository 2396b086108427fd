/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {

/** \brief Parameters of the pose objective F: how many scene points a pose explains, each
 * point's share falling linearly with its distance to the model, steeply beyond a near band,
 * to nothing at a cutoff. It is the objective of the ICF thesis (Armenise, KTH 2013, section 4.2.1;
 * doc/icf.md eq. 1-2), which its search maximises (thesisSearch) and PoseQuality::thesis_score
 * reports. Lengths in scene units.
 *
 * F(P, S) = sum over points x of f(x, P), with d the distance from x to the closest face of
 * the model in pose P, g = d when d < near_distance, else far_factor * d, and
 * f = 1 - g / cutoff when g < cutoff, else 0. Early exit (section 4.3.2): when more than
 * early_exit_count points lie farther than early_exit_distance, F = 0. Defaults are the
 * thesis's values converted from millimetres to metres. */
struct ObjectiveParams {
  float near_distance = 0.030f;        ///< 30 mm
  float far_factor = 4.f;              ///< g = 4 d beyond near_distance
  float cutoff = 0.200f;               ///< m = 200 mm
  bool early_exit = true;              ///< F = 0 when too many points are far
  float early_exit_distance = 0.050f;  ///< "max = 50 mm"
  int early_exit_count = 500;          ///< "more than 500 points"

  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;
};

/** \brief f(x, P): one point's share of F at distance \a d from the model (eq. 1). */
inline float objectivePointScore(float d, const ObjectiveParams& p) {
  const float g = d < p.near_distance ? d : p.far_factor * d;
  return g < p.cutoff ? 1.f - g / p.cutoff : 0.f;
}

/** \brief F(P, S), the objective's value, for points already in the model frame, with
 * distances from \a distance (the exact index or the field), honouring the early exit. */
template <typename DistanceFunction>
double objectiveValue(const std::vector<Eigen::Vector3f>& model_frame_points,
                      const DistanceFunction& distance, const ObjectiveParams& p) {
  double sum = 0.0;
  int far = 0;
  for (const Eigen::Vector3f& x : model_frame_points) {
    const float d = distance(x);
    if (p.early_exit && d > p.early_exit_distance && ++far > p.early_exit_count)
      return 0.0;
    sum += objectivePointScore(d, p);
  }
  return sum;
}

/** \brief The score kernel of the fast global search (doc/icf.md eq. 4): a truncated
 * quadratic, 1 - (d / scale)^2 for d < scale, else 0. Unlike the thesis's f, which falls by
 * only 2.5% from 0 to 5 mm, it separates poses a few millimetres apart; points farther than
 * scale (other objects in a merged cluster) add nothing. */
inline float kernelScore(float d, float scale) {
  const float r = d / scale;
  return r < 1.f ? 1.f - r * r : 0.f;
}

}  // namespace icf
}  // namespace pcl
