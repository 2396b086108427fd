/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to registration (not installed): the pieces of the fast global search
 * (global_search.h, doc/icf.md section 4) that estimatePose shares and unit tests check one by
 * one. Defined in registration/src/global_search.cpp. */

#include <pcl/icf/registration/distance_field.h>
#include <pcl/icf/registration/global_search.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {
namespace internal {

/** \brief Kernel score (doc/icf.md eq. 4) of a pose over points, distances from the field: the
 * sum of kernelScore(d, kernel) over \a scene_points moved by \a scene_to_model. */
double fieldKernelScore(const ClosestPointField& field,
                        const std::vector<Eigen::Vector3f>& scene_points,
                        const Eigen::Isometry3f& scene_to_model, float kernel);

/** \brief Centroid of a cluster that ignores a few far stray points (doc/icf.md section 4): the
 * coordinate-wise median, then the mean of the points within 1.5 x the 90th-percentile distance
 * (+1 cm) of it. \a points must not be empty. */
Eigen::Vector3f robustCentroid(const std::vector<Eigen::Vector3f>& points);

/** \brief The 90th percentile of the points' distances from \a centroid: the cluster's size
 * without the few outliers of a Kinect cut-out (0 for no points). */
float clusterSpread(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& centroid);

/** \brief Where the global search places the model's visible centroid, and the scene points
 * that score it there. */
struct SearchAnchor {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  std::vector<Eigen::Vector3f> subset;
};

/** \brief The search's anchors: the robust centroid of all points with a random subsample, or,
 * for a cluster that spreads wider than the model (GlobalSearchParams::merged_cluster_ratio),
 * local windows on a grid (GlobalSearchParams::anchor_spacing, min_anchor_points,
 * max_anchors). Deterministic for \a seed. */
std::vector<SearchAnchor> translationAnchors(const std::vector<Eigen::Vector3f>& points,
                                             float model_radius, const GlobalSearchParams& params,
                                             std::uint64_t seed);

/** \brief A seeded random subset of \a count points (all of them when there are fewer), in
 * their original order; our own draws (partial Fisher-Yates on std::mt19937_64), so the same
 * subset on every standard library. */
std::vector<Eigen::Vector3f> randomSubset(const std::vector<Eigen::Vector3f>& points,
                                          std::size_t count, std::uint64_t seed);

}  // namespace internal
}  // namespace icf
}  // namespace pcl
