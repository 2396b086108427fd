/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the OBJ mesh loader (our reader, io/src/obj_stl_readers.cpp), then
// FaceMesh::build and the index.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pcl_icf_fuzz::quiet();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const pcl_icf_fuzz::ScratchFile file("obj");
  pcl_icf_fuzz::fuzzMeshFile(file, data, size);
  return 0;
}
