/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief pcl_icf_bench --bop ROOT: every target image of a BOP dataset through the
 * many-objects call (localizeObjects), BOP's results CSV, and its scores (AR = the mean of the
 * VSD, MSSD and MSPD Average Recalls) per object and overall (doc/USER_GUIDE.md, "BOP"). */

namespace pcl_icf_bench {

/** Runs `pcl_icf_bench --bop ROOT [options]` (argv as main's); 0 when it ran, 2 for bad usage
 * or a bad dataset (said on stderr). */
int runBop(int argc, char** argv);

}  // namespace pcl_icf_bench
