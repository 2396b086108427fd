// Prepared-model files and the cache (model_file.h) against IcfModel::build itself: a model
// read back answers every field lookup and holds the point pair table exactly as the built one;
// every way a file can be unusable (truncated, one byte flipped, another format version,
// another mesh or other units, not a model file at all) is refused with its reason; the cache
// builds once, then reads, and rebuilds a corrupt entry with a warning; writers racing on one
// entry never leave a reader a broken file.
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/icf/registration/model_file.h>

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

namespace {

using namespace pcl::icf;
namespace fs = std::filesystem;

class ModelFile : public pcl_icf_test::TempDirTest {
 protected:
  ModelFile() : TempDirTest("pcl_icf_model_file") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  static void spit(const std::string& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
  }
  /** The error readModelFile gives for \a file, "" when it reads. */
  static std::string refusal(const std::string& file, const pcl::PolygonMesh& mesh,
                             const IcfModelParams& params = {}) {
    try {
      readModelFile(file, mesh, params);
    } catch (const ModelFileError& e) {
      return e.what();
    }
    return "";
  }
  const pcl::PolygonMesh mesh_ = synthetic::thesisModel("Cup").mesh;
};

TEST_F(ModelFile, ReadsBackTheModelBuildMakes) {
  const IcfModel::ConstPtr built = IcfModel::build(mesh_);
  writeModelFile(*built, mesh_, preparationKey(mesh_, {}), path("cup.icfmodel"));
  const IcfModel::ConstPtr read = readModelFile(path("cup.icfmodel"), mesh_, {});
  // The field: every lookup the same, bit for bit, over its box and beyond.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.2f, 0.2f);
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3f p(u(rng), u(rng), u(rng));
    ASSERT_EQ(read->field().distance(p), built->field().distance(p));
    ASSERT_EQ(read->field().distanceUpperBound(p), built->field().distanceUpperBound(p));
  }
  EXPECT_EQ(read->field().dimensions(), built->field().dimensions());
  // The table: the same samples, bins and entries.
  const PointPairModel &a = read->pointPairs(), &b = built->pointPairs();
  ASSERT_EQ(a.pairs(), b.pairs());
  EXPECT_EQ(a.points(), b.points());
  EXPECT_EQ(a.normals(), b.normals());
  EXPECT_EQ(a.step(), b.step());
  EXPECT_EQ(a.diameter(), b.diameter());
  for (int d = 0; d < a.distanceBins(); d += 3)
    for (int a1 = 0; a1 < a.featureAngleBins(); a1 += 5) {
      const long bin = a.binAt(d, a1, a1, a1);
      ASSERT_EQ(bin, b.binAt(d, a1, a1, a1));
      if (bin < 0)
        continue;
      ASSERT_EQ(a.binEnd(bin) - a.binBegin(bin), b.binEnd(bin) - b.binBegin(bin));
      ASSERT_EQ(a.binWeight(bin), b.binWeight(bin));
    }
  // What is rebuilt from the mesh: the same too.
  EXPECT_EQ(read->mesh().size(), built->mesh().size());
  EXPECT_EQ(read->radius(), built->radius());
  EXPECT_EQ(read->samples().size(), built->samples().size());
}

// A file stands alone: the mesh it holds is the mesh it was prepared from, byte for byte, and
// that mesh reads the model back.
TEST_F(ModelFile, HoldsTheMeshItWasPreparedFrom) {
  const std::string file = path("cup.icfmodel");
  writeModelFile(*IcfModel::build(mesh_), mesh_, preparationKey(mesh_, {}), file);
  EXPECT_TRUE(isModelFile(file));
  const pcl::PolygonMesh mesh = readModelFileMesh(file);
  EXPECT_EQ(mesh.cloud.data, mesh_.cloud.data);
  EXPECT_EQ(mesh.cloud.width, mesh_.cloud.width);
  EXPECT_EQ(mesh.cloud.point_step, mesh_.cloud.point_step);
  ASSERT_EQ(mesh.cloud.fields.size(), mesh_.cloud.fields.size());
  for (std::size_t f = 0; f < mesh.cloud.fields.size(); ++f) {
    EXPECT_EQ(mesh.cloud.fields[f].name, mesh_.cloud.fields[f].name);
    EXPECT_EQ(mesh.cloud.fields[f].offset, mesh_.cloud.fields[f].offset);
  }
  ASSERT_EQ(mesh.polygons.size(), mesh_.polygons.size());
  for (std::size_t p = 0; p < mesh.polygons.size(); ++p)
    ASSERT_EQ(mesh.polygons[p].vertices, mesh_.polygons[p].vertices) << "face " << p;
  EXPECT_EQ(preparationKey(mesh, {}), preparationKey(mesh_, {}));
  EXPECT_EQ(refusal(file, mesh), "");

  spit(path("mesh.ply"), "ply\nformat ascii 1.0\n");
  EXPECT_FALSE(isModelFile(path("mesh.ply")));
  EXPECT_FALSE(isModelFile(path("absent")));
  std::string bytes = slurp(file);
  bytes[40] ^= 0x01;  // inside the mesh's section
  spit(path("flipped"), bytes);
  EXPECT_THROW(readModelFileMesh(path("flipped")), ModelFileError);
}

TEST_F(ModelFile, EveryUnusableFileIsRefusedWithItsReason) {
  const std::string good = path("cup.icfmodel");
  writeModelFile(*IcfModel::build(mesh_), mesh_, preparationKey(mesh_, {}), good);
  const std::string bytes = slurp(good);
  ASSERT_GT(bytes.size(), 1000u);

  spit(path("short"), bytes.substr(0, bytes.size() / 2));
  EXPECT_NE(refusal(path("short"), mesh_).find("truncated"), std::string::npos);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x40;
  spit(path("flipped"), flipped);
  EXPECT_NE(refusal(path("flipped"), mesh_).find("checksum"), std::string::npos);
  std::string other_version = bytes;
  other_version[8] = static_cast<char>(kModelFileVersion + 1);  // after the 8-byte magic
  spit(path("version"), other_version);
  EXPECT_NE(refusal(path("version"), mesh_).find("format version"), std::string::npos);
  spit(path("text"), "ply\nformat ascii 1.0\n");
  EXPECT_NE(refusal(path("text"), mesh_).find("not a pcl_icf prepared model"), std::string::npos);
  EXPECT_NE(refusal(path("absent"), mesh_).find("cannot be read"), std::string::npos);

  // The right file for another mesh, or for the same mesh in other units.
  const std::string mismatch = "prepared from another mesh or other parameters";
  EXPECT_NE(refusal(good, synthetic::thesisModel("Box5").mesh).find(mismatch), std::string::npos);
  IcfModelParams millimetres;
  millimetres.mesh.scale = 0.001f;
  EXPECT_NE(refusal(good, mesh_, millimetres).find(mismatch), std::string::npos);
  EXPECT_EQ(refusal(good, mesh_), "");
}

TEST_F(ModelFile, TheKeyFollowsWhatThePreparationDependsOn) {
  const IcfModelParams defaults;
  const std::string key = preparationKey(mesh_, defaults);
  EXPECT_EQ(key.size(), 16u);
  EXPECT_EQ(key, preparationKey(mesh_, defaults)) << "deterministic";
  IcfModelParams threads = defaults;
  threads.field.threads = 1;
  EXPECT_EQ(preparationKey(mesh_, threads), key) << "the thread count changes nothing";
  IcfModelParams finer = defaults;
  finer.field.resolution = 120;
  EXPECT_NE(preparationKey(mesh_, finer), key);
  IcfModelParams step = defaults;
  step.point_pairs.sampling_step = 0.04f;
  EXPECT_NE(preparationKey(mesh_, step), key);
  pcl::PolygonMesh moved = mesh_;
  moved.cloud.data[0] ^= 1;  // one bit of one vertex
  EXPECT_NE(preparationKey(moved, defaults), key);
}

TEST_F(ModelFile, TheCacheBuildsOnceThenReadsAndRebuildsACorruptEntry) {
  const std::string folder = path("cache");
  const CachedModel first = buildModelCached(mesh_, {}, folder);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(first.warning.empty()) << first.warning;
  ASSERT_TRUE(fs::exists(first.path));
  const CachedModel second = buildModelCached(mesh_, {}, folder);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.path, first.path);
  EXPECT_EQ(second.model->pointPairs().pairs(), first.model->pointPairs().pairs());

  std::string bytes = slurp(first.path);
  bytes.resize(bytes.size() - 100);
  spit(first.path, bytes);
  const CachedModel rebuilt = buildModelCached(mesh_, {}, folder);
  EXPECT_FALSE(rebuilt.from_cache);
  EXPECT_NE(rebuilt.warning.find("rebuilt"), std::string::npos) << rebuilt.warning;
  EXPECT_TRUE(buildModelCached(mesh_, {}, folder).from_cache) << "the entry was rewritten";

  // No folder: built, nothing written; a folder that cannot be made: built, with a warning.
  const CachedModel none = buildModelCached(mesh_, {}, "");
  EXPECT_FALSE(none.from_cache);
  EXPECT_TRUE(none.path.empty());
  spit(path("a_file"), "x");
  const CachedModel unwritable = buildModelCached(mesh_, {}, path("a_file"));
  ASSERT_NE(unwritable.model, nullptr);
  EXPECT_NE(unwritable.warning.find("not cached"), std::string::npos) << unwritable.warning;
}

// Writers racing on one entry: each writes a temporary file and renames it, so a reader finds
// the entry whole every time (either writer's, they are the same model).
TEST_F(ModelFile, RacingWritersNeverLeaveABrokenEntry) {
  const IcfModel::ConstPtr model = IcfModel::build(mesh_);
  const std::string key = preparationKey(mesh_, {});
  const std::string entry = path("entry.icfmodel");
  writeModelFile(*model, mesh_, key, entry);
  std::atomic<bool> stop{false};
  std::vector<std::thread> writers;
  for (int w = 0; w < 3; ++w)
    writers.emplace_back([&] {
      while (!stop)
        writeModelFile(*model, mesh_, key, entry);
    });
  int reads = 0;
  for (; reads < 20; ++reads)
    ASSERT_EQ(refusal(entry, mesh_), "") << "read " << reads;
  stop = true;
  for (auto& t : writers)
    t.join();
  std::size_t leftovers = 0;
  for (const auto& f : fs::directory_iterator(dir_))
    leftovers += f.path().extension() == ".tmp";
  EXPECT_EQ(leftovers, 0u) << "temporary files left behind";
}

}  // namespace
