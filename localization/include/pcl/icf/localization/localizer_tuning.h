/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The localizer's calibration constants: what the hypotheses and their ranking were
 * calibrated with (doc/TUNING.md says what each means and how it was chosen). A user leaves
 * them as they are; a calibration run sets them here, through LocalizerParams::tuning(). */

#include <pcl/icf/localization/pose_alternatives.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/point_pair_voting.h>
#include <pcl/icf/segmentation/convexity_split.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl/icf/verification/depth_verification.h>

#include <cstddef>

namespace pcl {
namespace icf {
namespace localization {

/** \brief Where the localizer's pose hypotheses come from and how they are ranked
 * (doc/localizer.md, "Hypotheses"). Two sources feed one ranking:
 * - the whole scene's point pair votes (point_pair_voting.h): every scene point may be a
 *   reference, the table's excepted, so an object that no cluster holds alone (merged with its
 *   neighbours, cut by an occluder) is still hypothesised;
 * - the segmentation's clusters that look like one object (no wider than the model) and the
 *   convexity segments of the others, each searched without a guess (globalSearch): a prior
 *   that is cheap and sure on a clean table; what merged clusters hold, the votes find.
 * Every hypothesis is refined on the closest-point field with the scene points near it and
 * verified against the depth image (explainDepth); poses that put the model's surface in the
 * same place are one. The most confident are judged: refined with exact faces, verified,
 * their turns tried (judgeHypothesis), and the verification decides. */
struct SceneHypotheses {
  bool point_pairs = true;  ///< the whole scene's votes
  /** voting.kept: the voted poses the ranking verifies. */
  PointPairVotingParams voting = defaultVoting();
  /** The votes come from at most this many scene points (subsampleForVoting's max_points): a
   * cloud that keeps more on the model's step is gridded coarser. A 640 x 480 view keeps a few
   * thousand (real frames at most 5,140, the desks at 0.6-1.8 m 14,561); a million points
   * filling a volume kept 738,000 and spent 2.8 s estimating their normals. 0: no limit. */
  std::size_t max_voting_points = 50000;
  bool clusters = false;  ///< the clusters' searches
  /** The best hypotheses of each cluster's search that enter the ranking. */
  std::size_t per_cluster = 4;
  /** The most confident distinct hypotheses judged, when their ranking confidence reaches
   * min_prescore (with max_instances above 1, at least twice that many). */
  std::size_t judged = 3;
  double min_prescore = 0.1;
  /** Of one place (model centres within a quarter of the diameter), at most this many are
   * judged: the others of the quota go elsewhere (a second copy of the object). */
  std::size_t per_location = 2;
  /** A hypothesis is refined and judged on the scene points inside the model's box at its
   * pose, grown by crop_margin x the model's diameter on every side (the table's left out). */
  float crop_margin = 0.15f;
  /** Points of that crop the exact refinement uses per iteration (an evenly strided subset),
   * from the Tukey radius fine_start_radius (metres) for at most fine_iterations: the
   * field-refined pose is within a few millimetres of where the exact faces settle it. */
  std::size_t refine_points = 3000;
  float fine_start_radius = 0.01f;
  int fine_iterations = 15;
  /** A promising judged pose (LocalizerTuning::promising_share) is refined once more, as above
   * but on final_points of its crop (the refinement's stride: RefinementParams::max_points), and
   * kept when it explains the depth better: a subset's optimum lies a fraction of a millimetre
   * from the whole crop's, which at 1 m is a tenth of the fit's unit
   * (DepthVerificationParams::fitSigma) and decides a right pose near the limit. */
  std::size_t final_points = 20000;

  static PointPairVotingParams defaultVoting();
  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief Every calibration constant of the localizer that is not a user's knob (doc/TUNING.md).
 * Reached through LocalizerParams::tuning(); the fields LocalizerParams has itself (the
 * clusters, the strategy, the fallback, the seed, the threads) are read from there, so their
 * copies here (segmentation.cluster, icf.strategy, icf.fallback, icf.seed, icf.threads) are
 * not read. */
struct LocalizerTuning {
  /** The table plane, the points above it and the scene's sanity limits. */
  segmentation::TabletopParams segmentation;
  /** The registration of each hypothesis. Its depth tolerances (tuning().depth, mesh_accuracy,
   * depth_noise) are not read: the seen-through check uses verification, as everything the
   * localizer judges does. Its far-point gate
   * allows FarPointGate::kLocalizerMaxFraction of the points (defaultIcf). */
  IcfParams icf = defaultIcf();
  /** The verification that decides (depth_verification.h): the posed model rendered into the
   * camera's pixel grid and compared with the measured depth; tolerances scale with the
   * sensor's noise at each pixel's depth and with the model's size. */
  DepthVerificationParams verification;
  /** The convexity split of a cluster wider than the model (LocalizerParams::split_merged). */
  segmentation::ConvexitySplitParams split;
  /** The look-alike turns (LocalizerParams::check_turns); each is refined as
   * icf.tuning().refinement and verified as verification say (TurnChecks). */
  PoseAlternativeParams alternatives;
  SceneHypotheses hypotheses;
  /** A search's start pose whose confidence is below this is not given the final refinement,
   * and a refused start ends that cluster's search (estimatePose's worth_refining); used as
   * min(refine_min_confidence, LocalizerParams::min_confidence). 0: every start is refined. */
  double refine_min_confidence = 0.01;
  /** A judged pose with at least this share of the confidence an acceptance needs
   * (LocalizerParams::min_confidence) is worth more work: its turns are tried and it is
   * refined once more on its whole crop (SceneHypotheses::final_points). */
  double promising_share = 0.25;
  /** The scene must lie in front of the camera: at least this share of its finite points at
   * positive depth, else BadScene (a camera pose given the wrong way round). */
  double min_points_in_front = 0.5;
  /** Two instances share at most this share of their explained points (the lesser one's);
   * more, and they are one object found twice. */
  double max_shared_points = 0.2;

  /** IcfParams' defaults with the far-point gate's max_fraction at
   * FarPointGate::kLocalizerMaxFraction. */
  static IcfParams defaultIcf();
  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

}  // namespace localization
}  // namespace icf
}  // namespace pcl
