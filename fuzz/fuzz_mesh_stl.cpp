/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the STL mesh loader (ascii or binary; our reader, io/src/obj_stl_readers.cpp),
// then FaceMesh::build and the index.
#include "fuzz_common.h"

PCL_ICF_FILE_FUZZ_TARGET("stl", fuzzMeshFile)
