// BOP datasets (bop_dataset.h) against the same frames as the project's case sets, made by
// someone else from the same files: the depth PNG of ycbv video 0000 frame 2 read into a cloud
// is the frame's PCD point for point (the PCDs were made from these PNGs and intrinsics), the
// scene_gt pose is the case's gt.json pose, and the models' symmetries and targets are the
// README's. Then every way a file can be bad, each refused naming the file and the key.
#include "test_paths.h"

#include <pcl/icf/io/bop_dataset.h>
#include <pcl/icf/io/scene_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

namespace {

using namespace pcl::icf::io;

class BopDataset : public pcl_icf_test::TempDirTest {
 protected:
  BopDataset() : TempDirTest("pcl_icf_bop") {}
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  /** The message of the FileError \a f throws, "" when it throws none. */
  template <typename F>
  static std::string refusal(F f) {
    try {
      f();
    } catch (const FileError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(BopDataset, TheDepthPngIsTheFramesPcd) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  PCL_ICF_REQUIRE_SHARED(pcd, "ycbv-video0000/scenes/ycbv0000_000002.pcd");
  const BopCamera dataset = readBopDatasetCamera(root + "/camera.json");
  const auto cameras =
      readBopSceneCamera(root + "/test/000000/scene_camera.json", dataset.width, dataset.height);
  ASSERT_EQ(cameras.count(2), 1u);
  const auto cloud = readBopDepthImage(root + "/test/000000/depth/000002.png", cameras.at(2),
                                       root + "/test/000000/rgb/000002.png");
  const auto expected = loadSceneCloud(pcd);
  ASSERT_EQ(cloud->width, expected->width);
  ASSERT_EQ(cloud->height, expected->height);
  std::size_t finite = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const auto &a = (*cloud)[i], &b = (*expected)[i];
    ASSERT_EQ(std::isfinite(a.z), std::isfinite(b.z)) << "pixel " << i;
    if (!std::isfinite(a.z))
      continue;
    ++finite;
    // The PCD holds floats of the same formula: a few float roundings of ~1 m.
    ASSERT_NEAR(a.x, b.x, 1e-6f) << "pixel " << i;
    ASSERT_NEAR(a.y, b.y, 1e-6f) << "pixel " << i;
    ASSERT_NEAR(a.z, b.z, 1e-6f) << "pixel " << i;
    ASSERT_EQ(a.r, b.r) << "pixel " << i;
    ASSERT_EQ(a.g, b.g) << "pixel " << i;
    ASSERT_EQ(a.b, b.b) << "pixel " << i;
  }
  EXPECT_GT(finite, 200000u);
}

TEST_F(BopDataset, PosesSymmetriesAndTargetsAreTheCaseSets) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  PCL_ICF_REQUIRE_SHARED(gt_json, "ycbv-video0000/cases/y0000_002_gelatin_box/gt.json");
  const auto gt = readBopSceneGt(root + "/test/000000/scene_gt.json");
  ASSERT_EQ(gt.at(2).front().obj_id, 8);
  // The case's pose of the gelatin box in frame 2, metres (its gt.json's first rows).
  const Eigen::Isometry3d& p = gt.at(2).front().model_to_camera;
  EXPECT_NEAR(p.linear()(0, 0), 0.02372846099135041, 1e-12);
  EXPECT_NEAR(p.linear()(0, 1), -0.6305601464283022, 1e-12);
  EXPECT_NEAR(p.translation().x() / 1000.0, -0.030958847310268475, 1e-12);
  const auto visibility = readBopSceneVisibility(root + "/test/000000/scene_gt_info.json");
  EXPECT_EQ(visibility.at(2).size(), gt.at(2).size());
  EXPECT_DOUBLE_EQ(visibility.at(2).front(), 1.0);

  const auto models = readBopModelsInfo(root + "/models/models_info.json");
  EXPECT_EQ(models.size(), 6u);
  EXPECT_EQ(models.at(21).symmetries_discrete.size(), 1u) << "the foam brick";
  EXPECT_NEAR(models.at(21).symmetries_discrete[0].translation().x(), 0.486948, 1e-9);
  EXPECT_EQ(models.at(1).symmetries_continuous.size(), 1u) << "the master chef can";
  EXPECT_TRUE(models.at(2).symmetries_discrete.empty() &&
              models.at(2).symmetries_continuous.empty());
  EXPECT_NEAR(models.at(8).diameter, 113.997141, 1e-9);
  const auto targets = readBopTargets(root + "/test_targets_bop19.json");
  EXPECT_EQ(targets.size(), 38u);
  EXPECT_EQ(targets.front().scene_id, 0);
  EXPECT_EQ(targets.front().im_id, 2);
}

TEST_F(BopDataset, BadFilesAreRefusedNamingTheFileAndKey) {
  EXPECT_NE(
      refusal([&] { readBopTargets((dir_ / "absent.json").string()); }).find("cannot be read"),
      std::string::npos);
  const std::string bad = write("bad.json", "{\"2\": [");
  EXPECT_NE(refusal([&] { readBopSceneGt(bad); }).find("not valid JSON"), std::string::npos);
  const std::string no_t =
      write("gt.json", "{\"2\": [{\"obj_id\": 8, \"cam_R_m2c\": [1,0,0,0,1,0,0,0,1]}]}");
  EXPECT_NE(refusal([&] { readBopSceneGt(no_t); }).find("2[0].cam_t_m2c is missing"),
            std::string::npos)
      << refusal([&] { readBopSceneGt(no_t); });
  const std::string skew = write(
      "gt2.json",
      "{\"2\": [{\"obj_id\": 8, \"cam_R_m2c\": [2,0,0,0,1,0,0,0,1], \"cam_t_m2c\": [0,0,1]}]}");
  EXPECT_NE(refusal([&] { readBopSceneGt(skew); }).find("is not a rotation"), std::string::npos);
  const std::string id = write("cam.json", "{\"two\": {}}");
  EXPECT_NE(refusal([&] { readBopSceneCamera(id); }).find("\"two\" is not an id"),
            std::string::npos);
  const std::string scale =
      write("cam2.json", "{\"2\": {\"cam_K\": [1,0,0,0,1,0,0,0,1], \"depth_scale\": 0}}");
  EXPECT_NE(refusal([&] { readBopSceneCamera(scale); }).find("2.depth_scale must be > 0"),
            std::string::npos);
  const std::string count =
      write("targets.json", "[{\"im_id\": 2, \"inst_count\": 0, \"obj_id\": 8, \"scene_id\": 0}]");
  EXPECT_NE(refusal([&] { readBopTargets(count); }).find("[0].inst_count must be >= 1"),
            std::string::npos);
  const std::string diameter = write("models_info.json", "{\"1\": {\"diameter\": \"big\"}}");
  EXPECT_NE(refusal([&] { readBopModelsInfo(diameter); }).find("1.diameter is not a number"),
            std::string::npos);
}

TEST_F(BopDataset, BadDepthImagesAreRefused) {
  PCL_ICF_REQUIRE_SHARED(root, "bop-ycbv");
  const std::string depth = root + "/test/000000/depth/000002.png";
  const std::string rgb = root + "/test/000000/rgb/000002.png";
  BopCamera camera = readBopSceneCamera(root + "/test/000000/scene_camera.json").at(2);
  EXPECT_NE(refusal([&] { readBopDepthImage(rgb, camera); }).find("not a 16-bit"),
            std::string::npos)
      << "a colour PNG is no depth image";
  camera.width = 320;
  camera.height = 240;
  EXPECT_NE(refusal([&] { readBopDepthImage(depth, camera); }).find("the camera's images are"),
            std::string::npos);
  camera.width = camera.height = 0;
  camera.depth_scale = -1.0;
  EXPECT_NE(refusal([&] { readBopDepthImage(depth, camera); }).find("must be > 0"),
            std::string::npos);
  camera.depth_scale = 0.1;
  const std::string text = write("fake.png", "not a png");
  EXPECT_NE(refusal([&] { readBopDepthImage(text, camera); }).find("not a PNG"), std::string::npos);
  EXPECT_NE(refusal([&] { readBopDepthImage(depth, camera, depth); }).find("8-bit colour"),
            std::string::npos)
      << "a depth PNG is no colour image";
  std::ifstream in(depth, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = write("cut.png", bytes.substr(0, bytes.size() / 2));
  EXPECT_NE(refusal([&] { readBopDepthImage(cut, camera); }).find("truncated or corrupt"),
            std::string::npos)
      << refusal([&] { readBopDepthImage(cut, camera); });
}

}  // namespace
