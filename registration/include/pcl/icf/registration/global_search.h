/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/refinement.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Parameters of the fast global search (doc/icf.md section 4). Lengths in scene units. */
struct GlobalSearchParams {
  /** Rotations sampled uniformly over SO(3) (super-Fibonacci); 3000 leave no rotation
   * more than about 15 degrees of turning from a sample (doc/icf.md section 4), inside the
   * refinement's basin. */
  std::size_t rotations = 3000;
  /** Scene points scored per hypothesis (a seeded random subset). */
  std::size_t subsample = 256;
  /** Model surface samples used to place each rotation's visible centroid. */
  std::size_t centroid_samples = 512;
  /** When 10% of the scene points lie farther from their centroid than merged_cluster_ratio x
   * the model's radius (about its surface centroid), the cluster probably holds other objects
   * too. The search then runs in windows: on a grid of pitch anchor_spacing x the model's
   * radius, each cell with at least min_anchor_points points anchors a window of the points
   * within the model's radius of their mean, scored on its own subsample, with half the
   * rotations; at most max_anchors windows (the densest). */
  float merged_cluster_ratio = 1.2f;
  float anchor_spacing = 0.5f;
  std::size_t min_anchor_points = 30;
  std::size_t max_anchors = 64;
  /** Kernel scale of the coarse score (eq. 4): tolerant of the rotation grid's spacing. */
  float coarse_kernel = 0.02f;
  /** Coarse pass as a cascade: every (rotation, anchor) is first scored on the first
   * prescreen_points of its subsample (itself a random subset), and only the best
   * prescreen_share of them (at least 20 x keep) on the whole subsample. 0 for either: every
   * hypothesis on the whole subsample (calibration: doc/TUNING.md, "The global search"). */
  std::size_t prescreen_points = 64;
  float prescreen_share = 0.1f;
  /** Hypotheses kept after the coarse pass and refined on the field. */
  std::size_t keep = 12;
  /** Two kept hypotheses closer than this (rotation, radians) and ... */
  float distinct_rotation = 0.2f;
  /** ... this (translation, scene units) count as one. */
  float distinct_translation = 0.02f;
  /** Two hypotheses that put the model's surface in the same place count as one too: when
   * every one of the model's (first 64) surface samples, moved from one pose to the other, lies
   * within distinct_surface x the model's radius of its surface. A symmetric model's turns
   * about its axis (a can spun) are then one hypothesis instead of filling the keep slots with
   * copies of one pose while the right one is left out (0: off). 0.2 is distinct_rotation's
   * bound: a turn of 0.2 rad moves no model point more than 0.2 radii. */
  float distinct_surface = 0.2f;
  /** The cheap refinement of each kept hypothesis on the field. */
  RefinementParams field_refinement = defaultFieldRefinement();
  /** Kernel scale of the score that ranks the refined hypotheses. */
  float fine_kernel = 0.008f;

  static RefinementParams defaultFieldRefinement();
  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;
};

/** \brief One pose hypothesis: the registration transform (scene -> model) and its score. */
struct PoseHypothesis {
  Eigen::Isometry3f scene_to_model = Eigen::Isometry3f::Identity();
  double score = 0.0;
};

/** \brief Global search without an initial guess (doc/icf.md section 4).
 *
 * For every rotation R of a uniform SO(3) set, the model is placed so that the centroid of its
 * camera-facing surface (projected-area weighted) falls on the centroid of the scene points,
 * which corrects for the camera seeing only the near side (for a cluster much wider than the
 * model, on local centroids too); the pose is scored on a subsample
 * through the closest-point field with the kernel of eq. 4. The best distinct hypotheses are
 * refined on the field and re-scored with a finer kernel. Returns them best first.
 * Deterministic for a seed; independent of the thread count. */
std::vector<PoseHypothesis> globalSearch(const IcfModel& model,
                                         const std::vector<Eigen::Vector3f>& scene_points,
                                         const Eigen::Vector3f& camera,
                                         const GlobalSearchParams& params, std::uint64_t seed,
                                         int threads = 1);

/** \brief True when a cluster holds more than one object (or more than this one): its spread
 * (the 90th percentile of its points' distances from their robust centroid, which ignores a
 * few far stray points) exceeds params.merged_cluster_ratio x \a model_radius. The global
 * search then searches local windows of the cluster; the localizer splits such a cluster by
 * convexity. */
bool spreadsWiderThanModel(const std::vector<Eigen::Vector3f>& points, float model_radius,
                           const GlobalSearchParams& params);

}  // namespace icf
}  // namespace pcl
