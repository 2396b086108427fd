// The SampleConsensus initial alignment (FPFH + pcl::SampleConsensusPrerejective /
// SampleConsensusInitialAlignment) on synthetic depth views, alone and as the fallback of
// estimatePose: it recovers a pose, is reproducible for a seed, fires under policy Auto only
// when the search's pose is rejected, never under Off, and replaces the search under Always.
#include "synthetic/depth_camera.h"
#include "synthetic/pose_error.h"
#include "synthetic/synthetic_models.h"
#include "test_paths.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/iterative_closest_face.h>
#include <pcl/icf/registration/sample_consensus_alignment.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <iterator>
#include <memory>

namespace {

using pcl::icf::FallbackPolicy;
using pcl::icf::IcfModel;
using pcl::icf::SacParams;
using pcl::icf::SacStatus;
using pcl::icf::synthetic::SyntheticModel;

struct Trial {
  Eigen::Isometry3d truth;
  std::vector<Eigen::Vector3f> points;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud;
};

/** A random pose 0.7 - 1.1 m in front of the camera and its noisy view (1.5 mm at 1 m,
 * growing with depth^2; 5% outliers within +-5 cm along the ray). */
Trial makeTrial(const SyntheticModel& model, std::uint64_t seed) {
  const pcl::icf::synthetic::RandomView view = pcl::icf::synthetic::randomView(model.mesh, seed);
  Trial t;
  t.truth = view.truth;
  t.cloud = view.cluster;
  for (const auto& p : *t.cloud)
    t.points.push_back(p.getVector3fMap());
  return t;
}

pcl::icf::synthetic::PoseError errorOf(const Eigen::Matrix4f& scene_to_model, const Trial& t,
                                       const SyntheticModel& model) {
  const Eigen::Isometry3d pose(scene_to_model.cast<double>().inverse());
  return pcl::icf::synthetic::poseError(pose, t.truth, model.symmetry);
}

/** The Stanford bunny (real scanned mesh) from \p path (PCL_ICF_REQUIRE_SHARED's
 * ../shared/data/meshes/bunny.ply). */
std::unique_ptr<SyntheticModel> bunny(const std::string& path) {
  auto model = std::make_unique<SyntheticModel>();
  model->name = "bunny";
  model->mesh = pcl::icf::io::loadPolygonMesh(path);
  model->symmetry = pcl::icf::synthetic::Symmetry::none();
  return model;
}

// SAC alone, no refinement, on the shape FPFH was made for (a free-form scan). Keypoints are
// centroids of 5 mm voxels, so a 3-point fit is quantised to a few millimetres: we ask for the
// issue's success bar (1 cm and 5 degrees, about 1 cm of arc over the bunny's 8 cm radius)
// from prerejective, and for the refinement's basin (2 cm, 10 degrees) from SAC-IA, whose
// truncated score is coarser. 8 of 10 seeded views each. (On the thesis's primitives, flat
// faces and bodies of revolution, FPFH is far weaker: doc/BENCHMARKS.md.)
TEST(SampleConsensusAlign, RecoversBunnyViewsWithoutRefinement) {
  PCL_ICF_REQUIRE_SHARED(bunny_path, "meshes/bunny.ply");
  const auto model = bunny(bunny_path);
  const IcfModel::ConstPtr prepared = IcfModel::build(model->mesh);
  for (const auto method :
       {pcl::icf::SacMethod::Prerejective, pcl::icf::SacMethod::InitialAlignment}) {
    SacParams params;
    params.method = method;
    const bool ia = method == pcl::icf::SacMethod::InitialAlignment;
    if (ia)
      params.max_iterations = 1000;
    const double max_t = ia ? 0.02 : 0.01, max_r = ia ? 10.0 : 5.0;
    int successes = 0;
    // Under the sanitizers (PCL_ICF_SANITIZED) 3 views check memory and behaviour; the release
    // run holds the 8-of-10 bar.
    const std::uint64_t views = std::getenv("PCL_ICF_SANITIZED") ? 3 : 10;
    for (std::uint64_t seed = 300; seed < 300 + views; ++seed) {
      const Trial t = makeTrial(*model, seed);
      const auto r =
          pcl::icf::sampleConsensusAlign(*prepared, t.points, Eigen::Vector3f::Zero(), params, 2);
      const auto e = errorOf(r.scene_to_model, t, *model);
      const bool ok = r.found() && e.translation <= max_t && e.rotation_deg <= max_r;
      successes += ok;
      if (!ok)
        std::cout << pcl::icf::toString(method) << " seed " << seed << ": "
                  << pcl::icf::toString(r.status) << ", " << 1e3 * e.translation << " mm, "
                  << e.rotation_deg << " deg, inliers " << r.inlier_fraction << " of "
                  << r.keypoints << "\n";
      if (r.found() && !ia) {
        EXPECT_GE(r.inlier_fraction, params.inlier_fraction);
      }
      if (r.found()) {
        EXPECT_LE(r.fitness,
                  params.max_correspondence_distance * params.max_correspondence_distance);
      }
    }
    EXPECT_GE(successes, views == 10 ? 8 : 2) << pcl::icf::toString(method);
  }
}

TEST(SampleConsensusAlign, SameSeedSameResultForAnyThreadCount) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Amicelly");
  const IcfModel::ConstPtr prepared = IcfModel::build(model.mesh);
  const Trial t = makeTrial(model, 17);
  for (const auto method :
       {pcl::icf::SacMethod::Prerejective, pcl::icf::SacMethod::InitialAlignment}) {
    SacParams params;
    params.method = method;
    params.max_iterations = method == pcl::icf::SacMethod::Prerejective ? 5000 : 300;
    const auto a =
        pcl::icf::sampleConsensusAlign(*prepared, t.points, Eigen::Vector3f::Zero(), params, 1);
    const auto b =
        pcl::icf::sampleConsensusAlign(*prepared, t.points, Eigen::Vector3f::Zero(), params, 2);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.scene_to_model, b.scene_to_model) << pcl::icf::toString(method);
    EXPECT_EQ(a.inliers, b.inliers);
    // Another seed draws other hypotheses (the pose may still agree; the draws must differ
    // somewhere, and rarely end bit-identical).
    params.seed = 7;
    const auto c =
        pcl::icf::sampleConsensusAlign(*prepared, t.points, Eigen::Vector3f::Zero(), params, 2);
    EXPECT_NE(a.scene_to_model, c.scene_to_model) << pcl::icf::toString(method);
  }
}

TEST(SampleConsensusAlign, ModelFeaturesAreCachedByContent) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Box5");
  const IcfModel::ConstPtr a = IcfModel::build(model.mesh);
  const IcfModel::ConstPtr b = IcfModel::build(model.mesh);  // same mesh, another object
  SacParams params;
  const auto fa = pcl::icf::cachedSacModel(*a, params);
  EXPECT_EQ(fa, pcl::icf::cachedSacModel(*a, params));
  EXPECT_EQ(fa, pcl::icf::cachedSacModel(*b, params));
  params.max_iterations = 10;  // does not affect the features
  EXPECT_EQ(fa, pcl::icf::cachedSacModel(*a, params));
  params.feature_radius = 0.03f;  // does
  EXPECT_NE(fa, pcl::icf::cachedSacModel(*a, params));
  // Features built with other parameters are refused rather than silently misused.
  const Trial t = makeTrial(model, 2);
  EXPECT_THROW(pcl::icf::sampleConsensusAlign(*fa, t.points, Eigen::Vector3f::Zero(), params, 1),
               std::invalid_argument);
  // Cleared, the cache builds the features again: the same features, a new object.
  params.feature_radius = SacParams().feature_radius;
  pcl::icf::clearSacModelCache();
  const auto rebuilt = pcl::icf::cachedSacModel(*a, params);
  EXPECT_NE(fa, rebuilt);
  ASSERT_EQ(fa->features->size(), rebuilt->features->size());
  for (std::size_t i = 0; i < fa->features->size(); ++i)
    ASSERT_TRUE(std::equal(std::begin((*fa->features)[i].histogram),
                           std::end((*fa->features)[i].histogram),
                           std::begin((*rebuilt->features)[i].histogram)));
}

TEST(SampleConsensusAlign, TooFewPointsIsAStatusNotAnError) {
  const IcfModel::ConstPtr model = IcfModel::build(pcl::icf::synthetic::thesisModel("Box5").mesh);
  const std::vector<Eigen::Vector3f> few = {Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(0, 0.01f, 1)};
  const auto r = pcl::icf::sampleConsensusAlign(*model, few, Eigen::Vector3f::Zero(), {}, 1);
  EXPECT_EQ(r.status, SacStatus::TooFewPoints);
  EXPECT_TRUE(r.scene_to_model.isIdentity());
  EXPECT_EQ(pcl::icf::sampleConsensusAlign(*model, {}, Eigen::Vector3f::Zero(), {}, 1).status,
            SacStatus::TooFewPoints);
}

TEST(SacParams, DocumentedDefaultsAndValidation) {
  const SacParams p;
  EXPECT_EQ(p.method, pcl::icf::SacMethod::Prerejective);
  EXPECT_FLOAT_EQ(p.voxel_size, 0.005f);
  EXPECT_EQ(p.model_samples, 50000u);
  EXPECT_FLOAT_EQ(p.normal_radius, 0.01f);
  EXPECT_FLOAT_EQ(p.feature_radius, 0.025f);
  EXPECT_EQ(p.max_iterations, 20000);
  EXPECT_EQ(p.samples_per_hypothesis, 3);
  EXPECT_EQ(p.correspondence_randomness, 5);
  EXPECT_FLOAT_EQ(p.similarity_threshold, 0.9f);
  EXPECT_FLOAT_EQ(p.max_correspondence_distance, 0.0125f);
  EXPECT_FLOAT_EQ(p.inlier_fraction, 0.25f);
  EXPECT_EQ(p.seed, 42u);
  EXPECT_NO_THROW(p.validate());
  EXPECT_EQ(pcl::icf::IcfParams().fallback, FallbackPolicy::Auto);

  auto expectNamed = [](const SacParams& bad, const std::string& field) {
    try {
      bad.validate();
      FAIL() << field << " must be refused";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  SacParams bad;
  bad.voxel_size = -1.f;
  expectNamed(bad, "voxel_size");
  bad = {};
  bad.similarity_threshold = 1.f;
  expectNamed(bad, "similarity_threshold");
  bad = {};
  bad.inlier_fraction = 1.5f;
  expectNamed(bad, "inlier_fraction");
  bad = {};
  bad.feature_radius = 0.005f;  // below normal_radius
  expectNamed(bad, "feature_radius");
  bad = {};
  bad.samples_per_hypothesis = 2;
  expectNamed(bad, "samples_per_hypothesis");
  // estimatePose validates the SAC params only when the fallback can run.
  pcl::icf::IcfParams icf;
  icf.tuning().sac.max_iterations = 0;
  EXPECT_THROW(icf.validate(), std::invalid_argument);
  icf.fallback = FallbackPolicy::Off;
  EXPECT_NO_THROW(icf.validate());

  EXPECT_EQ(pcl::icf::parseFallbackPolicy("off"), FallbackPolicy::Off);
  EXPECT_EQ(pcl::icf::parseFallbackPolicy("auto"), FallbackPolicy::Auto);
  EXPECT_EQ(pcl::icf::parseFallbackPolicy("always"), FallbackPolicy::Always);
  EXPECT_THROW(pcl::icf::parseFallbackPolicy("sometimes"), std::invalid_argument);
  EXPECT_EQ(pcl::icf::toString(FallbackPolicy::Always), "always");
  EXPECT_EQ(pcl::icf::parseSacMethod("ia"), pcl::icf::SacMethod::InitialAlignment);
  EXPECT_THROW(pcl::icf::parseSacMethod("ransac"), std::invalid_argument);
}

/** The global search reduced to one rotation and one kept hypothesis: a view whose true
 * rotation is far from that single rotation cannot be found by it. The thesis's gate is on
 * (10% of the points may lie beyond 27 mm: the scan's outliers) so that a wrong pose that
 * leaves part of this single-object cluster unexplained is rejected. */
pcl::icf::IcfParams crippledSearch(std::size_t points) {
  pcl::icf::IcfParams params;
  params.tuning().global.rotations = 1;
  params.tuning().global.keep = 1;
  params.tuning().exact_candidates = 1;
  params.acceptance.gate.enabled = true;
  params.acceptance.gate.max_points = static_cast<int>(points / 10);
  return params;
}

/** Over seeded views: with policy Off the crippled search is often rejected; then policy Auto
 * must run the fallback (always) and recover the pose wherever SampleConsensus can: the oracle
 * is policy Always on the same points (SAC alone, then the refinement), so a view FPFH cannot
 * match on does not count against the fallback. A rejected search pose is one the acceptance
 * test (coverage, RMSE, the gate, the seen-through check) turns down. */
void expectFallbackRecovers(const SyntheticModel& model, std::uint64_t first, std::uint64_t last,
                            int min_fired, int min_recoverable) {
  const IcfModel::ConstPtr prepared = IcfModel::build(model.mesh);
  int fired = 0, recoverable = 0, recovered = 0;
  for (std::uint64_t seed = first; seed < last; ++seed) {
    const Trial t = makeTrial(model, seed);
    pcl::icf::IcfParams params = crippledSearch(t.points.size());
    params.fallback = FallbackPolicy::Off;
    const auto off = pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params);
    EXPECT_FALSE(off.fallback_ran);
    EXPECT_EQ(off.method, "fast+icf");
    EXPECT_EQ(off.sac_status, SacStatus::NotRun);
    params.fallback = FallbackPolicy::Auto;
    const auto r = pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params);
    if (off.accepted()) {  // nothing to fall back from: Auto is Off
      EXPECT_FALSE(r.fallback_ran) << model.name << " seed " << seed;
      EXPECT_EQ(r.scene_to_model, off.scene_to_model);
      continue;
    }
    ++fired;
    EXPECT_TRUE(r.fallback_ran) << model.name << " seed " << seed;
    EXPECT_NE(r.sac_status, SacStatus::NotRun);
    params.fallback = FallbackPolicy::Always;
    const auto sac = pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params);
    const auto e_sac = errorOf(sac.scene_to_model, t, model);
    if (!(sac.accepted() && e_sac.translation <= 0.005 && e_sac.rotation_deg <= 3.0))
      continue;  // SampleConsensus cannot find this view: nothing to recover
    ++recoverable;
    const auto e = errorOf(r.scene_to_model, t, model);
    const bool ok =
        r.accepted() && r.method == "sac+icf" && e.translation <= 0.005 && e.rotation_deg <= 3.0;
    recovered += ok;
    if (!ok)
      std::cout << model.name << " seed " << seed << ": " << r.method << ", "
                << pcl::icf::toString(r.status) << ", sac " << pcl::icf::toString(r.sac_status)
                << ", " << 1e3 * e.translation << " mm, " << e.rotation_deg << " deg\n";
  }
  std::cout << model.name << ": the search rejected on " << fired << " views, SampleConsensus "
            << "alone right on " << recoverable << ", the fallback recovered " << recovered << "\n";
  EXPECT_GE(fired, min_fired) << model.name << ": the crippled search should fail sometimes";
  EXPECT_GE(recoverable, min_recoverable) << model.name << ": SampleConsensus finds too few";
  EXPECT_EQ(recovered, recoverable) << model.name << ": recovered " << recovered << " of "
                                    << recoverable << " that SampleConsensus alone finds";
}

TEST(Fallback, AutoFiresWhenTheSearchFailsAndRecoversThePose) {
  // The thesis's primitives: the crippled search is rejected on 4 of 12 salt views and 4 of 12
  // box views (one of each a wrong pose that only the seen-through check rejects);
  // SampleConsensus alone finds 3 and 2 of those (FPFH is weak on flat faces), and the fallback
  // must recover exactly those.
  expectFallbackRecovers(pcl::icf::synthetic::thesisModel("YellowRoundSalt"), 40, 52, 1, 1);
  expectFallbackRecovers(pcl::icf::synthetic::thesisModel("Box5"), 40, 52, 1, 1);
}

TEST(Fallback, AutoRecoversBunnyViewsTheCrippledSearchMisses) {
  if (std::getenv("PCL_ICF_SANITIZED"))
    GTEST_SKIP() << "24 bunny registrations take minutes under ASan; the release run covers it";
  PCL_ICF_REQUIRE_SHARED(bunny_path, "meshes/bunny.ply");
  const auto model = bunny(bunny_path);
  expectFallbackRecovers(*model, 40, 52, 3, 0);
}

TEST(Fallback, AutoStaysQuietWhenTheSearchSucceedsAndAlwaysReplacesIt) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("Amicelly");
  const IcfModel::ConstPtr prepared = IcfModel::build(model.mesh);
  const Trial t = makeTrial(model, 23);
  pcl::icf::IcfParams params;  // default: fast search, fallback Auto
  const auto automatic =
      pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params);
  ASSERT_TRUE(automatic.accepted());
  EXPECT_FALSE(automatic.fallback_ran);
  EXPECT_EQ(automatic.method, "fast+icf");
  EXPECT_EQ(automatic.sac_status, SacStatus::NotRun);

  params.fallback = FallbackPolicy::Always;
  const auto always = pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params);
  EXPECT_TRUE(always.fallback_ran);
  EXPECT_EQ(always.method, "sac+icf");
  EXPECT_EQ(always.sac_status, SacStatus::Found);
  EXPECT_TRUE(always.accepted());
  const auto e = errorOf(always.scene_to_model, t, model);
  EXPECT_LE(e.translation, 0.005);
  EXPECT_LE(e.rotation_deg, 3.0);

  // A guess means "refine from here": no fallback, whatever the policy.
  pcl::icf::PoseEstimateOptions options;
  options.guess = Eigen::Isometry3f(always.scene_to_model);
  const auto guessed =
      pcl::icf::estimatePose(*prepared, t.points, Eigen::Vector3f::Zero(), params, options);
  EXPECT_FALSE(guessed.fallback_ran);
  EXPECT_EQ(guessed.method, "guess+icf");
}

TEST(Fallback, ReachesIterativeClosestFaceThroughItsParams) {
  const SyntheticModel model = pcl::icf::synthetic::thesisModel("YellowRoundSalt");
  const Trial t = makeTrial(model, 40);
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputTarget(pcl::make_shared<pcl::PolygonMesh>(model.mesh));
  icf.setInputSource(t.cloud);
  pcl::icf::IcfParams params = crippledSearch(t.points.size());
  params.fallback = FallbackPolicy::Always;
  icf.setParams(params);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icf.align(aligned);
  EXPECT_EQ(icf.getResult().method, "sac+icf");
  EXPECT_TRUE(icf.hasConverged());
  const auto e = pcl::icf::synthetic::poseError(
      Eigen::Isometry3d(icf.getObjectPose().cast<double>()), t.truth, model.symmetry);
  EXPECT_LE(e.translation, 0.005);
  EXPECT_LE(e.rotation_deg, 3.0);
}

}  // namespace
