// The pose verification's terms (pose_verification.h; doc/icf.md section 6) on a case built by
// hand, where each term is known without running the measurement: a 20 x 20 x 10 cm box 1 m in
// front of the camera, and scene points on a 5 mm grid over the face it shows, lifted off that
// face by chosen distances. Visible are exactly that face's surface samples; a point's distance
// to the model is its lift; the inliers, their RMSE and the far points follow by counting; the
// coverage follows from the grid spacing. The same numbers must come out wherever the scene
// lies (a rigid motion of scene, camera and pose together changes nothing but rounding).
#include "synthetic/synthetic_models.h"

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/verification/pose_verification.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <vector>

namespace {

using pcl::icf::IcfModel;
using pcl::icf::PoseQuality;

constexpr float kInlier = 0.005f;  // inlier and coverage radius
constexpr float kGate = 0.027f;    // the thesis's far-point distance

/** The box's model -> scene pose: its -z face (the one towards the camera at the origin) at
 * z = 0.95 m. */
Eigen::Isometry3f boxPose() {
  return Eigen::Isometry3f(Eigen::Translation3f(0.f, 0.f, 1.f));
}

/** Scene points on a 5 mm grid over the whole shown face (x, y in [-0.1, 0.1], 41 x 41),
 * each moved towards the camera by lift(x) (scene frame). */
std::vector<Eigen::Vector3f> gridOnFace(const std::function<float(float)>& lift) {
  std::vector<Eigen::Vector3f> points;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) {
      const float x = 0.005f * static_cast<float>(i), y = 0.005f * static_cast<float>(j);
      points.emplace_back(x, y, 0.95f - lift(x));
    }
  return points;
}

PoseQuality measure(const IcfModel& model, const std::vector<Eigen::Vector3f>& points,
                    const Eigen::Isometry3f& model_to_scene, const Eigen::Vector3f& camera) {
  return pcl::icf::measurePoseQuality(model, points, model_to_scene.inverse(), camera, kInlier,
                                      kGate, {}, {});
}

/** Surface samples of the box on its -z face (model frame), and how many of them have
 * x >= \a min_x. */
std::size_t frontSamples(const IcfModel& model, float min_x = -1.f) {
  std::size_t n = 0;
  for (const auto& s : model.samples())
    n += s.normal.z() < -0.99f && s.point.x() >= min_x;
  return n;
}

class PoseVerificationByHand : public ::testing::Test {
 protected:
  void SetUp() override { model_ = IcfModel::build(pcl::icf::synthetic::makeBox(0.2, 0.2, 0.1)); }
  IcfModel::ConstPtr model_;
};

TEST_F(PoseVerificationByHand, PointsOnTheFaceExplainAllOfIt) {
  const auto points = gridOnFace([](float) { return 0.f; });
  const PoseQuality q = measure(*model_, points, boxPose(), Eigen::Vector3f::Zero());
  // Visible: the face towards the camera, all of it (the side faces are seen edge-on, below
  // min_view_cosine; the back face faces away).
  EXPECT_EQ(q.visible_samples, frontSamples(*model_));
  EXPECT_GT(q.visible_samples, 500u);  // a quarter of the area of 4000 samples
  EXPECT_EQ(q.inliers, points.size());
  EXPECT_EQ(q.inlier_ratio, 1.0);
  // Distances are zero up to float rounding of coordinates near 1 m (6e-8 m).
  EXPECT_LE(q.rmse, 1e-6);
  EXPECT_EQ(q.far_points, 0);
  // Every sample lies within half a grid diagonal (3.5 mm < 5 mm) of a point.
  EXPECT_EQ(q.surface_coverage, 1.0);
  // The thesis's F counts a point at distance 0 as 1 (eq. 1).
  EXPECT_NEAR(q.thesis_score, static_cast<double>(points.size()), 1e-3);
  EXPECT_EQ(q.seen_through, 0.0);  // measured by estimatePose only
}

TEST_F(PoseVerificationByHand, LiftedPointsGiveTheirLiftAsRmseAndFarPointsCount) {
  // Points over x >= 0 lifted 3 mm (inliers), over x < 0 lifted 8 mm (not inliers), and 25
  // strays 5 cm in front of the face (beyond the 27 mm gate).
  auto points = gridOnFace([](float x) { return x >= 0.f ? 0.003f : 0.008f; });
  const std::size_t near = 21 * 41;  // the columns x = 0 ... 0.1
  for (int k = 0; k < 25; ++k)
    points.emplace_back(0.004f * static_cast<float>(k - 12), 0.01f, 0.90f);
  const PoseQuality q = measure(*model_, points, boxPose(), Eigen::Vector3f::Zero());
  EXPECT_EQ(q.inliers, near);
  EXPECT_DOUBLE_EQ(q.inlier_ratio, static_cast<double>(near) / static_cast<double>(points.size()));
  // Every inlier lies 3 mm off (a point over an edge, too: its closest point is on the edge);
  // 1e-6 m covers the float rounding of 0.947 and of the distance.
  EXPECT_NEAR(q.rmse, 0.003, 1e-6);
  EXPECT_EQ(q.far_points, 25);
  // Covered: every sample with x >= 0 (a 3 mm point within 3.5 mm sideways: 4.6 mm < 5 mm);
  // none with x < -4 mm (the 3 mm points are 4 mm or more sideways: 5 mm or more; the 8 mm
  // points never reach). Between, the strip x in [-4, 0) mm may go either way.
  const auto n = static_cast<double>(frontSamples(*model_));
  EXPECT_GE(q.surface_coverage, static_cast<double>(frontSamples(*model_, 0.f)) / n);
  EXPECT_LE(q.surface_coverage, static_cast<double>(frontSamples(*model_, -0.004f)) / n);
}

TEST_F(PoseVerificationByHand, TheSameWhereverTheSceneLies) {
  // A rigid motion W of the scene, the camera and the pose together: the verification measures
  // only relative geometry. The counts must agree exactly: the move rounds coordinates by about
  // 1e-7 m, which could flip only a point or sample lying that close to the 5 mm or 27 mm
  // radius (the lifts keep 2 mm from them; of the 1000 seeded samples, none in the strip
  // x in [-4, 0) mm lies that close); the RMSE up to that rounding.
  const auto points = gridOnFace([](float x) { return x >= 0.f ? 0.003f : 0.008f; });
  const PoseQuality here = measure(*model_, points, boxPose(), Eigen::Vector3f::Zero());
  Eigen::Isometry3f w = Eigen::Isometry3f::Identity();
  w.rotate(Eigen::AngleAxisf(2.1f, Eigen::Vector3f(0.2f, -0.7f, 0.4f).normalized()));
  w.pretranslate(Eigen::Vector3f(0.3f, -1.2f, 0.5f));
  std::vector<Eigen::Vector3f> moved;
  for (const auto& p : points)
    moved.push_back(w * p);
  const PoseQuality there = measure(*model_, moved, w * boxPose(), w * Eigen::Vector3f::Zero());
  EXPECT_EQ(there.inliers, here.inliers);
  EXPECT_EQ(there.far_points, here.far_points);
  EXPECT_EQ(there.visible_samples, here.visible_samples);
  EXPECT_NEAR(there.rmse, here.rmse, 1e-6);
  EXPECT_NEAR(there.surface_coverage, here.surface_coverage, 1e-12);
}

}  // namespace
