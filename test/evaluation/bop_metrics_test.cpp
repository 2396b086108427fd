// The BOP pose errors and scores (pcl/icf/evaluation/) against hand-worked cases: the
// symmetry set's size and what each member fixes; MSSD and MSPD of the truth itself (0), of a
// listed symmetry (0), of a known shift (its length; fx dx / z pixels); VSD on a 4 x 4 image
// worked pixel by pixel (an occluder, a depth offset, a sideways shift), then on a rendered
// box; ADD, ADD-S and ADD-S to the surface of a shift and a turn; the greedy matching, the top-n
// rule, invalid instances and the recalls.
#include <pcl/icf/evaluation/average_distance.h>
#include <pcl/icf/evaluation/bop_pose_errors.h>
#include <pcl/icf/evaluation/bop_recall.h>

#include "synthetic/synthetic_models.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace pcl::icf::evaluation;

// Sums of a few doubles: exact to well below this.
constexpr double kExact = 1e-9;
constexpr double kPi = 3.14159265358979323846;

Eigen::Isometry3d pose(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(angle, axis.normalized()).matrix();
  p.translation() = t;
  return p;
}

/** The corners of a 2 x 4 x 6 box centred at \a c. */
std::vector<Eigen::Vector3d> boxCorners(const Eigen::Vector3d& c) {
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i)
    corners.push_back(c + Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 2 : -2, i & 4 ? 3 : -3));
  return corners;
}

/** 180 degrees about z through \a c (the foam brick's symmetry in models_info.json's form). */
Eigen::Isometry3d halfTurnAbout(const Eigen::Vector3d& c) {
  Eigen::Isometry3d s = Eigen::Isometry3d::Identity();
  s.linear() = Eigen::Vector3d(-1, -1, 1).asDiagonal();
  s.translation() = Eigen::Vector3d(2 * c.x(), 2 * c.y(), 0);
  return s;
}

TEST(BopSymmetries, IdentityDiscreteAndDiscretisedContinuous) {
  EXPECT_EQ(symmetryTransformations({}, {}).size(), 1u);
  const Eigen::Vector3d c(0.5, -0.1, 8.0);
  const auto two = symmetryTransformations({halfTurnAbout(c)}, {});
  ASSERT_EQ(two.size(), 2u);
  EXPECT_TRUE(two[0].isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_NEAR((two[1] * c - c).norm(), 0.0, kExact) << "the turn fixes its axis point";

  const ContinuousSymmetry can{Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(-1.4, 0.5, -3.6)};
  const auto turns = symmetryTransformations({}, {can});
  ASSERT_EQ(turns.size(), 315u) << "ceil(pi / 0.01)";
  EXPECT_TRUE(turns[0].isApprox(Eigen::Isometry3d::Identity()));
  for (const auto& s : turns) {
    EXPECT_NEAR((s * can.offset - can.offset).norm(), 0.0, kExact);
    EXPECT_NEAR((s.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(), 0.0,
                kExact);
  }
  // Neighbouring turns move a point one radius from the axis by 2 sin(pi / 315) radii.
  const Eigen::Vector3d rim = can.offset + Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR((turns[1] * rim - rim).norm(), 2 * std::sin(M_PI / 315), kExact);
  EXPECT_EQ(symmetryTransformations({halfTurnAbout(c)}, {can}).size(), 630u);
  EXPECT_THROW(symmetryTransformations({}, {can}, 0.0), std::invalid_argument);
}

TEST(BopErrors, MssdOfTheTruthASymmetryAndAShift) {
  const Eigen::Vector3d c(0.5, -0.1, 8.0);
  const auto corners = boxCorners(c);
  const Eigen::Isometry3d gt = pose(0.7, {1, 2, 3}, {10, -20, 800});
  const std::vector<Eigen::Isometry3d> none = symmetryTransformations({}, {});
  const std::vector<Eigen::Isometry3d> brick = symmetryTransformations({halfTurnAbout(c)}, {});
  EXPECT_NEAR(mssd(gt, gt, corners, none), 0.0, kExact);
  const Eigen::Isometry3d turned = gt * halfTurnAbout(c);
  EXPECT_NEAR(mssd(turned, gt, corners, brick), 0.0, 1e-9);
  // Without the symmetry: the corner (+-1, +-2) from the axis moves by twice that.
  EXPECT_NEAR(mssd(turned, gt, corners, none), 2 * std::sqrt(5.0), 1e-9);
  Eigen::Isometry3d shifted = gt;
  shifted.translation() += Eigen::Vector3d(3, 4, 0);
  EXPECT_NEAR(mssd(shifted, gt, corners, brick), 5.0, 1e-9);
  // No points would make every pose right; no symmetries (not even the identity), none.
  EXPECT_THROW(mssd(shifted, gt, {}, brick), std::invalid_argument);
  EXPECT_THROW(mssd(shifted, gt, corners, {}), std::invalid_argument);
}

TEST(BopErrors, MspdOfAKnownShift) {
  Eigen::Matrix3d K;
  K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  const std::vector<Eigen::Vector3d> points = {{0, 0, 1000}, {50, 20, 1000}, {-30, 10, 2000}};
  const Eigen::Isometry3d gt = Eigen::Isometry3d::Identity();
  const auto none = symmetryTransformations({}, {});
  EXPECT_NEAR(mspd(gt, gt, K, points, none), 0.0, kExact);
  Eigen::Isometry3d shifted = gt;
  shifted.translation().x() = 10;
  // fx dx / z: 5 pixels at 1000, 2.5 at 2000; the maximum.
  EXPECT_NEAR(mspd(shifted, gt, K, points, none), 5.0, 1e-9);
  const Eigen::Vector3d c(0, 0, 1500);
  const auto brick = symmetryTransformations({halfTurnAbout(c)}, {});
  EXPECT_NEAR(mspd(gt * halfTurnAbout(c), gt, K, points, brick), 0.0, 1e-9);
}

/** A 4 x 4 depth map filled with \a value. */
DepthMap filled(float value) {
  return DepthMap{4, 4, std::vector<float>(16, value)};
}
void set(DepthMap& m, int u, int v, float value) {
  m.z[static_cast<std::size_t>(v) * 4 + u] = value;
}

TEST(BopErrors, VsdWorkedPixelByPixel) {
  // The truth covers columns 0-1 at 1000; the test image sees it there, except two pixels of
  // row 0 hidden by an occluder at 900, and a background at 1500 elsewhere.
  DepthMap gt = filled(0.f), test = filled(1500.f);
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 2; ++u) {
      set(gt, u, v, 1000.f);
      set(test, u, v, v == 0 ? 900.f : 1000.f);
    }
  const std::vector<double> taus = {0.05, 0.10, 0.15};
  const double delta = 15.0, diameter = 100.0;
  // The truth against itself: nothing differs, the occluder changes nothing.
  for (const double e : vsdFromDistances(test, gt, gt, delta, taus, diameter))
    EXPECT_EQ(e, 0.0);
  // 10 behind: the same 6 pixels visible for both (10 <= delta), each off by 0.1 diameter:
  // wrong for tau 0.05 and 0.10 (>= tau counts), right for 0.15.
  DepthMap behind = gt;
  for (auto& z : behind.z)
    if (z > 0.f)
      z += 10.f;
  EXPECT_EQ(vsdFromDistances(test, behind, gt, delta, taus, diameter),
            (std::vector<double>{1.0, 1.0, 0.0}));
  // One column to the right: the truth visible at column 0-1 rows 1-3 (6), the estimate at
  // column 1 rows 1-3 and all of column 2 (7, the background is behind it); union 10,
  // intersection 3 (equal depths): 7 / 10 for every tau.
  DepthMap right = filled(0.f);
  for (int v = 0; v < 4; ++v)
    for (int u = 1; u < 3; ++u)
      set(right, u, v, 1000.f);
  for (const double e : vsdFromDistances(test, right, gt, delta, taus, diameter))
    EXPECT_NEAR(e, 0.7, kExact);
  // Nothing visible of either: 1.
  EXPECT_EQ(vsdFromDistances(test, filled(0.f), filled(0.f), delta, taus, diameter),
            (std::vector<double>{1.0, 1.0, 1.0}));
  EXPECT_THROW(
      vsdFromDistances(test, DepthMap{2, 2, std::vector<float>(4, 1.f)}, gt, delta, taus, diameter),
      std::invalid_argument);
}

TEST(BopErrors, DistanceImageOfKnownPixels) {
  Eigen::Matrix3d K;
  K << 2, 0, 1, 0, 2, 1, 0, 0, 1;
  DepthMap depth = filled(3.f);
  set(depth, 2, 2, 0.f);
  const DepthMap d = distanceImage(depth, K);
  EXPECT_FLOAT_EQ(d.at(1, 1), 3.f) << "the principal point";
  EXPECT_FLOAT_EQ(d.at(3, 1), 3.f * std::sqrt(2.f)) << "one focal length aside: 45 degrees";
  EXPECT_FLOAT_EQ(d.at(2, 2), 0.f) << "missing stays missing";
  EXPECT_THROW(distanceImage(DepthMap{4, 4, std::vector<float>(3, 1.f)}, K), std::invalid_argument);
}

// A 10 cm cube 0.6 m in front of the camera, turned, rendered: against itself 0 with or
// without an occluder. Then square on, its front face at 0.55 m, and 2 cm farther away: every
// visible pixel is off by 2 cm (0.115-0.117 diameters with the ray's slant), wrong for tau 0.05
// and 0.10 (the estimate is 2 cm behind the measurement, so only its overlap with the truth
// counts: error 1); for tau >= 0.15 only the truth's pixels the smaller face leaves,
// 1 - (0.55 / 0.57)^2 = 0.069, within 0.02 for the silhouette's whole pixels (95 pixels a side:
// a pixel row each way is 2%).
TEST(BopErrors, VsdOfARenderedCube) {
  const auto model = pcl::icf::IcfModel::build(pcl::icf::synthetic::makeBox(0.1, 0.1, 0.1));
  Eigen::Matrix3d K;
  K << 525, 0, 319.5, 0, 525, 239.5, 0, 0, 1;
  const Eigen::Isometry3d gt = pose(0.4, {1, 1, 0}, {0.02, -0.01, 0.6});
  DepthMap test = renderDepth(*model, gt, K, 640, 480);
  const double diameter = 0.1 * std::sqrt(3.0), delta = 0.015;
  const std::vector<double> taus = bopFractions();
  for (const double e : vsd(*model, gt, gt, test, K, delta, taus, diameter))
    EXPECT_NEAR(e, 0.0, 1e-12);
  for (int v = 200; v < 260; ++v)
    for (int u = 280; u < 330; ++u)
      test.z[static_cast<std::size_t>(v) * 640 + u] = 0.3f;  // an occluder in front
  for (const double e : vsd(*model, gt, gt, test, K, delta, taus, diameter))
    EXPECT_NEAR(e, 0.0, 1e-12);

  const Eigen::Isometry3d square = pose(0.0, {0, 0, 1}, {0, 0, 0.6});
  const Eigen::Isometry3d farther = pose(0.0, {0, 0, 1}, {0, 0, 0.62});
  const auto errors = vsd(*model, farther, square, renderDepth(*model, square, K, 640, 480), K,
                          delta, taus, diameter);
  EXPECT_EQ(errors[0], 1.0);
  EXPECT_EQ(errors[1], 1.0);
  const double uncovered = 1.0 - std::pow(0.55 / 0.57, 2.0);
  for (std::size_t t = 2; t < taus.size(); ++t)
    EXPECT_NEAR(errors[t], uncovered, 0.02) << "tau " << taus[t];
}

MatchGroup threeEstimatesTwoInstances() {
  MatchGroup g;
  g.gt_valid = {true, true};
  g.max_estimates = 2;
  g.estimates = {{0.9, {0.30, 0.05}}, {0.8, {0.04, 0.06}}, {0.7, {0.01, 0.01}}};
  return g;
}

// ADD of a shift is its length; ADD-S of four points on a line shifted by their spacing is a
// quarter of it (three land on a neighbour, the end one is a spacing away); a half turn of the
// box's corners about their centre maps them onto each other: ADD-S 0, ADD the mean distance
// between each corner and its opposite in x and y.
TEST(AverageDistance, AddAndAdiOfAShiftAndAHalfTurn) {
  const std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  const Eigen::Isometry3d gt = pose(0.3, {1, 2, 3}, {0.1, -0.2, 5.0});
  const Eigen::Isometry3d shifted = gt * pose(0.0, {0, 0, 1}, {1, 0, 0});
  EXPECT_NEAR(add(shifted, gt, line), 1.0, kExact);
  EXPECT_NEAR(adi(shifted, gt, line), 0.25, 1e-6);  // the tree's floats: 1e-6 of a unit
  EXPECT_NEAR(add(gt, gt, line), 0.0, kExact);
  const Eigen::Vector3d c(0.5, -1.0, 2.0);
  const auto corners = boxCorners(c);
  const Eigen::Isometry3d turned = gt * halfTurnAbout(c);
  EXPECT_NEAR(adi(turned, gt, corners), 0.0, 1e-6);
  EXPECT_NEAR(add(turned, gt, corners), 2.0 * std::sqrt(1.0 + 4.0), kExact);
  EXPECT_THROW(add(gt, gt, {}), std::invalid_argument);
  EXPECT_THROW(adi(gt, gt, {}), std::invalid_argument);
}

// A 10 cm cube: a quarter turn about its centre maps the surface onto itself (0); after a 1 cm
// shift along x the four -x corners are 1 cm outside the shifted cube and the four +x corners
// lie on its y and z faces (which now span x in [-4, 6] cm), so the mean is 5 mm; float faces:
// 1e-6 m.
TEST(AverageDistance, AddSToTheSurfaceOfACube) {
  const auto model = pcl::icf::IcfModel::build(pcl::icf::synthetic::makeBox(0.1, 0.1, 0.1));
  std::vector<Eigen::Vector3d> corners;
  for (int i = 0; i < 8; ++i)
    corners.emplace_back(i & 1 ? 0.05 : -0.05, i & 2 ? 0.05 : -0.05, i & 4 ? 0.05 : -0.05);
  const Eigen::Isometry3d gt = pose(0.4, {1, -1, 2}, {0.02, 0.01, 0.6});
  EXPECT_NEAR(addSToSurface(*model, gt * pose(kPi / 2, {0, 0, 1}, {0, 0, 0}), gt, corners), 0.0,
              1e-6);
  EXPECT_NEAR(addSToSurface(*model, gt * pose(0.0, {0, 0, 1}, {0.01, 0, 0}), gt, corners), 0.005,
              1e-6);
  EXPECT_THROW(addSToSurface(*model, gt, gt, {}), std::invalid_argument);
}

TEST(BopRecall, GreedyByScoreTopNAndInvalidInstances) {
  MatchGroup g = threeEstimatesTwoInstances();
  // At 0.1: the best-scored takes instance 1 (0.05), the next instance 0 (0.04).
  EXPECT_EQ(matchedInstances(g, 0.1), 2u);
  // At 0.045: the first matches nothing, the second instance 0; the third would match
  // instance 1 but only the best two estimates count.
  EXPECT_EQ(matchedInstances(g, 0.045), 1u);
  g.max_estimates = 0;
  EXPECT_EQ(matchedInstances(g, 0.045), 2u);
  // An instance seen too little is neither matched nor counted.
  MatchGroup half = threeEstimatesTwoInstances();
  half.gt_valid = {true, false};
  EXPECT_EQ(matchedInstances(half, 0.1), 1u);
  EXPECT_DOUBLE_EQ(recall({half}, 0.1), 1.0);
  // An image where the object was not found: its instance counts, unmatched.
  MatchGroup missed;
  missed.gt_valid = {true};
  EXPECT_NEAR(recall({threeEstimatesTwoInstances(), missed}, 0.1), 2.0 / 3.0, kExact);
  EXPECT_NEAR(averageRecall({threeEstimatesTwoInstances()}, {0.045, 0.1}), 0.75, kExact);
  // Ties keep the order given.
  MatchGroup tie;
  tie.gt_valid = {true};
  tie.max_estimates = 1;
  tie.estimates = {{0.5, {0.2}}, {0.5, {0.01}}};
  EXPECT_EQ(matchedInstances(tie, 0.1), 0u);
  tie.estimates[0].errors = {0.3, 0.1};
  EXPECT_THROW(matchedInstances(tie, 0.1), std::invalid_argument);
}

TEST(BopRecall, TheBop19Thresholds) {
  const auto f = bopFractions();
  ASSERT_EQ(f.size(), 10u);
  EXPECT_NEAR(f.front(), 0.05, kExact);
  EXPECT_NEAR(f.back(), 0.50, kExact);
  const auto px = bopMspdThresholds(640);
  ASSERT_EQ(px.size(), 10u);
  EXPECT_NEAR(px.front(), 5.0, kExact);
  EXPECT_NEAR(px.back(), 50.0, kExact);
  EXPECT_NEAR(bopMspdThresholds(1280).back(), 100.0, kExact);
}

}  // namespace
