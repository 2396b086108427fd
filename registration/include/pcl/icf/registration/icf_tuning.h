/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The registration's calibration constants: how the pose is searched, refined and
 * measured (doc/TUNING.md says what each means and how it was chosen). A user leaves them as
 * they are; a calibration run sets them through IcfParams::tuning(). */

#include <pcl/icf/registration/global_search.h>
#include <pcl/icf/registration/objective.h>
#include <pcl/icf/registration/refinement.h>
#include <pcl/icf/registration/sample_consensus_alignment.h>
#include <pcl/icf/registration/thesis_search.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl/icf/verification/pose_verification.h>

#include <cstddef>

namespace pcl {
namespace icf {

/** \brief Every constant of estimatePose that is not a user's knob. Lengths in scene units. */
struct IcfTuning {
  GlobalSearchParams global;    ///< the fast search (IcfParams::strategy Fast)
  ThesisSearchParams thesis;    ///< the thesis's search (strategy Thesis)
  ObjectiveParams objective;    ///< the searches' score
  RefinementParams refinement;  ///< the final refinement (Tukey-weighted point-to-face ICF)
  /** Best hypotheses of the fast search refined with exact faces before the final choice. */
  std::size_t exact_candidates = 3;
  /** Points per iteration when refining those candidates (the final refinement uses
   * refinement.max_points). */
  std::size_t candidate_points = 1000;
  /** With the caller's worth_refining check (estimatePose), the candidates are first checked
   * as the global search left them: when it refuses every one, none is refined with exact
   * faces and the search's best is the start as it is (which the same check then refuses:
   * the cluster's search ends). Most clusters of a real scene are other objects, whose exact
   * refinement this saves. false: the candidates are always refined. */
  bool check_candidates = true;
  /** Without a guess, the final refinement first runs on at most this many points (an evenly
   * strided subset) through the whole Tukey schedule, then on refinement.max_points from the
   * smallest radius (coarse to fine: a real cluster of 20-40k points would cost 30
   * full-resolution iterations otherwise). 0: one refinement at full resolution. With a guess
   * the refinement is ICP's: one stage, as configured. */
  std::size_t coarse_points = 3000;
  /** At most this many full-resolution iterations after the coarse stage (a pose that fits
   * converges in 4-7 on real clusters; one that keeps moving is a misfit). */
  int fine_iterations = 10;
  /** Which model samples face the camera and are seen (PoseQuality's coverage). */
  VisibilityParams visibility;
  /** The seen-through check's tolerances (depth_verification.h) without the two the user sets
   * (IcfParams::mesh_accuracy and depth_noise, which IcfParams::depthParams() puts in). */
  DepthVerificationParams depth;
  /** The SampleConsensus alignment of the fallback (IcfParams::fallback); its own seed. */
  SacParams sac;

  /** \throws std::invalid_argument naming the field and value; \a with_sac: check sac too. */
  void validate(bool with_sac) const;
};

}  // namespace icf
}  // namespace pcl
