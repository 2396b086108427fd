// pcl_icf_bench --bop on one image of the shared BOP-layout frames (bop-ycbv, scene 0 image 2:
// the gelatin box and the foam brick at 0.55 m): BOP's CSV (header, R row-major and
// orthonormal, t in millimetres within 15 mm of scene_gt.json's, one time per image), the
// scores' table, and bad datasets refused with exit 2. Three images run once and as two shards
// under mpirun -np 2, merged: the same CSV but for the times and the same scores; bad shard
// specs, a missing shard and shards of two runs refused with exit 2.
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
  int run(const std::string& args, const std::string& launcher = "") const {
    const std::string cmd = launcher + std::string(PCL_ICF_BENCH) + " " + args + " >" +
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

// The peer selection (--selection ghv): PCL's Global Hypotheses Verification over the same
// hypotheses writes its own CSV (BOP's method name pcl-icf-ghv), at most inst_count rows per
// target, and is scored as the default one; an unknown selection is a usage error.
TEST_F(BenchBop, GhvSelectionWritesThePeersCsv) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const std::string targets =
      write("targets.json",
            "[{\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 8, \"scene_id\": 0},\n"
            " {\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 21, \"scene_id\": 0}]");
  const std::string common = "--bop " + root + " --targets " + targets + " --out " + dir_.string();
  ASSERT_EQ(run(common + " --selection ghv"), 0) << slurp("err.txt");
  EXPECT_FALSE(fs::exists(dir_ / "pcl-icf_bop-ycbv-test.csv"));
  std::ifstream csv(dir_ / "pcl-icf-ghv_bop-ycbv-test.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "scene_id,im_id,obj_id,score,R,t,time");
  std::map<std::string, int> per_object;
  while (std::getline(csv, line))
    ++per_object[line.substr(0, line.find(',', line.find(',', line.find(',') + 1) + 1))];
  for (const auto& [object, rows] : per_object)
    EXPECT_EQ(rows, 1) << object << ": at most inst_count per target";
  EXPECT_NE(slurp("bop_scores.md").find("| all | 2 |"), std::string::npos)
      << slurp("bop_scores.md");
  EXPECT_EQ(run(common + " --selection best"), 2);
  EXPECT_NE(slurp("err.txt").find("--selection: icf or ghv"), std::string::npos)
      << slurp("err.txt");
}

/** The CSV's rows without their time column (times differ between any two runs). */
std::vector<std::string> rowsWithoutTimes(const fs::path& csv) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);)
    rows.push_back(line.substr(0, line.rfind(',')));
  return rows;
}

/** The scores' table: the lines from its header on (the title names the CSV's path). */
std::string table(const std::string& scores) {
  const std::size_t at = scores.find("| object");
  return at == std::string::npos ? "" : scores.substr(at);
}

// Three images of two scenes (so shard 1 of 2 holds two images and shard 2 one), once in one
// process and once as mpirun -np 2 (each rank its shard from OMPI_COMM_WORLD_RANK/SIZE), then
// --merge: the rows are identical but for the time column, and so are the scores.
TEST_F(BenchBop, MpirunShardsMergeToTheSingleRun) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const std::string targets =
      write("targets.json",
            "[{\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 8, \"scene_id\": 0},\n"
            " {\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 21, \"scene_id\": 0},\n"
            " {\"im_id\": 7, \"inst_count\": 1, \"obj_id\": 21, \"scene_id\": 0},\n"
            " {\"im_id\": 3, \"inst_count\": 1, \"obj_id\": 5, \"scene_id\": 1}]");
  const fs::path one = dir_ / "one", two = dir_ / "two";
  const std::string common = "--bop " + root + " --targets " + targets + " --threads 1 --out ";
  ASSERT_EQ(run(common + one.string()), 0) << slurp("err.txt");
  const std::string single = slurp("out.txt");
  // Open MPI refuses root unless told; CI's containers run as root.
  const std::string mpirun = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                             std::string(PCL_ICF_MPIRUN) + " -np 2 --oversubscribe ";
  ASSERT_EQ(run(common + two.string(), mpirun), 0) << slurp("err.txt");
  EXPECT_FALSE(fs::exists(two / "pcl-icf_bop-ycbv-test.csv")) << "shards do not score";
  ASSERT_TRUE(fs::exists(two / "pcl-icf_bop-ycbv-test.shard-1-of-2.json"));
  ASSERT_TRUE(fs::exists(two / "pcl-icf_bop-ycbv-test.shard-2-of-2.json"));
  ASSERT_EQ(run(common + two.string() + " --merge"), 0) << slurp("err.txt");
  const auto a = rowsWithoutTimes(one / "pcl-icf_bop-ycbv-test.csv");
  EXPECT_GE(a.size(), 3u);
  EXPECT_EQ(a, rowsWithoutTimes(two / "pcl-icf_bop-ycbv-test.csv"));
  EXPECT_FALSE(table(single).empty()) << single;
  EXPECT_EQ(table(single), table(slurp("out.txt")));

  // A shard of another run (another seed) beside the others: refused, no CSV written.
  fs::remove(two / "pcl-icf_bop-ycbv-test.csv");
  ASSERT_EQ(run(common + two.string() + " --shard 2/2 --seed 7"), 0) << slurp("err.txt");
  EXPECT_EQ(run(common + two.string() + " --merge"), 2);
  EXPECT_NE(slurp("err.txt").find("of another run"), std::string::npos) << slurp("err.txt");
  EXPECT_FALSE(fs::exists(two / "pcl-icf_bop-ycbv-test.csv"));
  // A missing shard, and a record without its CSV.
  fs::remove(two / "pcl-icf_bop-ycbv-test.shard-2-of-2.csv");
  EXPECT_EQ(run(common + two.string() + " --merge"), 2);
  EXPECT_NE(slurp("err.txt").find("did not finish"), std::string::npos) << slurp("err.txt");
  fs::remove(two / "pcl-icf_bop-ycbv-test.shard-2-of-2.json");
  EXPECT_EQ(run(common + two.string() + " --merge"), 2);
  EXPECT_NE(slurp("err.txt").find("shard 2 of 2 is missing"), std::string::npos)
      << slurp("err.txt");
  EXPECT_FALSE(fs::exists(two / "pcl-icf_bop-ycbv-test.csv"));
}

// A test split whose truth is withheld (no scene_gt.json, no scene_gt_info.json; the dataset
// here is bop-ycbv's files linked without them): the CSV is written, the scores are not.
TEST_F(BenchBop, SplitWithoutTruthGetsItsCsvOnly) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const fs::path ds = dir_ / "withheld", scene = ds / "test" / "000000";
  fs::create_directories(scene);
  for (const char* f : {"camera.json", "models"})
    fs::create_symlink(fs::path(root) / f, ds / f);
  for (const char* f : {"depth", "rgb", "scene_camera.json"})
    fs::create_symlink(fs::path(root) / "test" / "000000" / f, scene / f);
  const std::string targets =
      write("targets.json", "[{\"im_id\": 2, \"inst_count\": 1, \"obj_id\": 21, \"scene_id\": 0}]");
  ASSERT_EQ(run("--bop " + ds.string() + " --targets " + targets + " --out " + dir_.string()), 0)
      << slurp("err.txt");
  EXPECT_NE(slurp("out.txt").find("not scored"), std::string::npos) << slurp("out.txt");
  EXPECT_EQ(rowsWithoutTimes(dir_ / "pcl-icf_withheld-test.csv").size(), 2u)
      << "the header and the brick";
  EXPECT_FALSE(fs::exists(dir_ / "bop_scores.md"));
}

// Shard specs that name no shard, from the option or from the environment: exit 2 before any
// work.
TEST_F(BenchBop, BadShardSpecsExitTwo) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const std::string common = "--bop " + root + " --out " + dir_.string();
  for (const char* spec : {"3/2", "0/0", "0/2", "1", "a/b", "1/-2", "2/"}) {
    EXPECT_EQ(run(common + " --shard " + spec), 2) << spec;
    EXPECT_NE(slurp("err.txt").find("--shard"), std::string::npos) << slurp("err.txt");
  }
  EXPECT_EQ(run(common, "OMPI_COMM_WORLD_RANK=2 OMPI_COMM_WORLD_SIZE=2 "), 2);
  EXPECT_NE(slurp("err.txt").find("OMPI_COMM_WORLD"), std::string::npos) << slurp("err.txt");
  EXPECT_EQ(run(common, "SLURM_ARRAY_TASK_ID=x SLURM_ARRAY_TASK_COUNT=4 "), 2);
  EXPECT_NE(slurp("err.txt").find("SLURM_ARRAY_TASK_ID=x"), std::string::npos) << slurp("err.txt");
  EXPECT_EQ(run(common + " --merge --shard 1/2"), 2);
  EXPECT_EQ(run(common + " --merge"), 2);
  EXPECT_NE(slurp("err.txt").find("no shards to merge"), std::string::npos) << slurp("err.txt");
}

}  // namespace
