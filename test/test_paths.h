// Paths of test data: the committed fixtures and the real data beside the repository.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <utility>

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

/** True when the environment variable CI is "true" (CI sets it and has ../shared/data): a test
 * whose real data is absent then fails instead of skipping. */
inline bool inCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::strcmp(ci, "true") == 0;
}

/** Why a test cannot run without ../shared/data/<relative>. */
inline std::string absentMessage(const std::string& relative) {
  return "../shared/data/" + relative +
         (inCi() ? " is absent, and CI=true requires the real data"
                 : " is absent (clone beside the project's shared folder to run this test)");
}

/** A test fixture with a fresh, empty folder of its own, dir_ =
 * <tmp>/<prefix>_<pid>_<test name>, removed after the test. */
class TempDirTest : public ::testing::Test {
 protected:
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + "_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace pcl_icf_test

/** Declares `const std::string var`, the path of ../shared/data/<relative>. When that is
 * missing, ends the current test saying why: a failure when CI=true (pcl_icf_test::inCi(); CI
 * has the data, so a real-data test must run there), a skip elsewhere. */
#define PCL_ICF_REQUIRE_SHARED(var, relative)                 \
  const std::string var = pcl_icf_test::sharedData(relative); \
  if (!var.empty()) {                                         \
  } else if (pcl_icf_test::inCi())                            \
    GTEST_FAIL() << pcl_icf_test::absentMessage(relative);    \
  else                                                        \
    GTEST_SKIP() << pcl_icf_test::absentMessage(relative)
