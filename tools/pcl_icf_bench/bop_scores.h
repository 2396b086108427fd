/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The scores of a BOP results CSV against the dataset's truth: BOP's Average Recalls
 * (VSD, MSSD, MSPD and their mean AR, pcl/icf/evaluation/) and beside them the recall of ADD(-S)
 * below 10% of the diameter and of the project's rule (the model's box centre within 1 cm and
 * ADD-S to the surface below 10% of the diameter), per object and overall. */

#include "bop_bench_data.h"
#include "bop_results.h"

#include <string>
#include <vector>

namespace pcl_icf_bench {

struct BopScoreParams {
  /** Instances seen less than this are not counted (BOP 2019's targets are those seen 10%). */
  double visib_gt_min = 0.1;
  double vsd_delta_mm = 15.0;  ///< BOP 2019's delta for every dataset but ITODD (5)
};

/** The scores' table (markdown, one row per object and one for all) of \a rows, BOP's
 * matching: per target, the best inst_count estimates by score, each to the unmatched visible
 * instance of least error below the threshold. Rows of images or objects that are not targets
 * are not scored. */
std::string bopScoresTable(BopBenchData& data, const std::vector<BopEstimate>& rows,
                           const BopScoreParams& params);

}  // namespace pcl_icf_bench
