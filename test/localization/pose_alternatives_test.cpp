// turnedAlternatives against the models' known symmetries (the oracle): a box seen from a
// general viewpoint looks the same after a 180-degree turn about any of its axes, so those
// turns must come back as alternatives as good as the pose; a frustum (a cup, wider at the
// top) looks the same after any turn about its axis and different upside down, so only turns
// about its axis may come back. principalAxes against a box's known axes.
#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <pcl/icf/localization/pose_alternatives.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace pcl::icf;
using namespace pcl::icf::localization;

struct View {
  IcfModel::ConstPtr model;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  std::vector<Eigen::Vector3f> points;
  DepthImage image;
  DepthExplanation found;
};

View viewOf(const pcl::PolygonMesh& mesh) {
  View v;
  v.model = IcfModel::build(mesh);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.02, -0.01, 0.75);
  synthetic::SceneObject object;
  object.mesh = &mesh;
  object.pose = pose;
  object.label = 1;
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  noise.seed = 3;
  const synthetic::Scan scan =
      synthetic::renderScan({object}, synthetic::CameraIntrinsics(), noise);
  for (const auto& p : *scan.cloud)
    if (std::isfinite(p.z))
      v.points.emplace_back(p.x, p.y, p.z);
  std::vector<Eigen::Vector3f> grid;
  for (const auto& p : *scan.cloud)
    grid.emplace_back(p.x, p.y, p.z);
  v.image = DepthImage(grid, PinholeIntrinsics());
  v.pose = pose.cast<float>();
  v.found = explainDepth(*v.model, v.pose, v.image);
  return v;
}

// The box's axes, longest first, are its x, y, z (14 x 9 x 5 cm): 1e-3 in direction, its
// sides to float rounding.
TEST(PoseAlternatives, PrincipalAxesOfABox) {
  const IcfModel::ConstPtr box = IcfModel::build(synthetic::makeBox(0.14, 0.09, 0.05));
  const PrincipalAxes a = principalAxes(*box);
  EXPECT_LT(a.centre.norm(), 1e-5f);
  EXPECT_NEAR(std::abs(a.axes.col(0).x()), 1.f, 1e-3f);
  EXPECT_NEAR(std::abs(a.axes.col(1).y()), 1.f, 1e-3f);
  EXPECT_NEAR(std::abs(a.axes.col(2).z()), 1.f, 1e-3f);
  EXPECT_NEAR(a.axes.determinant(), 1.f, 1e-4f);
  EXPECT_NEAR(a.extent.x(), 0.14f, 1e-5f);
  EXPECT_NEAR(a.extent.y(), 0.09f, 1e-5f);
  EXPECT_NEAR(a.extent.z(), 0.05f, 1e-5f);
}

// A box's three 180-degree flips explain the depth as well as its pose (within the default
// margin, 0.05) and are distinct poses: all three are reported, each a 180-degree turn.
TEST(PoseAlternatives, ABoxHasThreeFlips) {
  const View v = viewOf(synthetic::makeBox(0.14, 0.09, 0.05));
  ASSERT_GT(v.found.confidence, 0.8);
  const auto alts =
      turnedAlternatives(*v.model, principalAxes(*v.model), v.points, v.pose, v.found, v.image);
  ASSERT_EQ(alts.size(), 3u);
  for (const auto& alt : alts) {
    EXPECT_NEAR(alt.rotation_offset_deg, 180.f, 2.f);
    EXPECT_GE(alt.verification.confidence, v.found.confidence - 0.05);
  }
}

// A cup turned about its axis is the same cup; upside down or on its side it is not: every
// alternative must turn about the cup's axis (model z, within 3 degrees).
TEST(PoseAlternatives, ACupTurnsOnlyAboutItsAxis) {
  const View v = viewOf(synthetic::makeCup());
  ASSERT_GT(v.found.confidence, 0.8);
  const auto alts =
      turnedAlternatives(*v.model, principalAxes(*v.model), v.points, v.pose, v.found, v.image);
  EXPECT_FALSE(alts.empty()) << "a turn about the axis explains the depth as well";
  for (const auto& alt : alts) {
    const Eigen::AngleAxisf turn(v.pose.linear().transpose() * alt.object_pose.linear());
    EXPECT_GT(std::abs(turn.axis().z()), std::cos(3.f * static_cast<float>(M_PI) / 180.f))
        << "turned " << alt.turn_deg << " degrees about " << alt.axis.transpose();
  }
}

TEST(PoseAlternatives, InvalidParametersNameTheField) {
  PoseAlternativeParams p;
  p.confidence_margin = -1.0;
  try {
    p.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("confidence_margin"), std::string::npos) << e.what();
  }
}

}  // namespace
