/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The localizer's calibration constants: what the hypotheses and their ranking were
 * calibrated with (doc/TUNING.md says what each means and how it was chosen). A user leaves
 * them as they are; a calibration run sets them here, through LocalizerParams::tuning. */

#include <pcl/icf/registration/point_pair_voting.h>

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
 * their turns tried (judgeCluster), and the verification decides. */
struct SceneHypotheses {
  bool point_pairs = true;  ///< the whole scene's votes
  /** voting.kept: the voted poses the ranking verifies. */
  PointPairVotingParams voting = defaultVoting();
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

  static PointPairVotingParams defaultVoting();
  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief Every calibration constant of the localizer that is not a user's knob. */
struct LocalizerTuning {
  SceneHypotheses hypotheses;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

}  // namespace localization
}  // namespace icf
}  // namespace pcl
