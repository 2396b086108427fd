/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/depth_verification.h>
#include <pcl/icf/estimate_pose.h>
#include <pcl/icf/icf_model.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/point_cloud.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

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
  /** The verification that decides (depth_verification.h): the posed model rendered into the
   * camera's pixel grid and compared with the measured depth; tolerances scale with the
   * sensor's noise at each pixel's depth and with the model's size. */
  DepthVerificationParams verification;
  /** A pose is accepted when its confidence (DepthExplanation::confidence) reaches this.
   * Chosen from the curve of false poses against missed objects (doc/BENCHMARKS.md,
   * "Identification"). */
  double min_confidence = 0.5;
  /** Intrinsics of the camera, for an unorganized cloud (an organized one gives its own, fitted
   * to its points). Unset: a virtual camera at the cloud's point spacing. */
  std::optional<PinholeIntrinsics> intrinsics;
  /** The thesis's gate (section 6.2), off by default (the verification decides): a cluster is
   * rejected when more than max(gate_max_far_points, gate_max_far_fraction x its size) of the
   * points the posed model claims lie farther than gate_distance from its closest face. A
   * cluster of one object (compact, or a convexity segment) is counted whole, as in the
   * thesis; in a merged cluster only the points inside the rendered model's silhouette and
   * behind its surface count. */
  bool thesis_gate = false;
  float gate_distance = 0.027f;  ///< 27 mm
  int gate_max_far_points = 5;   ///< "more than 5 points"
  /** Ours: the thesis's clusters had a few hundred points after its voxel filter; a
   * full-resolution Kinect cluster of thousands has more stray edge pixels. */
  double gate_max_far_fraction = 0.03;
  ColourCue colour;
  /** Touching objects merge into one Euclidean cluster (the YCB-Video frame's four do). A
   * cluster that spreads wider than the model (icf.global.merged_cluster_ratio) is also split
   * where its surface turns concave (splitByConvexity) and every segment is tried as a
   * cluster of its own, besides the whole. */
  bool split_merged = true;
  ConvexitySplitParams split;
  /** Clusters localised in parallel (0: all cores). The result does not depend on it. */
  int threads = 0;
  /** The camera's pose in the scene's frame (camera -> scene; camera frame x right, y down,
   * z forward, as PCL's and every depth camera's driver give it). Unset: the cloud's own
   * sensor_origin_ and sensor_orientation_ (a PCD's VIEWPOINT). A cloud moved into a robot's
   * base frame needs it: pcl::transformPointCloud does not move sensor_origin_. The scene is
   * localised in the camera's frame and every pose is reported in the scene's frame, so a
   * cloud and the same cloud moved rigidly with its camera give the same poses up to the move
   * (and float rounding). */
  std::optional<Eigen::Isometry3f> camera_pose;
  /** The scene must lie in front of the camera: at least this share of its finite points at
   * positive depth, else BadScene (a camera pose given the wrong way round). */
  double min_points_in_front = 0.5;

  void validate() const;
};

/** \brief The camera pose localizeObject uses for \a scene: params.camera_pose, else the
 * cloud's sensor_origin_ / sensor_orientation_. \throws std::invalid_argument when that pose
 * is not a rigid motion (NaN, a non-unit quaternion). */
template <typename PointT>
Eigen::Isometry3f cameraPoseOf(const pcl::PointCloud<PointT>& scene, const LocalizerParams& params);

/** \brief Checks that \a camera_to_scene is a finite rigid motion (rotation orthonormal to 1e-4,
 * determinant +1); \throws std::invalid_argument naming \a what otherwise. */
void validateCameraPose(const Eigen::Isometry3f& camera_to_scene, const std::string& what);

/** \brief One cluster's outcome. */
struct ClusterLocalization {
  pcl::PointIndices indices;  ///< the cluster's points in the scene cloud
  /** -1 for a cluster of the segmentation; else the index (in Localization::clusters) of the
   * merged cluster this convexity segment was split from. */
  int parent = -1;
  IcfResult icf;            ///< pose (object_pose: model -> scene), quality, status
  int gate_far_points = 0;  ///< points beyond gate_distance counted by the thesis's gate
  bool gate_passed = true;
  /** How the posed model explains the depth image; its confidence decides acceptance. */
  DepthExplanation verification;
  std::optional<double> colour_similarity;  ///< histogram intersection in [0, 1], when used
  /** Ranking score: the verification's confidence x (colour similarity ^ weight), comparable
   * across clusters of any size (doc/localizer.md). */
  double score = 0.0;
  bool single_object = true;  ///< judged as one object's points (see thesis_gate)
  bool accepted = false;      ///< confidence >= min_confidence (and the gate, when on)
  std::string reason;         ///< why not accepted ("" when accepted)
};

enum class LocalizationStatus {
  Found,       ///< a cluster was accepted: best >= 0
  NotFound,    ///< clusters were tried, none accepted
  NoClusters,  ///< segmentation gave no cluster (see segmentation.status / message)
  BadScene,    ///< empty, all-NaN or millimetre scene, or behind the camera (see message)
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
  /** The camera pose used (camera -> scene): every pose and plane above is in the scene's
   * frame. */
  Eigen::Isometry3f camera_pose = Eigen::Isometry3f::Identity();
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
