/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The BOP benchmark's scores from pose errors (bop_pose_errors.h): estimates matched to
 * ground-truth instances greedily in the order of their scores, the recall at a threshold of
 * correctness, the Average Recall over BOP 2019's thresholds (Hodan et al., ECCV workshops
 * 2020, section 2.3: AR = the mean of AR_VSD, AR_MSSD and AR_MSPD). */

#include <cstddef>
#include <vector>

namespace pcl {
namespace icf {
namespace evaluation {

/** \brief One object in one image: its ground-truth instances and the estimates of it, each
 * with its error against every instance (one error kind, one setting: e.g. VSD at one tau). */
struct MatchGroup {
  /** Per ground-truth instance: counted (BOP: visible fraction >= the minimum asked). */
  std::vector<bool> gt_valid;
  /** Only the best this many estimates by score are matched (BOP: the target's instance
   * count); 0: all. */
  std::size_t max_estimates = 0;
  struct Estimate {
    double score = 0.0;
    std::vector<double> errors;  ///< one per ground-truth instance
  };
  std::vector<Estimate> estimates;
};

/** \brief How many valid instances of \a group are matched at \a threshold: the estimates in
 * the order of decreasing score (ties in the order given), each to the unmatched valid
 * instance of smallest error below \a threshold, if any (BOP toolkit's match_poses).
 * \throws std::invalid_argument when an estimate's errors do not number the instances. */
std::size_t matchedInstances(const MatchGroup& group, double threshold);

/** \brief The share of all valid instances of \a groups matched at \a threshold (0 when there
 * are none). */
double recall(const std::vector<MatchGroup>& groups, double threshold);

/** \brief The mean of recall over \a thresholds. */
double averageRecall(const std::vector<MatchGroup>& groups, const std::vector<double>& thresholds);

/** \brief BOP 2019's thresholds of VSD (and its taus) and of MSSD, as fractions (of the error
 * for VSD, of the diameter for tau and MSSD): 0.05, 0.10, ..., 0.50. */
std::vector<double> bopFractions();

/** \brief BOP 2019's thresholds of MSPD in pixels for an image \a width pixels wide:
 * 5, 10, ..., 50 times width / 640. */
std::vector<double> bopMspdThresholds(int width);

}  // namespace evaluation
}  // namespace icf
}  // namespace pcl
