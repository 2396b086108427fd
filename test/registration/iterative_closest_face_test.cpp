// pcl::IterativeClosestFace on synthetic depth-camera views of the thesis's four models at
// random poses, with no initial guess: the fast strategy must recover >= 95% of 50 seeded
// trials per model within 5 mm and 3 degrees (symmetry-aware, thesis chapter 7). Plus the
// Registration contract, the thesis strategy on a reduced budget, and bad input.
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"

#include <pcl/common/io.h>
#include <pcl/common/transforms.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/iterative_closest_face.h>
#include <pcl/registration/registration.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <random>
#include <tuple>

namespace {

using pcl::icf::synthetic::CameraIntrinsics;
using pcl::icf::synthetic::ScanNoise;
using pcl::icf::synthetic::SyntheticModel;

using Trial = pcl::icf::synthetic::RandomView;

/** A random pose in front of the camera (0.7 - 1.1 m) and its noisy view: noise 1.5 mm at
 * 1 m growing with depth^2, 5% outliers within +-5 cm along the ray. */
Trial makeTrial(const SyntheticModel& model, std::uint64_t seed) {
  return pcl::icf::synthetic::randomView(model.mesh, seed);
}

/** estimatePose's options with only a start check (PoseEstimateOptions::worth_refining). */
pcl::icf::PoseEstimateOptions withStartCheck(pcl::icf::StartCheck check) {
  pcl::icf::PoseEstimateOptions options;
  options.worth_refining = std::move(check);
  return options;
}

/** estimatePose's options with a start check and a guess. */
pcl::icf::PoseEstimateOptions withStartCheck(const Eigen::Isometry3f& guess,
                                             pcl::icf::StartCheck check) {
  pcl::icf::PoseEstimateOptions options = withStartCheck(std::move(check));
  options.guess = guess;
  return options;
}

/** estimatePose's options with only a guess. */
pcl::icf::PoseEstimateOptions fromGuess(const Eigen::Isometry3f& guess) {
  pcl::icf::PoseEstimateOptions options;
  options.guess = guess;
  return options;
}

/** The trial's cluster as estimatePose takes it. */
std::vector<Eigen::Vector3f> trialPoints(const Trial& t) {
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : *t.cluster)
    points.push_back(p.getVector3fMap());
  return points;
}

Eigen::Isometry3d toIsometry(const Eigen::Matrix4f& m) {
  return Eigen::Isometry3d(m.cast<double>());
}

class ThesisModels : public ::testing::TestWithParam<std::string> {};

// Tolerances: 5 mm and 3 degrees are the bar, about 3x the sensor's noise at 1 m;
// 95% of 50 trials allows 2 failures.
TEST_P(ThesisModels, FastStrategyFindsThePoseWithoutAGuess) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel(GetParam());
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
        pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), t.truth, model.symmetry);
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
  return pcl::make_shared<pcl::PolygonMesh>(pcl::icf::synthetic::thesisModel(name).mesh);
}

TEST(IterativeClosestFace, WorksThroughARegistrationPointerBesideIcp) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Amicelly");
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
      pcl::icf::synthetic::poseError(toIsometry(icf->getObjectPose()), t.truth, model.symmetry);
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
  // The base's fitness, through the pointer, is point-to-face: small for a right pose.
  EXPECT_LT(registration->getFitnessScore(0.01), 1e-4);
}

TEST(IterativeClosestFace, GuessRefinesLocallyAndIdentityMeansSearch) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
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
  auto error =
      pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), t.truth, model.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().method, "fast+icf");
}

TEST(IterativeClosestFace, SameSeedSameResultForAnyThreadCount) {
  const Trial t = makeTrial(pcl::icf::synthetic::thesisModel("YellowRoundSalt"), 3);
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
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  const Trial t = makeTrial(model, 21);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(t.cluster);
  icf.setSearchStrategy(pcl::icf::SearchStrategy::Thesis);
  pcl::icf::IcfParams params = icf.getParams();
  params.tuning().thesis.outer_iterations = 5;
  params.tuning().thesis.orientation_iterations = 20;
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().method, "thesis+icf");
  EXPECT_GT(icf.getResult().search_score, 0.0);
  EXPECT_TRUE(icf.getObjectPose().allFinite());
  const Eigen::Matrix4f first = icf.getObjectPose();
  icf.align(aligned);
  EXPECT_EQ(first, icf.getObjectPose()) << "same seed, same result";
  const auto error = pcl::icf::synthetic::poseError(toIsometry(first), t.truth, model.symmetry);
  EXPECT_LE(error.translation, 0.023);
}

TEST(IterativeClosestFace, ClusterHoldingAnotherObjectStillFindsTheTarget) {
  // The salt cylinder's view merged with a box's view 3 cm beside it: points far from the
  // model add nothing, and acceptance judges how much of the model's visible surface is
  // explained, so the merged cluster is accepted with the right pose.
  const SyntheticModel salt = pcl::icf::synthetic::thesisModel("YellowRoundSalt");
  const SyntheticModel box = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d salt_pose = Eigen::Isometry3d::Identity();
  salt_pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.9);
  salt_pose.rotate(Eigen::AngleAxisd(1.2, Eigen::Vector3d(1, 0.3, 0).normalized()));
  Eigen::Isometry3d box_pose = Eigen::Isometry3d::Identity();
  box_pose.translation() = Eigen::Vector3d(0.13, 0.0, 0.92);
  box_pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0).normalized()));
  ScanNoise noise;
  auto merged = pcl::icf::synthetic::renderCluster(salt.mesh, salt_pose, CameraIntrinsics(), noise);
  noise.seed = 2;
  *merged += *pcl::icf::synthetic::renderCluster(box.mesh, box_pose, CameraIntrinsics(), noise);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("YellowRoundSalt"));
  icf.setInputSource(merged);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  const auto error =
      pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), salt_pose, salt.symmetry);
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
  const Trial t = makeTrial(pcl::icf::synthetic::thesisModel("Box5"), 5);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("EisKaffe"));
  icf.setInputSource(t.cluster);
  pcl::icf::IcfParams params;
  params.acceptance.gate.enabled = true;
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_FALSE(icf.hasConverged());
  EXPECT_EQ(icf.getResult().status, pcl::icf::IcfStatus::Rejected);
  EXPECT_GT(icf.getResult().quality.far_points, 5);
  EXPECT_LT(icf.getResult().quality.inlier_ratio, 0.8);
}

TEST(IterativeClosestFace, FarPointGateAcceptsTheRightModelOnASingleObjectCluster) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  const Trial t = makeTrial(model, 5);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(t.cluster);
  pcl::icf::IcfParams params;
  params.acceptance.gate.enabled = true;
  // The simulated scan has 5% outliers up to 5 cm off along the ray: the thesis's gate of
  // 5 points beyond 27 mm assumed a cleaner cut-out, so allow 10% of the cluster here.
  params.acceptance.gate.max_points = static_cast<int>(t.cluster->size() / 10);
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_TRUE(icf.hasConverged()) << icf.getResult().quality.far_points << " far points";
}

TEST(IterativeClosestFace, OrganizedCloudWithNaNsAndColourTypes) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  std::mt19937_64 rng(8);
  pcl::icf::synthetic::SceneObject object;
  object.mesh = &model.mesh;
  object.pose = pcl::icf::synthetic::randomTabletopPose(rng);
  object.rgb = model.rgb;
  object.label = 1;
  const auto scan = pcl::icf::synthetic::renderScan({object}, CameraIntrinsics(), ScanNoise());
  ASSERT_FALSE(scan.cloud->is_dense);  // organized, NaN background
  pcl::IterativeClosestFace<pcl::PointXYZRGB> icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(scan.cloud);
  pcl::PointCloud<pcl::PointXYZRGB> aligned;
  icf.align(aligned);
  EXPECT_TRUE(icf.hasConverged());
  EXPECT_LT(icf.getResult().points, scan.cloud->size());
  const auto error =
      pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), object.pose, model.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);
}

TEST(IterativeClosestFace, BadInputGivesAClearStatusOrException) {
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  pcl::PointCloud<pcl::PointXYZ> aligned;
  // No mesh: status NoModel (PCL's initCompute would stop silently without a target).
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->push_back(pcl::PointXYZ(0.f, 0.f, 1.f));
  icf.setInputSource(cloud);
  icf.align(aligned);
  EXPECT_FALSE(icf.hasConverged());
  EXPECT_EQ(icf.getResult().status, pcl::icf::IcfStatus::NoModel);
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
  const Trial t = makeTrial(pcl::icf::synthetic::thesisModel("Box5"), 4);
  icf.setInputSource(t.cluster);
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  guess(0, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(icf.align(aligned, guess), std::invalid_argument);
  // Nonsense parameters, named in the message.
  pcl::icf::IcfParams params;
  params.tuning().global.rotations = 0;
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

// The coarse-to-fine final refinement (IcfParams::coarse_points) against the oracle of one
// full-resolution refinement from the same search. Uncapped (fine_iterations = 30, the single
// stage's budget) the fine stage minimises the same full-resolution objective from the
// smallest Tukey radius, so both land on the same minimum up to the stopping rule (steps below
// 1e-5 m and 1e-5 rad): 0.1 mm and 0.05 degrees leave 10x that. With the default cap of 10
// full-resolution iterations a pose may stop short along a weakly constrained direction (a box
// seen on two faces): within 0.5 mm and 0.25 degrees, a third of the sensor's 1.5 mm noise.
// 200 coarse points force the coarse stage on every view (400+ points).
TEST(IcfParams, CoarseToFineRefinementLandsWhereFullResolutionDoes) {
  const SyntheticModel box = pcl::icf::synthetic::thesisModel("Box5");
  const auto model = pcl::icf::IcfModel::build(box.mesh);
  for (std::uint64_t seed = 3000; seed < 3006; ++seed) {
    const std::vector<Eigen::Vector3f> points = trialPoints(makeTrial(box, seed));
    pcl::icf::IcfParams full, uncapped;
    full.tuning().coarse_points = 0;
    uncapped.tuning().coarse_points = 200;
    uncapped.tuning().fine_iterations = uncapped.tuning().refinement.max_iterations;
    full.threads = uncapped.threads = 1;
    pcl::icf::IcfParams capped = uncapped;
    capped.tuning().fine_iterations = pcl::icf::IcfParams().tuning().fine_iterations;
    const auto a = pcl::icf::estimatePose(*model, points, Eigen::Vector3f::Zero(), full);
    for (const auto& [params, metres, degrees] :
         {std::tuple{uncapped, 1e-4, 0.05}, std::tuple{capped, 5e-4, 0.25}}) {
      const auto b = pcl::icf::estimatePose(*model, points, Eigen::Vector3f::Zero(), params);
      const auto error =
          pcl::icf::synthetic::poseError(toIsometry(b.object_pose), toIsometry(a.object_pose), {});
      SCOPED_TRACE("seed " + std::to_string(seed) + ", " + std::to_string(points.size()) +
                   " points, fine_iterations " + std::to_string(params.tuning().fine_iterations));
      EXPECT_LE(error.translation, metres);
      EXPECT_LE(error.rotation_deg, degrees);
      EXPECT_EQ(a.status, b.status);
    }
  }
}

// estimatePose's worth_refining check against the same call without it (the oracle): a check
// that always says yes changes nothing (same pose to the bit, same status); one that says no
// is asked once, with the very start the unchecked run refined from (the pose then stays that
// start: the refinement and the measure are skipped), the result is Rejected with
// refinement_skipped, and under Auto the SAC fallback does not run after it; with a guess it
// is never asked. The candidates' check is off here (the next test).
TEST(IcfParams, StartCheckSkipsOnlyTheRefinementItRefuses) {
  const SyntheticModel box = pcl::icf::synthetic::thesisModel("Box5");
  const auto model = pcl::icf::IcfModel::build(box.mesh);
  const std::vector<Eigen::Vector3f> points = trialPoints(makeTrial(box, 3100));
  pcl::icf::IcfParams params;
  params.threads = 1;
  params.fallback = pcl::icf::FallbackPolicy::Off;
  params.tuning().check_candidates = false;
  const Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  const auto plain = pcl::icf::estimatePose(*model, points, camera, params);
  ASSERT_TRUE(plain.accepted());

  const auto yes =
      pcl::icf::estimatePose(*model, points, camera, params,
                             withStartCheck([](const Eigen::Isometry3f&) { return true; }));
  EXPECT_TRUE(yes.object_pose.isApprox(plain.object_pose, 0.f));
  EXPECT_EQ(yes.status, plain.status);
  EXPECT_FALSE(yes.refinement_skipped);

  std::vector<Eigen::Isometry3f> asked;
  const auto no = pcl::icf::estimatePose(*model, points, camera, params,
                                         withStartCheck([&](const Eigen::Isometry3f& start) {
                                           asked.push_back(start);
                                           return false;
                                         }));
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_EQ(no.status, pcl::icf::IcfStatus::Rejected);
  EXPECT_TRUE(no.refinement_skipped);
  EXPECT_EQ(no.refinement_iterations, 0);
  EXPECT_TRUE(no.scene_to_model.isApprox(asked.front().matrix(), 0.f));
  // The start the check saw is where the unchecked refinement began: within its 5 mm / 3 degree
  // reach of the final pose.
  const auto start_error = pcl::icf::synthetic::poseError(
      toIsometry(no.object_pose), toIsometry(plain.object_pose), box.symmetry);
  EXPECT_LE(start_error.translation, 0.005);
  EXPECT_LE(start_error.rotation_deg, 3.0);

  params.fallback = pcl::icf::FallbackPolicy::Auto;
  asked.clear();
  const auto refused = pcl::icf::estimatePose(*model, points, camera, params,
                                              withStartCheck([&](const Eigen::Isometry3f& start) {
                                                asked.push_back(start);
                                                return false;
                                              }));
  EXPECT_EQ(asked.size(), 1u);
  EXPECT_FALSE(refused.fallback_ran) << "a refused search start ends the search";

  asked.clear();
  const Eigen::Isometry3f guess(plain.scene_to_model);
  const auto guided = pcl::icf::estimatePose(
      *model, points, camera, params, withStartCheck(guess, [&](const Eigen::Isometry3f& start) {
        asked.push_back(start);
        return false;
      }));
  EXPECT_TRUE(asked.empty());
  EXPECT_FALSE(guided.refinement_skipped);
}

// IcfParams::check_candidates against the global search itself (the oracle: globalSearch's
// hypotheses, computed apart). A check that refuses everything is asked first with the search's
// exact_candidates best hypotheses, to the bit as globalSearch gives them, then with the start,
// which is the best hypothesis unrefined (no exact refinement ran); a check that accepts any one
// candidate (here only the last) leaves the result as the unchecked run's, to the bit.
TEST(IcfParams, CandidateCheckSkipsTheExactRefinementOnlyWhenAllAreRefused) {
  const SyntheticModel box = pcl::icf::synthetic::thesisModel("Box5");
  const auto model = pcl::icf::IcfModel::build(box.mesh);
  const std::vector<Eigen::Vector3f> points = trialPoints(makeTrial(box, 3101));
  pcl::icf::IcfParams params;
  params.threads = 1;
  params.fallback = pcl::icf::FallbackPolicy::Off;
  const Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  const auto plain = pcl::icf::estimatePose(*model, points, camera, params);
  const auto hypotheses = pcl::icf::globalSearch(*model, points, camera, params.tuning().global,
                                                 params.seed, params.threads);
  ASSERT_GE(hypotheses.size(), params.tuning().exact_candidates);

  std::vector<Eigen::Isometry3f> asked;
  const auto refused = pcl::icf::estimatePose(*model, points, camera, params,
                                              withStartCheck([&](const Eigen::Isometry3f& start) {
                                                asked.push_back(start);
                                                return false;
                                              }));
  ASSERT_EQ(asked.size(), params.tuning().exact_candidates + 1);
  for (std::size_t i = 0; i < params.tuning().exact_candidates; ++i)
    EXPECT_TRUE(asked[i].isApprox(hypotheses[i].scene_to_model, 0.f)) << "candidate " << i;
  EXPECT_TRUE(asked.back().isApprox(hypotheses.front().scene_to_model, 0.f));
  EXPECT_TRUE(refused.refinement_skipped);
  EXPECT_EQ(refused.status, pcl::icf::IcfStatus::Rejected);
  EXPECT_TRUE(refused.scene_to_model.isApprox(hypotheses.front().scene_to_model.matrix(), 0.f));

  const Eigen::Isometry3f last = hypotheses[params.tuning().exact_candidates - 1].scene_to_model;
  bool last_seen = false;
  const auto one_passes = pcl::icf::estimatePose(
      *model, points, camera, params, withStartCheck([&](const Eigen::Isometry3f& start) {
        last_seen = last_seen || start.isApprox(last, 0.f);
        return last_seen;
      }));
  EXPECT_TRUE(last_seen);
  EXPECT_TRUE(one_passes.object_pose.isApprox(plain.object_pose, 0.f));
  EXPECT_EQ(one_passes.status, plain.status);
  EXPECT_FALSE(one_passes.refinement_skipped);
}

// The seen-through check (AcceptanceParams::max_seen_through) on a view of the box where the
// camera sees through it in a square window of 4 x 4 cm around the ray through the view's
// centroid: the window's points are moved 4 cm farther along their rays, a depth the camera
// could only measure through the box. Oracle: the true pose. Without the window it conflicts
// with the depth nowhere (below 1% of its pixels: noise); with it the same pose is seen through
// on a clear share (above the 5% default), so it is rejected, while coverage stays above its
// bar (the moved points lie beyond the refinement's 2 cm and the 1 cm inlier distance, and the
// pose does not move), and the fallback runs.
TEST(IcfParams, SeenThroughRejectsAPoseTheCameraSeesThrough) {
  const SyntheticModel box = pcl::icf::synthetic::thesisModel("Box5");
  const auto model = pcl::icf::IcfModel::build(box.mesh);
  const Trial t = makeTrial(box, 3100);
  std::vector<Eigen::Vector3f> view;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : *t.cluster) {
    view.push_back(p.getVector3fMap());
    centroid += view.back();
  }
  centroid /= static_cast<float>(view.size());
  const Eigen::Vector3f ray = centroid.normalized();
  const Eigen::Vector3f across = ray.unitOrthogonal(), up = ray.cross(across);
  const float half_angle = 0.02f / centroid.norm();
  std::vector<Eigen::Vector3f> seen_through = view;
  std::size_t moved = 0;
  for (auto& p : seen_through) {
    const Eigen::Vector3f d = p.normalized();
    if (std::abs(d.dot(across)) < half_angle && std::abs(d.dot(up)) < half_angle) {
      p = d * (p.norm() + 0.04f);
      ++moved;
    }
  }
  ASSERT_GT(moved, 100u) << "the window must hold a good part of the view";

  pcl::icf::IcfParams params;
  params.threads = 1;
  params.fallback = pcl::icf::FallbackPolicy::Off;
  const Eigen::Isometry3f truth = t.truth.inverse().cast<float>();  // scene -> model
  const Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  const auto clean = pcl::icf::estimatePose(*model, view, camera, params, fromGuess(truth));
  ASSERT_TRUE(clean.accepted());
  EXPECT_LT(clean.quality.seen_through, 0.01);

  const auto patched =
      pcl::icf::estimatePose(*model, seen_through, camera, params, fromGuess(truth));
  EXPECT_EQ(patched.status, pcl::icf::IcfStatus::Rejected);
  EXPECT_GT(patched.quality.seen_through, params.acceptance.max_seen_through);
  // One point per pixel: the moved share of the points is about the seen-through share of the
  // judged pixels (within half of it: the silhouette's ring of pixels is not judged, and
  // a pixel on the window's edge can hold a moved and an unmoved point).
  const double moved_share = static_cast<double>(moved) / static_cast<double>(view.size());
  EXPECT_NEAR(patched.quality.seen_through, moved_share, 0.5 * moved_share);
  EXPECT_GE(patched.quality.surface_coverage, params.acceptance.min_surface_coverage);
  const auto error =
      pcl::icf::synthetic::poseError(toIsometry(patched.object_pose), t.truth, box.symmetry);
  EXPECT_LE(error.translation, 0.005);
  EXPECT_LE(error.rotation_deg, 3.0);

  params.acceptance.max_seen_through = 1.0;  // the check off: the other rules accept
  const auto unchecked =
      pcl::icf::estimatePose(*model, seen_through, camera, params, fromGuess(truth));
  EXPECT_TRUE(unchecked.accepted());
  EXPECT_EQ(unchecked.quality.seen_through, 0.0) << "not measured when the check is off";
  std::cout << "seen through: " << clean.quality.seen_through << " without the window, "
            << patched.quality.seen_through << " with it (" << moved << " of " << view.size()
            << " points moved)\n";

  params.acceptance.max_seen_through = 0.05;
  params.fallback = pcl::icf::FallbackPolicy::Auto;
  const auto searched = pcl::icf::estimatePose(*model, seen_through, camera, params);
  EXPECT_TRUE(searched.fallback_ran) << "a pose seen through is rejected, so SAC is tried";
  EXPECT_FALSE(searched.accepted());
}

TEST(IcfParams, DocumentedDefaultsAreTheRealDefaults) {
  const pcl::icf::IcfParams p;
  // The thesis's values (section 4.2.1, 4.3.2, 6.2) in metres.
  EXPECT_FLOAT_EQ(p.tuning().objective.near_distance, 0.030f);
  EXPECT_FLOAT_EQ(p.tuning().objective.far_factor, 4.f);
  EXPECT_FLOAT_EQ(p.tuning().objective.cutoff, 0.200f);
  EXPECT_FLOAT_EQ(p.tuning().objective.early_exit_distance, 0.050f);
  EXPECT_EQ(p.tuning().objective.early_exit_count, 500);
  EXPECT_EQ(p.tuning().thesis.outer_iterations, 50);
  EXPECT_EQ(p.tuning().thesis.orientation_iterations, 100);
  EXPECT_EQ(p.tuning().thesis.samples_per_kernel, 20);
  EXPECT_FLOAT_EQ(p.tuning().thesis.translation_sigma_step, 0.010f);
  EXPECT_NEAR(p.tuning().thesis.rotation_sigma_step * 180.0 / M_PI, 10.0, 1e-5);
  EXPECT_EQ(p.tuning().thesis.stall_limit, 3);
  EXPECT_FLOAT_EQ(p.acceptance.gate.distance, 0.027f);
  EXPECT_EQ(p.acceptance.gate.max_points, 5);
  EXPECT_DOUBLE_EQ(p.acceptance.max_seen_through, 0.05);
  EXPECT_EQ(p.strategy, pcl::icf::SearchStrategy::Fast);
  EXPECT_NO_THROW(p.validate());
}

TEST(Objective, MatchesThesisSection421) {
  const pcl::icf::ObjectiveParams p;
  EXPECT_FLOAT_EQ(pcl::icf::objectivePointScore(0.f, p), 1.f);
  EXPECT_FLOAT_EQ(pcl::icf::objectivePointScore(0.020f, p), 1.f - 0.020f / 0.2f);  // g = d
  EXPECT_FLOAT_EQ(pcl::icf::objectivePointScore(0.040f, p), 1.f - 0.160f / 0.2f);  // g = 4 d
  EXPECT_FLOAT_EQ(pcl::icf::objectivePointScore(0.050f, p), 0.f);                  // g = m
  EXPECT_FLOAT_EQ(pcl::icf::objectivePointScore(0.150f, p), 0.f);
  // Early exit: 501 far points make F = 0 however good the rest is.
  std::vector<Eigen::Vector3f> points(1000, Eigen::Vector3f::Zero());
  for (int i = 0; i < 501; ++i)
    points[static_cast<std::size_t>(i)].x() = 1.f;
  auto distance = [](const Eigen::Vector3f& x) { return x.x(); };
  EXPECT_EQ(pcl::icf::objectiveValue(points, distance, p), 0.0);
  points[0].x() = 0.f;  // 500 far points: no exit, F = 500 near points * 1
  EXPECT_DOUBLE_EQ(pcl::icf::objectiveValue(points, distance, p), 500.0);
}

}  // namespace

// pcl::IterativeClosestFace as a drop-in for pcl::IterativeClosestPoint, checked
// through pcl::Registration pointers against independent oracles: the known pose, the source
// moved by hand, brute-force point-to-face distances.
namespace {

using PointN = pcl::PointNormal;
using CloudN = pcl::PointCloud<PointN>;
using RegistrationN = pcl::Registration<PointN, PointN>;
using IcfN = pcl::IterativeClosestFace<PointN>;

/** Box5 seen at a seeded table-top pose with 1 mm noise at 1 m (no outliers); each normal is
 * the unit vector towards the camera, so rotating it is checkable. */
CloudN::Ptr boxView(const SyntheticModel& model, std::uint64_t seed, Eigen::Isometry3d& truth) {
  std::mt19937_64 rng(seed);
  ScanNoise noise;
  noise.sigma_at_1m = 0.001;
  noise.outlier_ratio = 0.0;
  noise.seed = seed;
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz;
  do {
    truth = pcl::icf::synthetic::randomTabletopPose(rng);
    xyz = pcl::icf::synthetic::renderCluster(model.mesh, truth, CameraIntrinsics(), noise);
  } while (xyz->size() < 500);
  auto cloud = pcl::make_shared<CloudN>();
  pcl::copyPointCloud(*xyz, *cloud);
  for (auto& p : *cloud)
    p.getNormalVector3fMap() = -p.getVector3fMap().normalized();
  return cloud;
}

/** Scene-to-model start 5 mm and 3 degrees off the truth (the drop-in guess). */
Eigen::Matrix4f guessOff(const Eigen::Isometry3d& truth, double mm = 5.0, double deg = 3.0) {
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  delta.translation() = 1e-3 * mm * Eigen::Vector3d(0.6, -0.8, 0.0);
  delta.linear() =
      Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d(1, 2, 3).normalized()).matrix();
  return (delta * truth.inverse()).matrix().cast<float>();
}

/** The oracle: mean squared brute-force point-to-face distance of the finite source points
 * moved by \a scene_to_model. */
double bruteForceMeanSquared(const pcl::PolygonMesh& mesh, const CloudN& source,
                             const Eigen::Matrix4f& scene_to_model) {
  const pcl::icf::FaceMesh faces = pcl::icf::FaceMesh::build(mesh);
  const pcl::icf::BruteForceClosestFace brute(faces);
  const Eigen::Affine3f T(scene_to_model);
  double sum = 0.0;
  int n = 0;
  for (const auto& p : source) {
    if (!p.getVector3fMap().allFinite())
      continue;
    const double d = brute.closestFace(T * p.getVector3fMap()).distance;
    sum += d * d;
    ++n;
  }
  return sum / n;
}

/** Pose accuracy of a refinement from the 5 mm / 3 degree guess: 1 mm and 0.3 degrees, 5x and
 * 10x below the guess's error, so a refinement that did not move fails. The bound is set by the
 * data, not the method: refined from the true pose itself, these 1 mm-noise views of the box
 * end 0.002-0.6 mm and 0.01-0.18 degrees away (seeds 31-40; the worst shows mostly one face,
 * so the in-plane position rests on a few edge points). */
void expectRefined(pcl::Registration<PointN, PointN>& reg, const Eigen::Isometry3d& truth,
                   const SyntheticModel& model) {
  const auto error = pcl::icf::synthetic::poseError(
      toIsometry(Eigen::Matrix4f(reg.getFinalTransformation().inverse())), truth, model.symmetry);
  EXPECT_LE(error.translation, 0.001) << 1e3 * error.translation << " mm";
  EXPECT_LE(error.rotation_deg, 0.3);
}

/** ICF on Box5 behind a Registration pointer, its source a fresh view (boxView). */
struct BoxSetup {
  SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  CloudN::Ptr source;
  IcfN::Ptr icf = pcl::make_shared<IcfN>();
  RegistrationN::Ptr reg;
  explicit BoxSetup(std::uint64_t seed) : source(boxView(model, seed, truth)), reg(icf) {
    icf->setInputTarget(meshOf("Box5"));
    reg->setInputSource(source);
  }
};

TEST(IterativeClosestFaceDropIn, ThroughTheBasePointerLikeIcp) {
  BoxSetup box(31);
  const SyntheticModel& model = box.model;
  const Eigen::Isometry3d& truth = box.truth;
  const CloudN::Ptr& source = box.source;
  const IcfN::Ptr& icf = box.icf;
  const RegistrationN::Ptr& reg = box.reg;
  CloudN output;
  reg->align(output, guessOff(truth));
  ASSERT_TRUE(reg->hasConverged()) << pcl::icf::toString(icf->getResult().status);
  EXPECT_EQ(icf->getResult().method, "guess+icf");
  expectRefined(*reg, truth, model);

  // The output is the source moved by the final transformation, normals rotated (ICP's).
  const Eigen::Matrix4f T = reg->getFinalTransformation();
  const Eigen::Matrix3f R = T.topLeftCorner<3, 3>();
  ASSERT_EQ(output.size(), source->size());
  for (std::size_t i = 0; i < source->size(); ++i) {
    const Eigen::Vector3f x = R * (*source)[i].getVector3fMap() + T.block<3, 1>(0, 3);
    const Eigen::Vector3f n = R * (*source)[i].getNormalVector3fMap();
    ASSERT_LE((output[i].getVector3fMap() - x).norm(), 1e-6f) << i;
    ASSERT_LE((output[i].getNormalVector3fMap() - n).norm(), 1e-6f) << i;
  }

  // Fitness: ICP's definition with the mesh as target. The same quantity computed by brute
  // force at the final pose (float rounding: 1e-4 relative); within 30% of the true mean
  // squared point-to-mesh distance (at the true pose), the bar. The old
  // point-to-sample score read about 5x.
  const double fitness = reg->getFitnessScore();
  const double at_final = bruteForceMeanSquared(model.mesh, *source, T);
  const double at_truth =
      bruteForceMeanSquared(model.mesh, *source, truth.inverse().matrix().cast<float>());
  RecordProperty("fitness_over_truth", std::to_string(fitness / at_truth));
  EXPECT_NEAR(fitness, at_final, 1e-4 * at_final);
  EXPECT_NEAR(fitness, at_truth, 0.3 * at_truth);
  // max_range is compared with the squared distance (PCL's rule): 1 mm^2 keeps about the
  // points within 1 mm, so the mean is below 1e-6 and below the unbounded one.
  const double near = reg->getFitnessScore(1e-6);
  EXPECT_LE(near, 1e-6);
  EXPECT_LT(near, fitness);

  // Reuse on a new source.
  Eigen::Isometry3d truth2;
  const CloudN::Ptr source2 = boxView(model, 32, truth2);
  reg->setInputSource(source2);
  reg->align(output, guessOff(truth2, 4.0, -2.0));
  EXPECT_TRUE(reg->hasConverged());
  EXPECT_EQ(output.size(), source2->size());
  expectRefined(*reg, truth2, model);

  // No mesh: a clear failure, the output the unmoved source.
  auto bare = pcl::make_shared<IcfN>();
  RegistrationN::Ptr none = bare;
  none->setInputSource(source);
  none->align(output, guessOff(truth));
  EXPECT_FALSE(none->hasConverged());
  EXPECT_EQ(bare->getResult().status, pcl::icf::IcfStatus::NoModel);
  ASSERT_EQ(output.size(), source->size());
  EXPECT_EQ(output[0].getVector3fMap(), (*source)[0].getVector3fMap());
  EXPECT_TRUE(none->getFinalTransformation().isIdentity());
}

TEST(IterativeClosestFaceDropIn, ParamsAndBaseSettersShareOneStore) {
  IcfN icf;
  const pcl::icf::IcfParams defaults;
  // Defaults reach the base's members.
  EXPECT_EQ(icf.getMaximumIterations(), defaults.tuning().refinement.max_iterations);
  EXPECT_EQ(icf.getTransformationEpsilon(), defaults.tuning().refinement.transformation_epsilon);
  EXPECT_DOUBLE_EQ(icf.getMaxCorrespondenceDistance(),
                   defaults.tuning().refinement.initial_inlier_distance);
  EXPECT_NEAR(std::acos(icf.getTransformationRotationEpsilon()),
              defaults.tuning().refinement.rotation_epsilon, 1e-9);
  // setParams writes the base's members ...
  pcl::icf::IcfParams p;
  p.tuning().refinement.max_iterations = 17;
  p.tuning().refinement.transformation_epsilon = 1e-8;
  p.tuning().refinement.rotation_epsilon = 1e-3;
  p.tuning().refinement.euclidean_fitness_epsilon = 1e-4;
  p.tuning().refinement.initial_inlier_distance = 0.03f;
  icf.setParams(p);
  EXPECT_EQ(icf.getMaximumIterations(), 17);
  EXPECT_EQ(icf.getTransformationEpsilon(), 1e-8);
  EXPECT_EQ(icf.getEuclideanFitnessEpsilon(), 1e-4);
  EXPECT_DOUBLE_EQ(icf.getMaxCorrespondenceDistance(), double(0.03f));
  EXPECT_NEAR(icf.getParams().tuning().refinement.rotation_epsilon, 1e-3, 1e-9);
  // ... and the base setters write what getParams() (and align) use; the last call wins.
  icf.setMaximumIterations(9);
  icf.setMaxCorrespondenceDistance(0.004);
  icf.setEuclideanFitnessEpsilon(-1.0);       // PCL's "off"
  icf.setTransformationRotationEpsilon(0.0);  // ICP: 1 - transformation epsilon
  const pcl::icf::IcfParams q = icf.getParams();
  EXPECT_EQ(q.tuning().refinement.max_iterations, 9);
  EXPECT_FLOAT_EQ(q.tuning().refinement.initial_inlier_distance, 0.004f);
  EXPECT_FLOAT_EQ(q.tuning().refinement.final_inlier_distance, 0.004f);  // min(d, 6 mm)
  EXPECT_EQ(q.tuning().refinement.euclidean_fitness_epsilon, 0.0);
  EXPECT_NEAR(q.tuning().refinement.rotation_epsilon, std::acos(1.0 - 1e-8), 1e-9);
  EXPECT_NO_THROW(q.validate());
  icf.setParams(p);
  EXPECT_EQ(icf.getParams().tuning().refinement.max_iterations, 17);
}

TEST(IterativeClosestFaceDropIn, MaxCorrespondenceDistanceBoundsTheRefinement) {
  // The guess puts the points 8 cm in front of the box. With a correspondence distance below
  // the nearest point's brute-force distance to the mesh, no point has a partner (ICP's "not
  // converged": fewer than 3 correspondences) and the pose stays; with 15 cm the refinement
  // pulls it in.
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  const CloudN::Ptr source = boxView(model, 33, truth);
  const Eigen::Matrix4f guess =
      (truth.inverse() * Eigen::Translation3d(0.0, 0.0, -0.08)).matrix().cast<float>();
  const pcl::icf::FaceMesh faces = pcl::icf::FaceMesh::build(model.mesh);
  const pcl::icf::BruteForceClosestFace brute(faces);
  float nearest = std::numeric_limits<float>::infinity();
  for (const auto& p : *source)
    nearest =
        std::min(nearest, brute.closestFace(Eigen::Affine3f(guess) * p.getVector3fMap()).distance);
  ASSERT_GT(nearest, 0.002f);
  IcfN icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(source);
  CloudN output;
  icf.setMaxCorrespondenceDistance(0.5 * nearest);
  icf.align(output, guess);
  EXPECT_FALSE(icf.hasConverged());
  EXPECT_EQ(icf.getCorrespondenceCount(), 0u);
  EXPECT_TRUE(icf.getFinalTransformation().isApprox(guess, 1e-6f));
  icf.setMaxCorrespondenceDistance(0.15);
  icf.align(output, guess);
  EXPECT_TRUE(icf.hasConverged());
  EXPECT_GT(icf.getCorrespondenceCount(), source->size() / 2);
  expectRefined(icf, truth, model);
}

TEST(IterativeClosestFaceDropIn, EuclideanFitnessEpsilonIsRelative) {
  // With the step criteria off (translation epsilon 0, rotation cosine 1), only the fitness
  // criterion can stop the refinement before max_iterations: off (negative, PCL's) it runs all
  // 30; at 5% relative change it stops soon after the Tukey radius is final (iteration 5).
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  const CloudN::Ptr source = boxView(model, 34, truth);
  IcfN icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(source);
  icf.setTransformationEpsilon(0.0);
  icf.setTransformationRotationEpsilon(1.0);
  CloudN output;
  icf.setEuclideanFitnessEpsilon(-std::numeric_limits<double>::max());
  icf.align(output, guessOff(truth));
  EXPECT_EQ(icf.getResult().refinement_iterations, 30);
  icf.setEuclideanFitnessEpsilon(0.05);
  icf.align(output, guessOff(truth));
  EXPECT_LT(icf.getResult().refinement_iterations, 10);
  EXPECT_TRUE(icf.getResult().refinement_converged);
  expectRefined(icf, truth, model);
}

TEST(IterativeClosestFaceDropIn, HasConvergedIsIcpsAfterAGuessAndAcceptanceAfterASearch) {
  // A third of the box's view (the points with the smallest x): the refinement from a guess is
  // right, so hasConverged() is true as with ICP, while the acceptance test rejects the pose
  // (too little of the visible surface covered). Searched without a guess, the same cloud
  // reports the acceptance verdict.
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  const CloudN::Ptr full = boxView(model, 35, truth);
  std::vector<float> xs;
  for (const auto& p : *full)
    xs.push_back(p.x);
  std::nth_element(xs.begin(), xs.begin() + static_cast<long>(xs.size() / 3), xs.end());
  auto part = pcl::make_shared<CloudN>();
  for (const auto& p : *full)
    if (p.x < xs[xs.size() / 3])
      part->push_back(p);
  IcfN icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(part);
  CloudN output;
  icf.align(output, guessOff(truth));
  EXPECT_TRUE(icf.hasConverged());
  EXPECT_EQ(icf.getResult().status, pcl::icf::IcfStatus::Rejected)
      << "coverage " << icf.getResult().quality.surface_coverage;
  const auto error =
      pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), truth, model.symmetry);
  EXPECT_LE(error.translation, 0.002);
  icf.setGuessPolicy(IcfN::GuessPolicy::Never);
  icf.align(output, guessOff(truth));
  EXPECT_NE(icf.getResult().method, "guess+icf");
  EXPECT_EQ(icf.hasConverged(), icf.getResult().accepted());
}

TEST(IterativeClosestFaceDropIn, PreAlignedSourceIsRefinedInPlace) {
  // An ICP user moves the source by the guess and calls align(output): the identity is
  // refined first and, accepted, kept: no global search, no symmetric flip (checked without
  // the box's symmetry).
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  const CloudN::Ptr source = boxView(model, 36, truth);
  const Eigen::Matrix4f guess = guessOff(truth);
  auto moved = pcl::make_shared<CloudN>();
  pcl::transformPointCloudWithNormals(*source, *moved, guess);
  IcfN icf;
  icf.setInputTarget(meshOf("Box5"));
  icf.setInputSource(moved);
  icf.setCameraPose(Eigen::Isometry3f(guess));  // the camera moved with the cloud
  CloudN output;
  icf.align(output);
  EXPECT_EQ(icf.getResult().method, "identity+icf");
  EXPECT_TRUE(icf.hasConverged());
  const Eigen::Isometry3d truth_in_moved = Eigen::Isometry3d(guess.cast<double>()) * truth;
  const auto error = pcl::icf::synthetic::poseError(toIsometry(icf.getObjectPose()), truth_in_moved,
                                                    pcl::icf::synthetic::Symmetry::none());
  EXPECT_LE(error.translation, 0.0005);
  EXPECT_LE(error.rotation_deg, 0.3);
  // The same cloud far from the model (the camera's frame): the identity is not tried.
  icf.setInputSource(source);
  icf.resetCameraPose();
  icf.align(output);
  EXPECT_EQ(icf.getResult().method, "fast+icf");
}

TEST(IterativeClosestFaceDropIn, CameraPoseLikeTheLocalizers) {
  // camera -> source, defaulting to the cloud's sensor pose; moving the cloud and its camera
  // by M moves the found object by M (Amicelly: no symmetry to flip between).
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Amicelly");
  const Trial t = makeTrial(model, 12);
  IcfN::Ptr icf = pcl::make_shared<IcfN>();
  icf->setInputTarget(meshOf("Amicelly"));
  auto source = pcl::make_shared<CloudN>();
  pcl::copyPointCloud(*t.cluster, *source);
  icf->setInputSource(source);
  EXPECT_TRUE(icf->getCameraPose().isApprox(Eigen::Isometry3f::Identity()));
  CloudN output;
  icf->align(output);
  ASSERT_TRUE(icf->hasConverged());
  const Eigen::Isometry3d first = toIsometry(icf->getObjectPose());

  Eigen::Isometry3f M = Eigen::Isometry3f::Identity();
  M.translation() = Eigen::Vector3f(0.5f, -1.2f, 0.8f);
  M.linear() = Eigen::AngleAxisf(2.0f, Eigen::Vector3f(0.3f, 1.f, -0.2f).normalized()).matrix();
  auto moved = pcl::make_shared<CloudN>();
  pcl::transformPointCloud(*source, *moved, M.matrix());
  moved->sensor_origin_.head<3>() = M.translation();
  moved->sensor_orientation_ = Eigen::Quaternionf(M.linear());
  icf->setInputSource(moved);
  EXPECT_TRUE(icf->getCameraPose().isApprox(M, 1e-5f));
  icf->align(output);
  ASSERT_TRUE(icf->hasConverged());
  const auto error = pcl::icf::synthetic::poseError(toIsometry(icf->getObjectPose()),
                                                    M.cast<double>() * first, model.symmetry);
  // The same search in another frame differs by float rounding only; 1 mm / 0.5 degrees
  // allow the refinement to stop one iteration apart.
  EXPECT_LE(error.translation, 0.001);
  EXPECT_LE(error.rotation_deg, 0.5);
  // setCameraPose overrides the sensor pose; a non-rigid pose is refused.
  icf->setCameraPose(Eigen::Isometry3f::Identity());
  EXPECT_TRUE(icf->getCameraPose().isApprox(Eigen::Isometry3f::Identity()));
  Eigen::Isometry3f scaled = Eigen::Isometry3f::Identity();
  scaled.linear() *= 1.1f;
  EXPECT_THROW(icf->setCameraPose(scaled), std::invalid_argument);
}

template <typename PointT>
void refineWithType() {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  Eigen::Isometry3d truth;
  const CloudN::Ptr view = boxView(model, 37, truth);
  auto source = pcl::make_shared<pcl::PointCloud<PointT>>();
  pcl::copyPointCloud(*view, *source);
  typename pcl::Registration<PointT, PointT>::Ptr reg =
      pcl::make_shared<pcl::IterativeClosestFace<PointT>>();
  std::static_pointer_cast<pcl::IterativeClosestFace<PointT>>(reg)->setInputTarget(meshOf("Box5"));
  reg->setInputSource(source);
  pcl::PointCloud<PointT> output;
  reg->align(output, guessOff(truth));
  EXPECT_TRUE(reg->hasConverged());
  EXPECT_EQ(output.size(), source->size());
  const auto error = pcl::icf::synthetic::poseError(
      toIsometry(Eigen::Matrix4f(reg->getFinalTransformation().inverse())), truth, model.symmetry);
  EXPECT_LE(error.translation, 0.0005);
}

TEST(IterativeClosestFaceDropIn, PointTypesIcpIsUsedWith) {
  refineWithType<pcl::PointXYZ>();
  refineWithType<pcl::PointXYZI>();
  refineWithType<pcl::PointXYZRGB>();
  refineWithType<pcl::PointXYZRGBA>();
  refineWithType<pcl::PointNormal>();
  refineWithType<pcl::PointXYZRGBNormal>();
  refineWithType<pcl::PointXYZINormal>();
}

TEST(IterativeClosestFaceDropIn, BadInputThroughTheBasePointer) {
  BoxSetup box(38);
  const CloudN::Ptr& source = box.source;
  const IcfN::Ptr& icf = box.icf;
  const RegistrationN::Ptr& reg = box.reg;
  const Eigen::Isometry3d& truth = box.truth;
  // A point cloud is not a mesh target, also through the base pointer (virtual).
  EXPECT_THROW(reg->setInputTarget(source), std::invalid_argument);
  CloudN output;
  // A guess with a NaN, a scale, a shear, a reflection, a projective row.
  const Eigen::Matrix4f good = guessOff(truth);
  std::vector<Eigen::Matrix4f> bad(5, good);
  bad[0](1, 3) = std::numeric_limits<float>::quiet_NaN();
  bad[1].topLeftCorner<3, 3>() *= 1.01f;
  bad[2](0, 1) += 0.05f;
  bad[3].row(2) *= -1.f;
  bad[4](3, 0) = 0.1f;
  for (const auto& g : bad)
    EXPECT_THROW(reg->align(output, g), std::invalid_argument) << g;
  // max_range <= 0: refused by ICF's own getFitnessScore; through the base pointer PCL's
  // non-virtual function counts no point and returns its "none" value.
  reg->align(output, good);
  ASSERT_TRUE(reg->hasConverged());
  EXPECT_THROW(icf->getFitnessScore(0.0), std::invalid_argument);
  EXPECT_THROW(icf->getFitnessScore(-1.0), std::invalid_argument);
  EXPECT_THROW(icf->getFitnessScore(std::numeric_limits<double>::quiet_NaN()),
               std::invalid_argument);
  EXPECT_EQ(reg->getFitnessScore(-1.0), std::numeric_limits<double>::max());
  // Base setters with nonsense, refused at align with the setter's name.
  reg->setMaxCorrespondenceDistance(-0.01);
  try {
    reg->align(output, good);
    FAIL() << "a negative correspondence distance must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("setMaxCorrespondenceDistance"), std::string::npos);
  }
  reg->setMaxCorrespondenceDistance(0.02);
  reg->setMaximumIterations(-1);
  EXPECT_THROW(reg->align(output, good), std::invalid_argument);
}

}  // namespace
