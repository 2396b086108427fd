// Scene loaders on good files of every format (.pcd ascii / binary / binary_compressed,
// organized or not, with and without colour; .ply ascii and binary; .xyz / .asc) and on
// missing, empty, garbage, truncated, absurd and all-NaN files: a FileError (EmptyCloudError
// for clouds without a usable point) naming the file, never a crash.
#include "test_paths.h"

#include <pcl/common/io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace {

using pcl::icf::io::EmptyCloudError;
using pcl::icf::io::FileError;
using pcl::icf::io::loadSceneCloud;
using pcl::icf::io::SceneFileInfo;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

class SceneIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("pcl_icf_scene_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& content) {
    std::ofstream(path(name), std::ios::binary) << content;
    return path(name);
  }
  std::string truncated(const std::string& source, const std::string& name, double keep) {
    std::ifstream in(source, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return write(name, all.substr(0, static_cast<std::size_t>(keep * all.size())));
  }
  /** A 4 x 3 organized coloured cloud with two NaN pixels and a viewpoint. */
  static pcl::PointCloud<pcl::PointXYZRGBA> organized() {
    pcl::PointCloud<pcl::PointXYZRGBA> cloud(4, 3);
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      auto& q = cloud[i];
      q.x = 0.01f * static_cast<float>(i % 4);
      q.y = 0.02f * static_cast<float>(i / 4);
      q.z = 1.f + 0.001f * static_cast<float>(i);
      q.r = static_cast<std::uint8_t>(10 * i);
      q.g = static_cast<std::uint8_t>(200 - i);
      q.b = 7;
      q.a = 255;
    }
    cloud[1].x = cloud[1].y = cloud[1].z = kNaN;
    cloud[6].x = cloud[6].y = cloud[6].z = kNaN;
    cloud.is_dense = false;
    cloud.sensor_origin_ = Eigen::Vector4f(0.1f, -0.2f, 0.3f, 0.f);
    cloud.sensor_orientation_ =
        Eigen::Quaternionf(Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitY()));
    return cloud;
  }
  template <typename F>
  void expectError(F&& load, const std::string& fragment, bool empty_cloud = false) {
    try {
      load();
      FAIL() << "loaded without error, expected '" << fragment << "'";
    } catch (const EmptyCloudError& e) {
      EXPECT_TRUE(empty_cloud) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    } catch (const FileError& e) {
      EXPECT_FALSE(empty_cloud) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
    }
  }
  void expectFileError(const std::string& file, const std::string& fragment) {
    expectError([&] { loadSceneCloud(file); }, fragment);
  }
  void expectEmpty(const std::string& file, const std::string& fragment) {
    expectError([&] { loadSceneCloud(file); }, fragment, true);
  }
  std::filesystem::path dir_;
};

TEST_F(SceneIo, PcdKeepsOrganizationColourNaNAndViewpoint) {
  const auto expected = organized();
  for (int mode = 0; mode < 3; ++mode) {
    SCOPED_TRACE(mode);
    const std::string file = path("scene" + std::to_string(mode) + ".pcd");
    pcl::PCDWriter writer;
    if (mode == 0)
      writer.writeASCII(file, expected);
    else if (mode == 1)
      writer.writeBinary(file, expected);
    else
      writer.writeBinaryCompressed(file, expected);
    SceneFileInfo info;
    const auto cloud = loadSceneCloud(file, &info);
    EXPECT_EQ(info.format, "pcd");
    EXPECT_TRUE(info.has_colour);
    EXPECT_TRUE(info.organized);
    EXPECT_EQ(info.points, 12u);
    EXPECT_EQ(info.finite_points, 10u);
    ASSERT_EQ(cloud->width, 4u);
    ASSERT_EQ(cloud->height, 3u);
    EXPECT_FALSE(cloud->is_dense);
    EXPECT_TRUE(cloud->sensor_origin_.isApprox(expected.sensor_origin_, 1e-6f));
    EXPECT_TRUE(cloud->sensor_orientation_.isApprox(expected.sensor_orientation_, 1e-5f));
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      if (i == 1 || i == 6) {
        EXPECT_TRUE(std::isnan((*cloud)[i].z));
        continue;
      }
      EXPECT_NEAR((*cloud)[i].x, expected[i].x, 1e-6f);
      EXPECT_NEAR((*cloud)[i].z, expected[i].z, 1e-6f);
      EXPECT_EQ((*cloud)[i].r, expected[i].r);
      EXPECT_EQ((*cloud)[i].g, expected[i].g);
      EXPECT_EQ((*cloud)[i].b, expected[i].b);
    }
  }
}

TEST_F(SceneIo, PcdWithoutColourIsWhite) {
  pcl::PointCloud<pcl::PointXYZ> xyz;
  xyz.push_back({1.f, 2.f, 3.f});
  xyz.push_back({4.f, 5.f, 6.f});
  pcl::io::savePCDFileBinary(path("xyz.pcd"), xyz);
  SceneFileInfo info;
  const auto cloud = loadSceneCloud(path("xyz.pcd"), &info);
  EXPECT_FALSE(info.has_colour);
  EXPECT_FALSE(info.organized);
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_FLOAT_EQ((*cloud)[1].y, 5.f);
  EXPECT_EQ((*cloud)[1].r, 255);
  EXPECT_TRUE(cloud->is_dense);
}

TEST_F(SceneIo, PlyAsciiAndBinaryWithColour) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  for (int i = 0; i < 5; ++i) {
    pcl::PointXYZRGB q;
    q.x = 0.1f * i;
    q.y = -0.1f * i;
    q.z = 1.f;
    q.r = static_cast<std::uint8_t>(50 * i);
    q.g = 3;
    q.b = 4;
    cloud.push_back(q);
  }
  for (bool binary : {false, true}) {
    SCOPED_TRACE(binary);
    const std::string file = path(binary ? "b.ply" : "a.ply");
    pcl::io::savePLYFile(file, cloud, binary);
    SceneFileInfo info;
    const auto loaded = loadSceneCloud(file, &info);
    EXPECT_EQ(info.format, "ply");
    EXPECT_TRUE(info.has_colour);
    ASSERT_EQ(loaded->size(), 5u);
    EXPECT_NEAR((*loaded)[3].x, 0.3f, 1e-6f);
    EXPECT_EQ((*loaded)[4].r, 200);
    EXPECT_EQ((*loaded)[4].g, 3);
  }
}

TEST_F(SceneIo, PlyMeshVerticesArePoints) {
  SceneFileInfo info;
  const auto cloud = loadSceneCloud(pcl_icf_test::fixture("box_quads.ply"), &info);
  EXPECT_GE(cloud->size(), 8u);
  EXPECT_FALSE(info.has_colour);
}

TEST_F(SceneIo, XyzTextFormats) {
  const std::string text =
      "# captured by the thesis's program\n"
      "0.1 0.2 0.3\n"
      "\n"
      "  -1e-3\t2.5,+3   # trailing comment\r\n"
      "nan nan nan\n"
      "4 5 6";  // no final newline
  SceneFileInfo info;
  const auto cloud = loadSceneCloud(write("scene.xyz", text), &info);
  EXPECT_EQ(info.format, "xyz");
  EXPECT_FALSE(info.has_colour);
  EXPECT_EQ(info.points, 4u);
  EXPECT_EQ(info.finite_points, 3u);
  ASSERT_EQ(cloud->size(), 4u);
  EXPECT_FLOAT_EQ((*cloud)[1].x, -1e-3f);
  EXPECT_FLOAT_EQ((*cloud)[1].z, 3.f);
  EXPECT_TRUE(std::isnan((*cloud)[2].x));
  EXPECT_FLOAT_EQ((*cloud)[3].z, 6.f);
  EXPECT_FALSE(cloud->is_dense);

  const auto coloured = loadSceneCloud(write("scene.ASC", "1 2 3 255 0 10\n4 5 6 1 2 3\n"), &info);
  EXPECT_TRUE(info.has_colour);
  ASSERT_EQ(coloured->size(), 2u);
  EXPECT_EQ((*coloured)[0].r, 255);
  EXPECT_EQ((*coloured)[0].b, 10);
}

TEST_F(SceneIo, MissingEmptyAndUnknownFiles) {
  expectFileError(path("nope.pcd"), "no such file");
  expectFileError(write("empty.pcd", ""), "empty");
  expectFileError(write("scene.txt", "1 2 3\n"), "unknown scene extension");
  expectFileError(write("scene.obj", "v 1 2 3\n"), "unknown scene extension");
  expectFileError(dir_.string(), "not a regular file");
}

TEST_F(SceneIo, XyzGarbageNamesTheLine) {
  expectFileError(write("a.xyz", "1 2 3\n4 5 six\n"), "a.xyz:2: 'six' is not a number");
  expectFileError(write("b.xyz", "1 2 3\n4 5\n"), "b.xyz:2: expected 3 numbers");
  expectFileError(write("c.xyz", "# header\n1 2 3\n1 2 3 4 5 6\n"), "c.xyz:3:");
  expectFileError(write("d.xyz", "1 2 3 300 0 0\n"), "not an integer in [0, 255]");
  expectFileError(write("e.xyz", "1 2 3 4\n"), "found 4 fields");
  static const char kBinary[] = "\x01\x02\xff\xfe garbage\0\0 x";
  expectFileError(write("f.xyz", std::string(kBinary, sizeof kBinary - 1)), "f.xyz:1:");
  expectFileError(write("g.xyz", "1 2 3\n4 5 6e\n"), "g.xyz:2:");
  // A file cut inside its last line.
  expectFileError(write("h.xyz", "0.1 0.2 0.3\n0.4 0.5 0.6\n0.7 0."), "h.xyz:3:");
}

TEST_F(SceneIo, XyzTextInMemory) {
  bool colour = true;
  const auto cloud = pcl::icf::io::parseXyzText("1 2 3\r\n# note\n4,5,6\n", "stream", &colour);
  EXPECT_FALSE(colour);
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_EQ(cloud->height, 1u);
  EXPECT_FLOAT_EQ((*cloud)[1].y, 5.f);
  EXPECT_EQ((*cloud)[1].r, 255);
  EXPECT_TRUE(cloud->is_dense);
  expectError([] { pcl::icf::io::parseXyzText("1 2 3\n4 5\n", "stream"); }, "stream:2: expected");
  expectError([] { pcl::icf::io::parseXyzText("# only a comment\n", "stream"); }, "no points",
              true);
  // All NaN: a cloud (loadSceneCloud refuses it, parseXyzText leaves the choice to the caller).
  const auto nan = pcl::icf::io::parseXyzText("nan nan nan\n", "stream");
  ASSERT_EQ(nan->size(), 1u);
  EXPECT_FALSE(nan->is_dense);
}

TEST_F(SceneIo, EmptyAndAllNaNCloudsAreTheirOwnError) {
  expectEmpty(write("comments.xyz", "# nothing here\n\n   \n"), "no points");
  expectEmpty(write("nan.xyz", "nan nan nan\nnan 1 2\n"), "NaN");
  pcl::PointCloud<pcl::PointXYZ> nan(3, 2);
  for (auto& q : nan)
    q.x = q.y = q.z = kNaN;
  nan.is_dense = false;
  pcl::io::savePCDFileBinaryCompressed(path("nan.pcd"), nan);
  expectEmpty(path("nan.pcd"), "all 6 points");
  write("zero.pcd",
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH 0\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n");
  try {
    loadSceneCloud(path("zero.pcd"));
    FAIL() << "zero.pcd loaded";
  } catch (const FileError& e) {  // PCL's reader may refuse it first; either way a FileError
    SUCCEED() << e.what();
  }
}

TEST_F(SceneIo, GarbagePcdAndPly) {
  const std::string garbage = "\x01\x02 this is not a cloud \xff\xfe\n1 2 3\n";
  expectFileError(write("garbage.pcd", garbage), "not a PCD file");
  expectFileError(write("garbage.ply", garbage), "not a PLY file");
  expectFileError(write("nofields.pcd",
                        "# .PCD v0.7\nVERSION 0.7\nFIELDS a b\nSIZE 4 4\nTYPE F F\n"
                        "COUNT 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2\n"),
                  "");
  expectFileError(write("baddata.pcd",
                        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
                        "TYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\nPOINTS 1\n"
                        "DATA zip\n1 2 3\n"),
                  "unknown DATA type");
}

TEST_F(SceneIo, InvalidViewpointIsTheIdentity) {
  const auto cloud = loadSceneCloud(
      write("view.pcd",
            "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            "WIDTH 2\nHEIGHT 1\nVIEWPOINT 1 2 3 0 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n"));
  ASSERT_EQ(cloud->size(), 2u);
  EXPECT_TRUE(cloud->sensor_origin_.isZero());
  EXPECT_TRUE(cloud->sensor_orientation_.isApprox(Eigen::Quaternionf::Identity()));
}

TEST_F(SceneIo, AbsurdHeadersFailFast) {
  expectFileError(write("huge.pcd",
                        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
                        "TYPE F F F\nCOUNT 1 1 1\nWIDTH 100000000000\nHEIGHT 1000\n"
                        "POINTS 100000000000000\nDATA binary\n"),
                  "more than");
  expectFileError(write("huge.ply",
                        "ply\nformat binary_little_endian 1.0\n"
                        "element vertex 4000000000\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\n"),
                  "more than");
  expectFileError(write("short.ply",
                        "ply\nformat binary_little_endian 1.0\n"
                        "element vertex 1000\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\nabc"),
                  "truncated");
}

TEST_F(SceneIo, TruncatedFilesThrow) {
  const auto cloud = organized();
  pcl::PCDWriter writer;
  writer.writeBinary(path("bin.pcd"), cloud);
  writer.writeBinaryCompressed(path("zip.pcd"), cloud);
  writer.writeASCII(path("txt.pcd"), cloud);
  pcl::PointCloud<pcl::PointXYZRGB> rgb;
  pcl::copyPointCloud(cloud, rgb);
  pcl::io::savePLYFileBinary(path("bin.ply"), rgb);
  for (const char* name : {"bin.pcd", "zip.pcd", "txt.pcd", "bin.ply"})
    for (double keep : {0.1, 0.5, 0.9}) {
      SCOPED_TRACE(std::string(name) + " " + std::to_string(keep));
      const std::string cut = truncated(path(name), "cut_" + std::to_string(keep) + name, keep);
      try {
        const auto loaded = loadSceneCloud(cut);
        // Only a text format cut exactly between points may load, and then with fewer points.
        EXPECT_LT(loaded->size(), cloud.size());
      } catch (const FileError& e) {
        SUCCEED() << e.what();
      }
    }
}

TEST_F(SceneIo, RealOrganizedKinectScene) {
  PCL_ICF_REQUIRE_SHARED(file, "pcl/milk_cartoon_all_small_clorox.pcd");
  SceneFileInfo info;
  const auto cloud = loadSceneCloud(file, &info);
  EXPECT_EQ(cloud->width, 640u);
  EXPECT_EQ(cloud->height, 480u);
  EXPECT_TRUE(info.has_colour);
  EXPECT_GT(info.finite_points, 200000u);
  EXPECT_LT(info.finite_points, info.points);
}

}  // namespace
