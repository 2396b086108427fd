// The accelerated exact index (Embree), and the same bounded first by the closest-point field
// (what IcfModel::index() answers with), against the brute-force reference on random points
// around synthetic and real meshes, radius-bounded queries, and concurrent queries.
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/icf/closest_face_query.h>
#include <pcl/icf/field_bounded_closest_face.h>
#include <pcl/icf/io/mesh_io.h>

#include <gtest/gtest.h>

#include <random>
#include <thread>

namespace {

using pcl::icf::BruteForceClosestFace;
using pcl::icf::ClosestFaceQuery;
using pcl::icf::ClosestPointField;
using pcl::icf::EmbreeClosestFaceIndex;
using pcl::icf::FaceMesh;
using pcl::icf::FieldBoundedClosestFace;

// Both answers are computed by the same float closest-point routine on the winning face, so
// equal distances are expected up to the rounding of ties: 1e-6 relative to the mesh size.
// Points uniform over the bounding box widened by \a spread of its size on every side.
void expectSameAnswers(const FaceMesh& mesh, const ClosestFaceQuery& index, int count,
                       std::uint64_t seed, float radius, float spread = 0.25f) {
  const BruteForceClosestFace brute(mesh);
  const Eigen::Vector3f lo = mesh.boundsMin(), hi = mesh.boundsMax();
  const float size = (hi - lo).norm();
  const float tolerance = 1e-6f * size;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-spread, 1.f + spread);
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3f t(u(rng), u(rng), u(rng));
    const Eigen::Vector3f p = lo + t.cwiseProduct(hi - lo);
    const auto expected = brute.closestFace(p, radius);
    const auto actual = index.closestFace(p, radius);
    ASSERT_EQ(expected.found(), actual.found()) << "seed " << seed << " point " << i;
    if (!expected.found())
      continue;
    ASSERT_NEAR(actual.distance, expected.distance, tolerance) << "seed " << seed << " #" << i;
    ASSERT_NEAR((actual.point - p).norm(), actual.distance, tolerance);
    if (actual.face != expected.face) {  // a tie: both faces must be at that distance
      ASSERT_NEAR(pcl::icf::closestPointOnMeshFace(mesh, static_cast<std::size_t>(actual.face), p)
                      .squared_distance,
                  expected.distance * expected.distance, 2 * tolerance * size);
    }
  }
}

TEST(ClosestFaceIndex, MatchesBruteForceOnThesisModels) {
  for (const auto& name : pcl::icf::synthetic::thesisModelNames()) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel(name).mesh);
    const EmbreeClosestFaceIndex index(mesh);
    expectSameAnswers(mesh, index, 3000, 11, std::numeric_limits<float>::infinity());
    expectSameAnswers(mesh, index, 3000, 12, 0.01f);  // 1 cm radius: some points find nothing
  }
}

// The field's bound only narrows the search: the same answers inside the field's grid, near the
// surface, and far beyond the grid (points up to 3 model sizes away), with and without radius.
TEST(FieldBoundedClosestFace, MatchesBruteForceOnThesisModels) {
  for (const auto& name : pcl::icf::synthetic::thesisModelNames()) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel(name).mesh);
    const EmbreeClosestFaceIndex exact(mesh);
    const ClosestPointField field(exact);
    const FieldBoundedClosestFace bounded(exact, field);
    expectSameAnswers(mesh, bounded, 3000, 15, std::numeric_limits<float>::infinity());
    expectSameAnswers(mesh, bounded, 3000, 16, 0.01f);
    expectSameAnswers(mesh, bounded, 1000, 17, std::numeric_limits<float>::infinity(), 3.f);
    expectSameAnswers(mesh, bounded, 3000, 18, 0.006f, 0.02f);  // a refinement's radius
  }
}

TEST(FieldBoundedClosestFace, MatchesBruteForceOnTheBunny) {
  PCL_ICF_REQUIRE_SHARED(path, "meshes/bunny.ply");
  const auto mesh = FaceMesh::build(pcl::icf::io::loadPolygonMesh(path));
  const EmbreeClosestFaceIndex exact(mesh);
  const ClosestPointField field(exact);
  const FieldBoundedClosestFace bounded(exact, field);
  expectSameAnswers(mesh, bounded, 2000, 19, std::numeric_limits<float>::infinity());
  expectSameAnswers(mesh, bounded, 2000, 20, 0.01f, 0.05f);
}

TEST(ClosestFaceIndex, MatchesBruteForceOnTheBunny) {
  PCL_ICF_REQUIRE_SHARED(path, "meshes/bunny.ply");
  const auto mesh = FaceMesh::build(pcl::icf::io::loadPolygonMesh(path));
  EXPECT_EQ(mesh.size() + mesh.report().degenerate_dropped + mesh.report().duplicate_dropped,
            3851u);
  const EmbreeClosestFaceIndex index(mesh);
  expectSameAnswers(mesh, index, 2000, 13, std::numeric_limits<float>::infinity());
  expectSameAnswers(mesh, index, 2000, 14, 0.01f);
}

TEST(ClosestFaceIndex, RadiusBoundsTheSearch) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.2));
  const EmbreeClosestFaceIndex index(mesh);
  const Eigen::Vector3f p(0.f, 0.f, 0.15f);  // 5 cm above the top face
  EXPECT_FALSE(index.closestFace(p, 0.049f).found());
  const auto hit = index.closestFace(p, 0.051f);
  ASSERT_TRUE(hit.found());
  EXPECT_NEAR(hit.distance, 0.05f, 1e-6f);
  EXPECT_EQ(hit.feature, pcl::icf::FaceFeature::Interior);
  EXPECT_FALSE(index.closestFace(Eigen::Vector3f(NAN, 0.f, 0.f)).found());
}

TEST(ClosestFaceIndex, ConcurrentQueriesGiveTheSameAnswers) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel("YellowRoundSalt").mesh);
  const EmbreeClosestFaceIndex index(mesh);
  std::vector<Eigen::Vector3f> points;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> u(-0.15f, 0.15f);
  for (int i = 0; i < 4000; ++i)
    points.emplace_back(u(rng), u(rng), u(rng));
  std::vector<float> serial(points.size()), parallel(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    serial[i] = index.closestFace(points[i]).distance;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = static_cast<std::size_t>(t); i < points.size(); i += 4)
        parallel[i] = index.closestFace(points[i]).distance;
    });
  for (auto& t : threads)
    t.join();
  EXPECT_EQ(serial, parallel);
}

TEST(ResidualDirection, FaceNormalInsideAndOffsetOnEdges) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.2));
  const BruteForceClosestFace brute(mesh);
  const Eigen::Vector3f above(0.f, 0.f, 0.2f);
  auto hit = brute.closestFace(above);
  EXPECT_TRUE(pcl::icf::residualDirection(mesh, above, hit).isApprox(Eigen::Vector3f::UnitZ()));
  const Eigen::Vector3f corner(0.2f, 0.2f, 0.2f);  // beyond the (0.1, 0.1, 0.1) vertex
  hit = brute.closestFace(corner);
  EXPECT_EQ(hit.feature, pcl::icf::FaceFeature::Vertex);
  EXPECT_TRUE(pcl::icf::residualDirection(mesh, corner, hit)
                  .isApprox(Eigen::Vector3f(1.f, 1.f, 1.f).normalized(), 1e-5f));
}

}  // namespace
