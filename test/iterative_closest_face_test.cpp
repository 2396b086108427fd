// pcl::IterativeClosestFace on synthetic depth-camera views of the thesis's four models at
// random poses, with no initial guess: the fast strategy must recover >= 95% of 50 seeded
// trials per model within 5 mm and 3 degrees (symmetry-aware, thesis chapter 7). Plus the
// Registration contract, the thesis strategy on a reduced budget, and bad input.
#include "support/depth_camera.h"
#include "support/pose_error.h"
#include "support/synthetic_models.h"

#include <pcl/icf/iterative_closest_face.h>
#include <pcl/registration/registration.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>

namespace {

using pcl::icf::test::CameraIntrinsics;
using pcl::icf::test::ScanNoise;
using pcl::icf::test::SyntheticModel;

using Trial = pcl::icf::test::RandomView;

/** A random pose in front of the camera (0.7 - 1.1 m) and its noisy view: noise 1.5 mm at
 * 1 m growing with depth^2, 5% outliers within +-5 cm along the ray. */
Trial makeTrial(const SyntheticModel& model, std::uint64_t seed) {
  return pcl::icf::test::randomView(model.mesh, seed);
}

Eigen::Isometry3d toIsometry(const Eigen::Matrix4f& m) {
  return Eigen::Isometry3d(m.cast<double>());
}

class ThesisModels : public ::testing::TestWithParam<std::string> {};

// Tolerances: 5 mm and 3 degrees are the bar, about 3x the sensor's noise at 1 m;
// 95% of 50 trials allows 2 failures.
TEST_P(ThesisModels, FastStrategyFindsThePoseWithoutAGuess) {
  const SyntheticModel model = pcl::icf::test::thesisModel(GetParam());
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(pcl::make_shared<pcl::PolygonMesh>(model.mesh));
  // Under the sanitizers (PCL_ICF_SANITIZED, set by the asan test preset) 8 trials check
  // memory and behaviour; the release run holds the 50-trial bar.
  const int kTrials = std::getenv("PCL_ICF_SANITIZED") ? 8 : 50;
  int successes = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(trial);
    const Trial t = makeTrial(model, seed);
    icf.setInputSource(t.cluster);
    pcl::PointCloud<pcl::PointXYZ> aligned;
    icf.align(aligned);
    const auto error =
        pcl::icf::test::poseError(toIsometry(icf.getObjectPose()), t.truth, model.symmetry);
    const bool ok = error.translation <= 0.005 && error.rotation_deg <= 3.0;
    successes += ok;
    if (!ok || !icf.hasConverged())
      std::cout << GetParam() << " trial seed " << seed << ": " << 1e3 * error.translation
                << " mm, " << error.rotation_deg << " deg, "
                << pcl::icf::toString(icf.getResult().status) << ", coverage "
                << icf.getResult().quality.surface_coverage << ", rmse "
                << icf.getResult().quality.rmse << ", points " << t.cluster->size() << "\n";
    if (ok) {
      EXPECT_TRUE(icf.hasConverged()) << "seed " << seed << ": a right pose must be accepted";
    }
  }
  RecordProperty("successes", successes);
  EXPECT_GE(successes, kTrials - std::max(1, kTrials / 20))
      << GetParam() << ": " << successes << " / " << kTrials;
}

INSTANTIATE_TEST_SUITE_P(IterativeClosestFace, ThesisModels,
                         ::testing::Values("Box5", "EisKaffe", "YellowRoundSalt", "Amicelly"));

}  // namespace

namespace {

pcl::PolygonMesh::ConstPtr meshOf(const std::string& name) {
  return pcl::make_shared<pcl::PolygonMesh>(pcl::icf::test::thesisModel(name).mesh);
}

TEST(IterativeClosestFace, WorksThroughARegistrationPointerBesideIcp) {
  const SyntheticModel model = pcl::icf::test::thesisModel("Amicelly");
  const Trial t = makeTrial(model, 7);
  auto icf = pcl::make_shared<pcl::IterativeClosestFace<pcl::PointXYZ>>();
  icf->setInputTarget(meshOf("Amicelly"));
  int callbacks = 0;
  std::function<pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::UpdateVisualizerCallbackSignature>
      callback = [&callbacks](const pcl::PointCloud<pcl::PointXYZ>&, const pcl::Indices&,
                              const pcl::PointCloud<pcl::PointXYZ>& target, const pcl::Indices&) {
        EXPECT_FALSE(target.empty());
        ++callbacks;
      };
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>::Ptr registration = icf;
  // PCL calls the callback at once with the source and target: set both first.
  registration->setInputSource(t.cluster);
  registration->registerVisualizationCallback(callback);
  registration->setMaximumIterations(25);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  registration->align(aligned);
  ASSERT_TRUE(registration->hasConverged());
  EXPECT_GT(callbacks, 1);  // once at registration, then per refinement iteration
  EXPECT_LE(icf->getResult().refinement_iterations, 25);
  // getFinalTransformation maps the scene into the model frame; getObjectPose is its inverse.
  const Eigen::Matrix4f T = registration->getFinalTransformation();
  EXPECT_TRUE((T * icf->getObjectPose()).isIdentity(1e-4f));
  const auto error =
      pcl::icf::test::poseError(toIsometry(icf->getObjectPose()), t.truth, model.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
  // The aligned cloud is the source in the model frame: it lies on the model surface.
  const pcl::icf::FaceMesh faces = pcl::icf::FaceMesh::build(model.mesh);
  const pcl::icf::BruteForceClosestFace brute(faces);
  std::vector<float> d;
  for (const auto& p : aligned)
    d.push_back(brute.closestFace(p.getVector3fMap()).distance);
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  EXPECT_LE(d[d.size() / 2], 0.002f);  // median within noise (1.5 mm at 1 m)
  // The base fitness is point-to-sample and stays small for a right pose.
  EXPECT_LT(registration->getFitnessScore(0.01), 1e-4);
}

TEST(IterativeClosestFace, GuessRefinesLocallyAndIdentityMeansSearch) {
  const SyntheticModel model = pcl::icf::test::thesisModel("Box5");
  const Trial t = makeTrial(model, 11);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(t.cluster);
  // A guess 2 cm and 8 degrees off the truth.
  Eigen::Isometry3d perturbed = t.truth;
  perturbed.translate(Eigen::Vector3d(0.02, 0, 0));
  perturbed.rotate(Eigen::AngleAxisd(8.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned, perturbed.inverse().matrix().cast<float>());
  EXPECT_EQ(icf.getResult().method, "guess+icf");
  auto error = pcl::icf::test::poseError(toIsometry(icf.getObjectPose()), t.truth, model.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().method, "fast+icf");
}

TEST(IterativeClosestFace, SameSeedSameResultForAnyThreadCount) {
  const Trial t = makeTrial(pcl::icf::test::thesisModel("YellowRoundSalt"), 3);
  Eigen::Matrix4f poses[2];
  for (int threads : {1, 2}) {
    pcl::IterativeClosestFace<pcl::PointXYZ> icf;
    icf.setInputTarget(meshOf("YellowRoundSalt"));
    icf.setInputSource(t.cluster);
    icf.setNumberOfThreads(threads);
    icf.setSeed(99);
    pcl::PointCloud<pcl::PointXYZ> aligned;
    icf.align(aligned);
    poses[threads - 1] = icf.getObjectPose();
  }
  EXPECT_EQ(poses[0], poses[1]);
}

TEST(IterativeClosestFace, ThesisStrategyOnAReducedBudget) {
  // The thesis's search with 5 x 20 x 20 instead of 50 x 100 x 20 evaluations, then refined:
  // it must return a finite pose, spend its budget deterministically and, on this easy view
  // of the box, end within the thesis's own accuracy (12-23 mm mean error, chapter 7).
  const SyntheticModel model = pcl::icf::test::thesisModel("Box5");
  const Trial t = makeTrial(model, 21);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(t.cluster);
  icf.setSearchStrategy(pcl::icf::SearchStrategy::Thesis);
  pcl::icf::IcfParams params = icf.getParams();
  params.thesis.outer_iterations = 5;
  params.thesis.orientation_iterations = 20;
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().method, "thesis+icf");
  EXPECT_GT(icf.getResult().search_score, 0.0);
  EXPECT_TRUE(icf.getObjectPose().allFinite());
  const Eigen::Matrix4f first = icf.getObjectPose();
  icf.align(aligned);
  EXPECT_EQ(first, icf.getObjectPose()) << "same seed, same result";
  const auto error = pcl::icf::test::poseError(toIsometry(first), t.truth, model.symmetry);
  EXPECT_LE(error.translation, 0.023);
}

TEST(IterativeClosestFace, ClusterHoldingAnotherObjectStillFindsTheTarget) {
  // The salt cylinder's view merged with a box's view 3 cm beside it: points far from the
  // model add nothing, and acceptance judges how much of the model's visible surface is
  // explained, so the merged cluster is accepted with the right pose.
  const SyntheticModel salt = pcl::icf::test::thesisModel("YellowRoundSalt");
  const SyntheticModel box = pcl::icf::test::thesisModel("Box5");
  Eigen::Isometry3d salt_pose = Eigen::Isometry3d::Identity();
  salt_pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.9);
  salt_pose.rotate(Eigen::AngleAxisd(1.2, Eigen::Vector3d(1, 0.3, 0).normalized()));
  Eigen::Isometry3d box_pose = Eigen::Isometry3d::Identity();
  box_pose.translation() = Eigen::Vector3d(0.13, 0.0, 0.92);
  box_pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0).normalized()));
  ScanNoise noise;
  auto merged = pcl::icf::test::renderCluster(salt.mesh, salt_pose, CameraIntrinsics(), noise);
  noise.seed = 2;
  *merged += *pcl::icf::test::renderCluster(box.mesh, box_pose, CameraIntrinsics(), noise);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("YellowRoundSalt"));
  icf.setInputSource(merged);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  const auto error =
      pcl::icf::test::poseError(toIsometry(icf.getObjectPose()), salt_pose, salt.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
  EXPECT_TRUE(icf.hasConverged()) << "coverage " << icf.getResult().quality.surface_coverage;
  EXPECT_LT(icf.getResult().quality.inlier_ratio, 0.8);  // the box's points are not inliers
}

TEST(IterativeClosestFace, WrongModelLeavesTheClusterUnexplained) {
  // A cluster of the box registered against the coffee cylinder. The default acceptance judges
  // the model's visible surface (a cylinder's cap can lie on the box's face), so for a cluster
  // known to hold one object the thesis's gate is what rejects: far more than 5 points lie
  // beyond 27 mm. Either way most of the cluster is left unexplained.
  const Trial t = makeTrial(pcl::icf::test::thesisModel("Box5"), 5);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("EisKaffe"));
  icf.setInputSource(t.cluster);
  pcl::icf::IcfParams params;
  params.acceptance.thesis_gate = true;
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_FALSE(icf.hasConverged());
  EXPECT_EQ(icf.getResult().status, pcl::icf::IcfStatus::Rejected);
  EXPECT_GT(icf.getResult().quality.far_points, 5);
  EXPECT_LT(icf.getResult().quality.inlier_ratio, 0.8);
}

TEST(IterativeClosestFace, ThesisGateAcceptsTheRightModelOnASingleObjectCluster) {
  const SyntheticModel model = pcl::icf::test::thesisModel("Box5");
  const Trial t = makeTrial(model, 5);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(t.cluster);
  pcl::icf::IcfParams params;
  params.acceptance.thesis_gate = true;
  // The simulated scan has 5% outliers up to 5 cm off along the ray: the thesis's gate of
  // 5 points beyond 27 mm assumed a cleaner cut-out, so allow 10% of the cluster here.
  params.acceptance.gate_max_far_points = static_cast<int>(t.cluster->size() / 10);
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_TRUE(icf.hasConverged()) << icf.getResult().quality.far_points << " far points";
}

TEST(IterativeClosestFace, OrganizedCloudWithNaNsAndColourTypes) {
  const SyntheticModel model = pcl::icf::test::thesisModel("Box5");
  std::mt19937_64 rng(8);
  pcl::icf::test::SceneObject object;
  object.mesh = &model.mesh;
  object.pose = pcl::icf::test::randomTabletopPose(rng);
  object.rgb = model.rgb;
  object.label = 1;
  const auto scan = pcl::icf::test::renderScan({object}, CameraIntrinsics(), ScanNoise());
  ASSERT_FALSE(scan.cloud->is_dense);  // organized, NaN background
  pcl::IterativeClosestFace<pcl::PointXYZRGB> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(scan.cloud);
  pcl::PointCloud<pcl::PointXYZRGB> aligned;
  icf.align(aligned);
  EXPECT_TRUE(icf.hasConverged());
  EXPECT_LT(icf.getResult().points, scan.cloud->size());
  const auto error =
      pcl::icf::test::poseError(toIsometry(icf.getObjectPose()), object.pose, model.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
}

TEST(IterativeClosestFace, BadInputGivesAClearStatusOrException) {
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  pcl::PointCloud<pcl::PointXYZ> aligned;
  // No mesh: PCL's initCompute refuses (target empty); our status says why.
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->push_back(pcl::PointXYZ(0.f, 0.f, 1.f));
  icf.setInputSource(cloud);
  icf.align(aligned);
  EXPECT_FALSE(icf.hasConverged());
  // A point cloud is not a mesh target.
  EXPECT_THROW(icf.setInputTarget(pcl::PointCloud<pcl::PointXYZ>::ConstPtr(cloud)),
               std::invalid_argument);
  EXPECT_THROW(icf.setInputTarget(pcl::PolygonMesh::ConstPtr()), std::invalid_argument);
  EXPECT_THROW(icf.setInputTarget(pcl::make_shared<pcl::PolygonMesh>()),
               pcl::icf::InvalidMeshError);

  icf.setInputTarget(meshOf("Box5"));
  // Empty and all-NaN sources.
  icf.setInputSource(pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>());
  icf.align(aligned);
  EXPECT_FALSE(icf.hasConverged());
  auto nans = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>(40, 30);
  for (auto& p : *nans)
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
  icf.setInputSource(nans);
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().status, pcl::icf::IcfStatus::TooFewPoints);
  EXPECT_FALSE(icf.hasConverged());
  // A NaN in the guess.
  const Trial t = makeTrial(pcl::icf::test::thesisModel("Box5"), 4);
  icf.setInputSource(t.cluster);
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  guess(0, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(icf.align(aligned, guess), std::invalid_argument);
  // Nonsense parameters, named in the message.
  pcl::icf::IcfParams params;
  params.global.rotations = 0;
  icf.setParams(params);
  try {
    icf.align(aligned);
    FAIL() << "rotations = 0 must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rotations"), std::string::npos) << e.what();
  }
  params = {};
  params.acceptance.inlier_distance = -1.f;
  icf.setParams(params);
  EXPECT_THROW(icf.align(aligned), std::invalid_argument);
  EXPECT_THROW(icf.setNumberOfThreads(-3), std::invalid_argument);
}

TEST(IcfParams, DocumentedDefaultsAreTheRealDefaults) {
  const pcl::icf::IcfParams p;
  // The thesis's values (section 4.2.1, 4.3.2, 6.2) in metres.
  EXPECT_FLOAT_EQ(p.objective.near_distance, 0.030f);
  EXPECT_FLOAT_EQ(p.objective.far_factor, 4.f);
  EXPECT_FLOAT_EQ(p.objective.cutoff, 0.200f);
  EXPECT_FLOAT_EQ(p.objective.early_exit_distance, 0.050f);
  EXPECT_EQ(p.objective.early_exit_count, 500);
  EXPECT_EQ(p.thesis.outer_iterations, 50);
  EXPECT_EQ(p.thesis.orientation_iterations, 100);
  EXPECT_EQ(p.thesis.samples_per_kernel, 20);
  EXPECT_FLOAT_EQ(p.thesis.translation_sigma_step, 0.010f);
  EXPECT_NEAR(p.thesis.rotation_sigma_step * 180.0 / M_PI, 10.0, 1e-5);
  EXPECT_EQ(p.thesis.stall_limit, 3);
  EXPECT_FLOAT_EQ(p.acceptance.gate_distance, 0.027f);
  EXPECT_EQ(p.acceptance.gate_max_far_points, 5);
  EXPECT_EQ(p.strategy, pcl::icf::SearchStrategy::Fast);
  EXPECT_NO_THROW(p.validate());
}

TEST(ThesisObjective, MatchesSection421) {
  const pcl::icf::ThesisObjectiveParams p;
  EXPECT_FLOAT_EQ(pcl::icf::thesisPointScore(0.f, p), 1.f);
  EXPECT_FLOAT_EQ(pcl::icf::thesisPointScore(0.020f, p), 1.f - 0.020f / 0.2f);  // g = d
  EXPECT_FLOAT_EQ(pcl::icf::thesisPointScore(0.040f, p), 1.f - 0.160f / 0.2f);  // g = 4 d
  EXPECT_FLOAT_EQ(pcl::icf::thesisPointScore(0.050f, p), 0.f);                  // g = m
  EXPECT_FLOAT_EQ(pcl::icf::thesisPointScore(0.150f, p), 0.f);
  // Early exit: 501 far points make F = 0 however good the rest is.
  std::vector<Eigen::Vector3f> points(1000, Eigen::Vector3f::Zero());
  for (int i = 0; i < 501; ++i)
    points[static_cast<std::size_t>(i)].x() = 1.f;
  auto distance = [](const Eigen::Vector3f& x) { return x.x(); };
  EXPECT_EQ(pcl::icf::thesisObjective(points, distance, p), 0.0);
  points[0].x() = 0.f;  // 500 far points: no exit, F = 500 near points * 1
  EXPECT_DOUBLE_EQ(pcl::icf::thesisObjective(points, distance, p), 500.0);
}

}  // namespace
