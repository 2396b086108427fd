/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_tool --track (issue 15) end to end on the bundled demo scene: one JSON line per
// frame, bad frames named and skipped, the stream going on, exit status as in batch mode.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Tracked {
  int code = -1;
  std::vector<nlohmann::json> lines;  ///< stdout, one JSON object a line
  std::string err;
};

/** Runs pcl_icf_tool --track \a frames on the demo's Box5 (paths without quotes). */
Tracked track(const fs::path& frames, const fs::path& dir) {
  const fs::path out = dir / "out.jsonl", err = dir / "err.txt";
  const std::string cmd = std::string(PCL_ICF_TOOL) + " --track " + frames.string() + " " +
                          PCL_ICF_DEMO_DATA + "/box5.ply >" + out.string() + " 2>" + err.string() +
                          " </dev/null";
  const int status = std::system(cmd.c_str());
  Tracked t;
  t.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream lines(out);
  for (std::string line; std::getline(lines, line);)
    t.lines.push_back(nlohmann::json::parse(line));
  std::ifstream e(err);
  t.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return t;
}

class ToolTrack : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pcl_icf_tool_track_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "frames");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ToolTrack, BadFramesAreNamedAndTheStreamGoesOn) {
  const fs::path frames = dir_ / "frames";
  const fs::path scene = fs::path(PCL_ICF_DEMO_DATA) / "tabletop_box5.pcd";
  fs::copy_file(scene, frames / "f1.pcd");
  std::ofstream(frames / "f2.pcd") << "not a point cloud\n";
  fs::copy_file(scene, frames / "f3.pcd");
  fs::copy_file(fs::path(PCL_ICF_DEMO_DATA) / "box5_cluster.pcd", frames / "f4.pcd");
  fs::copy_file(scene, frames / "f5.pcd");
  const Tracked t = track(frames, dir_);
  EXPECT_EQ(t.code, 2) << "a bad frame: exit 2 as in batch mode\n" << t.err;
  ASSERT_EQ(t.lines.size(), 5u) << t.err;
  const char* states[] = {"found", nullptr, "tracking", nullptr, "tracking"};
  for (std::size_t f = 0; f < 5; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const auto& line = t.lines[f];
    EXPECT_EQ(line.at("frame").get<std::size_t>(), f);
    if (!states[f]) {
      EXPECT_TRUE(line.contains("error"));
      EXPECT_NE(t.err.find("(f" + std::to_string(f + 1) + ".pcd) skipped"), std::string::npos)
          << t.err;
      continue;
    }
    const auto& o = line.at("objects").at(0);
    EXPECT_EQ(o.at("name").get<std::string>(), "box5");
    EXPECT_EQ(o.at("state").get<std::string>(), states[f]);
    EXPECT_GE(o.at("confidence").get<double>(), 0.875);
    EXPECT_EQ(o.at("pose").size(), 4u);
  }
  EXPECT_NE(t.lines[3].at("error").get<std::string>().find("size"), std::string::npos);
}

TEST_F(ToolTrack, EmptyFolderIsBadInput) {
  const Tracked t = track(dir_ / "frames", dir_);
  EXPECT_EQ(t.code, 2);
  EXPECT_TRUE(t.lines.empty());
  EXPECT_NE(t.err.find("no .pcd"), std::string::npos) << t.err;
}

}  // namespace
