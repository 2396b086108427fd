// Results do not depend on the thread count (doc/ARCHITECTURE.md "Threads and
// determinism"): the same seed gives bit-identical poses, scores and decisions with 1, 2 and 3
// threads, for the localizer over a whole scene, for the thesis search and for the
// SampleConsensus fallback. Run under ThreadSanitizer by the "tsan" preset.
#include "synthetic/depth_camera.h"
#include "synthetic/synthetic_models.h"

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/icf_model.h>

#include <gtest/gtest.h>

namespace {

using namespace pcl::icf;
using localization::LocalizerParams;

std::vector<Eigen::Vector3f> boxView(std::uint64_t seed) {
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.translate(Eigen::Vector3d(-0.02, 0.03, 0.85));
  truth.rotate(Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, 1, 0.5).normalized()));
  synthetic::ScanNoise noise;
  noise.seed = seed;
  const auto cloud =
      synthetic::renderCluster(synthetic::makeBox5(), truth, synthetic::CameraIntrinsics(), noise);
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : *cloud)
    points.push_back(p.getVector3fMap());
  return points;
}

TEST(ThreadDeterminism, LocalizerOnAScene) {
  // The target among two distractors that touch it: merged clusters, convexity segments,
  // clusters judged in parallel.
  const std::vector<synthetic::SyntheticModel> models = {synthetic::thesisModel("Box5"),
                                                         synthetic::thesisModel("Cup"),
                                                         synthetic::thesisModel("Amicelly")};
  synthetic::ScanNoise noise;
  noise.outlier_ratio = 0.0;
  const synthetic::TabletopScene scene = synthetic::makeTabletopScene(
      models,
      {Eigen::Vector3d(0.0, 0.0, 0.4), Eigen::Vector3d(0.12, 0.02, 0.0),
       Eigen::Vector3d(-0.15, -0.05, 1.0)},
      synthetic::CameraIntrinsics(), noise);
  const IcfModel::ConstPtr model = IcfModel::build(models.front().mesh);
  std::vector<localization::Localization> runs;
  for (int threads : {1, 2, 3}) {
    LocalizerParams params;
    params.threads = threads;
    params.seed = 7;
    runs.push_back(localization::localizeObject(*scene.scan.cloud, *model, params));
  }
  ASSERT_GE(runs[0].clusters.size(), 1u);
  for (std::size_t r = 1; r < runs.size(); ++r) {
    SCOPED_TRACE("threads " + std::to_string(r + 1));
    EXPECT_EQ(runs[r].status, runs[0].status);
    EXPECT_EQ(runs[r].best, runs[0].best);
    ASSERT_EQ(runs[r].clusters.size(), runs[0].clusters.size());
    for (std::size_t k = 0; k < runs[0].clusters.size(); ++k) {
      const auto& a = runs[0].clusters[k];
      const auto& b = runs[r].clusters[k];
      EXPECT_EQ(a.indices.indices, b.indices.indices);
      EXPECT_EQ(a.icf.object_pose, b.icf.object_pose) << "cluster " << k;
      EXPECT_EQ(a.icf.method, b.icf.method);
      EXPECT_EQ(a.score, b.score);
      EXPECT_EQ(a.accepted, b.accepted);
      EXPECT_EQ(a.reason, b.reason);
    }
  }
}

TEST(ThreadDeterminism, ThesisSearchAndSampleConsensusFallback) {
  const IcfModel::ConstPtr model = IcfModel::build(synthetic::makeBox5());
  const std::vector<Eigen::Vector3f> points = boxView(3);
  for (const bool thesis : {true, false}) {
    SCOPED_TRACE(thesis ? "thesis search" : "SampleConsensus (fallback Always)");
    IcfParams params;
    params.seed = 11;
    params.tuning().sac.seed = 12;
    if (thesis) {
      params.strategy = SearchStrategy::Thesis;
      params.fallback = FallbackPolicy::Off;
      params.tuning().thesis.outer_iterations = 4;
      params.tuning().thesis.orientation_iterations = 15;
    } else {
      params.fallback = FallbackPolicy::Always;
      params.tuning().sac.max_iterations = 5000;
    }
    Eigen::Matrix4f first = Eigen::Matrix4f::Zero();
    for (int threads : {1, 2, 3}) {
      params.threads = threads;
      const IcfResult r = estimatePose(*model, points, Eigen::Vector3f::Zero(), params);
      ASSERT_TRUE(r.object_pose.allFinite());
      if (threads == 1)
        first = r.object_pose;
      else
        EXPECT_EQ(r.object_pose, first) << threads << " threads";
    }
  }
}

}  // namespace
