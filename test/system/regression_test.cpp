// Regression tests for what the fuzzers (fuzz/) found: every input that crashed,
// hung or exhausted memory is kept under test/data/regression/ and must now give a clear error.
// Also: every seed of the fuzzers' corpora (fuzz/corpus/) is a valid file and loads, and our
// readers (which replaced PCL's and VTK's, io/src/file_formats.h) give what PCL's gave on the
// real files of ../shared/data and the demo.
#include "synthetic/mesh_geometry.h"
#include "test_paths.h"

#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/io/vtk_lib_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace {

namespace fs = std::filesystem;
using pcl::icf::FaceMesh;
using pcl::icf::io::FileError;
using pcl::icf::io::loadPolygonMesh;
using pcl::icf::io::loadSceneCloud;

struct Finding {
  const char* file;      ///< under test/data/regression/
  bool mesh;             ///< loadPolygonMesh + FaceMesh::build, else loadSceneCloud
  const char* fragment;  ///< expected in the error's message; nullptr: a valid file
  bool invalid_mesh;     ///< the error is an InvalidMeshError (the file itself is well formed)
  const char* was;       ///< what it did before the fix
};

std::ostream& operator<<(std::ostream& out, const Finding& f) {
  return out << f.file;
}

const Finding kFindings[] = {
    {"pcd_fields_control_bytes.pcd", false, "not printable", false,
     "SIGSEGV in pcl::PCDReader::read (a FIELDS line of control bytes)"},
    {"pcd_binary_data_read_as_header.pcd", false, nullptr, false,
     "a 100 TB allocation in pcl::PCDReader: binary data after DATA parsed as header lines"},
    {"ply_scene_vertex_list_assert.ply", false, "is not a PLY header line", false,
     "assert() in pcl::PLYReader::vertexListPropertyContentCallback"},
    {"ply_mesh_vertex_list_assert.ply", true, "is not a PLY header line", false,
     "assert() in pcl::PLYReader::vertexListPropertyContentCallback"},
    {"obj_bad_face_segv.obj", true, ":9: expected 'v x y z", false,
     "SIGSEGV in vtkOBJReader::RequestData (a malformed face line)"},
    {"stl_lying_triangle_count.stl", true, "claims", false,
     "a 7 GB allocation in vtkSTLReader::ReadBinarySTL (a lying triangle count)"},
    {"stl_denormal_face_normal.stl", true, "squared bounding-box diagonal", true,
     "FaceMesh kept a face of denormal area whose normal was not a unit vector"},
};

class FuzzFinding : public ::testing::TestWithParam<Finding> {};

TEST_P(FuzzFinding, GivesAClearError) {
  const Finding& f = GetParam();
  const std::string path = pcl_icf_test::fixture(std::string("regression/") + f.file);
  ASSERT_TRUE(fs::exists(path)) << path;
  std::string error;
  bool invalid_mesh = false;
  try {
    if (f.mesh)
      EXPECT_GT(FaceMesh::build(loadPolygonMesh(path)).size(), 0u);
    else
      EXPECT_GT(loadSceneCloud(path)->size(), 0u);
  } catch (const FileError& e) {
    error = e.what();
    EXPECT_NE(error.find(f.file), std::string::npos) << "names the file: " << error;
  } catch (const pcl::icf::InvalidMeshError& e) {
    error = e.what();
    invalid_mesh = true;
  }
  if (!f.fragment) {
    EXPECT_EQ(error, "") << "a valid file failed";
    return;
  }
  ASSERT_NE(error, "") << f.file << " loaded; before the fix: " << f.was;
  EXPECT_EQ(invalid_mesh, f.invalid_mesh) << error;
  EXPECT_NE(error.find(f.fragment), std::string::npos) << error << "\nexpected: " << f.fragment;
}

TEST(FuzzFinding, TinyAndHugeMeshesKeepUnitNormals) {
  // The same tetrahedron at 1e-20 and 1e17 units: every face kept, unit normals, the area
  // scaling with the square (float cross products underflowed and overflowed before).
  for (const float scale : {1e-20f, 1.f, 1e17f}) {
    SCOPED_TRACE(scale);
    const pcl::PolygonMesh mesh =
        pcl::icf::synthetic::meshOf({{0, 0, 0}, {scale, 0, 0}, {0, scale, 0}, {0, 0, scale}},
                                    {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}});
    const FaceMesh faces = FaceMesh::build(mesh);
    ASSERT_EQ(faces.size(), 4u);
    for (const auto& face : faces.faces())
      EXPECT_NEAR(face.normal.norm(), 1.f, 1e-6f);
    EXPECT_NEAR(faces.totalArea() / (double(scale) * scale), 1.5 + std::sqrt(3.0) / 2, 1e-5);
  }
}

INSTANTIATE_TEST_SUITE_P(Regression, FuzzFinding, ::testing::ValuesIn(kFindings),
                         [](const ::testing::TestParamInfo<Finding>& info) {
                           std::string name = info.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c)))
                               c = '_';
                           return name;
                         });

TEST(FuzzFinding, EveryFindingIsListed) {
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(pcl_icf_test::fixture("regression"))) {
    const std::string name = entry.path().filename().string();
    if (name == "README.md")
      continue;
    ++files;
    bool listed = false;
    for (const Finding& f : kFindings)
      listed = listed || name == f.file;
    EXPECT_TRUE(listed) << name << " is not in kFindings";
  }
  EXPECT_EQ(files, std::size(kFindings));
}

/** fuzz/corpus/<target>/ beside test/. */
fs::path corpus(const std::string& target) {
  return fs::path(PCL_ICF_TEST_DATA) / ".." / ".." / "fuzz" / "corpus" / target;
}

TEST(FuzzSeeds, EverySceneSeedLoads) {
  for (const char* target : {"fuzz_scene_pcd", "fuzz_scene_ply", "fuzz_scene_xyz"}) {
    const fs::path dir = corpus(target);
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    for (const auto& entry : fs::directory_iterator(dir)) {
      SCOPED_TRACE(entry.path().string());
      pcl::icf::io::SceneFileInfo info;
      const auto cloud = loadSceneCloud(entry.path().string(), &info);
      EXPECT_GE(cloud->size(), 3u);
      EXPECT_GE(info.finite_points, 2u);
    }
  }
}

TEST(FuzzSeeds, EveryMeshSeedBuilds) {
  for (const char* target : {"fuzz_mesh_ply", "fuzz_mesh_obj", "fuzz_mesh_stl", "fuzz_mesh_vtk"}) {
    const fs::path dir = corpus(target);
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    for (const auto& entry : fs::directory_iterator(dir)) {
      SCOPED_TRACE(entry.path().string());
      const FaceMesh mesh = FaceMesh::build(loadPolygonMesh(entry.path().string()));
      EXPECT_GE(mesh.size(), 6u);
      EXPECT_GT(mesh.totalArea(), 0.0);
    }
  }
}

bool sameFloat(float a, float b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}

TEST(ReadersMatchPcl, RealScenes) {
  std::vector<std::string> files = {
      (fs::path(PCL_ICF_TEST_DATA) / ".." / ".." / "data" / "demo" / "tabletop_box5.pcd").string(),
      (fs::path(PCL_ICF_TEST_DATA) / ".." / ".." / "data" / "demo" / "box5_cluster.pcd").string()};
  for (const char* shared :
       {"pcl/milk.pcd", "pcl/milk_cartoon_all_small_clorox.pcd",
        "pcl/table_scene_mug_stereo_textured.pcd", "mosd/test0.pcd", "ycbv/ycbv_frame000002.pcd"})
    if (!pcl_icf_test::sharedData(shared).empty())
      files.push_back(pcl_icf_test::sharedData(shared));
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    pcl::icf::io::SceneFileInfo info;
    const auto ours = loadSceneCloud(file, &info);
    pcl::PointCloud<pcl::PointXYZRGBA> pcl_cloud;
    ASSERT_EQ(pcl::io::loadPCDFile(file, pcl_cloud), 0);
    ASSERT_EQ(ours->width, pcl_cloud.width);
    ASSERT_EQ(ours->height, pcl_cloud.height);
    EXPECT_EQ(ours->sensor_origin_.head<3>(), pcl_cloud.sensor_origin_.head<3>());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ours->size(); ++i) {
      const auto& a = (*ours)[i];
      const auto& b = pcl_cloud[i];
      differ += !(sameFloat(a.x, b.x) && sameFloat(a.y, b.y) && sameFloat(a.z, b.z)) ||
                (info.has_colour && (a.r != b.r || a.g != b.g || a.b != b.b));
    }
    EXPECT_EQ(differ, 0u);
  }
}

TEST(ReadersMatchPcl, RealMeshes) {
  std::vector<std::string> files = {
      (fs::path(PCL_ICF_TEST_DATA) / ".." / ".." / "data" / "demo" / "box5.ply").string(),
      pcl_icf_test::fixture("box_quads.ply"), pcl_icf_test::fixture("box_quads.obj"),
      pcl_icf_test::fixture("box_triangles.stl")};
  for (const char* shared :
       {"pcl/cube.ply", "meshes/bunny.ply", "meshes/parasaurolophus_low_normals2.ply",
        "ycbv/004_sugar_box_textured.obj", "ycbv/010_potted_meat_can_textured.obj"})
    if (!pcl_icf_test::sharedData(shared).empty())
      files.push_back(pcl_icf_test::sharedData(shared));
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const pcl::PolygonMesh ours = loadPolygonMesh(file);
    pcl::PolygonMesh theirs;
    const bool ply = fs::path(file).extension() == ".ply";
    ASSERT_GE(ply ? pcl::io::loadPLYFile(file, theirs) : pcl::io::loadPolygonFile(file, theirs), 0);
    if (ply) {  // the same vertices in the same order, the same polygons
      ASSERT_EQ(ours.cloud.width * ours.cloud.height, theirs.cloud.width * theirs.cloud.height);
      ASSERT_EQ(ours.polygons.size(), theirs.polygons.size());
      for (std::size_t f = 0; f < ours.polygons.size(); ++f)
        ASSERT_EQ(ours.polygons[f].vertices, theirs.polygons[f].vertices) << "face " << f;
    }
    // VTK's OBJ and STL readers number vertices their own way: compare the surfaces.
    const FaceMesh a = FaceMesh::build(ours);
    const FaceMesh b = FaceMesh::build(theirs);
    EXPECT_EQ(a.size() + a.report().duplicate_dropped + a.report().degenerate_dropped,
              b.size() + b.report().duplicate_dropped + b.report().degenerate_dropped);
    EXPECT_NEAR(a.totalArea(), b.totalArea(), 1e-6 * b.totalArea());
    EXPECT_EQ(a.boundsMin(), b.boundsMin());
    EXPECT_EQ(a.boundsMax(), b.boundsMax());
    if (ply) {
      EXPECT_EQ(a.vertices(), b.vertices());
    }
  }
}

}  // namespace
