/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/localization/localizer_tuning.h>
#include <pcl/icf/localization/pose_alternatives.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/rigid_transform.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/icf/segmentation/precompiled_point_types.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl/point_cloud.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace localization {

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

/** \brief Parameters of localizeObject: the knobs a user sets; lengths in scene units
 * (metres by default). The calibration constants are in tuning() (LocalizerTuning,
 * doc/TUNING.md), left as they are by a user. */
struct LocalizerParams {
  /** false: the whole cloud is one cluster (a cloud already cut to one object). */
  bool segment = true;
  /** The Euclidean clusters of the points above the table. */
  segmentation::ClusterParams cluster;
  /** Touching objects merge into one Euclidean cluster (the YCB-Video frame's four do). A
   * cluster that spreads wider than the model is also split where its surface turns concave
   * (segmentation::splitByConvexity) and every segment is tried as a cluster of its own,
   * besides the whole. */
  bool split_merged = true;
  /** Instances reported (Localization::instances), best first. 1: the best only. Above 1,
   * after a search that accepts a pose the points it explains are left out (as
   * explained_indices are) and the rest of the scene is searched again, until this many are
   * found or a search accepts nothing new (a touching copy is found on its own points). */
  int max_instances = 1;
  /** Every promising pose (confidence at least a quarter of min_confidence; doc/TUNING.md,
   * promising_share) is turned about the model's principal axes, refined and verified
   * (turnedAlternatives) before it is judged: a clearly more confident turn replaces it, and
   * the others as confident are reported (ClusterLocalization::alternatives). false: the
   * search's pose as it is. */
  bool check_turns = true;
  ColourCue colour;
  /** A pose is accepted when its confidence (DepthExplanation::confidence) reaches this.
   * Chosen from the curve of false poses against missed objects over 160 present and absent
   * cases, real and synthetic (doc/TUNING.md): the middle of the gap between the look-alikes
   * (at most 0.80, one real case excepted) and the right poses (at least 0.95). */
  double min_confidence = 0.875;
  /** How far the mesh's surface may lie from the real object's, in metres: about 0 for a CAD
   * model of a manufactured part, 1-2 mm for a scanned mesh (YCB's). The verification then
   * forgives a right pose that much misfit of its depth and silhouette
   * (DepthVerificationParams::mesh_accuracy); a value larger than the mesh's real error lets
   * a look-alike that many millimetres off pass. */
  float mesh_accuracy = 0.f;
  /** The camera's depth noise: sigma(z) of a pixel and the low-frequency error over an
   * object's extent, both growing with z^2 (DepthNoiseModel; a Kinect v1 or Xtion by default).
   * A simulated camera without low-frequency error: depth_noise.systematic = 0; a
   * time-of-flight camera: coefficient 0 and its constant noise as the floor. */
  DepthNoiseModel depth_noise;
  /** The search of a hypothesis (IcfParams::strategy). */
  SearchStrategy strategy = IcfParams{}.strategy;
  /** The SampleConsensus (FPFH) alignment as a fallback (IcfParams::fallback). */
  FallbackPolicy fallback = IcfParams{}.fallback;
  /** Seed of every random choice; same seed, same result. */
  std::uint64_t seed = IcfParams{}.seed;
  /** Threads of the clusters and of each search (0: all cores). The result does not depend
   * on it. */
  int threads = 0;
  /** The camera's pose in the scene's frame (camera -> scene; camera frame x right, y down,
   * z forward, as PCL's and every depth camera's driver give it). Unset: the cloud's own
   * sensor_origin_ and sensor_orientation_ (a PCD's VIEWPOINT). A cloud moved into a robot's
   * base frame needs it: pcl::transformPointCloud does not move sensor_origin_. The scene is
   * localised in the camera's frame and every pose is reported in the scene's frame, so a
   * cloud and the same cloud moved rigidly with its camera give the same poses up to the move
   * (and float rounding). */
  std::optional<Eigen::Isometry3f> camera_pose;
  /** Intrinsics of the camera, for an unorganized cloud (an organized one gives its own, fitted
   * to its points). Unset: a virtual camera at the cloud's point spacing. */
  std::optional<PinholeIntrinsics> intrinsics;
  /** Indices of scene points already explained, such as the points of another object's
   * accepted pose (pointsExplainedBy): the verification treats them as explained background
   * (DepthImage::markExplained). Like the table, they are no evidence for the model and stop
   * its silhouette continuation, so a neighbour touching the target does not read as the
   * target's surface carrying on; unlike the table, they may lie in front of it (occlusion).
   * They are taken out of the clusters (a cluster left below the minimum size is dropped), so
   * a target touching an explained neighbour is searched on its own points. Each must index
   * the scene. */
  std::vector<int> explained_indices;

  /** The calibration constants (LocalizerTuning): the one door to them, for calibration runs
   * and comparisons. */
  LocalizerTuning& tuning() { return tuning_; }
  const LocalizerTuning& tuning() const { return tuning_; }
  /** What each hypothesis is registered with: tuning().icf with this struct's strategy,
   * fallback, seed and threads, and the verification's tolerances (verificationParams()). */
  IcfParams icfParams() const;
  /** What the scene is segmented with: tuning().segmentation with this struct's cluster. */
  segmentation::TabletopParams segmentationParams() const;
  /** What every pose is verified with: tuning().verification with this struct's
   * mesh_accuracy and depth_noise. */
  DepthVerificationParams verificationParams() const;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;

 private:
  LocalizerTuning tuning_;
};

/** \brief The camera pose localizeObject uses for \a scene: params.camera_pose, else the
 * cloud's sensor_origin_ / sensor_orientation_. \throws std::invalid_argument when that pose
 * is not a rigid motion (NaN, a non-unit quaternion). */
template <typename PointT>
Eigen::Isometry3f cameraPoseOf(const pcl::PointCloud<PointT>& scene, const LocalizerParams& params);

/** \brief One judged hypothesis: a pose from the ranking (localizer_tuning.h), refined and
 * verified. */
struct ClusterLocalization {
  /** The scene points near the hypothesis (inside the model's box at its pose, grown by a
   * share of its diameter; the table's left out): what it was refined on and explains. */
  pcl::PointIndices indices;
  /** The cluster whose search proposed it: an index into the segmentation's clusters, or past
   * them into the convexity segments of merged ones (in their clusters' order); -1 when the
   * whole scene's point pair votes did. */
  int source_cluster = -1;
  /** Its confidence in the ranking, before the exact refinement (field-refined pose). */
  double prescore = 0.0;
  IcfResult icf;            ///< pose (object_pose: model -> scene), quality, status
  int gate_far_points = 0;  ///< points beyond the gate's distance (icf.acceptance.gate)
  bool gate_passed = true;
  /** How the posed model explains the depth image; its confidence decides acceptance. */
  DepthExplanation verification;
  std::optional<double> colour_similarity;  ///< histogram intersection in [0, 1], when used
  /** Ranking score: the verification's confidence x (colour similarity ^ weight), comparable
   * across clusters of any size (doc/localizer.md). */
  double score = 0.0;
  bool single_object = true;  ///< judged as one object's points (see the far-point gate)
  bool accepted = false;      ///< confidence >= min_confidence (and the gate, when on)
  /** Poses as good as this one (within alternatives.confidence_margin of its confidence) that
   * differ from it by a turn: the depth cannot decide between them (a box's flip, a can's
   * spin). Empty: the pose is unique as far as the depth tells, or the pose was not
   * promising (confidence below a quarter of min_confidence: its turns are not tried). */
  std::vector<PoseAlternative> alternatives;
  /** The search's pose was replaced by a turned one that explains the depth better; icf.quality
   * was measured again at it. */
  bool turned = false;
  /** The cluster's points the posed model explains: within the verification's depth
   * tolerance (DepthVerificationParams: noise_sigmas x sigma(z) + size_tolerance x diameter)
   * of its surface. */
  pcl::Indices explained;
  std::string reason;  ///< why not accepted ("" when accepted)
};

enum class LocalizationStatus {
  Found,       ///< a cluster was accepted: best >= 0
  NotFound,    ///< clusters were tried, none accepted
  NoClusters,  ///< segmentation gave no cluster (see segmentation.status / message)
  BadScene,    ///< empty, all-NaN or millimetre scene, or behind the camera (see message)
};
std::string toString(LocalizationStatus status);

/** \brief The whole scene's outcome. */
struct Localization {
  LocalizationStatus status = LocalizationStatus::NotFound;
  std::string message;
  segmentation::TabletopSegmentation segmentation;  ///< empty when params.segment is false
  /** The judged hypotheses, most confident in the ranking first. */
  std::vector<ClusterLocalization> clusters;
  /** Indices into clusters of the accepted instances, by score (best first), at most
   * params.max_instances, no two explaining the same points (rankInstances). */
  std::vector<int> instances;
  int best = -1;  ///< instances.front(), -1 when none
  /** The camera pose used (camera -> scene): every pose and plane above is in the scene's
   * frame. */
  Eigen::Isometry3f camera_pose = Eigen::Isometry3f::Identity();
  double total_ms = 0.0;
  double segmentation_ms = 0.0;
  /** Everything after the segmentation; of it, the hypotheses (votes, clusters' searches), their
   * ranking and the judging of the best. */
  double registration_ms = 0.0;
  double hypotheses_ms = 0.0, ranking_ms = 0.0, judging_ms = 0.0;
};

/** \brief The accepted clusters of \a clusters ranked by score (ties: the lower index), each
 * kept only when at most \a max_shared of its explained points are explained by a better one
 * too (a merged cluster and its convexity segment posed on one object are one instance), at
 * most \a max_instances. */
std::vector<int> rankInstances(const std::vector<ClusterLocalization>& clusters, int max_instances,
                               double max_shared = 0.2);

/** \brief Find a known object in a table-top scene (thesis chapters 5-6): segment the table
 * and the clusters, run IterativeClosestFace on every cluster in parallel, apply the
 * acceptance rules and rank. Deterministic for params.seed; independent of threads.
 * \throws std::invalid_argument for invalid parameters only; bad data gives a status. */
template <typename PointT>
Localization localizeObject(const pcl::PointCloud<PointT>& scene, const IcfModel& model,
                            const LocalizerParams& params = {});

}  // namespace localization
}  // namespace icf
}  // namespace pcl

// cameraPoseOf and localizeObject are compiled into pcl_icf_localization for
// PCL_ICF_SEGMENTATION_POINT_TYPES (precompiled_point_types.h: other point types, how); their
// bodies are in the library's sources (src/impl/object_localizer.hpp), not installed.
