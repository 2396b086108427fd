/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the PCD scene loader (ascii, binary, binary_compressed; our reader,
// io/src/pcd_reader.cpp).
#include "fuzz_common.h"

PCL_ICF_FILE_FUZZ_TARGET("pcd", fuzzSceneFile)
