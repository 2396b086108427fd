/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/closest_face_query.h>

#include <Eigen/Geometry>

#include <functional>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Parameters of the local refinement (iterative closest face; doc/icf.md section 5).
 * Lengths in scene units. */
struct RefinementParams {
  int max_iterations = 30;
  /** Tukey radius of the first iteration: residuals beyond it get no weight. */
  float initial_inlier_distance = 0.02f;
  /** The radius shrinks by this factor per iteration down to final_inlier_distance. */
  float inlier_shrink = 0.7f;
  /** Smallest Tukey radius: about 3 sigma of the sensor noise at 1 m, plus model error. */
  float final_inlier_distance = 0.006f;
  /** Levenberg-Marquardt damping, relative to the mean diagonal of the normal equations. */
  float damping = 1e-4f;
  /** A direction whose eigenvalue is below this fraction of the largest is degenerate (the
   * axis of a cylinder, the in-plane motions of a plane) and is not moved. */
  float degeneracy_ratio = 1e-3f;
  /** Stop when a step moves less than this (squared translation, PCL's convention) ... */
  double transformation_epsilon = 1e-10;
  /** ... and turns less than this (radians). */
  double rotation_epsilon = 1e-5;
  /** Stop when the weighted mean squared residual changes by less than this fraction of its
   * previous value (relative, PCL's ICP convention; 0: never). */
  double euclidean_fitness_epsilon = 0.0;
  /** About this many points per iteration: every k-th point, k = (points / max_points) rounded
   * down, so from max_points to just under twice as many (5,999 points and 3,000 use all).
   * 0: all. */
  std::size_t max_points = 0;

  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;
};

/** \brief What the refinement did. */
struct RefinementResult {
  Eigen::Isometry3f scene_to_model = Eigen::Isometry3f::Identity();
  int iterations = 0;
  bool converged = false;         ///< a stopping criterion was met before max_iterations
  int degenerate_directions = 0;  ///< at the last iteration
  double weighted_rmse = 0.0;     ///< at the last iteration, scene units
};

/** \brief Called after each iteration with the current scene-to-model transform. */
using IterationCallback = std::function<void(const Eigen::Isometry3f&, int iteration)>;

/** \brief Iterative closest face (doc/icf.md eq. 5-7): exact closest faces for the points, a
 * Tukey-weighted point-to-plane Gauss-Newton step (the residual along the face normal inside
 * a face, along (p - c)/|p - c| on edges and vertices), Levenberg-Marquardt damping and a
 * degeneracy check that freezes unconstrained directions; repeated to convergence.
 *
 * \param index exact closest-face queries in the model frame
 * \param scene_points finite points in the scene frame
 * \param initial scene-to-model transform to start from
 * \param threads for the closest-face queries (the sum is reduced in a fixed order, so the
 *        result does not depend on it) */
RefinementResult refinePose(const ClosestFaceQuery& index,
                            const std::vector<Eigen::Vector3f>& scene_points,
                            const Eigen::Isometry3f& initial, const RefinementParams& params,
                            int threads = 1, const IterationCallback& callback = {});

class ClosestPointField;

/** \brief The same iteration with closest points from the field instead of exact faces (the
 * residual direction is (p - c~)/|p - c~|): a cheap first refinement of many hypotheses.
 * Accurate to the field's error (ClosestPointField::errorBound). */
RefinementResult refinePoseOnField(const ClosestPointField& field, const Eigen::Vector3f& pivot,
                                   double scale, const std::vector<Eigen::Vector3f>& scene_points,
                                   const Eigen::Isometry3f& initial,
                                   const RefinementParams& params);

}  // namespace icf
}  // namespace pcl
