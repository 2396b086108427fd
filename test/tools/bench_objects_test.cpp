// pcl_icf_bench --methods icf-objects on the shared YCB-Video frame (the sugar box and the
// potted meat can, touching, at 0.8 m): every model of the manifest searched for in one call
// and the case's model scored against the frame's ground truth (data/manifests/ycbv.txt), beside
// icf-scene (one call per model). With one model in the manifest, icf-objects is the single
// call: the same pose and confidence to the last printed digit (localizeObject is the
// one-model case of localizeObjects).
#include "test_paths.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

/** One row of NAME_cases.csv: its fields by the header's names. */
using Row = std::map<std::string, std::string>;

/** The fields of one CSV line; quoted fields may hold commas. */
std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      fields.emplace_back();
    else
      fields.back() += c;
  }
  return fields;
}

class BenchObjects : public pcl_icf_test::TempDirTest {
 protected:
  BenchObjects() : TempDirTest("pcl_icf_bench_objects") {}

  /** The committed YCB-V manifest's cases whose names are in \a names, paths into the
   * shared data, written as dir_/NAME.txt. */
  std::string manifest(const std::string& name, const std::vector<std::string>& names) const {
    std::ifstream in(fs::path(PCL_ICF_SOURCE_DIR) / "data" / "manifests" / "ycbv.txt");
    std::ofstream out(dir_ / (name + ".txt"));
    const std::string relative = "../../../shared/data/";
    for (std::string line; std::getline(in, line);) {
      bool wanted = false;
      for (const auto& n : names)
        wanted = wanted || line.rfind("name=" + n + " ", 0) == 0;
      if (!wanted)
        continue;
      for (auto at = line.find(relative); at != std::string::npos; at = line.find(relative))
        line.replace(at, relative.size(), std::string(PCL_ICF_SHARED_DATA) + "/");
      out << line << "\n";
    }
    return (dir_ / (name + ".txt")).string();
  }

  int run(const std::string& args) const {
    const std::string cmd = std::string(PCL_ICF_BENCH) + " --no-plots --out " + dir_.string() +
                            " " + args + " >" + (dir_ / "out.txt").string() + " 2>" +
                            (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::string slurp(const std::string& name) const {
    std::ifstream in(dir_ / name);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }

  /** Rows of dir_/NAME_cases.csv keyed by "case method". */
  std::map<std::string, Row> rows(const std::string& name) const {
    std::ifstream csv(dir_ / (name + "_cases.csv"));
    std::string line;
    std::getline(csv, line);
    const std::vector<std::string> header = csvFields(line);
    std::map<std::string, Row> out;
    while (std::getline(csv, line)) {
      const std::vector<std::string> f = csvFields(line);
      Row row;
      for (std::size_t i = 0; i < header.size() && i < f.size(); ++i)
        row[header[i]] = f[i];
      out[row["case"] + " " + row["method"]] = row;
    }
    return out;
  }
};

TEST_F(BenchObjects, BothObjectsOfTheFrameAreFoundInOneCall) {
  PCL_ICF_REQUIRE_SHARED(root, "ycbv/ycbv_frame000002.pcd");
  const std::string list = manifest("both", {"ycbv2_sugar_box", "ycbv2_potted_meat_can"});
  ASSERT_EQ(run("--methods icf-scene,icf-objects " + list), 0) << slurp("err.txt");
  const auto r = rows("both");
  ASSERT_EQ(r.size(), 4u) << slurp("both_cases.csv");
  // The suites' rule against the frame's ground truth: centre within 1 cm, ADD-S < 10% of
  // the diameter. Both objects are found by the single calls (doc/BENCHMARKS.md); asked for
  // together, each keeps its own points.
  for (const std::string c : {"ycbv2_sugar_box", "ycbv2_potted_meat_can"})
    for (const std::string m : {"icf-scene", "icf-objects"}) {
      const std::string key = c + " " + m;
      ASSERT_TRUE(r.count(key)) << key;
      EXPECT_EQ(r.at(key).at("success"), "1") << key << ": " << r.at(key).at("detail");
    }
}

TEST_F(BenchObjects, OneModelIsTheSingleCall) {
  PCL_ICF_REQUIRE_SHARED(root, "ycbv/ycbv_frame000002.pcd");
  const std::string list = manifest("one", {"ycbv2_sugar_box"});
  ASSERT_EQ(run("--methods icf-scene,icf-objects --threads 2 " + list), 0) << slurp("err.txt");
  const auto r = rows("one");
  ASSERT_EQ(r.size(), 2u) << slurp("one_cases.csv");
  const Row& single = r.at("ycbv2_sugar_box icf-scene");
  const Row& objects = r.at("ycbv2_sugar_box icf-objects");
  EXPECT_EQ(objects.at("pose_row_major"), single.at("pose_row_major"));
  EXPECT_EQ(objects.at("confidence"), single.at("confidence"));
  EXPECT_EQ(objects.at("verification"), single.at("verification"));
}

}  // namespace
