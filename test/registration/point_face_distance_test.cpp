// Exact point-to-face distance: every region of a triangle and of a rectangle by hand, the
// thesis's 9-region rectangle logic against the general polygon code, and random points
// against an independent reference (plane projection + segment clamping), in float and double.
#include <pcl/icf/registration/point_face_distance.h>

#include <gtest/gtest.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <random>

namespace {

using pcl::icf::FaceFeature;

template <typename Scalar>
using Vec = Eigen::Matrix<Scalar, 3, 1>;

template <typename Scalar>
class PointFaceDistance : public ::testing::Test {
 protected:
  // Tolerance: a few hundred ulps at unit scale covers the handful of products and
  // divisions on the way (each adds ~1 eps relative).
  static constexpr Scalar kTol = Scalar(256) * std::numeric_limits<Scalar>::epsilon();
  const Vec<Scalar> a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};

  void expectTriangle(const Vec<Scalar>& p, const Vec<Scalar>& expected, FaceFeature feature,
                      int index) {
    const auto r = pcl::icf::closestPointOnTriangle(p, a, b, c);
    EXPECT_LE((r.point - expected).norm(), kTol) << "p = " << p.transpose();
    EXPECT_NEAR(std::sqrt(r.squared_distance), (p - expected).norm(), kTol);
    EXPECT_EQ(r.feature, feature) << "p = " << p.transpose();
    EXPECT_EQ(r.feature_index, index) << "p = " << p.transpose();
  }
};

using ScalarTypes = ::testing::Types<float, double>;
// The name generator given: clang -Wpedantic warns on an empty variadic argument.
TYPED_TEST_SUITE(PointFaceDistance, ScalarTypes, ::testing::internal::DefaultNameGenerator);

TYPED_TEST(PointFaceDistance, TriangleEveryRegion) {
  using S = TypeParam;
  using V = Vec<S>;
  this->expectTriangle(V(0.2, 0.2, 0.5), V(0.2, 0.2, 0), FaceFeature::Interior, -1);
  this->expectTriangle(V(0.2, 0.2, -0.5), V(0.2, 0.2, 0), FaceFeature::Interior, -1);
  this->expectTriangle(V(0.5, -1, 0.3), V(0.5, 0, 0), FaceFeature::Edge, 0);
  this->expectTriangle(V(1, 1, 0), V(0.5, 0.5, 0), FaceFeature::Edge, 1);
  this->expectTriangle(V(-1, 0.5, 0.7), V(0, 0.5, 0), FaceFeature::Edge, 2);
  this->expectTriangle(V(-1, -1, 0.2), V(0, 0, 0), FaceFeature::Vertex, 0);
  this->expectTriangle(V(2, -0.5, 0), V(1, 0, 0), FaceFeature::Vertex, 1);
  this->expectTriangle(V(-0.5, 2, -1), V(0, 1, 0), FaceFeature::Vertex, 2);
}

TYPED_TEST(PointFaceDistance, PointsOnEdgesAndVerticesHaveZeroDistance) {
  using S = TypeParam;
  using V = Vec<S>;
  for (const V& p : {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0), V(0.5, 0, 0), V(0.5, 0.5, 0),
                     V(0, 0.25, 0), V(0.25, 0.25, 0)}) {
    const auto r = pcl::icf::closestPointOnTriangle(p, this->a, this->b, this->c);
    EXPECT_LE(std::sqrt(r.squared_distance), this->kTol) << p.transpose();
    EXPECT_LE((r.point - p).norm(), this->kTol) << p.transpose();
  }
}

TYPED_TEST(PointFaceDistance, DegenerateTrianglesFallBackToTheirEdges) {
  using S = TypeParam;
  using V = Vec<S>;
  // Collinear: the "triangle" is the segment [0, 2] on x.
  auto r = pcl::icf::closestPointOnTriangle(V(1, 1, 0), V(0, 0, 0), V(1, 0, 0), V(2, 0, 0));
  EXPECT_NEAR(std::sqrt(r.squared_distance), S(1), this->kTol);
  EXPECT_LE((r.point - V(1, 0, 0)).norm(), this->kTol);
  // All three vertices coincide: a point.
  r = pcl::icf::closestPointOnTriangle(V(0, 3, 4), V(0, 0, 0), V(0, 0, 0), V(0, 0, 0));
  EXPECT_NEAR(std::sqrt(r.squared_distance), S(5), this->kTol);
  EXPECT_EQ(r.feature, FaceFeature::Vertex);
}

// Rectangle A(0,0) B(2,0) C(2,1) D(0,1) at z = 0 and the 9 regions of the thesis's Fig. 4.4.
TYPED_TEST(PointFaceDistance, RectangleNineRegionsThesisAgreesWithGeneral) {
  using S = TypeParam;
  using V = Vec<S>;
  const V corners[4] = {V(0, 0, 0), V(2, 0, 0), V(2, 1, 0), V(0, 1, 0)};
  const V normal(0, 0, 1);
  struct Case {
    V p, expected;
    FaceFeature feature;
  };
  const Case cases[] = {
      {V(1, 0.5, 0.3), V(1, 0.5, 0), FaceFeature::Interior},  // inside
      {V(1, -1, 0.3), V(1, 0, 0), FaceFeature::Edge},         // below AB
      {V(3, 0.5, -0.2), V(2, 0.5, 0), FaceFeature::Edge},     // right of BC
      {V(1, 2, 0.1), V(1, 1, 0), FaceFeature::Edge},          // above CD
      {V(-1, 0.5, 0), V(0, 0.5, 0), FaceFeature::Edge},       // left of DA
      {V(-1, -1, 0.5), V(0, 0, 0), FaceFeature::Vertex},      // corner A
      {V(3, -1, 0.5), V(2, 0, 0), FaceFeature::Vertex},       // corner B
      {V(3, 2, -0.5), V(2, 1, 0), FaceFeature::Vertex},       // corner C
      {V(-1, 2, 0.5), V(0, 1, 0), FaceFeature::Vertex},       // corner D
  };
  for (const Case& k : cases) {
    const auto thesis = pcl::icf::closestPointOnRectangleThesis(k.p, corners);
    const auto general = pcl::icf::closestPointOnConvexPolygon(k.p, corners, 4, normal);
    EXPECT_LE((thesis.point - k.expected).norm(), this->kTol) << k.p.transpose();
    EXPECT_LE((general.point - k.expected).norm(), this->kTol) << k.p.transpose();
    EXPECT_EQ(thesis.feature, k.feature) << k.p.transpose();
    EXPECT_EQ(general.feature, k.feature) << k.p.transpose();
  }
  // Random points around a tilted rectangle: both methods give the same distance.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  const Eigen::Matrix<S, 3, 3> R =
      Eigen::AngleAxis<S>(S(0.7), Vec<S>(1, 2, 3).normalized()).toRotationMatrix();
  V tilted[4];
  for (int k = 0; k < 4; ++k)
    tilted[k] = R * corners[k] + V(0.3, -0.2, 0.5);
  for (int i = 0; i < 2000; ++i) {
    const V p(S(u(rng)), S(u(rng)), S(u(rng)));
    const auto thesis = pcl::icf::closestPointOnRectangleThesis(p, tilted);
    const auto general = pcl::icf::closestPointOnConvexPolygon(p, tilted, 4, V(R * normal));
    ASSERT_NEAR(std::sqrt(thesis.squared_distance), std::sqrt(general.squared_distance),
                S(8) * this->kTol)
        << "p = " << p.transpose();
  }
}

// Independent reference for a triangle: the plane projection when its barycentric coordinates
// (solved by a 2x2 linear system) are all non-negative, else the best of the three clamped
// segment projections.
template <typename S>
S referenceTriangleDistance(const Vec<S>& p, const Vec<S>& a, const Vec<S>& b, const Vec<S>& c) {
  const Vec<S> e0 = b - a, e1 = c - a, ap = p - a;
  Eigen::Matrix<S, 2, 2> G;
  G << e0.dot(e0), e0.dot(e1), e0.dot(e1), e1.dot(e1);
  const Eigen::Matrix<S, 2, 1> st = G.ldlt().solve(Eigen::Matrix<S, 2, 1>(e0.dot(ap), e1.dot(ap)));
  if (st.minCoeff() >= 0 && st.sum() <= 1)
    return (p - (a + st[0] * e0 + st[1] * e1)).norm();
  auto segment = [&](const Vec<S>& x, const Vec<S>& y) {
    const S t = std::clamp((p - x).dot(y - x) / (y - x).squaredNorm(), S(0), S(1));
    return (p - (x + t * (y - x))).norm();
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

TYPED_TEST(PointFaceDistance, RandomPointsAgainstIndependentReference) {
  using S = TypeParam;
  using V = Vec<S>;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-2, 2);
  auto random = [&] { return V(S(u(rng)), S(u(rng)), S(u(rng))); };
  for (int i = 0; i < 5000; ++i) {
    const V a = random(), b = random(), c = random(), p = random();
    // Skip near-degenerate triangles: the reference's 2x2 solve is ill-conditioned there.
    if ((b - a).cross(c - a).norm() < S(0.05))
      continue;
    const auto r = pcl::icf::closestPointOnTriangle(p, a, b, c);
    const S expected = referenceTriangleDistance(p, a, b, c);
    // Coordinates up to 2 and a conditioning margin of the reference: 64x the base tolerance.
    ASSERT_NEAR(std::sqrt(r.squared_distance), expected, S(64) * this->kTol)
        << "seed 42, case " << i;
    ASSERT_NEAR((p - r.point).norm(), std::sqrt(r.squared_distance), S(64) * this->kTol);
  }
}

}  // namespace
