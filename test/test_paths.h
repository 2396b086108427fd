// Paths of test data: the committed fixtures and the real data beside the repository.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace pcl_icf_test {

/** Path of a file under ../shared/data, or "" when the folder is absent. */
inline std::string sharedData(const std::string& relative) {
  const std::filesystem::path p = std::filesystem::path(PCL_ICF_SHARED_DATA) / relative;
  return std::filesystem::exists(p) ? p.string() : std::string();
}

/** Path of a committed fixture under test/data. */
inline std::string fixture(const std::string& relative) {
  return (std::filesystem::path(PCL_ICF_TEST_DATA) / relative).string();
}

}  // namespace pcl_icf_test

/** Skips the current test, saying why, when ../shared/data/<relative> is missing. */
#define PCL_ICF_REQUIRE_SHARED(var, relative)                 \
  const std::string var = pcl_icf_test::sharedData(relative); \
  if (var.empty())                                            \
  GTEST_SKIP() << "../shared/data/" << (relative)             \
               << " is absent (clone beside the project's shared folder to run this test)"
