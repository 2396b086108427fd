/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the PLY mesh loader (our reader, io/src/ply_reader.cpp), then FaceMesh::build
// and the index.
#include "fuzz_common.h"

PCL_ICF_FILE_FUZZ_TARGET("ply", fuzzMeshFile)
