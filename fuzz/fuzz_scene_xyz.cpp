/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the .xyz / .asc text parser, in memory (parseXyzText is what
// loadSceneCloud runs on the file's bytes).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pcl_icf_fuzz::quiet();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    bool colour = false;
    const auto cloud = pcl::icf::io::parseXyzText(text, "fuzz.xyz", &colour);
    PCL_ICF_FUZZ_CHECK(cloud && !cloud->empty(), "a parsed cloud has points");
    PCL_ICF_FUZZ_CHECK(cloud->height == 1 && cloud->width == cloud->size(), "a plain list");
    bool dense = true;
    for (const auto& p : *cloud) {
      dense = dense && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      PCL_ICF_FUZZ_CHECK(colour || (p.r == 255 && p.g == 255 && p.b == 255), "white default");
      PCL_ICF_FUZZ_CHECK(p.a == 255, "opaque");
    }
    PCL_ICF_FUZZ_CHECK(dense == cloud->is_dense, "is_dense");
  } catch (const pcl::icf::io::FileError&) {
  }
  return 0;
}
