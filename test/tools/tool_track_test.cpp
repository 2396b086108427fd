/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_tool --track end to end on the bundled demo scene: one JSON line per
// frame, bad frames named and skipped, the stream going on, exit status as in batch mode.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include "test_paths.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Tracked {
  int code = -1;
  std::vector<nlohmann::json> lines;  ///< stdout, one JSON object a line
  std::string err;
};

/** Runs pcl_icf_tool --track \a frames on the demo's Box5 with \a extra options (paths without
 * quotes), under `timeout` so that a --follow that never stops fails instead of hanging. */
Tracked track(const fs::path& frames, const fs::path& dir, const std::string& extra = "") {
  const fs::path out = dir / "out.jsonl", err = dir / "err.txt";
  const std::string cmd = "timeout 600 " + std::string(PCL_ICF_TOOL) + " --track " +
                          frames.string() + " " + PCL_ICF_DEMO_DATA + "/box5.ply " + extra + " >" +
                          out.string() + " 2>" + err.string() + " </dev/null";
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

bool canRender() {
  const char* display = std::getenv("DISPLAY");
  return (display && *display) || std::system("command -v xvfb-run >/dev/null 2>&1") == 0;
}

/** A PNG's width and height from its IHDR chunk; {0, 0} when \a path is not a PNG. */
std::pair<unsigned, unsigned> pngSize(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char head[24] = {};
  in.read(reinterpret_cast<char*>(head), sizeof(head));
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!in || !std::equal(signature, signature + 8, head) ||
      std::string(reinterpret_cast<char*>(head + 12), 4) != "IHDR")
    return {0, 0};
  auto be32 = [&](int at) {
    return (unsigned(head[at]) << 24) | (unsigned(head[at + 1]) << 16) |
           (unsigned(head[at + 2]) << 8) | unsigned(head[at + 3]);
  };
  return {be32(16), be32(20)};
}

class ToolTrack : public pcl_icf_test::TempDirTest {
 protected:
  ToolTrack() : TempDirTest("pcl_icf_tool_track_test") {}
  void SetUp() override {
    TempDirTest::SetUp();
    fs::create_directories(dir_ / "frames");
  }
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

// --render-dir: one picture per good frame, the camera's 320 x 240 scaled to 640 x 480; the
// unreadable frame has a JSON line but no picture.
TEST_F(ToolTrack, RenderDirWritesOnePicturePerFrame) {
  if (!canRender())
    GTEST_SKIP() << "no DISPLAY and no xvfb-run: cannot test --render-dir";
  const fs::path frames = dir_ / "frames";
  const fs::path scene = fs::path(PCL_ICF_DEMO_DATA) / "tabletop_box5.pcd";
  fs::copy_file(scene, frames / "a.pcd");
  std::ofstream(frames / "b.pcd") << "not a point cloud\n";
  fs::copy_file(scene, frames / "c.pcd");
  const fs::path pictures = dir_ / "pictures" / "new";  // created by the tool
  const Tracked t = track(frames, dir_, "--render-dir " + pictures.string());
  EXPECT_EQ(t.code, 2) << "the unreadable frame: exit 2\n" << t.err;
  ASSERT_EQ(t.lines.size(), 3u) << t.err;
  for (const char* name : {"0000_a.png", "0002_c.png"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(fs::exists(pictures / name)) << t.err;
    EXPECT_GT(fs::file_size(pictures / name), 3000u);  // flat colours: 6-7 kB
    EXPECT_EQ(pngSize(pictures / name), std::make_pair(640u, 480u));
  }
  EXPECT_FALSE(fs::exists(pictures / "0001_b.png"));
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(pictures))
    files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 2u) << "no temporary file left behind";

  // Again: the pictures exist, so without --force nothing is tracked.
  const Tracked again = track(frames, dir_, "--render-dir " + pictures.string());
  EXPECT_EQ(again.code, 2);
  EXPECT_TRUE(again.lines.empty());
  EXPECT_NE(again.err.find("0000_a.png"), std::string::npos) << again.err;
}

TEST_F(ToolTrack, RenderDirAndFollowMisuseIsBadUsage) {
  fs::copy_file(fs::path(PCL_ICF_DEMO_DATA) / "tabletop_box5.pcd", dir_ / "frames" / "a.pcd");
  std::ofstream(dir_ / "file") << "x\n";
  std::ofstream(dir_ / "list.txt") << "frames/a.pcd\n";
  const struct {
    std::string frames, extra, says;
  } cases[] = {
      {(dir_ / "frames").string(), "--render-dir " + (dir_ / "file").string(), "not a directory"},
      {(dir_ / "list.txt").string(), "--follow", "--follow watches a directory"},
      {(dir_ / "frames").string(), "--idle-seconds 1", "--idle-seconds is for --follow"},
      {(dir_ / "frames").string(), "--follow --idle-seconds 0", "must be > 0"},
      {(dir_ / "frames").string(), "--follow --idle-seconds x", "not a number"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.extra);
    const Tracked t = track(c.frames, dir_, c.extra);
    EXPECT_EQ(t.code, 2);
    EXPECT_TRUE(t.lines.empty());
    EXPECT_NE(t.err.find(c.says), std::string::npos) << t.err;
  }
  // Without --track.
  const std::string cmd = std::string(PCL_ICF_TOOL) + " " + PCL_ICF_DEMO_DATA +
                          "/tabletop_box5.pcd " + PCL_ICF_DEMO_DATA + "/box5.ply --follow >" +
                          (dir_ / "o").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

// --follow: a frame there from the start (and a hidden file, ignored), one renamed into the
// folder while the tool runs, one written in two parts; each tracked once, in name order, and
// the tool stops after the idle time.
TEST_F(ToolTrack, FollowTracksFramesAsTheyAppearAndStopsWhenIdle) {
  const fs::path frames = dir_ / "frames";
  const fs::path scene = fs::path(PCL_ICF_DEMO_DATA) / "tabletop_box5.pcd";
  fs::copy_file(scene, frames / "f1.pcd");
  fs::copy_file(scene, frames / ".f0.pcd");  // hidden: a writer's temporary, never tracked
  Tracked t;
  const auto start = std::chrono::steady_clock::now();
  std::thread tool([&] { t = track(frames, dir_, "--follow --idle-seconds 2"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  fs::copy_file(scene, dir_ / "f2.tmp");
  fs::rename(dir_ / "f2.tmp", frames / "f2.pcd");
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  {
    std::ifstream in(scene, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream out(frames / "f3.pcd", std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
    out.flush();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    out.write(bytes.data() + bytes.size() / 2,
              static_cast<std::streamsize>(bytes.size() - bytes.size() / 2));
  }
  tool.join();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(t.code, 0) << t.err;
  ASSERT_EQ(t.lines.size(), 3u) << t.err;
  const char* states[] = {"found", "tracking", "tracking"};
  for (std::size_t f = 0; f < 3; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    EXPECT_EQ(t.lines[f].at("frame").get<std::size_t>(), f);
    EXPECT_EQ(fs::path(t.lines[f].at("file").get<std::string>()).filename(),
              "f" + std::to_string(f + 1) + ".pcd");
    ASSERT_FALSE(t.lines[f].contains("error")) << t.lines[f].dump();
    EXPECT_EQ(t.lines[f].at("objects").at(0).at("state").get<std::string>(), states[f]);
  }
  EXPECT_GE(seconds, 2.0) << "stopped before the idle time";
}

TEST_F(ToolTrack, FollowWithoutAnyFrameIsBadInput) {
  const Tracked t = track(dir_ / "frames", dir_, "--follow --idle-seconds 0.5");
  EXPECT_EQ(t.code, 2);
  EXPECT_TRUE(t.lines.empty());
  EXPECT_NE(t.err.find("no frame appeared"), std::string::npos) << t.err;
}

}  // namespace
