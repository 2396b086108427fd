// The accelerated exact index (Embree), and the same bounded first by the closest-point field
// (what IcfModel::index() answers with), against the brute-force reference on random points
// around synthetic and real meshes, radius-bounded queries, and concurrent queries.
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/field_bounded_closest_face.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/refinement.h>

#include <gtest/gtest.h>

#include <cmath>
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

// Where the bound is tightest: at the grid's nodes (the bound is then the stored point's own
// distance, up to its widening) and a rounding away from them; and non-finite or absurd points,
// which the exact index answers with "not found".
TEST(FieldBoundedClosestFace, MatchesBruteForceAtTheNodesAndOnBadPoints) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel("Amicelly").mesh);
  const BruteForceClosestFace brute(mesh);
  const EmbreeClosestFaceIndex exact(mesh);
  const ClosestPointField field(exact);
  const FieldBoundedClosestFace bounded(exact, field);
  const float tolerance = 1e-6f * (mesh.boundsMax() - mesh.boundsMin()).norm();
  std::mt19937_64 rng(24);
  std::uniform_int_distribution<int> node_x(0, field.dimensions().x() - 1),
      node_y(0, field.dimensions().y() - 1), node_z(0, field.dimensions().z() - 1);
  std::uniform_real_distribution<float> jitter(-1e-4f, 1e-4f);
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3f node =
        field.origin() + field.cellSize() * Eigen::Vector3f(static_cast<float>(node_x(rng)),
                                                            static_cast<float>(node_y(rng)),
                                                            static_cast<float>(node_z(rng)));
    const Eigen::Vector3f p =
        i % 2 ? node : node + field.cellSize() * Eigen::Vector3f(jitter(rng), jitter(rng), 0.f);
    const auto expected = brute.closestFace(p);
    const auto actual = bounded.closestFace(p);
    ASSERT_TRUE(actual.found()) << "node " << i << " " << p.transpose();
    ASSERT_NEAR(actual.distance, expected.distance, tolerance) << "node " << i;
  }
  for (const Eigen::Vector3f& p :
       {Eigen::Vector3f(NAN, 0.f, 0.f), Eigen::Vector3f(0.f, INFINITY, 0.f),
        Eigen::Vector3f(0.f, 0.f, -INFINITY)}) {
    EXPECT_FALSE(bounded.closestFace(p).found()) << p.transpose();
    EXPECT_FALSE(bounded.closestFace(p, 0.01f).found()) << p.transpose();
  }
  EXPECT_FALSE(bounded.closestFace(Eigen::Vector3f::Zero(), NAN).found());
  const auto far = bounded.closestFace(Eigen::Vector3f(1e6f, -1e6f, 3e5f));
  ASSERT_TRUE(far.found());
  EXPECT_NEAR(far.distance, brute.closestFace(Eigen::Vector3f(1e6f, -1e6f, 3e5f)).distance, 1.f);
}

// The refinement with the model's index (the field's bound, then each point's previous face)
// against the same refinement on the brute force, which has no bound to take: the same pose,
// up to the float rounding of the same sums (1e-6).
TEST(FieldBoundedClosestFace, RefinementLandsWhereTheBruteForceDoes) {
  for (const auto& name : pcl::icf::synthetic::thesisModelNames()) {
    SCOPED_TRACE(name);
    const auto model = pcl::icf::IcfModel::build(pcl::icf::synthetic::thesisModel(name).mesh);
    const BruteForceClosestFace brute(model->mesh());
    std::vector<Eigen::Vector3f> points;  // the model's samples moved off by a small pose
    for (std::size_t i = 0; i < model->samples().size(); i += 4)
      points.push_back(model->samples()[i].point);
    const Eigen::Isometry3f start(Eigen::Translation3f(0.004f, -0.003f, 0.002f) *
                                  Eigen::AngleAxisf(0.08f, Eigen::Vector3f(1, 2, 3).normalized()));
    const pcl::icf::RefinementParams params;
    const auto a = pcl::icf::refinePose(brute, points, start, params, 2);
    const auto b = pcl::icf::refinePose(model->index(), points, start, params, 2);
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_TRUE(a.scene_to_model.matrix().isApprox(b.scene_to_model.matrix(), 1e-6f))
        << a.scene_to_model.matrix() << "\n"
        << b.scene_to_model.matrix();
    EXPECT_LT(b.weighted_rmse, 1e-4);  // back on the surface (a turn about an axis of symmetry
                                       // stays: the refinement does not move it)
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
