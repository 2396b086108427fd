// FaceMesh::build: faces kept or triangulated, degenerate and duplicate faces dropped and
// counted, and clear errors for meshes that cannot be models.
#include "synthetic/mesh_geometry.h"

#include <pcl/conversions.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

namespace {

using pcl::icf::synthetic::meshOf;

const std::vector<Eigen::Vector3f> kSquare = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

TEST(FaceMesh, RectangleStaysOneFaceWithNormalAndArea) {
  const auto mesh = pcl::icf::FaceMesh::build(meshOf(kSquare, {{0, 1, 2, 3}}));
  ASSERT_EQ(mesh.size(), 1u);
  EXPECT_EQ(mesh.faces()[0].count, 4u);
  EXPECT_NEAR(mesh.faces()[0].area, 1.f, 1e-6f);
  EXPECT_TRUE(mesh.faces()[0].normal.isApprox(Eigen::Vector3f::UnitZ()));
  EXPECT_EQ(mesh.report().kept_faces, 1u);
  EXPECT_TRUE(mesh.surfaceCentroid().isApprox(Eigen::Vector3f(0.5f, 0.5f, 0.f)));
}

TEST(FaceMesh, ConcavePolygonIsTriangulatedKeepingItsArea) {
  // An L shape of area 3 (unit squares), concave at (1, 1).
  const std::vector<Eigen::Vector3f> l = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0},
                                          {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  const auto mesh = pcl::icf::FaceMesh::build(meshOf(l, {{0, 1, 2, 3, 4, 5}}));
  EXPECT_EQ(mesh.report().triangulated_polygons, 1u);
  EXPECT_EQ(mesh.size(), 4u);
  EXPECT_NEAR(mesh.totalArea(), 3.0, 1e-6);
  for (const auto& f : mesh.faces())
    EXPECT_GT(f.normal.z(), 0.99f);
}

TEST(FaceMesh, NonPlanarQuadIsTriangulated) {
  auto bent = kSquare;
  bent[2].z() = 0.3f;
  const auto mesh = pcl::icf::FaceMesh::build(meshOf(bent, {{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.report().triangulated_polygons, 1u);
  EXPECT_EQ(mesh.size(), 2u);
}

TEST(FaceMesh, DegenerateAndDuplicateFacesAreDroppedAndCounted) {
  auto v = kSquare;
  v.push_back({2, 0, 0});              // collinear with 0 and 1
  v.push_back({std::nanf(""), 0, 0});  // non-finite vertex
  const auto mesh = pcl::icf::FaceMesh::build(
      meshOf(v, {{0, 1, 2}, {2, 0, 1}, {0, 1, 4}, {0, 0, 1}, {0, 2, 5}, {0, 2, 3}}));
  EXPECT_EQ(mesh.size(), 2u);
  EXPECT_EQ(mesh.report().duplicate_dropped, 1u);   // {2, 0, 1} is {0, 1, 2} again
  EXPECT_EQ(mesh.report().degenerate_dropped, 2u);  // zero area, repeated vertex
  EXPECT_EQ(mesh.report().nonfinite_dropped, 1u);
}

TEST(FaceMesh, MeshesThatCannotBeModelsThrowClearly) {
  using pcl::icf::InvalidMeshError;
  EXPECT_THROW(pcl::icf::FaceMesh::build(pcl::PolygonMesh()), InvalidMeshError);
  EXPECT_THROW(pcl::icf::FaceMesh::build(meshOf(kSquare, {})), InvalidMeshError);
  EXPECT_THROW(pcl::icf::FaceMesh::build(meshOf(kSquare, {{0, 1, 7}})), InvalidMeshError);
  EXPECT_THROW(pcl::icf::FaceMesh::build(meshOf(kSquare, {{0, 1, -1}})), InvalidMeshError);
  try {
    pcl::icf::FaceMesh::build(meshOf(kSquare, {{0, 1, 1}, {2, 2, 2}}));
    FAIL() << "an all-degenerate mesh must throw";
  } catch (const InvalidMeshError& e) {
    EXPECT_NE(std::string(e.what()).find("no usable face"), std::string::npos) << e.what();
  }
  pcl::icf::FaceMeshOptions bad;
  bad.scale = -1.f;
  EXPECT_THROW(pcl::icf::FaceMesh::build(meshOf(kSquare, {{0, 1, 2}}), bad), std::invalid_argument);
}

/** kSquare's vertices as x, y, z fields of \a datatype (4 bytes apart, or 8 for 64-bit types),
 * values written as that type: the layout PLY files with integer or double coordinates give. */
pcl::PolygonMesh squareWithCoordinateType(std::uint8_t datatype) {
  pcl::PolygonMesh mesh = meshOf(kSquare, {{0, 1, 2, 3}});
  const std::uint32_t size =
      datatype == pcl::PCLPointField::FLOAT64 || datatype == pcl::PCLPointField::INT64 ? 8 : 4;
  pcl::PCLPointCloud2& c = mesh.cloud;
  c.fields.clear();
  for (std::uint32_t k = 0; k < 3; ++k) {
    pcl::PCLPointField f;
    f.name = std::string(1, static_cast<char>('x' + k));
    f.offset = k * size;
    f.datatype = datatype;
    f.count = 1;
    c.fields.push_back(f);
  }
  c.point_step = 3 * size;
  c.row_step = c.point_step * c.width;
  c.data.assign(static_cast<std::size_t>(c.row_step) * c.height, 0);
  for (std::size_t i = 0; i < kSquare.size(); ++i)
    for (std::uint32_t k = 0; k < 3; ++k) {
      std::uint8_t* p = c.data.data() + i * c.point_step + k * size;
      const auto v = static_cast<std::int32_t>(kSquare[i][static_cast<int>(k)]);
      if (datatype == pcl::PCLPointField::FLOAT64) {
        const double d = v;
        std::memcpy(p, &d, 8);
      } else if (datatype == pcl::PCLPointField::INT64) {
        const std::int64_t d = v;
        std::memcpy(p, &d, 8);
      } else {
        std::memcpy(p, &v, 4);  // INT32
      }
    }
  return mesh;
}

TEST(FaceMesh, CoordinatesOfEveryNumberTypeReadAlikeAndOthersRefused) {
  // Oracle: the float mesh of the same square. INT32 and FLOAT64 coordinates give the same
  // face (area 1, exact: the values are small integers); INT64, which the one field reader
  // (pcl_icf_internal/point_field.h) cannot read exactly, is refused with a clear error rather
  // than read as zeros (which built a degenerate mesh before).
  for (const std::uint8_t t : {pcl::PCLPointField::INT32, pcl::PCLPointField::FLOAT64}) {
    const auto mesh = pcl::icf::FaceMesh::build(squareWithCoordinateType(t));
    EXPECT_EQ(mesh.size(), 1u) << "datatype " << int(t);
    EXPECT_DOUBLE_EQ(mesh.totalArea(), 1.0) << "datatype " << int(t);
  }
  try {
    pcl::icf::FaceMesh::build(squareWithCoordinateType(pcl::PCLPointField::INT64));
    FAIL() << "a 64-bit integer coordinate must be refused";
  } catch (const pcl::icf::InvalidMeshError& e) {
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
}

TEST(FaceMesh, ScaleConvertsUnits) {
  pcl::icf::FaceMeshOptions mm;
  mm.scale = 1e-3f;
  std::vector<Eigen::Vector3f> big;
  for (const auto& v : kSquare)
    big.push_back(1000.f * v);
  const auto mesh = pcl::icf::FaceMesh::build(meshOf(big, {{0, 1, 2, 3}}), mm);
  EXPECT_NEAR(mesh.totalArea(), 1.0, 1e-5);
}

TEST(FaceMesh, SurfaceSamplesLieOnFacesAndFollowArea) {
  // Two faces: a unit square at z = 0 and a 2x1 rectangle at z = 1 (area 1 and 2).
  std::vector<Eigen::Vector3f> v = kSquare;
  for (const auto& p : std::vector<Eigen::Vector3f>{{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {0, 1, 1}})
    v.push_back(p);
  const auto mesh = pcl::icf::FaceMesh::build(meshOf(v, {{0, 1, 2, 3}, {4, 5, 6, 7}}));
  const auto samples = pcl::icf::sampleSurface(mesh, 30000, 3);
  std::size_t upper = 0;
  for (const auto& s : samples) {
    ASSERT_NEAR(s.point.z(), s.face == 0 ? 0.f : 1.f, 1e-6f);
    upper += s.face == 1;
  }
  // Binomial(30000, 2/3): standard deviation 82; 5 sigma is about 410.
  EXPECT_NEAR(static_cast<double>(upper), 20000.0, 410.0);
  EXPECT_EQ(pcl::icf::sampleSurface(mesh, 10, 3)[7].point,
            pcl::icf::sampleSurface(mesh, 10, 3)[7].point);
}

}  // namespace
