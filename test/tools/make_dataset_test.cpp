/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_make_dataset --kind sequence end to end: the frames, their list and the
// ground truth, checked against the frames' own points; the same seed gives the same bytes;
// bad options are refused.
#include "synthetic/mesh_geometry.h"
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Outcome {
  int code = -1;
  std::string err;
};

Outcome makeDataset(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "err.txt";
  const std::string cmd = std::string(PCL_ICF_MAKE_DATASET) + " " + args + " >/dev/null 2>" +
                          err.string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  Outcome r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream e(err);
  r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return r;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

Eigen::Isometry3d poseOf(const json& rows) {
  Eigen::Isometry3d pose;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      pose.matrix()(r, c) = rows.at(r).at(c).get<double>();
  return pose;
}

/** Points of \a frame inside \a model's bounding box at \a pose, shrunk by 5 mm at the bottom
 * (the table) and grown by 5 mm elsewhere (the sensor's noise). */
int pointsInside(const pcl::PointCloud<pcl::PointXYZRGB>& frame, const pcl::PolygonMesh& model,
                 const Eigen::Isometry3d& pose) {
  const Eigen::AlignedBox3d box = pcl::icf::synthetic::boundingBox(model);
  const Eigen::Vector3d lo = box.min() + Eigen::Vector3d(-0.005, -0.005, 0.005);
  const Eigen::Vector3d hi = box.max() + Eigen::Vector3d::Constant(0.005);
  const Eigen::Isometry3d to_model = pose.inverse();
  int inside = 0;
  for (const auto& p : frame)
    if (std::isfinite(p.z)) {
      const Eigen::Vector3d q = to_model * p.getVector3fMap().cast<double>();
      inside += (q.array() >= lo.array()).all() && (q.array() <= hi.array()).all();
    }
  return inside;
}

class MakeDataset : public pcl_icf_test::TempDirTest {
 protected:
  MakeDataset() : TempDirTest("pcl_icf_make_dataset_test") {}
};

TEST_F(MakeDataset, SequenceFramesAgreeWithTheirGroundTruth) {
  constexpr int kFrames = 12;
  const Outcome r =
      makeDataset("--kind sequence --frames 12 --seed 7 --out " + (dir_ / "a").string(), dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path seq = dir_ / "a" / "sequence" / "seq_000";
  const json truth = json::parse(slurp(seq / "truth.json"));

  // The list: the frames in order, relative to the sequence's folder.
  std::vector<std::string> listed;
  std::istringstream list(slurp(seq / "frames.txt"));
  for (std::string line; std::getline(list, line);)
    if (!line.empty() && line[0] != '#')
      listed.push_back(line);
  ASSERT_EQ(listed.size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(truth.at("frames").size(), static_cast<std::size_t>(kFrames));

  // Three objects: two tracked (their models listed for the tool), one occluder.
  const json& objects = truth.at("objects");
  ASSERT_EQ(objects.size(), 3u);
  std::istringstream tracked(slurp(seq / "tracked_models.txt"));
  std::vector<std::string> tracked_models;
  for (std::string line; std::getline(tracked, line);)
    tracked_models.push_back(line);
  ASSERT_EQ(tracked_models.size(), 2u);
  std::map<std::string, pcl::PolygonMesh> meshes;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string name = objects[i].at("name");
    EXPECT_EQ(objects[i].at("tracked").get<bool>(), i < 2) << name;
    EXPECT_TRUE(fs::exists(seq / objects[i].at("model").get<std::string>())) << name;
    if (i < 2) {
      EXPECT_EQ(tracked_models[i], objects[i].at("model").get<std::string>());
    }
    meshes[name] = name == "TallCylinder" ? pcl::icf::synthetic::makeCylinder(0.035, 0.16, 32)
                                          : pcl::icf::synthetic::thesisModel(name).mesh;
  }
  const std::string moved = objects[0].at("name"), occluded = objects[1].at("name");
  const int gone = objects[0].at("absent").at(0), back = objects[0].at("absent").at(1);
  EXPECT_GE(back - gone, 3);
  EXPECT_LE(back - gone, 6);
  EXPECT_LT(back, kFrames);

  double least_visible = 1.0;
  int most_absent = 0, least_present = 1 << 30;
  for (int f = 0; f < kFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const json& line = truth.at("frames").at(static_cast<std::size_t>(f));
    EXPECT_EQ(line.at("file").get<std::string>(), listed[static_cast<std::size_t>(f)]);
    pcl::PointCloud<pcl::PointXYZRGB> frame;
    ASSERT_EQ(pcl::io::loadPCDFile((seq / listed[static_cast<std::size_t>(f)]).string(), frame), 0);
    EXPECT_EQ(frame.width, 640u);
    EXPECT_EQ(frame.height, 480u);
    for (const auto& o : line.at("objects")) {
      const std::string name = o.at("name");
      SCOPED_TRACE(name);
      const Eigen::Isometry3d pose = poseOf(o.at("pose"));
      EXPECT_LT((pose.linear().transpose() * pose.linear() - Eigen::Matrix3d::Identity()).norm(),
                1e-9);
      const bool present = o.at("present");
      const double visible = o.at("visible");
      const int inside = pointsInside(frame, meshes.at(name), pose);
      if (name == moved)
        EXPECT_EQ(present, f < gone || f >= back);
      else
        EXPECT_TRUE(present);
      if (!present) {
        EXPECT_EQ(visible, 0.0);
        most_absent = std::max(most_absent, inside);  // the table's outliers only
      } else if (visible >= 0.5) {
        EXPECT_GT(inside, 300) << "visible " << visible;
        least_present = std::min(least_present, inside);
      }
      if (name == occluded)
        least_visible = std::min(least_visible, visible);
    }
  }
  EXPECT_LT(5 * most_absent, least_present)
      << "points where the absent object would stand: " << most_absent;
  // The occluder crosses in front of the second object mid-sequence.
  EXPECT_LT(least_visible, 0.9);

  // The same seed, the same bytes; another seed, another sequence.
  ASSERT_EQ(
      makeDataset("--kind sequence --frames 12 --seed 7 --out " + (dir_ / "b").string(), dir_).code,
      0);
  const fs::path again = dir_ / "b" / "sequence" / "seq_000";
  EXPECT_EQ(slurp(seq / "truth.json"), slurp(again / "truth.json"));
  EXPECT_EQ(slurp(seq / listed[5]), slurp(again / listed[5]));
  ASSERT_EQ(
      makeDataset("--kind sequence --frames 12 --seed 8 --out " + (dir_ / "c").string(), dir_).code,
      0);
  EXPECT_NE(slurp(seq / "truth.json"), slurp(dir_ / "c" / "sequence" / "seq_000" / "truth.json"));
}

// pcl_icf_track_score on made-up tracker outputs: the truth itself (a perfect tracker) meets
// every bar; a pose while absent, a pose 2 cm off and a late loss are each reported.
TEST_F(MakeDataset, TrackScoreOfAPerfectAndOfAFaultyTracker) {
  ASSERT_EQ(
      makeDataset("--kind sequence --frames 12 --seed 7 --out " + (dir_ / "a").string(), dir_).code,
      0);
  const fs::path seq = dir_ / "a" / "sequence" / "seq_000";
  const json truth = json::parse(slurp(seq / "truth.json"));
  const std::string moved = truth.at("objects").at(0).at("name");
  const int gone = truth.at("objects").at(0).at("absent").at(0);
  enum Fault { kNone, kPoseWhileAbsent, kOff, kLateLoss };
  auto write = [&](Fault fault) {
    std::ofstream out(seq / "poses.jsonl");
    for (const auto& frame : truth.at("frames")) {
      const int f = frame.at("frame");
      json line = {{"frame", f}, {"file", frame.at("file")}, {"ms", 20.0}};
      for (const auto& o : frame.at("objects")) {
        if (o.at("name") == "TallCylinder")
          continue;
        bool posed = o.at("present").get<bool>();
        json pose = o.at("pose");
        if (o.at("name") == moved && f == gone && (fault == kPoseWhileAbsent || fault == kLateLoss))
          posed = true;
        if (o.at("name") == moved && f == gone + 1 && fault == kLateLoss)
          posed = true;
        if (o.at("name") == moved && f == 1 && fault == kOff)
          pose[0][3] = pose[0][3].get<double>() + 0.02;
        line["objects"].push_back({{"name", o.at("name")},
                                   {"state", posed ? "tracking" : "lost"},
                                   {"pose", posed ? pose : json(nullptr)},
                                   {"refine_ms", 1.0}});
      }
      out << line.dump() << "\n";
    }
  };
  auto score = [&](std::string& text) {
    const fs::path out = dir_ / "score.txt";
    const int status = std::system(
        (std::string(PCL_ICF_TRACK_SCORE) + " " + seq.string() + " >" + out.string() + " 2>&1")
            .c_str());
    text = slurp(out);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  std::string text;
  write(kNone);
  EXPECT_EQ(score(text), 0) << text;
  EXPECT_NE(text.find("| 0/"), std::string::npos) << "no pose while absent\n" << text;
  EXPECT_EQ(text.find("missed:"), std::string::npos) << text;
  write(kPoseWhileAbsent);
  EXPECT_EQ(score(text), 1) << text;
  EXPECT_NE(text.find("no pose while absent: NOT met"), std::string::npos) << text;
  write(kOff);
  EXPECT_EQ(score(text), 1) << text;
  EXPECT_NE(text.find("frame 1 (visible"), std::string::npos) << text;
  EXPECT_NE(text.find("20.0 mm"), std::string::npos) << text;
  write(kLateLoss);
  EXPECT_EQ(score(text), 1) << text;
  EXPECT_NE(text.find("loss within 3 frames: met"), std::string::npos) << "lost after 2\n" << text;
  EXPECT_NE(text.find("| 2 |"), std::string::npos) << text;
  // Bad input: no truth.
  const int status = std::system(
      (std::string(PCL_ICF_TRACK_SCORE) + " " + dir_.string() + " >/dev/null 2>&1").c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

TEST_F(MakeDataset, BadOptionsAreRefused) {
  const std::string out = " --out " + (dir_ / "x").string();
  const struct {
    std::string args, says;
  } cases[] = {
      {"--kind sequence --frames 3" + out, "--frames must lie in [10, 100000]"},
      {"--kind sequence --frames ten" + out, "--frames: 'ten' is not an integer"},
      {"--kind sequence --seed -1" + out, "--seed: '-1' is not an integer"},
      {"--kind sequence --manifest m.txt" + out, "no --manifest"},
      {"--kind film" + out, "--kind must be"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    const Outcome r = makeDataset(c.args, dir_);
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "x" / "sequence"));
}

}  // namespace
