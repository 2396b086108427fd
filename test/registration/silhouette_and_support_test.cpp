// Two cues of the depth verification against geometry known by construction: where the scene's
// occluding edge lies beside the model's silhouette (DepthExplanation::silhouette_offset) for a
// model of the object's own size and for one a few per cent larger or smaller, rendered by the
// test support's ray caster; and how deep a model sinks into the table it stands on
// (DepthExplanation::sunk_into_support) for a pose moved a known distance into it.
#include "synthetic/depth_camera.h"
#include "synthetic/mesh_geometry.h"
#include "synthetic/synthetic_models.h"

#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace {

using namespace pcl::icf;

/** \a mesh with every vertex scaled by \a factor about the origin (its centre). */
pcl::PolygonMesh scaled(const pcl::PolygonMesh& mesh, float factor) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2(mesh.cloud, cloud);
  for (auto& p : cloud)
    p.getVector3fMap() *= factor;
  pcl::PolygonMesh out = mesh;
  pcl::toPCLPointCloud2(cloud, out.cloud);
  return out;
}

TEST(DepthImage, SupportHullContainsTheFeetOfPointsAboveIt) {
  std::vector<Eigen::Vector3f> points(4, Eigen::Vector3f(0.f, 0.f, 1.f));
  DepthImage image(points, PinholeIntrinsics());
  EXPECT_FALSE(image.hasSupportPlane());
  EXPECT_FALSE(image.overSupport(Eigen::Vector3f(0.f, 0.f, 0.9f)));
  // The plane z = 1 (normal away from the camera: turned towards it), a 1 m square about the
  // optical axis, its vertices given clockwise as seen from the camera.
  const std::vector<Eigen::Vector3f> square = {
      {-0.5f, -0.5f, 1.f}, {-0.5f, 0.5f, 1.f}, {0.5f, 0.5f, 1.f}, {0.5f, -0.5f, 1.f}};
  image.setSupportPlane(Eigen::Vector4f(0.f, 0.f, 1.f, -1.f), square);
  ASSERT_TRUE(image.hasSupportPlane());
  EXPECT_FLOAT_EQ(image.supportPlane()[2], -1.f);
  EXPECT_FLOAT_EQ(image.supportPlane()[3], 1.f);
  EXPECT_TRUE(image.overSupport(Eigen::Vector3f(0.1f, -0.2f, 0.7f)));    // above, inside
  EXPECT_TRUE(image.overSupport(Eigen::Vector3f(0.4f, 0.4f, 1.2f)));     // beneath, inside
  EXPECT_FALSE(image.overSupport(Eigen::Vector3f(0.6f, 0.f, 0.9f)));     // beyond an edge
  EXPECT_FALSE(image.overSupport(Eigen::Vector3f(-0.3f, -0.7f, 0.9f)));  // beyond another
  // The same square counter-clockwise: the same inside.
  const std::vector<Eigen::Vector3f> reversed(square.rbegin(), square.rend());
  image.setSupportPlane(Eigen::Vector4f(0.f, 0.f, -1.f, 1.f), reversed);
  EXPECT_TRUE(image.overSupport(Eigen::Vector3f(0.1f, -0.2f, 0.7f)));
  EXPECT_FALSE(image.overSupport(Eigen::Vector3f(0.6f, 0.f, 0.9f)));

  EXPECT_THROW(image.setSupportPlane(Eigen::Vector4f(0.f, 0.f, 2.f, -1.f), square),
               std::invalid_argument);
  EXPECT_THROW(image.setSupportPlane(Eigen::Vector4f(0.f, 0.f, 1.f, -1.f), {square[0], square[1]}),
               std::invalid_argument);
  EXPECT_THROW(image.setSupportPlane(Eigen::Vector4f(0.f, 0.f, 1.f, std::nanf("")), square),
               std::invalid_argument);
}

/** A 4.5 cm can standing upright 0.8 m in front of the camera, a wall 0.3 m behind it, rendered
 * without noise: the can's occluding edges step back to the wall. */
struct CanBeforeAWall {
  pcl::PolygonMesh can = synthetic::makeCylinder(0.045, 0.13, 48);
  pcl::PolygonMesh wall = synthetic::makePlane(1.5, 1.2);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  DepthImage image;
};

CanBeforeAWall canBeforeAWall() {
  CanBeforeAWall c;
  // The can's axis along the camera's y (upright), tilted 20 degrees towards the camera.
  Eigen::Isometry3d can_pose = Eigen::Isometry3d::Identity();
  can_pose.linear() = (Eigen::AngleAxisd(-M_PI / 2 + 0.35, Eigen::Vector3d::UnitX()) *
                       Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()))
                          .toRotationMatrix();
  can_pose.translation() = Eigen::Vector3d(0.02, 0.01, 0.8);
  Eigen::Isometry3d wall_pose = Eigen::Isometry3d::Identity();
  wall_pose.translation() = Eigen::Vector3d(0.0, 0.0, 1.1);
  synthetic::SceneObject can{&c.can, can_pose, Eigen::Vector3f::Ones(), 1};
  synthetic::SceneObject wall{&c.wall, wall_pose, Eigen::Vector3f::Ones(), 2};
  const synthetic::Scan scan = synthetic::renderScan({can, wall}, synthetic::CameraIntrinsics(),
                                                     synthetic::ScanNoise::none());
  c.pose = can_pose.cast<float>();
  c.image = DepthImage(synthetic::scanPoints(scan), PinholeIntrinsics());
  return c;
}

// The right model's silhouette lies on the scene's edge: within a quarter of a pixel on average
// (the rasteriser and the ray caster sample the same pixel centres; an edge pixel is the
// object's or the wall's, half a pixel either way, alike on every side). A model 6% larger in
// every direction posed there overhangs the can by 6% of its half-size, 1.6 (sides) to 2.2
// (ends) pixels at 0.8 m: the edge lies inside its silhouette, offset below -1; one 6% smaller
// leaves the can's surface going on past its silhouette, offset above +1. Both beyond twice
// edge_offset_pixels plus two standard errors: the factor is 0.
TEST(DepthVerification, SilhouetteOffsetIsTheSizeDifferenceInPixels) {
  const CanBeforeAWall c = canBeforeAWall();
  const IcfModel::ConstPtr right = IcfModel::build(c.can);
  const IcfModel::ConstPtr larger = IcfModel::build(scaled(c.can, 1.06f));
  const IcfModel::ConstPtr smaller = IcfModel::build(scaled(c.can, 0.94f));
  const DepthVerificationParams params;

  const DepthExplanation own = explainDepth(*right, c.pose, c.image, params);
  ASSERT_GT(own.silhouette_edges, 100u);
  EXPECT_LT(std::abs(own.silhouette_offset), 0.25);
  EXPECT_GT(own.confidence, 0.95);

  const DepthExplanation over = explainDepth(*larger, c.pose, c.image, params);
  ASSERT_GT(over.silhouette_edges, 50u);
  EXPECT_LT(over.silhouette_offset, -1.0);
  EXPECT_GT(over.silhouette_offset, -3.0);
  EXPECT_DOUBLE_EQ(
      params.edgeOffsetFactor(over.silhouette_offset, over.silhouette_edges, over.allowed_offset),
      0.0);
  EXPECT_LT(over.confidence, 0.05);

  const DepthExplanation under = explainDepth(*smaller, c.pose, c.image, params);
  ASSERT_GT(under.silhouette_edges, 50u);
  EXPECT_GT(under.silhouette_offset, 1.0);
  EXPECT_LT(under.silhouette_offset, 3.0);
  EXPECT_LT(under.confidence, 0.05);
}

// The factor's shape (edgeOffsetFactor): 1 up to the allowed offset, either sign; linear to 0
// at twice it; 1 whatever the offset when fewer than min_edge_pixels edges were found. And the
// allowance in pixels grows with the mesh's accuracy seen at the model's depth.
TEST(DepthVerification, EdgeOffsetFactorAndItsAllowance) {
  DepthVerificationParams p;
  EXPECT_DOUBLE_EQ(p.edgeOffsetFactor(0.5, 100, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(p.edgeOffsetFactor(-0.5, 100, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(p.edgeOffsetFactor(0.75, 100, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(p.edgeOffsetFactor(-1.0, 100, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(p.edgeOffsetFactor(-3.0, p.min_edge_pixels - 1, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(p.allowedEdgeOffset(1.f, 525.f), p.edge_offset_pixels);
  p.mesh_accuracy = 0.002f;  // 2 mm at 1 m through a 525-pixel focal length: 1.05 pixels
  EXPECT_NEAR(p.allowedEdgeOffset(1.f, 525.f), p.edge_offset_pixels + 1.05, 1e-6);
  EXPECT_NEAR(p.allowedEdgeOffset(0.5f, 525.f), p.edge_offset_pixels + 2.1, 1e-6);
  // The mesh's accuracy adds to the sensor's pixel noise and low-frequency error where the fit
  // is judged, in quadrature.
  EXPECT_NEAR(p.fitSigma(1.f),
              std::sqrt(std::pow(p.noise.sigma(1.f), 2.f) +
                        std::pow(p.noise.systematicError(1.f), 2.f) + 0.002f * 0.002f),
              1e-7);
  EXPECT_NEAR(p.noise.systematicError(2.f), 4.f * p.noise.systematic, 1e-9);
}

/** Box5 standing on a 1.2 x 0.8 m table 0.6 m below a camera tilted 45 degrees, no outliers;
 * the image has the table's pixels marked and the table as its support (its four corners). */
struct BoxOnATable {
  synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  synthetic::TabletopScene scene;
  std::vector<Eigen::Vector3f> points;
  DepthImage image;
  IcfModel::ConstPtr model;
};

BoxOnATable boxOnATable(const Eigen::Vector4f* plane_given = nullptr) {
  BoxOnATable b;
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  noise.seed = 9;
  b.scene = synthetic::makeTabletopScene({b.box}, {{0.05, 0.02, 0.4}},
                                         synthetic::CameraIntrinsics(), noise);
  b.points = synthetic::scanPoints(b.scene.scan);
  pcl::Indices table;
  for (std::size_t i = 0; i < b.points.size(); ++i)
    if (b.scene.scan.labels[i] == 0)
      table.push_back(static_cast<pcl::index_t>(i));
  b.image = DepthImage(b.points, PinholeIntrinsics());
  b.image.markBackground(b.points, table);
  std::vector<Eigen::Vector3f> corners;
  for (const auto& [x, y] : {std::pair{-0.6, -0.4}, {0.6, -0.4}, {0.6, 0.4}, {-0.6, 0.4}})
    corners.push_back((b.scene.table_to_camera * Eigen::Vector3d(x, y, 0.0)).cast<float>());
  b.image.setSupportPlane(plane_given ? *plane_given : b.scene.table_plane, corners);
  b.model = IcfModel::build(b.box.mesh);
  return b;
}

// The box at its pose rests on the table: it sinks by less than 3 mm (the rendered surface's
// lowest pixels lie on the table's edge with the box; the table's pixels carry 1.5 mm noise at
// 1 m). Moved 4 cm into the table along its normal, it sinks 4 cm (the deepest rendered pixel,
// within 5 mm: the box's lowest edge may be hidden behind its own faces by up to a pixel's
// footprint), beyond three support tolerances: factor 0. The same pose moved 45 cm further
// from the camera, past the table's far edge and as deep, lies beyond the table's hull:
// nothing to sink into there.
TEST(DepthVerification, AModelSunkIntoItsSupportIsMeasuredAndRefused) {
  const BoxOnATable b = boxOnATable();
  const DepthVerificationParams params;
  const Eigen::Isometry3f right = b.scene.poses.front().cast<float>();
  const Eigen::Vector3f up = b.scene.table_plane.head<3>();
  const DepthExplanation rests = explainDepth(*b.model, right, b.image, params);
  EXPECT_LT(rests.sunk_into_support, 0.003);
  EXPECT_DOUBLE_EQ(params.sinkFactor(rests.sunk_into_support, rests.support_tolerance), 1.0);
  EXPECT_GT(rests.confidence, 0.9);

  Eigen::Isometry3f sunk = right;
  sunk.translation() -= 0.04f * up;
  const DepthExplanation through = explainDepth(*b.model, sunk, b.image, params);
  EXPECT_NEAR(through.sunk_into_support, 0.04, 0.005);
  EXPECT_GT(through.sunk_into_support, 3.0 * through.support_tolerance);
  EXPECT_DOUBLE_EQ(params.sinkFactor(through.sunk_into_support, through.support_tolerance), 0.0);
  EXPECT_DOUBLE_EQ(through.confidence, 0.0);

  Eigen::Isometry3f beyond = sunk;
  beyond.translation() += 0.45f * b.scene.table_to_camera.linear().col(1).cast<float>();
  const DepthExplanation off_the_table = explainDepth(*b.model, beyond, b.image, params);
  ASSERT_GT(off_the_table.model_pixels, 100u);
  EXPECT_DOUBLE_EQ(off_the_table.sunk_into_support, 0.0);
}

// The depth is measured from the plane through the table's own pixels around the model, not
// from the support plane as given: a plane given 1 cm too high (a table whose far end bends up
// towards the camera, as a real sensor's low-frequency error makes it) does not sink a box
// that rests on the table where it stands.
TEST(DepthVerification, SinkingIsMeasuredFromTheTableAroundTheModel) {
  const BoxOnATable truth = boxOnATable();
  Eigen::Vector4f too_high = truth.scene.table_plane;
  too_high[3] -= 0.01f;  // n.x + d = 0 one centimetre nearer the camera along n
  const BoxOnATable b = boxOnATable(&too_high);
  const DepthExplanation rests =
      explainDepth(*b.model, b.scene.poses.front().cast<float>(), b.image);
  EXPECT_LT(rests.sunk_into_support, 0.003);
}

}  // namespace
