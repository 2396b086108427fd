/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the PLY scene loader (the vertices as points; our reader,
// io/src/ply_reader.cpp).
#include "fuzz_common.h"

PCL_ICF_FILE_FUZZ_TARGET("ply", fuzzSceneFile)
