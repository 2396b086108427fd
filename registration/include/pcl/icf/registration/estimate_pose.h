/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/icf_tuning.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl/icf/verification/pose_verification.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {

/** \brief How the pose is searched when there is no initial guess. */
enum class SearchStrategy {
  Fast,    ///< uniform SO(3) x visible-centroid placement on the field (doc/icf.md section 4)
  Thesis,  ///< the thesis's three-loop stochastic kernel search (section 7)
};

/** \brief Parse "fast" / "thesis"; throws std::invalid_argument otherwise. */
SearchStrategy parseSearchStrategy(const std::string& name);
std::string toString(SearchStrategy strategy);

/** \brief When the feature-based sample-consensus alignment (sample_consensus_alignment.h)
 * runs inside estimatePose. It never runs when an initial guess is given. */
enum class FallbackPolicy {
  Off,     ///< never: the search's pose is the answer
  Auto,    ///< default: when the searched and refined pose is not accepted, also try SAC + ICF
           ///< and keep the better of the two (see estimatePose)
  Always,  ///< SAC instead of the global search, then ICF
};

/** \brief Parse "off" / "auto" / "always"; throws std::invalid_argument otherwise. */
FallbackPolicy parseFallbackPolicy(const std::string& name);
std::string toString(FallbackPolicy policy);

/** \brief The ICF thesis's acceptance test (Armenise, KTH 2013, section 6.2): a pose is refused
 * when more of the points it is judged on than allowed() lie farther than distance from the
 * posed model's closest face. The one gate of the library: estimatePose applies it to the
 * cluster's points (AcceptanceParams::gate), localizeObject to the points its pose claims
 * (LocalizerParams, far_point_gate). */
struct FarPointGate {
  bool enabled = false;
  float distance = 0.027f;  ///< 27 mm, the thesis's
  int max_points = 5;       ///< "more than 5 points", the thesis's
  /** Ours, as a share of the points judged: the thesis's clusters had a few hundred points
   * after its voxel filter; a full-resolution Kinect cluster of thousands has more stray edge
   * pixels. 0 here, the thesis's rule; localizeObject's default is kLocalizerMaxFraction. */
  double max_fraction = 0.0;
  static constexpr double kLocalizerMaxFraction = 0.03;

  /** Far points allowed among \a points judged: max(max_points, max_fraction x points). */
  double allowed(std::size_t points) const {
    return std::max<double>(max_points, max_fraction * static_cast<double>(points));
  }
  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief When a pose is accepted (hasConverged() is true). Lengths in scene units. */
struct AcceptanceParams {
  /** Scene points within this distance of the posed model are inliers; a visible model
   * sample with a scene point within it is covered. */
  float inlier_distance = 0.01f;
  /** At least this share of the model's camera-facing surface must be covered. This, not the
   * share of the cluster explained, decides: a cluster that holds other objects too can
   * still be accepted when the target is well explained. */
  double min_surface_coverage = 0.6;
  /** RMS distance of the inliers at most this. */
  double max_rmse = 0.006;
  /** At least this many inliers. */
  std::size_t min_inliers = 30;
  /** The far-point gate (off by default: it assumes the cluster holds nothing but the
   * target). Its distance also sets what PoseQuality::far_points counts. */
  FarPointGate gate;
  /** Reject a pose the camera sees through: of the posed model's pixels where the camera could
   * have seen it (explainDepth's supported, seen_through and below_support), the share where
   * the measured depth lies behind it (PoseQuality::seen_through) must be at most this. A
   * partial view fitted onto the wrong side of a model can cover its points well (inliers,
   * rmse, coverage) while the model hides other points of the view behind it. 1 turns the
   * check off (calibration: doc/TUNING.md, "The depth verification"). Its tolerances scale
   * with IcfParams::depth_noise and mesh_accuracy. */
  double max_seen_through = 0.05;

  void validate() const;
};

/** \brief Everything estimatePose needs besides the data. Defaults documented per field;
 * lengths in scene units (metres). */
struct IcfParams {
  /** How the pose is searched without a guess. */
  SearchStrategy strategy = SearchStrategy::Fast;
  /** When a pose is accepted. */
  AcceptanceParams acceptance;
  /** How far the mesh's surface may lie from the real object's, in metres: about 0 for a CAD
   * model, 1-2 mm for a scanned mesh (DepthVerificationParams::mesh_accuracy). */
  float mesh_accuracy = 0.f;
  /** The camera's depth noise (DepthNoiseModel; a Kinect v1 or Xtion by default), which the
   * seen-through check's tolerances scale with. */
  DepthNoiseModel depth_noise;
  /** When the SampleConsensus alignment runs (default Auto: only after a rejection). */
  FallbackPolicy fallback = FallbackPolicy::Auto;
  std::uint64_t seed = 42;
  int threads = 0;  ///< 0: all cores. Results do not depend on it.

  /** The calibration constants (IcfTuning, doc/TUNING.md): the one door to them, for
   * calibration runs and comparisons. */
  IcfTuning& tuning() { return tuning_; }
  const IcfTuning& tuning() const { return tuning_; }
  /** What the seen-through check uses: tuning().depth with this struct's mesh_accuracy and
   * depth_noise. */
  DepthVerificationParams depthParams() const;

  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;

 private:
  IcfTuning tuning_;
};

/** \brief Outcome of one estimation. */
enum class IcfStatus {
  NotRun,        ///< nothing estimated yet
  Accepted,      ///< the pose passed the acceptance test
  Rejected,      ///< a pose was found but failed the acceptance test
  TooFewPoints,  ///< fewer finite scene points than needed (see IcfResult::points)
  NoModel,       ///< no mesh was given
};
std::string toString(IcfStatus status);

/** \brief The result of estimatePose / IterativeClosestFace::getResult. */
struct IcfResult {
  IcfStatus status = IcfStatus::NotRun;
  /** Registration transform: scene points into the model frame (PCL's source -> target). */
  Eigen::Matrix4f scene_to_model = Eigen::Matrix4f::Identity();
  /** The model's pose in the scene (model frame -> scene frame): the inverse. */
  Eigen::Matrix4f object_pose = Eigen::Matrix4f::Identity();
  PoseQuality quality;  ///< measured at the final pose with exact distances
  std::string method;   ///< "fast+icf", "thesis+icf", "sac+icf", "guess+icf"
  int refinement_iterations = 0;
  bool refinement_converged = false;
  std::size_t points = 0;     ///< finite scene points used
  double search_score = 0.0;  ///< the search's own score of its best hypothesis
  /** The SampleConsensus fallback ran (policy Always, or Auto after a rejection), whether or
   * not its pose was kept (method says which was). */
  bool fallback_ran = false;
  SacStatus sac_status = SacStatus::NotRun;  ///< its outcome when it ran
  /** The caller's worth_refining check turned the final refinement down (estimatePose): the
   * pose is the search's start as it was, Rejected, its quality not measured. */
  bool refinement_skipped = false;
  double time_ms = 0.0;

  bool accepted() const { return status == IcfStatus::Accepted; }
};

/** \brief A caller's check of a search's start pose (scene -> model) before the final
 * refinement: false when no refinement could make it acceptable, to save that refinement. */
using StartCheck = std::function<bool(const Eigen::Isometry3f& scene_to_model)>;

/** \brief What an estimatePose call may take besides the data and the parameters. */
struct PoseEstimateOptions {
  /** A scene-to-model start: then only the refinement runs (no search, no fallback). */
  std::optional<Eigen::Isometry3f> guess;
  IterationCallback callback;  ///< called after every refinement iteration
  /** Called with every start pose of a search (the search's best, SAC's) before its final
   * refinement, and with the fast search's candidates before their exact refinement
   * (IcfTuning::check_candidates); when it returns false that start is not refined nor measured
   * (IcfResult::refinement_skipped; the start is reported as it is, Rejected), and a refused
   * search start ends the search (no SAC fallback after it). Never called with a guess. The
   * localizer passes its depth verification here (LocalizerTuning::refine_min_confidence):
   * most clusters of a real scene are other objects, and their final refinement was a third of
   * a frame's time. */
  StartCheck worth_refining;
  /** The scene as a depth image with the scene's frame as the camera's, for the seen-through
   * check; not owned, it must outlive the call. Without it, the points themselves are projected
   * for a virtual camera at the call's camera looking at their centroid, at their own angular
   * spacing. */
  const DepthImage* camera_image = nullptr;
};

/** \brief Estimate the model's pose in a cluster of scene points (doc/icf.md): search (or
 * start from PoseEstimateOptions::guess), refine by iterative closest face, measure, accept or
 * reject.
 *
 * \param scene_points points of one cluster, scene frame and units; points with a NaN or
 * infinite coordinate, or one beyond +-kMaxPointCoordinate, are left out (IcfResult::points
 * counts the rest)
 * \param camera the sensor's position in the scene frame (visibility)
 * \param options a start, an iteration callback, the caller's check of start poses, the scene's
 * depth image (PoseEstimateOptions)
 *
 * The SampleConsensus fallback (params.fallback, sample_consensus_alignment.h): with Auto, when
 * the refined search result is not accepted, sampleConsensusAlign(params.tuning().sac) runs on the
 * same points, its pose is refined the same way and measured; the accepted one is kept (the
 * search's when both are), else the one covering more of the model's visible surface. With
 * Always, SAC replaces the search (method "sac+icf"); when it finds nothing the refinement
 * starts from the centroid start (model surface centroid on the cluster centroid, no
 * rotation), which is rarely accepted. The model's features are built on first use and cached
 * (cachedSacModel); SAC runs are serialised process-wide (PCL's aligners use rand()).
 * Deterministic for params.seed and params.tuning().sac.seed and independent of params.threads.
 *
 * The seen-through check (AcceptanceParams::max_seen_through) compares every measured pose with
 * the scene's depth image (PoseEstimateOptions::camera_image).
 * \throws std::invalid_argument for parameters out of range or a guess with a non-finite
 * entry. */
IcfResult estimatePose(const IcfModel& model, const std::vector<Eigen::Vector3f>& scene_points,
                       const Eigen::Vector3f& camera, const IcfParams& params,
                       const PoseEstimateOptions& options = {});

/** \brief Apply the acceptance rule to a measured quality (seen_through as estimatePose measured
 * it; 0 when not measured). */
bool isAcceptable(const PoseQuality& quality, const AcceptanceParams& params);

}  // namespace icf
}  // namespace pcl
