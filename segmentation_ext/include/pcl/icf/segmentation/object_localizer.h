/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/estimate_pose.h>
#include <pcl/icf/icf_model.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/point_cloud.h>

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {

/** \brief The colour cue the thesis proposed (section 6.2) and did not build: the cluster's
 * colour histogram against an expected colour. */
struct ColourCue {
  /** Expected colour in [0, 1] RGB; unset: the cue is off (meshColour() reads a mesh's
   * vertex colours, for callers whose CAD file has them). */
  std::optional<Eigen::Vector3f> expected;
  /** Weight of the colour similarity in the ranking score (0: report it, do not use it). */
  double weight = 1.0;
  /** Hue-saturation histogram bins per axis. */
  int bins = 8;

  void validate() const;
};

/** \brief Parameters of localizeObject; lengths in scene units (metres by default). */
struct LocalizerParams {
  /** false: the whole cloud is one cluster (a cloud already cut to one object). */
  bool segment = true;
  TabletopParams segmentation;
  IcfParams icf;
  /** The thesis's gate (section 6.2): a cluster is rejected when more than
   * max(gate_max_far_points, gate_max_far_fraction x its size) of its points lie farther than
   * gate_distance from the posed model's closest face. A cluster of one object (compact next
   * to the model, or a convexity segment) is counted whole, as in the thesis; in a merged
   * cluster only the points the posed model claims count: those whose line of sight crosses
   * the model's silhouette and that lie behind its visible surface (doc/localizer.md). */
  bool thesis_gate = true;
  float gate_distance = 0.027f;  ///< 27 mm
  int gate_max_far_points = 5;   ///< "more than 5 points"
  /** Ours: the thesis's clusters had a few hundred points after its voxel filter; a
   * full-resolution Kinect cluster of thousands has more stray edge pixels. */
  double gate_max_far_fraction = 0.03;
  /** A cluster of one object (compact, or a convexity segment) must also be explained nearly
   * whole: at least this share of its points within the inlier distance of the posed model.
   * The right model explains 96-100% (Kinect noise, 5% flying pixels); a box laid on a cup or
   * a statue 80-90%. */
  double min_single_object_inliers = 0.93;
  /** So that a bigger object cannot win by having more points (thesis scenario 2) when its
   * surface merely contains the model's: the share of the posed model's silhouette border
   * where the scene's surface carries on at the model's depth (within boundary_tolerance). An
   * object seen whole ends in a depth jump or in nothing; above max_boundary_continuation the
   * model explains only part of a bigger surface. */
  float boundary_tolerance = 0.01f;
  double max_boundary_continuation = 0.6;
  /** Free-space check: a camera-facing sample of the posed model that lies more than
   * free_space_tolerance in front of the scene surface seen along the same ray means the
   * camera saw through the model. Rejected above max_free_space_violation (share of the
   * visible samples). */
  float free_space_tolerance = 0.015f;
  double max_free_space_violation = 0.15;
  ColourCue colour;
  /** Touching objects merge into one Euclidean cluster (the YCB-Video frame's four do). A
   * cluster that spreads wider than the model (icf.global.merged_cluster_ratio) is also split
   * where its surface turns concave (splitByConvexity) and every segment is tried as a
   * cluster of its own, besides the whole. */
  bool split_merged = true;
  ConvexitySplitParams split;
  /** Angular bin of the view grid used by the free-space, gate and boundary checks. */
  float view_bin_angle = 0.004f;
  /** Clusters localised in parallel (0: all cores). The result does not depend on it. */
  int threads = 0;

  void validate() const;
};

/** \brief One cluster's outcome. */
struct ClusterLocalization {
  pcl::PointIndices indices;  ///< the cluster's points in the scene cloud
  /** -1 for a cluster of the segmentation; else the index (in Localization::clusters) of the
   * merged cluster this convexity segment was split from. */
  int parent = -1;
  IcfResult icf;            ///< pose (object_pose: model -> scene), quality, status
  int gate_far_points = 0;  ///< points beyond gate_distance counted by the thesis's gate
  bool gate_passed = true;
  double boundary_continuation = 0.0;  ///< share of the silhouette border where the surface goes on
  double free_space_violation = 0.0;   ///< share of visible model samples seen through
  std::optional<double> colour_similarity;  ///< histogram intersection in [0, 1], when used
  /** Ranking score: surface coverage x sqrt(inlier ratio) x (1 - free-space violation) x
   * (colour similarity ^ weight): how much of the model the cluster shows and how much of the
   * cluster the model explains, comparable across clusters of any size (doc/localizer.md). */
  double score = 0.0;
  bool single_object = true;  ///< judged as one object's points (see thesis_gate)
  bool accepted = false;      ///< ICF accepted, gate passed, free space respected
  std::string reason;         ///< why not accepted ("" when accepted)
};

enum class LocalizationStatus {
  Found,       ///< a cluster was accepted: best >= 0
  NotFound,    ///< clusters were tried, none accepted
  NoClusters,  ///< segmentation gave no cluster (see segmentation.status / message)
  BadScene,    ///< empty, all-NaN or millimetre scene (see segmentation.message)
};
const char* toString(LocalizationStatus status);

/** \brief The whole scene's outcome. */
struct Localization {
  LocalizationStatus status = LocalizationStatus::NotFound;
  std::string message;
  TabletopSegmentation segmentation;  ///< empty when params.segment is false
  /** The segmentation's clusters in its order, then the convexity segments of merged ones. */
  std::vector<ClusterLocalization> clusters;
  int best = -1;  ///< index into clusters of the best accepted cluster, -1 when none
  double total_ms = 0.0;
  double segmentation_ms = 0.0;
  double registration_ms = 0.0;
};

/** \brief Find a known object in a table-top scene (thesis chapters 5-6): segment the table
 * and the clusters, run IterativeClosestFace on every cluster in parallel, apply the
 * acceptance rules and rank. Deterministic for params.icf.seed; independent of threads.
 * \throws std::invalid_argument for invalid parameters only; bad data gives a status. */
template <typename PointT>
Localization localizeObject(const pcl::PointCloud<PointT>& scene, const IcfModel& model,
                            const LocalizerParams& params = {});

}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl/icf/segmentation/impl/object_localizer.hpp>
#endif
