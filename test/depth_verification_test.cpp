// The verification's pieces against an independent oracle: the test support's ray caster
// (depth_camera.h, Moeller-Trumbore on every triangle) renders the same mesh at the same pose;
// the intrinsics fit must recover the simulator's camera; explainDepth must call a right pose
// explained and a pose moved off the object, or a model smaller than the object, not.
#include "support/depth_camera.h"
#include "support/synthetic_models.h"

#include <pcl/icf/depth_verification.h>

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace pcl::icf;

struct RenderedBox {
  test::SyntheticModel model = test::thesisModel("Box5");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  test::Scan scan;
  std::vector<Eigen::Vector3f> points;
};

RenderedBox renderBox(const test::ScanNoise& noise, double tilt = 0.6) {
  RenderedBox r;
  r.pose.linear() = (Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()) *
                     Eigen::AngleAxisd(-tilt / 1.5, Eigen::Vector3d::UnitY()))
                        .toRotationMatrix();
  r.pose.translation() = Eigen::Vector3d(0.03, -0.02, 0.8);
  test::SceneObject object;
  object.mesh = &r.model.mesh;
  object.pose = r.pose;
  object.label = 1;
  r.scan = test::renderScan({object}, test::CameraIntrinsics(), noise);
  for (const auto& p : *r.scan.cloud)
    r.points.emplace_back(p.x, p.y, p.z);
  return r;
}

// The simulator's camera is an exact pinhole: the least-squares fit recovers it to float
// rounding (1e-3 pixel on a 640-pixel image).
TEST(DepthImage, FitsTheIntrinsicsOfAnOrganizedCloud) {
  const RenderedBox box = renderBox(test::ScanNoise::none());
  double rms = 0.0;
  const PinholeIntrinsics k = DepthImage::fitIntrinsics(box.points, 640, 480, rms);
  const test::CameraIntrinsics truth;
  EXPECT_NEAR(k.fx, truth.fx, 1e-2);
  EXPECT_NEAR(k.fy, truth.fy, 1e-2);
  EXPECT_NEAR(k.cx, truth.cx, 1e-2);
  EXPECT_NEAR(k.cy, truth.cy, 1e-2);
  EXPECT_LT(rms, 1e-3);
}

// The rasteriser against the ray caster: on the pixels both cover, the same depth (1e-5 m:
// float rounding of a ray-plane intersection at 0.8 m); the covered sets differ only on
// silhouette pixels whose centre lies within float rounding of an edge (under 2% of them).
TEST(DepthVerification, RendersWhatTheRayCasterSees) {
  const RenderedBox box = renderBox(test::ScanNoise::none());
  const IcfModel::ConstPtr model = IcfModel::build(box.model.mesh);
  PinholeIntrinsics k;
  const ModelDepth m = renderModelDepth(*model, box.pose.cast<float>(), k);
  std::size_t both = 0, only_one = 0;
  double worst = 0.0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const auto& p = (*box.scan.cloud)[static_cast<std::size_t>(v) * 640 + u];
      const bool cast = std::isfinite(p.z);
      if (cast && m.covers(u, v)) {
        ++both;
        worst =
            std::max(worst, std::abs(double(p.z) - m.depth[static_cast<std::size_t>(v) * 640 + u]));
      } else if (cast != m.covers(u, v))
        ++only_one;
    }
  ASSERT_GT(both, 1000u);
  EXPECT_LT(worst, 1e-5);
  EXPECT_LT(static_cast<double>(only_one) / static_cast<double>(both), 0.02);
}

// Kinect-like noise (1.5 mm at 1 m, 5% outliers up to 5 cm): the right pose is explained
// (outliers are single pixels: behind the right surface they are isolated conflicts, fewer
// than 2 of 4 neighbours conflicting, not seen through; at 2.5% density about 0.4% of them
// pair up); the same model 3 cm nearer the
// camera floats in front of the measured surface (seen through everywhere); a box half the
// size placed on the big box's face (seen nearly face-on) explains depth but the big box's
// face carries on past its silhouette (on the model's surface extended) around much of it:
// continuation above max_continuation (0.2), confidence 0.
TEST(DepthVerification, TellsARightPoseFromWrongOnes) {
  test::ScanNoise noise;
  noise.seed = 7;
  const RenderedBox box = renderBox(noise);
  const IcfModel::ConstPtr model = IcfModel::build(box.model.mesh);
  const DepthImage image(box.points, PinholeIntrinsics());
  const DepthExplanation right = explainDepth(*model, box.pose.cast<float>(), image);
  EXPECT_GT(right.supported, 0.85);
  EXPECT_GT(right.isolated_conflicts, 0.005);
  EXPECT_LT(right.seen_through, 0.005);
  EXPECT_LT(right.silhouette_continuation, 0.02);
  EXPECT_GT(right.confidence, 0.9);

  Eigen::Isometry3d nearer = box.pose;
  nearer.translation() *= (0.77 / 0.8);
  const DepthExplanation floating = explainDepth(*model, nearer.cast<float>(), image);
  EXPECT_GT(floating.seen_through, 0.8);
  EXPECT_EQ(floating.confidence, 0.0);

  const test::SyntheticModel small{"HalfBox", test::makeBox(0.07, 0.045, 0.05),
                                   test::Symmetry::box(0.07, 0.045, 0.05), Eigen::Vector3f::Ones()};
  const IcfModel::ConstPtr half = IcfModel::build(small.mesh);
  // Same orientation and the same front face (z = +0.025 in both boxes' frames).
  const RenderedBox facing = renderBox(noise, 0.15);
  const DepthImage facing_image(facing.points, PinholeIntrinsics());
  const DepthExplanation inside = explainDepth(*half, facing.pose.cast<float>(), facing_image);
  EXPECT_GT(inside.silhouette_continuation, 0.3);
  EXPECT_EQ(inside.confidence, 0.0);
}

// A box standing on a table, and the same box sunk 2 cm into it: where the table (marked as
// background) lies in front of the sunk model the model would be beneath the table, a
// conflict (below_support); the right pose has none. The sunk box's band along the table is
// about 2 cm of its 5 cm height on the faces the camera sees: more than 5% of its pixels.
TEST(DepthVerification, AModelBeneathTheTableIsAConflict) {
  const test::SyntheticModel box = test::thesisModel("Box5");
  test::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  noise.seed = 5;
  const test::TabletopScene scene =
      test::makeTabletopScene({box}, {{0.0, 0.0, 0.5}}, test::CameraIntrinsics(), noise);
  std::vector<Eigen::Vector3f> points;
  pcl::Indices table;
  for (std::size_t i = 0; i < scene.scan.cloud->size(); ++i) {
    const auto& p = (*scene.scan.cloud)[i];
    points.emplace_back(p.x, p.y, p.z);
    if (scene.scan.labels[i] == 0)
      table.push_back(static_cast<pcl::index_t>(i));
  }
  DepthImage image(points, PinholeIntrinsics());
  image.markBackground(points, table);
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  const Eigen::Isometry3f right = scene.poses.front().cast<float>();
  Eigen::Isometry3f sunk = right;
  sunk.translation() -= 0.02f * scene.table_plane.head<3>();
  const DepthExplanation good = explainDepth(*model, right, image);
  const DepthExplanation bad = explainDepth(*model, sunk, image);
  EXPECT_LT(good.below_support, 0.002);
  EXPECT_GT(good.confidence, 0.9);
  EXPECT_GT(bad.below_support, 0.05);
  EXPECT_LT(bad.confidence, 0.5 * good.confidence);
}

TEST(DepthVerification, InvalidParametersNameTheField) {
  DepthVerificationParams p;
  p.noise_sigmas = 0.f;
  try {
    p.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("noise_sigmas"), std::string::npos) << e.what();
  }
  PinholeIntrinsics k;
  k.fx = -1.f;
  EXPECT_THROW(k.validate(), std::invalid_argument);
}

}  // namespace
