// The closest-point field against exact distances: exact on planar patches (the interpolated
// closest point is affine there), within its documented bound everywhere in the grid, and
// "at least the margin" beyond it.
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/distance_field.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace {

using pcl::icf::ClosestPointField;
using pcl::icf::DistanceFieldParams;
using pcl::icf::EmbreeClosestFaceIndex;
using pcl::icf::FaceMesh;

struct ErrorStats {
  float max = 0.f, p99 = 0.f, median = 0.f;
};

ErrorStats measure(const ClosestPointField& field, const EmbreeClosestFaceIndex& index, float band,
                   int count, std::uint64_t seed) {
  const FaceMesh& mesh = index.mesh();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<float> errors;
  const Eigen::Vector3f lo = mesh.boundsMin() - Eigen::Vector3f::Constant(band);
  const Eigen::Vector3f hi = mesh.boundsMax() + Eigen::Vector3f::Constant(band);
  while (static_cast<int>(errors.size()) < count) {
    const Eigen::Vector3f p = lo + Eigen::Vector3f(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
    const float exact = index.closestFace(p).distance;
    if (exact > band)
      continue;
    errors.push_back(std::abs(field.distance(p) - exact));
  }
  std::sort(errors.begin(), errors.end());
  return {errors.back(), errors[errors.size() * 99 / 100], errors[errors.size() / 2]};
}

TEST(ClosestPointField, ExactAboveTheMiddleOfAFace) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.2));
  const EmbreeClosestFaceIndex index(mesh);
  const ClosestPointField field(index);
  // Across the surface of the top face, away from its edges: |error| is rounding only.
  for (float z = 0.08f; z <= 0.13f; z += 0.0007f)
    ASSERT_NEAR(field.distance(Eigen::Vector3f(0.013f, -0.021f, z)), std::abs(z - 0.1f), 2e-6f);
}

TEST(ClosestPointField, WithinItsBoundNearTheSurface) {
  for (const auto& name : pcl::icf::synthetic::thesisModelNames()) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel(name).mesh);
    const EmbreeClosestFaceIndex index(mesh);
    const ClosestPointField field(index);
    const ErrorStats e = measure(field, index, 0.03f, 20000, 21);
    RecordProperty(name + "_max_mm", std::to_string(1e3f * e.max));
    EXPECT_LE(e.max, field.errorBound()) << "cell " << field.cellSize();
    // Most of the band is above flat patches, where the field is exact.
    EXPECT_LE(e.median, 1e-5f);
  }
}

TEST(ClosestPointField, WithinItsBoundOnTheBunny) {
  PCL_ICF_REQUIRE_SHARED(path, "meshes/bunny.ply");
  const auto mesh = FaceMesh::build(pcl::icf::io::loadPolygonMesh(path));
  const EmbreeClosestFaceIndex index(mesh);
  const ClosestPointField field(index);
  const ErrorStats e = measure(field, index, 0.03f, 20000, 22);
  EXPECT_LE(e.max, field.errorBound()) << "cell " << field.cellSize();
  EXPECT_LE(e.p99, 0.25f * field.cellSize());
}

TEST(ClosestPointField, BeyondTheGridAtLeastTheMargin) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.2));
  const EmbreeClosestFaceIndex index(mesh);
  DistanceFieldParams params;
  params.margin = 0.05f;
  const ClosestPointField field(index, params);
  for (float x : {0.16f, 0.3f, 5.f, 1e6f})
    EXPECT_GE(field.distance(Eigen::Vector3f(x, 0.f, 0.f)), params.margin - 1e-6f) << x;
}

// distanceUpperBound is what FieldBoundedClosestFace cuts every exact query to: it must stay
// strictly above the exact distance (the closest face would be missed), and inside the grid at most
// the exact distance plus twice the half-diagonal to the nearest node (plus its 1e-5 widening).
TEST(ClosestPointField, UpperBoundIsAnUpperBoundAndTightInTheGrid) {
  for (const auto& name : pcl::icf::synthetic::thesisModelNames()) {
    SCOPED_TRACE(name);
    const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel(name).mesh);
    const EmbreeClosestFaceIndex index(mesh);
    const ClosestPointField field(index);
    const Eigen::Vector3f lo = field.origin();
    const Eigen::Vector3f hi =
        lo + field.cellSize() * (field.dimensions() - Eigen::Vector3i::Ones()).cast<float>();
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<float> u(-1.f, 2.f);  // a third inside the grid per axis
    const float slack = 1.7320508f * field.cellSize() + 1e-4f;
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector3f p = lo + Eigen::Vector3f(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
      const float exact = index.closestFace(p).distance;
      const float bound = field.distanceUpperBound(p);
      ASSERT_GT(bound, exact) << p.transpose();  // strictly: the BVH keeps faces below it
      const bool inside = (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
      if (inside) {
        ASSERT_LE(bound, exact + slack) << p.transpose();
      }
    }
  }
}

TEST(ClosestPointField, AbsurdParametersAreRejected) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.2));
  const EmbreeClosestFaceIndex index(mesh);
  DistanceFieldParams p;
  p.margin = -1.f;
  EXPECT_THROW(ClosestPointField(index, p), std::invalid_argument);
  p = {};
  p.resolution = 1;
  EXPECT_THROW(ClosestPointField(index, p), std::invalid_argument);
  p = {};
  p.cell_size = 1e-6f;  // 10^15 nodes: refused before allocating
  EXPECT_THROW(ClosestPointField(index, p), std::invalid_argument);
}

TEST(ClosestPointField, ContentDoesNotDependOnThreads) {
  const auto mesh = FaceMesh::build(pcl::icf::synthetic::thesisModel("Amicelly").mesh);
  const EmbreeClosestFaceIndex index(mesh);
  DistanceFieldParams one, two;
  one.threads = 1;
  two.threads = 2;
  const ClosestPointField a(index, one), b(index, two);
  for (float x = -0.1f; x < 0.1f; x += 0.0037f)
    ASSERT_EQ(a.distance(Eigen::Vector3f(x, 0.3f * x, 0.01f)),
              b.distance(Eigen::Vector3f(x, 0.3f * x, 0.01f)));
}

}  // namespace
