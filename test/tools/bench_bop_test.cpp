// pcl_icf_bench --bop on one image of the shared BOP-layout frames (bop-ycbv, scene 0 image 2:
// the gelatin box and the foam brick at 0.55 m): BOP's CSV (header, R row-major and
// orthonormal, t in millimetres within 15 mm of scene_gt.json's, one time per image), the
// scores' table, and bad datasets refused with exit 2.
#include "test_paths.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Dense>

namespace {

namespace fs = std::filesystem;

class BenchBop : public pcl_icf_test::TempDirTest {
 protected:
  BenchBop() : TempDirTest("pcl_icf_bench_bop") {}
  int run(const std::string& args) const {
    const std::string cmd = std::string(PCL_ICF_BENCH) + " " + args + " >" +
                            (dir_ / "out.txt").string() + " 2>" + (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string slurp(const std::string& name) const {
    std::ifstream in(dir_ / name);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
};

std::vector<double> numbers(const std::string& field) {
  std::vector<double> v;
  std::istringstream in(field);
  for (double x; in >> x;)
    v.push_back(x);
  return v;
}

TEST_F(BenchBop, OneImageGivesBopsCsvAndScores) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const std::string targets =
      write("targets.json",
            "[{\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 8, \"scene_id\": 0},\n"
            " {\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 21, \"scene_id\": 0}]");
  ASSERT_EQ(run("--bop " + root + " --targets " + targets + " --out " + dir_.string()), 0)
      << slurp("err.txt");
  std::ifstream csv(dir_ / "pcl-icf_bop-ycbv-test.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "scene_id,im_id,obj_id,score,R,t,time");
  // The truth of image 2 (scene_gt.json): obj 8 and obj 21's translations, mm.
  const std::map<int, Eigen::Vector3d> truth = {
      {8, {-30.958847310268474, -7.7727835367356395, 592.4974912924775}}};
  std::size_t rows = 0;
  std::string time;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream in(line);
    for (std::string part; std::getline(in, part, ',');)
      f.push_back(part);
    ASSERT_EQ(f.size(), 7u) << line;
    EXPECT_EQ(f[0], "0");
    EXPECT_EQ(f[1], "2");
    const std::vector<double> r = numbers(f[4]), t = numbers(f[5]);
    ASSERT_EQ(r.size(), 9u);
    ASSERT_EQ(t.size(), 3u);
    const Eigen::Matrix3d R =
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r.data());
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-6) << line;
    EXPECT_GT(R.determinant(), 0.0);
    const int obj = std::stoi(f[2]);
    if (truth.count(obj)) {
      EXPECT_LT((Eigen::Vector3d(t[0], t[1], t[2]) - truth.at(obj)).norm(), 15.0) << line;
    }
    if (!time.empty()) {
      EXPECT_EQ(f[6], time) << "one time per image";
    }
    time = f[6];
    ++rows;
  }
  EXPECT_GE(rows, 1u);
  EXPECT_LE(rows, 2u) << "at most inst_count per target";
  const std::string scores = slurp("bop_scores.md");
  EXPECT_NE(scores.find("| all | 2 |"), std::string::npos) << scores;
  EXPECT_NE(scores.find("| 8 | 1 |"), std::string::npos) << scores;
}

TEST_F(BenchBop, BadDatasetsExitTwo) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  EXPECT_EQ(run("--bop " + (dir_ / "absent").string() + " --out " + dir_.string()), 2);
  EXPECT_NE(slurp("err.txt").find("camera.json: cannot be read"), std::string::npos)
      << slurp("err.txt");
  const std::string unknown =
      write("t.json", "[{\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 99, \"scene_id\": 0}]");
  EXPECT_EQ(run("--bop " + root + " --targets " + unknown + " --out " + dir_.string()), 2);
  EXPECT_NE(slurp("err.txt").find("object 99 has no entry"), std::string::npos) << slurp("err.txt");
  EXPECT_EQ(run("--bop " + root + " --frobnicate"), 2);
}

}  // namespace
