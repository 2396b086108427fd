// The localizer on synthetic table-top scenes shaped like the thesis's scenarios (chapter 6):
// the target must be found in the right cluster at the right pose, among distractors that
// beat it on point count; scenario 6, where the thesis failed, with the colour cue. Real data:
// the YCB-Video frame, whose four objects touch and merge into one cluster.
#include "real_truth.h"
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_clutter.h"
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/common/transforms.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/localization/pose_alternatives.h>
#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace {

using namespace pcl::icf;
using pcl::icf::localization::LocalizationStatus;
using pcl::icf::localization::LocalizerParams;

struct Scenario {
  std::string name;
  std::vector<std::string> objects;  // the first is the target
  std::vector<Eigen::Vector3d> placements;
  bool use_colour = false;
};

/** Label (1-based object index) most of the cluster's points carry in the rendered scan. */
int majorityLabel(const std::vector<int>& labels, const pcl::PointIndices& cluster) {
  std::map<int, int> votes;
  for (const auto i : cluster.indices)
    ++votes[labels[static_cast<std::size_t>(i)]];
  int best = -1, count = -1;
  for (const auto& kv : votes)
    if (kv.second > count) {
      best = kv.first;
      count = kv.second;
    }
  return best;
}

synthetic::SyntheticModel scenarioModel(const std::string& name) {
  if (name == "BigBox")
    return {"BigBox", synthetic::makeBox(0.22, 0.15, 0.09),
            synthetic::Symmetry::box(0.22, 0.15, 0.09), Eigen::Vector3f(0.2f, 0.6f, 0.2f)};
  return synthetic::thesisModel(name);
}

/** The real scene at \a path (empty, with a failure, when it cannot be read). */
pcl::PointCloud<pcl::PointXYZRGB> loadScene(const std::string& path) {
  pcl::PointCloud<pcl::PointXYZRGB> scene;
  EXPECT_EQ(pcl::io::loadPCDFile(path, scene), 0) << path;
  return scene;
}

class ThesisScenarios : public ::testing::TestWithParam<Scenario> {};

// Tolerances: the target stands upright, seen from 0.6 m at 45 degrees with the Kinect-like
// noise; 5 mm and 3 degrees as for single clusters.
TEST_P(ThesisScenarios, FindsTheTargetInTheRightClusterAtTheRightPose) {
  const Scenario& s = GetParam();
  std::vector<synthetic::SyntheticModel> models;
  for (const auto& name : s.objects)
    models.push_back(scenarioModel(name));
  // Sensor noise as in the single-cluster tests, without their 5% uniform outliers: spread
  // over the whole table they would chain every object into one cluster at the thesis's 2 cm
  // tolerance, which no real depth camera does (its outliers sit at depth edges).
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const synthetic::TabletopScene scene =
      synthetic::makeTabletopScene(models, s.placements, synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(models.front().mesh);
  LocalizerParams params;
  if (s.use_colour)
    params.colour.expected = models.front().rgb;
  const auto result = localization::localizeObject(*scene.scan.cloud, *model, params);
  for (std::size_t k = 0; k < result.clusters.size(); ++k) {
    const auto& c = result.clusters[k];
    std::cout << s.name << " cluster " << k << " (label "
              << majorityLabel(scene.scan.labels, c.indices) << ", " << c.indices.indices.size()
              << " points): score " << c.score << ", coverage " << c.icf.quality.surface_coverage
              << ", inliers " << c.icf.quality.inlier_ratio << ", rmse " << 1e3 * c.icf.quality.rmse
              << " mm, confidence " << c.verification.confidence << " (support "
              << c.verification.visible_support << ", seen through " << c.verification.seen_through
              << ", continuation " << c.verification.silhouette_continuation << ", supported "
              << c.verification.supported << "), gate " << c.gate_far_points
              << (c.colour_similarity ? ", colour " + std::to_string(*c.colour_similarity) : "")
              << (c.accepted ? " ACCEPTED" : " rejected: " + c.reason) << "\n";
  }
  ASSERT_EQ(result.status, LocalizationStatus::Found) << result.message;
  ASSERT_EQ(result.segmentation.clusters.size(), s.objects.size()) << "one cluster per object";
  const auto& best = result.clusters[static_cast<std::size_t>(result.best)];
  EXPECT_EQ(majorityLabel(scene.scan.labels, best.indices), 1) << "the target's cluster";
  const auto error = synthetic::poseError(Eigen::Isometry3d(best.icf.object_pose.cast<double>()),
                                          scene.poses.front(), models.front().symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
}

INSTANTIATE_TEST_SUITE_P(
    Localizer, ThesisScenarios,
    ::testing::Values(
        Scenario{"S1_box_cup_statue",
                 {"Box5", "Cup", "Statue"},
                 {{0.0, 0.0, 0.4}, {-0.2, 0.05, 0.0}, {0.2, -0.03, 0.7}}},
        Scenario{
            "S2_small_box_big_box", {"Box5", "BigBox"}, {{-0.12, 0.0, 0.3}, {0.14, 0.02, -0.2}}},
        Scenario{"S3_salt_box", {"YellowRoundSalt", "Box5"}, {{-0.1, 0.0, 0.0}, {0.12, 0.0, 0.5}}},
        Scenario{"S4_salt_cup_box",
                 {"YellowRoundSalt", "Cup", "Box5"},
                 {{0.0, 0.0, 0.0}, {-0.17, 0.0, 0.0}, {0.18, 0.03, 1.0}}},
        Scenario{
            "S5_hexprism_cylinder", {"Amicelly", "EisKaffe"}, {{-0.1, 0.0, 0.3}, {0.1, 0.0, 0.0}}},
        Scenario{"S6_cylinder_hexprism_colour",
                 {"EisKaffe", "Amicelly"},
                 {{0.1, 0.0, 0.0}, {-0.1, 0.0, 0.3}},
                 true}),
    [](const auto& info) { return info.param.name; });

TEST(Localizer, BadScenesGiveAStatus) {
  const IcfModel::ConstPtr model = IcfModel::build(synthetic::thesisModel("Box5").mesh);
  pcl::PointCloud<pcl::PointXYZ> empty;
  EXPECT_EQ(localization::localizeObject(empty, *model).status, LocalizationStatus::BadScene);
  pcl::PointCloud<pcl::PointXYZ> three;
  for (int i = 0; i < 3; ++i)
    three.push_back(pcl::PointXYZ(0.01f * i, 0.f, 1.f));
  const auto r = localization::localizeObject(three, *model);
  EXPECT_NE(r.status, LocalizationStatus::Found);
  EXPECT_FALSE(r.message.empty());
  LocalizerParams whole;
  whole.segment = false;  // a 3-point "cluster": too few points, a status not a crash
  const auto w = localization::localizeObject(three, *model, whole);
  EXPECT_EQ(w.status, LocalizationStatus::NotFound);
  EXPECT_TRUE(w.clusters.empty());
  EXPECT_NE(w.message.find("no hypothesis"), std::string::npos) << w.message;
}

// Any camera frame: the scene of scenario S1 moved rigidly into a "robot base" frame, with the
// camera pose given, must give the same cluster and the same pose up to the move. Tolerance:
// the moved cloud is rounded to float in the new frame and moved back, so points differ from the
// original by about 1e-7 m; the pose may follow by a few times that, far below 1e-4 m / 0.01 deg.
TEST(Localizer, SameAnswerInAnyCameraFrame) {
  const std::vector<synthetic::SyntheticModel> models = {synthetic::thesisModel("Box5"),
                                                         synthetic::thesisModel("Cup"),
                                                         synthetic::thesisModel("Statue")};
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const synthetic::TabletopScene scene =
      synthetic::makeTabletopScene(models, {{0.0, 0.0, 0.4}, {-0.2, 0.05, 0.0}, {0.2, -0.03, 0.7}},
                                   synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(models.front().mesh);
  LocalizerParams params;
  params.threads = 1;
  const auto in_camera = localization::localizeObject(*scene.scan.cloud, *model, params);
  ASSERT_EQ(in_camera.status, LocalizationStatus::Found) << in_camera.message;

  // A camera 1.2 m up on a robot, looking forward and down, as TF would give it.
  Eigen::Isometry3f camera_to_base = Eigen::Isometry3f::Identity();
  camera_to_base.linear() = (Eigen::AngleAxisf(0.7f, Eigen::Vector3f::UnitZ()) *
                             Eigen::AngleAxisf(-2.2f, Eigen::Vector3f::UnitX()))
                                .toRotationMatrix();
  camera_to_base.translation() = Eigen::Vector3f(0.3f, -0.1f, 1.2f);
  pcl::PointCloud<pcl::PointXYZRGB> in_base;
  pcl::transformPointCloud(*scene.scan.cloud, in_base, camera_to_base.matrix());
  params.camera_pose = camera_to_base;
  const auto moved = localization::localizeObject(in_base, *model, params);
  ASSERT_EQ(moved.status, LocalizationStatus::Found) << moved.message;
  EXPECT_EQ(moved.best, in_camera.best);
  EXPECT_TRUE(moved.camera_pose.isApprox(camera_to_base));
  const Eigen::Isometry3d expected(
      (camera_to_base.matrix() *
       in_camera.clusters[static_cast<std::size_t>(in_camera.best)].icf.object_pose)
          .cast<double>());
  const Eigen::Isometry3d got(
      moved.clusters[static_cast<std::size_t>(moved.best)].icf.object_pose.cast<double>());
  // Box5 is symmetric: a flip explains the depth exactly as well, and a 1e-7 m change of the
  // points may choose the other one; modulo the symmetry the poses must agree.
  const auto error = synthetic::poseError(got, expected, models.front().symmetry);
  EXPECT_LE(error.translation, 1e-4);
  EXPECT_LE(error.rotation_deg, 0.01);
  // The table plane in the base frame: the table points lie on it.
  const Eigen::Vector4f plane = moved.segmentation.plane.coefficients;
  const auto& table_point = in_base[static_cast<std::size_t>(moved.segmentation.plane.inliers[0])];
  EXPECT_NEAR(plane.head<3>().dot(table_point.getVector3fMap()) + plane[3], 0.f, 0.01f);
  // Without the camera pose the camera would be taken at the base frame's origin.
  params.camera_pose.reset();
  in_base.sensor_origin_.head<3>() = camera_to_base.translation();
  in_base.sensor_orientation_ = Eigen::Quaternionf(camera_to_base.linear());
  const auto from_viewpoint = localization::localizeObject(in_base, *model, params);
  ASSERT_EQ(from_viewpoint.status, LocalizationStatus::Found) << "VIEWPOINT honoured";
  EXPECT_EQ(from_viewpoint.best, moved.best);
  // The orientation went through a float quaternion: the same rounding argument as above, and
  // the same tolerance modulo Box5's symmetry (clang's TSan build chose the other flip).
  const auto viewpoint_error = synthetic::poseError(
      Eigen::Isometry3d(from_viewpoint.clusters[static_cast<std::size_t>(from_viewpoint.best)]
                            .icf.object_pose.cast<double>()),
      got, models.front().symmetry);
  EXPECT_LE(viewpoint_error.translation, 1e-4);
  EXPECT_LE(viewpoint_error.rotation_deg, 0.01);
}

TEST(Localizer, BadCameraPosesAreRefused) {
  const IcfModel::ConstPtr model = IcfModel::build(synthetic::thesisModel("Box5").mesh);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (int i = 0; i < 100; ++i)
    cloud.push_back(pcl::PointXYZ(0.01f * (i % 10), 0.01f * (i / 10), 1.f));
  LocalizerParams params;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation().x() = std::numeric_limits<float>::quiet_NaN();
  params.camera_pose = pose;
  EXPECT_THROW(localization::localizeObject(cloud, *model, params), std::invalid_argument);
  pose = Eigen::Isometry3f::Identity();
  pose.linear() *= 2.f;  // a scale, not a rotation
  params.camera_pose = pose;
  EXPECT_THROW(localization::localizeObject(cloud, *model, params), std::invalid_argument);
  // A camera turned the wrong way: every point behind it.
  pose = Eigen::Isometry3f(Eigen::AngleAxisf(static_cast<float>(M_PI), Eigen::Vector3f::UnitY()));
  params.camera_pose = pose;
  const auto r = localization::localizeObject(cloud, *model, params);
  EXPECT_EQ(r.status, LocalizationStatus::BadScene);
  EXPECT_NE(r.message.find("behind the camera"), std::string::npos) << r.message;
}

// The same table top with the camera mirrored below the table (looking up at it): the box
// stands on the table's far side from that camera, hidden from it by the table top, so the
// camera pose must be wrong: BadScene naming the table's side, never "not found".
TEST(Localizer, ACameraBelowTheTableIsRefused) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const synthetic::TabletopScene scene =
      synthetic::makeTabletopScene({box}, {{0.0, 0.0, 0.4}}, synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  const Eigen::Vector3f n = scene.table_plane.head<3>();
  const Eigen::Vector3f below = -2.f * scene.table_plane[3] * n;  // the origin mirrored
  const Eigen::Vector3f forward =
      (scene.table_to_camera.translation().cast<float>() - below).normalized();
  Eigen::Matrix3f r;
  r.col(2) = forward;
  r.col(0) = forward.unitOrthogonal();
  r.col(1) = r.col(2).cross(r.col(0));
  LocalizerParams params;
  params.camera_pose = Eigen::Translation3f(below) * Eigen::Isometry3f(r);
  const auto result = localization::localizeObject(*scene.scan.cloud, *model, params);
  EXPECT_EQ(result.status, LocalizationStatus::BadScene) << result.message;
  EXPECT_NE(result.message.find("wrong side of the table"), std::string::npos) << result.message;
  // The right camera finds the box.
  EXPECT_EQ(localization::localizeObject(*scene.scan.cloud, *model).status,
            LocalizationStatus::Found);
}

// A small neighbour touching the target: one Euclidean cluster in which the neighbour holds a
// few per cent of the points, too few to move the 90th-percentile spread around the robust
// centroid, so the cluster may count as a single object; the target must still be found at
// its pose (5 mm / 3 degrees, as for the scenarios above) whichever way the cluster is judged.
TEST(Localizer, TargetWithASmallTouchingNeighbour) {
  const synthetic::SyntheticModel salt = synthetic::thesisModel("YellowRoundSalt");
  const synthetic::SyntheticModel cube{"Cube3cm", synthetic::makeBox(0.03, 0.03, 0.03),
                                       synthetic::Symmetry::box(0.03, 0.03, 0.03),
                                       Eigen::Vector3f(0.8f, 0.1f, 0.1f)};
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;  // as in the scenarios above
  // Salt radius 4.5 cm at x = 0; the cube's near face at x = 0.046: 1 mm apart.
  const synthetic::TabletopScene scene = synthetic::makeTabletopScene(
      {salt, cube}, {{0.0, 0.0, 0.0}, {0.061, 0.0, 0.0}}, synthetic::CameraIntrinsics(), noise);
  std::size_t salt_points = 0, cube_points = 0;
  for (const int label : scene.scan.labels) {
    salt_points += label == 1;
    cube_points += label == 2;
  }
  ASSERT_GT(cube_points, 0u);
  const IcfModel::ConstPtr model = IcfModel::build(salt.mesh);
  const auto result = localization::localizeObject(*scene.scan.cloud, *model);
  ASSERT_EQ(result.status, LocalizationStatus::Found)
      << result.message << " (salt " << salt_points << " points, cube " << cube_points << ")";
  // The premise: segmentation put both objects into one cluster.
  bool merged = false;
  for (const auto& cluster : result.segmentation.clusters) {
    std::set<int> labels;
    for (const auto i : cluster.indices)
      labels.insert(scene.scan.labels[static_cast<std::size_t>(i)]);
    merged = merged || (labels.count(1) && labels.count(2));
  }
  EXPECT_TRUE(merged) << "the cube should touch the salt within the 2 cm cluster tolerance";
  std::cout << "salt " << salt_points << " points, cube " << cube_points << " ("
            << 100.0 * cube_points / (salt_points + cube_points) << "%), " << result.clusters.size()
            << " candidates\n";
  const auto& best = result.clusters[static_cast<std::size_t>(result.best)];
  EXPECT_EQ(majorityLabel(scene.scan.labels, best.indices), 1);
  const auto error = synthetic::poseError(Eigen::Isometry3d(best.icf.object_pose.cast<double>()),
                                          scene.poses.front(), salt.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
}

// The clutter suite's desk 61 (pcl_icf_make_dataset --kind clutter --seed 2018, its 62nd desk:
// EisKaffe, a can of r 5 cm and h 15 cm, standing 50-75% visible among 10-25 objects). Its
// segment holds a few of a neighbour's points too, and the global search's best hypotheses were
// all the same pose, the can lying on its side, spun about its axis: each spin counted as a
// distinct hypothesis, the 12 kept were copies of one wrong pose and the upright one was left
// out (39 mm off, 41% of it seen through; a look-alike 18 cm away was posed instead). With the
// spins counted as one pose (GlobalSearchParams::distinct_surface) the upright can is found, within
// 1 cm / 5 degrees of the generator's ground truth (the bar; symmetry-aware); the control
// without it is not. Both search the clusters only (the cluster search is the unit under test);
// the default hypotheses (point pair voting and the ranking) find it too.
TEST(Localizer, ASymmetricTargetsSpinsAreOneHypothesis) {
  // The desk as numbers (its ClutterScene::layout and view as the release build draws it), so
  // that no build's floating-point rounding in the draws gives another desk.
  struct Placed {
    const char* name;
    double x, y, yaw, base;
    bool stacked, background;
  };
  const Placed desk_61[] = {
      {"EisKaffe", 0.31146968083528881, -0.059534649657571895, 2.937464842124621, 0, false, false},
      {"WideCylinder", 0.38819418190543681, -0.24729849553980898, -2.1842820875045801, 0, false,
       false},
      {"Amicelly", 0.38113438736511412, -0.24331165134779467, -2.2664077083081797,
       0.10000000149011612, true, false},
      {"YellowRoundSalt", 0.50047284809992321, -0.16949010000659148, -1.952452209563553, 0, false,
       false},
      {"Amicelly", -0.31852275147206893, -0.11580073713758106, -2.1287065476735756, 0, false,
       false},
      {"Statue", 0.26471752338936705, -0.31221414987619089, -0.56168986093338269, 0, false, false},
      {"WideCylinder", 0.10439439058462403, -0.037397493454220769, 1.1782102611388368, 0, false,
       false},
      {"WideCylinder", -0.35229913569550542, -0.23843007736015065, -0.68508003901029468, 0, false,
       false},
      {"Statue", -0.35374097939523191, -0.24803799675903745, -2.4486895999585139,
       0.10000000149011612, true, false},
      {"Statue", 0.5031680658022023, -0.16869383582368958, -3.0931307374911259, 0.12999999523162842,
       true, false},
      {"Statue", -0.19691838428943392, -0.1299101048696924, 1.1510154783491853, 0, false, false},
      {"TallCylinder", -0.0086691405420260548, -0.29242353739899762, -2.1547716532109451, 0, false,
       false},
      {"WideCylinder", 0.19924773981351163, -0.19694599535530616, 1.2493333839062775, 0, false,
       false},
      {"YellowRoundSalt", 0.22449280799382731, 0.045071174903278256, 1.462471250632488, 0, false,
       false},
      {"YellowRoundSalt", -0.46496115994970111, -0.15624518657307099, 2.8696171295664605, 0, false,
       false},
      {"YellowRoundSalt", 0.20283464729896922, -0.18990202305436299, 1.0691838010179042,
       0.10000000149011612, true, false},
      {"WideCylinder", 0.16372553932532824, 0.19527526911446449, -1.4065348700042624, 0, false,
       false},
      {"Cup", 0.029630830565884413, -0.18119665674232061, 1.7137406565135134, 0, false, false},
      {"Statue", 0.43868325666100744, 0.072783536403091278, 1.3323221586309373, 0, false, false},
      {"Statue", -0.51756628857691489, 0.29868483040962496, -0.91288731296258163, 0, false, false},
      {"OtherBox", 0.32108493308098451, 0.22425926784005573, -1.1710581477581119, 0, false, false},
      {"WideCylinder", -0.12571253098697902, 0.25305689056498865, -0.18532723235906756, 0, false,
       false},
      {"Statue", 0.44132017840087445, 0.56142007810282146, -2.5243834848980788, 0.14999999999999999,
       false, true},
      {"YellowRoundSalt", 0.13372564323859032, 0.58557110193648088, -1.0328658083534346,
       0.14999999999999999, false, true},
      {"OtherBox", -0.037673720596081858, 0.61974443866816054, -2.1355320132146476,
       0.14999999999999999, false, true},
      {"Amicelly", -0.45243667113485214, 0.69060424123274999, -2.8460533038903506,
       0.14999999999999999, false, true},
      {"Statue", -0.36663264351627123, 0.53686997177480722, 0.64972304296868089,
       0.14999999999999999, false, true},
  };
  std::map<std::string, synthetic::SyntheticModel> models;
  std::vector<synthetic::DeskObject> layout;
  for (const auto& p : desk_61) {
    const auto& model = models.try_emplace(p.name, synthetic::suiteModel(p.name)).first->second;
    layout.push_back({&model, p.x, p.y, p.yaw, p.base, p.stacked, p.background});
  }
  synthetic::DeskView view;
  view.camera_height = 0.7342549702170158;
  view.camera_tilt = 48.874904167313233;
  view.noise.seed = 12398169537870514827u;
  view.edges.seed = 13847733632459249515u;
  const synthetic::ClutterScene desk = synthetic::renderClutterDesk(layout, view);
  const synthetic::SyntheticModel& target = models.at("EisKaffe");
  // The premise: the can 61% visible, as drawn (a few edge pixels may round otherwise).
  ASSERT_NEAR(desk.target_visible, 0.614, 0.01);
  const IcfModel::ConstPtr model = IcfModel::build(target.mesh);
  LocalizerParams defaults, params;
  params.tuning().hypotheses.point_pairs = false;
  params.tuning().hypotheses.clusters = true;
  LocalizerParams control = params;
  control.tuning().icf.tuning().global.distinct_surface = 0.f;
  const auto voted = localization::localizeObject(*desk.present.cloud, *model, defaults);
  const auto found = localization::localizeObject(*desk.present.cloud, *model, params);
  const auto missed = localization::localizeObject(*desk.present.cloud, *model, control);
  auto accurate = [&](const localization::Localization& r) {
    if (r.status != LocalizationStatus::Found)
      return false;
    const auto& best = r.clusters[static_cast<std::size_t>(r.best)];
    const auto e = synthetic::poseError(Eigen::Isometry3d(best.icf.object_pose.cast<double>()),
                                        desk.poses.front(), target.symmetry);
    std::cout << "visible " << desk.target_visible << ": " << 1e3 * e.translation << " mm, "
              << e.rotation_deg << " deg, confidence " << best.verification.confidence << "\n";
    return e.translation <= 0.01 && e.rotation_deg <= 5.0;
  };
  EXPECT_TRUE(accurate(voted)) << voted.message;
  EXPECT_TRUE(accurate(found)) << found.message;
  EXPECT_FALSE(accurate(missed)) << "the control found it: the premise is gone";
}

// rankInstances against a hand-made oracle: accepted clusters by score (ties by index), a
// cluster whose explained points are more than max_shared explained by a better instance
// dropped (a merged cluster and its segment), rejected ones never, at most max_instances.
TEST(Localizer, RanksInstancesEachPointInOneAtMost) {
  auto cluster = [](std::vector<pcl::index_t> points, double score, bool accepted) {
    localization::ClusterLocalization c;
    c.indices.indices = points;
    c.explained = std::move(points);
    c.score = score;
    c.accepted = accepted;
    return c;
  };
  const std::vector<localization::ClusterLocalization> clusters = {
      cluster({0, 1, 2, 3, 4, 5}, 0.70, true),  // merged: shares points with 2 and 3
      cluster({10, 11}, 0.95, false),           // the best score, but rejected
      cluster({3, 4, 5}, 0.90, true),           // segment of 0
      cluster({0, 1, 2}, 0.80, true),           // segment of 0
      cluster({20, 21}, 0.80, true),            // ties with 3: the lower index first
  };
  EXPECT_EQ(localization::rankInstances(clusters, 10), (std::vector<int>{2, 3, 4}));
  EXPECT_EQ(localization::rankInstances(clusters, 2), (std::vector<int>{2, 3}));
  EXPECT_EQ(localization::rankInstances(clusters, 1), (std::vector<int>{2}));
  // Cluster 0 shares 3 of its 6 points with 2: kept only when half may be shared.
  EXPECT_EQ(localization::rankInstances(clusters, 10, 0.5), (std::vector<int>{2, 3, 4, 0}));
}

// Two copies of one object on a table, apart and touching (1 cm apart: one Euclidean
// cluster at the 2 cm tolerance, split at its concave seam): with max_instances 2 both are
// reported, each at its own pose (5 mm / 3 degrees, as above); with the default 1 only the
// best.
class TwoCopies : public ::testing::TestWithParam<std::vector<Eigen::Vector3d>> {};

TEST_P(TwoCopies, GiveTwoInstances) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;  // as in the scenarios above
  const synthetic::TabletopScene scene =
      synthetic::makeTabletopScene({box, box}, GetParam(), synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  LocalizerParams params;
  params.max_instances = 2;
  const auto two = localization::localizeObject(*scene.scan.cloud, *model, params);
  std::ostringstream candidates;
  for (std::size_t k = 0; k < two.clusters.size(); ++k) {
    const auto& c = two.clusters[k];
    candidates << "\n  " << k << ": from cluster " << c.source_cluster << ", "
               << c.indices.indices.size() << " points, label "
               << majorityLabel(scene.scan.labels, c.indices) << ", confidence "
               << c.verification.confidence << " " << c.reason;
  }
  ASSERT_EQ(two.status, LocalizationStatus::Found) << two.message << candidates.str();
  ASSERT_EQ(two.instances.size(), 2u) << candidates.str();
  EXPECT_EQ(two.best, two.instances.front());
  std::set<int> labels;
  for (int k : two.instances) {
    const auto& c = two.clusters[static_cast<std::size_t>(k)];
    const int label = majorityLabel(scene.scan.labels, c.indices);
    labels.insert(label);
    ASSERT_TRUE(label == 1 || label == 2);
    const auto error =
        synthetic::poseError(Eigen::Isometry3d(c.icf.object_pose.cast<double>()),
                             scene.poses[static_cast<std::size_t>(label - 1)], box.symmetry);
    EXPECT_LE(error.translation, 0.005) << "instance on object " << label;
    EXPECT_LE(error.rotation_deg, 3.0) << "instance on object " << label;
  }
  EXPECT_EQ(labels.size(), 2u) << "one instance per copy";
  const auto one = localization::localizeObject(*scene.scan.cloud, *model);
  ASSERT_EQ(one.instances.size(), 1u);
  EXPECT_EQ(one.best, one.instances.front());
}

// One copy's points given as explained (what a tracker passes for a neighbour it already has):
// the search runs on the other copy's points only (no candidate holds an explained point) and
// finds it, within 5 mm / 3 degrees; the explained copy is not reported. An index outside the
// scene is refused, naming the field.
TEST_P(TwoCopies, ExplainedPointsAreLeftOutOfTheSearch) {
  const synthetic::SyntheticModel box = synthetic::thesisModel("Box5");
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const synthetic::TabletopScene scene =
      synthetic::makeTabletopScene({box, box}, GetParam(), synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(box.mesh);
  LocalizerParams params;
  for (std::size_t i = 0; i < scene.scan.labels.size(); ++i)
    if (scene.scan.labels[i] == 2)
      params.explained_indices.push_back(static_cast<int>(i));
  const auto loc = localization::localizeObject(*scene.scan.cloud, *model, params);
  ASSERT_EQ(loc.status, LocalizationStatus::Found) << loc.message;
  for (const auto& c : loc.clusters)
    for (const auto i : c.indices.indices)
      ASSERT_NE(scene.scan.labels[static_cast<std::size_t>(i)], 2) << "an explained point";
  const auto& best = loc.clusters[static_cast<std::size_t>(loc.best)];
  const auto error = synthetic::poseError(Eigen::Isometry3d(best.icf.object_pose.cast<double>()),
                                          scene.poses[0], box.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);

  params.explained_indices = {static_cast<int>(scene.scan.cloud->size())};
  try {
    localization::localizeObject(*scene.scan.cloud, *model, params);
    FAIL() << "an index outside the scene was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("explained_indices"), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Localizer, TwoCopies,
    ::testing::Values(std::vector<Eigen::Vector3d>{{-0.12, 0.0, 0.3}, {0.12, 0.02, -0.5}},
                      std::vector<Eigen::Vector3d>{{-0.075, 0.0, 0.0}, {0.075, 0.0, 0.0}}));

// Real data: one YCB-Video frame with ground truth; the four objects on its table touch, so
// one cluster holds them all. The bar, the bench's success rule: the box-shaped object's
// centre within 1 cm of the truth modulo its 180-degree flips about its own axes (depth alone
// cannot tell a box from its flip, and the meat can's flip explains the depth better than the
// annotated pose: a turn replaces it), ADD-S under 10% of the object's diameter.
using pcl_icf_test::ycbTruth;

class YcbObjects : public ::testing::TestWithParam<std::string> {};

TEST_P(YcbObjects, FoundInTheMergedClusterWithin1cm) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "ycbv/ycbv_frame000002.pcd");
  PCL_ICF_REQUIRE_SHARED(gt_path, "ycbv/gt.json");
  const std::string object = GetParam();
  PCL_ICF_REQUIRE_SHARED(mesh_path, "ycbv/" + object + ".obj");
  const pcl::PointCloud<pcl::PointXYZRGB> scene = loadScene(scene_path);
  ASSERT_FALSE(scene.empty());
  const pcl::PolygonMesh mesh = io::loadPolygonMesh(mesh_path);
  const IcfModel::ConstPtr model = IcfModel::build(mesh);
  const auto result = localization::localizeObject(scene, *model);
  const Eigen::Isometry3d truth = ycbTruth(gt_path, object);
  for (const auto& c : result.clusters)
    std::cout
        << object << ": cluster of " << c.indices.indices.size() << " points (from cluster "
        << c.source_cluster << "), score " << c.score << ", coverage "
        << c.icf.quality.surface_coverage << ", inliers " << c.icf.quality.inlier_ratio
        << ", confidence " << c.verification.confidence << ", continuation "
        << c.verification.silhouette_continuation << ", seen through "
        << c.verification.seen_through << ", gate " << c.gate_far_points << ", off by "
        << 1e3 * (c.icf.object_pose.block<3, 1>(0, 3).cast<double>() - truth.translation()).norm()
        << " mm, " << (c.accepted ? "ACCEPTED" : "rejected: " + c.reason) << "\n";
  ASSERT_EQ(result.status, LocalizationStatus::Found) << result.message;
  const auto& best = result.clusters[static_cast<std::size_t>(result.best)];
  const Eigen::Isometry3d estimate(best.icf.object_pose.cast<double>());
  // The box's own frame: surface centroid and principal axes, its sides along them.
  const localization::PrincipalAxes axes = localization::principalAxes(*model);
  Eigen::Isometry3d box = Eigen::Isometry3d::Identity();
  box.translation() = axes.centre.cast<double>();
  box.linear() = axes.axes.cast<double>();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (std::size_t f = 0; f < model->mesh().size(); ++f)
    for (std::size_t k = 0; k < model->mesh().faces()[f].count; ++k) {
      const Eigen::Vector3d q = box.inverse() * model->mesh().faceVertex(f, k).cast<double>();
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  const Eigen::Vector3d sides = hi - lo;
  const double t_err =
      synthetic::poseError(estimate * box, truth * box,
                           synthetic::Symmetry::box(sides.x(), sides.y(), sides.z()))
          .translation;
  const double adds = synthetic::addS(mesh, estimate, truth);
  const double diameter = synthetic::modelDiameter(mesh);
  RecordProperty("translation_mm", std::to_string(1e3 * t_err));
  RecordProperty("adds_over_diameter", std::to_string(adds / diameter));
  std::cout << object << ": translation error " << 1e3 * t_err << " mm, ADD-S " << 1e3 * adds
            << " mm (" << 100 * adds / diameter << "% of " << 1e3 * diameter << " mm)\n";
  EXPECT_LE(t_err, 0.01);
  EXPECT_LE(adds, 0.1 * diameter);
}

INSTANTIATE_TEST_SUITE_P(Localizer, YcbObjects,
                         ::testing::Values("004_sugar_box_textured",
                                           "010_potted_meat_can_textured"));

// The fit's one rule on a real frame: its unit, fitSigma, holds the camera's low-frequency
// error. A real structured-light camera's depth differs from a right pose's surface by more
// than its pixel noise (YCB's gelatin box fits the real depth at 1.25-1.47 pixel sigmas,
// doc/experiments/2026-12-02-fit-residual-by-range.md): with the default camera the right pose
// is found within 1 cm of the annotation (translation of the model origin; the frame's gelatin
// box is posed 0.4 mm off); told that the camera is a simulated one without that error
// (depth_noise.systematic 0) the same pose is refused, and the refusal says why (the fit), so a
// user who set it on a real camera can tell.
TEST(Localizer, ASimulatedCamerasFitRefusesARealFrameAndSaysSo) {
  PCL_ICF_REQUIRE_SHARED(scene_path, "ycbv-video0000/scenes/ycbv0000_000002.pcd");
  PCL_ICF_REQUIRE_SHARED(mesh_path, "ycbv-video0000/models/ycb_009_gelatin_box.ply");
  PCL_ICF_REQUIRE_SHARED(gt_path, "ycbv-video0000/cases/y0000_002_gelatin_box/gt.json");
  const pcl::PointCloud<pcl::PointXYZRGB> scene = loadScene(scene_path);
  ASSERT_FALSE(scene.empty());
  const IcfModel::ConstPtr model = IcfModel::build(io::loadPolygonMesh(mesh_path));
  const Eigen::Vector3d truth = ycbTruth(gt_path, "ycb_009_gelatin_box").translation();
  const auto offBy = [&](const localization::ClusterLocalization& c) {
    return (c.icf.object_pose.block<3, 1>(0, 3).cast<double>() - truth).norm();
  };

  const localization::LocalizerParams real;
  const auto found = localization::localizeObject(scene, *model, real);
  ASSERT_EQ(found.status, LocalizationStatus::Found) << found.message;
  EXPECT_LT(offBy(found.clusters[static_cast<std::size_t>(found.best)]), 0.01);

  localization::LocalizerParams simulated;
  simulated.depth_noise.systematic = 0.f;
  EXPECT_EQ(simulated.verificationParams().noise.systematic, 0.f);
  // Every ranked hypothesis judged, however weak its ranking: the right pose is among them.
  simulated.tuning().hypotheses.min_prescore = 0.0;
  simulated.tuning().hypotheses.judged = 12;
  const auto refused = localization::localizeObject(scene, *model, simulated);
  EXPECT_EQ(refused.status, LocalizationStatus::NotFound);
  bool right_pose_judged = false;
  for (const auto& c : refused.clusters) {
    if (offBy(c) >= 0.01)
      continue;
    right_pose_judged = true;
    EXPECT_FALSE(c.accepted);
    EXPECT_GT(c.verification.residual, simulated.verificationParams().fit_residual);
    EXPECT_NE(c.reason.find("fits the depth at"), std::string::npos) << c.reason;
  }
  EXPECT_TRUE(right_pose_judged) << refused.message;
}

/** A frame of ycbv-video0001 in which the sugar box (the Xtion at 1 m) lies near the acceptance
 * limit, and whether its right pose fits the depth within full confidence (fit_residual). */
struct SugarBoxFrame {
  int frame;
  bool fits_at_full_confidence;
};

class SugarBoxAtOneMetre : public ::testing::TestWithParam<SugarBoxFrame> {};

// Frame 3: the search lands on the flip (ADD-S 1.9 mm). Refined on the 3000-point subsets the
// hypotheses and turns use, the pose fits the depth at 0.90 fit sigmas and is refused at
// 0.872 < 0.875; refined once more on its whole crop (SceneHypotheses::final_points) it fits
// within the 0.8 of full confidence, which is checked. Frame 4: the search's best pose can be a
// wrong turn that explains the depth at 0.43, whose turns include the right one (0.90); turns
// are tried from promising_share (0.25) of the confidence an acceptance needs. Where the search
// lands depends on its last digits (on one machine the right pose directly), so whether the
// answer is a turn is not checked. Both against the annotation: the mesh's surface centroid,
// which a turn about a principal axis (the box's flip, right under the scoring rule) leaves in
// place, within 1 cm (the rule's translation bar).
TEST_P(SugarBoxAtOneMetre, FoundWithinTheRule) {
  const std::string frame = std::to_string(GetParam().frame);
  PCL_ICF_REQUIRE_SHARED(scene_path, "ycbv-video0001/scenes/ycbv0001_00000" + frame + ".pcd");
  PCL_ICF_REQUIRE_SHARED(mesh_path, "ycbv-video0001/models/ycb_004_sugar_box.ply");
  PCL_ICF_REQUIRE_SHARED(gt_path, "ycbv-video0001/cases/y0001_00" + frame + "_sugar_box/gt.json");
  const pcl::PointCloud<pcl::PointXYZRGB> scene = loadScene(scene_path);
  ASSERT_FALSE(scene.empty());
  const IcfModel::ConstPtr model = IcfModel::build(io::loadPolygonMesh(mesh_path));
  const Eigen::Vector3d centroid = model->mesh().surfaceCentroid().cast<double>();
  const Eigen::Vector3d truth = ycbTruth(gt_path, "ycb_004_sugar_box") * centroid;

  const localization::LocalizerParams params;
  const auto found = localization::localizeObject(scene, *model, params);
  ASSERT_EQ(found.status, LocalizationStatus::Found) << found.message;
  const auto& best = found.clusters[static_cast<std::size_t>(found.best)];
  EXPECT_LT((Eigen::Isometry3d(best.icf.object_pose.cast<double>()) * centroid - truth).norm(),
            0.01);
  if (GetParam().fits_at_full_confidence) {
    EXPECT_LE(best.verification.residual, params.verificationParams().fit_residual);
  }
}

INSTANTIATE_TEST_SUITE_P(Localizer, SugarBoxAtOneMetre,
                         ::testing::Values(SugarBoxFrame{3, true}, SugarBoxFrame{4, false}),
                         [](const ::testing::TestParamInfo<SugarBoxFrame>& info) {
                           return "Frame" + std::to_string(info.param.frame);
                         });

}  // namespace
