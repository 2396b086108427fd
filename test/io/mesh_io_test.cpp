// Mesh loaders on good files of every format and on missing, empty, garbage and truncated
// files: a FileError naming the file, never a crash.
#include "test_paths.h"

#include <pcl/icf/face_mesh.h>
#include <pcl/icf/io/mesh_io.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using pcl::icf::FaceMesh;
using pcl::icf::io::FileError;
using pcl::icf::io::loadPolygonMesh;

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("pcl_icf_mesh_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& content) {
    const auto path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  std::string truncated(const std::string& source, const std::string& name, double keep) {
    std::ifstream in(source, std::ios::binary);
    const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return write(name, all.substr(0, static_cast<std::size_t>(keep * all.size())));
  }
  void expectFileError(const std::string& path, const std::string& fragment) {
    try {
      const auto mesh = loadPolygonMesh(path);
      // A reader may accept a damaged file partially; then the mesh must still be coherent
      // enough for FaceMesh to either build or throw its own clear error.
      FaceMesh::build(mesh);
      FAIL() << path << " loaded without error";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    } catch (const pcl::icf::InvalidMeshError& e) {
      SUCCEED() << e.what();
    }
  }
  std::filesystem::path dir_;
};

TEST_F(MeshIo, EveryFormatLoadsTheSameCube) {
  for (const char* name :
       {"box_quads.ply", "box_quads.obj", "box_triangles.stl", "box_quads.vtk"}) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(loadPolygonMesh(pcl_icf_test::fixture(name)));
    EXPECT_NEAR(mesh.totalArea(), 6.0, 1e-5);
    EXPECT_TRUE(mesh.boundsMax().isApprox(Eigen::Vector3f::Ones()));
    // Rectangles stay rectangles where the format keeps them.
    EXPECT_EQ(mesh.countFacesWithVertices(4),
              std::string(name).find("stl") == std::string::npos ? 6u : 0u);
  }
}

TEST_F(MeshIo, RealBinaryPlyAndRealObj) {
  PCL_ICF_REQUIRE_SHARED(cube, "pcl/cube.ply");
  EXPECT_EQ(FaceMesh::build(loadPolygonMesh(cube)).size(), 12u);
  PCL_ICF_REQUIRE_SHARED(can, "ycbv/010_potted_meat_can_textured.obj");
  const auto mesh = FaceMesh::build(loadPolygonMesh(can));
  EXPECT_EQ(mesh.size() + mesh.report().degenerate_dropped + mesh.report().duplicate_dropped,
            16384u);
}

TEST_F(MeshIo, MissingEmptyAndUnknownFilesThrow) {
  expectFileError((dir_ / "nope.ply").string(), "no such file");
  expectFileError(write("empty.ply", ""), "empty");
  expectFileError(write("mesh.xyz", "0 0 0\n"), "unknown mesh extension");
  expectFileError(dir_.string() + "/", "not a regular file");
}

TEST_F(MeshIo, GarbageFilesThrow) {
  const std::string garbage = "\x01\x02 this is not a mesh \xff\xfe\n1 2 3\n";
  expectFileError(write("garbage.ply", garbage), "PLY");
  expectFileError(write("garbage.obj", garbage), "");
  expectFileError(write("garbage.stl", garbage), "");
  expectFileError(write("garbage.vtk", garbage), "");
}

TEST_F(MeshIo, TruncatedFilesThrow) {
  for (const char* name :
       {"box_quads.ply", "box_quads.obj", "box_triangles.stl", "box_quads.vtk"}) {
    SCOPED_TRACE(name);
    // Cut inside the header and inside the vertex list.
    expectFileError(truncated(pcl_icf_test::fixture(name), std::string("h_") + name, 0.1), "");
    const std::string half = truncated(pcl_icf_test::fixture(name), std::string("v_") + name, 0.5);
    try {
      const auto mesh = FaceMesh::build(loadPolygonMesh(half));
      // A reader that keeps the complete faces before the cut gives a smaller, valid mesh.
      EXPECT_LT(mesh.totalArea(), 6.0 - 1e-3);
    } catch (const FileError&) {
    } catch (const pcl::icf::InvalidMeshError&) {
    }
  }
}

TEST_F(MeshIo, TruncatedBinaryPlyThrows) {
  PCL_ICF_REQUIRE_SHARED(cube, "pcl/cube.ply");
  for (double keep : {0.2, 0.6, 0.95})
    expectFileError(truncated(cube, "cut_" + std::to_string(keep) + ".ply", keep), "");
}

}  // namespace
