/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bench_peers.h"

#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/CorrespondenceChecker.h>
#include <open3d/pipelines/registration/FastGlobalRegistration.h>
#include <open3d/pipelines/registration/Feature.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>
#include <open3d/utility/Logging.h>
#include <open3d/utility/Random.h>
#include <opencv2/core.hpp>
#include <opencv2/surface_matching.hpp>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <thread>

namespace pcl_icf_tools {
namespace bench {

namespace o3g = open3d::geometry;
namespace o3r = open3d::pipelines::registration;
namespace ppf = cv::ppf_match_3d;
using Clock = std::chrono::steady_clock;

/** Open3D's down-sampled model with FPFH and the full model samples with face normals (the ICP
 * target); OpenCV's detector trained on the model samples with their normals. */
struct PeerModel {
  std::shared_ptr<o3g::PointCloud> down, dense;
  std::shared_ptr<o3r::Feature> fpfh;
  cv::Mat samples;  ///< N x 6 float: x y z nx ny nz (PPF's training set and ICP model)
  std::unique_ptr<ppf::PPF3DDetector> detector;
};

namespace {

int threadCount(int threads) {
  return threads > 0 ? threads
                     : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/** OpenMP's thread count for the calls in the scope (Open3D and OpenCV use the default team). */
class OmpThreads {
 public:
  explicit OmpThreads(int n) : saved_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~OmpThreads() { omp_set_num_threads(saved_); }
  OmpThreads(const OmpThreads&) = delete;
  OmpThreads& operator=(const OmpThreads&) = delete;

 private:
  int saved_;
};

/** Normals over 2 voxels, FPFH over 5 (Open3D's tutorial, in voxels). */
std::shared_ptr<o3r::Feature> fpfhOf(const o3g::PointCloud& cloud, double voxel_size) {
  return o3r::ComputeFPFHFeature(cloud, o3g::KDTreeSearchParamHybrid(5.0 * voxel_size, 100));
}

/** The cluster as Open3D's cloud, down-sampled with normals towards the camera, and in full
 * (the ICP source). */
struct PeerScene {
  std::shared_ptr<o3g::PointCloud> down, full;
};

PeerScene sceneOf(const CloudXYZ& cluster, double voxel_size) {
  PeerScene s;
  s.full = std::make_shared<o3g::PointCloud>();
  s.full->points_.reserve(cluster.size());
  for (const auto& p : cluster)
    s.full->points_.push_back(p.getVector3fMap().cast<double>());
  s.down = s.full->VoxelDownSample(voxel_size);
  s.down->EstimateNormals(o3g::KDTreeSearchParamHybrid(2.0 * voxel_size, 30));
  s.down->OrientNormalsTowardsCameraLocation(cluster.sensor_origin_.head<3>().cast<double>());
  return s;
}

/** Point-to-plane ICP of the full cluster onto the model samples (with face normals) from the
 * global method's scene-to-model start, pairs within 4 voxels (the PCL pipelines' 2 cm). */
o3r::RegistrationResult refine(const PeerScene& scene, const PeerModel& model,
                               const Eigen::Matrix4d& start, double voxel_size) {
  return o3r::RegistrationICP(*scene.full, *model.dense, 4.0 * voxel_size, start,
                              o3r::TransformationEstimationPointToPlane());
}

MethodRun runOpen3d(bool fgr, const CloudXYZ::Ptr& cluster, const PeerModel& model,
                    double voxel_size, int seed, int threads) {
  MethodRun run;
  const auto start = Clock::now();
  OmpThreads team(threadCount(threads));
  const PeerScene scene = sceneOf(*cluster, voxel_size);
  const auto scene_fpfh = fpfhOf(*scene.down, voxel_size);
  o3r::RegistrationResult global;
  open3d::utility::random::Seed(seed);
  if (fgr) {
    o3r::FastGlobalRegistrationOption option;
    option.maximum_correspondence_distance_ = 0.5 * voxel_size;
    global = o3r::FastGlobalRegistrationBasedOnFeatureMatching(*scene.down, *model.down,
                                                               *scene_fpfh, *model.fpfh, option);
  } else {
    OmpThreads one(1);  // repeatable: the parallel loop draws from one generator in thread order
    const double distance = 1.5 * voxel_size;
    const o3r::CorrespondenceCheckerBasedOnEdgeLength edges(0.9);
    const o3r::CorrespondenceCheckerBasedOnDistance near(distance);
    global = o3r::RegistrationRANSACBasedOnFeatureMatching(
        *scene.down, *model.down, *scene_fpfh, *model.fpfh, true, distance,
        o3r::TransformationEstimationPointToPoint(false), 3, {std::cref(edges), std::cref(near)},
        o3r::RANSACConvergenceCriteria(100000, 0.999));
  }
  const o3r::RegistrationResult icp = refine(scene, model, global.transformation_, voxel_size);
  run.ms = msSince(start);
  run.object_pose = icp.transformation_.inverse().cast<float>();
  // Open3D's verdict: the global step found a pose with inliers, and the ICP kept pairs.
  run.converged = global.fitness_ > 0.0 && icp.fitness_ > 0.0;
  char detail[128];
  std::snprintf(detail, sizeof(detail), "%s fitness %.2f, icp fitness %.2f rmse %.1f mm",
                fgr ? "fgr" : "ransac", global.fitness_, icp.fitness_, 1e3 * icp.inlier_rmse_);
  run.detail = detail;
  return run;
}

cv::Mat withNormals(const CloudN& samples) {
  cv::Mat m(static_cast<int>(samples.size()), 6, CV_32F);
  for (int i = 0; i < m.rows; ++i) {
    const auto& p = samples[static_cast<std::size_t>(i)];
    const float row[6] = {p.x, p.y, p.z, p.normal_x, p.normal_y, p.normal_z};
    std::copy(row, row + 6, m.ptr<float>(i));
  }
  return m;
}

/** OpenCV's sample: scene normals from 10 neighbours towards the camera, one scene reference
 * point in 40 after sampling at 5% of the scene's extent, then OpenCV's ICP (100 iterations,
 * tolerance 0.005, rejection 2.5, 8 levels) on the 5 best-voted poses; the lowest residual wins.
 * Its ICP pairs every model point, the far side included, with the partial view: on the bunny
 * it turned PPF's poses (about 12 mm / 11 degrees off) into 140-180 degree flips, and PCL's ICP
 * in its place reached 0 of 120 synthetic views (doc/BENCHMARKS.md). */
MethodRun runPpf(const CloudXYZ::Ptr& cluster, const PeerModel& model, int threads) {
  MethodRun run;
  const auto start = Clock::now();
  OmpThreads team(threadCount(threads));
  // Scene normals from 10 neighbours (the sample's count), turned towards the camera, as the PCL
  // rows' are. (OpenCV's computeNormalsPC3d gave the same poses after its ICP: the flips
  // described above come from that ICP, not from the normals.)
  const cv::Mat scene = withNormals(*clusterWithNormals(cluster, 10, 0.0, threadCount(threads)));
  std::vector<ppf::Pose3DPtr> poses;
  model.detector->match(scene, poses, 1.0 / 40.0, 0.05);
  if (poses.size() > 5)
    poses.resize(5);
  if (!poses.empty()) {
    ppf::ICP icp(100, 0.005f, 2.5f, 8);
    icp.registerModelToScene(model.samples, scene, poses);
    const auto best =
        std::min_element(poses.begin(), poses.end(),
                         [](const auto& a, const auto& b) { return a->residual < b->residual; });
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k)
        run.object_pose(r, k) = static_cast<float>((*best)->pose(r, k));
    run.detail = "ppf votes " + std::to_string((*best)->numVotes) + ", icp residual " +
                 std::to_string((*best)->residual);
  } else {
    run.detail = "ppf: no pose";
  }
  run.ms = msSince(start);
  run.converged = !poses.empty();
  return run;
}

}  // namespace

const std::vector<std::string>& peerMethods() {
  static const std::vector<std::string> methods = {"o3d-ransac+icp", "o3d-fgr+icp", "ppf+icp"};
  return methods;
}

std::shared_ptr<const PeerModel> preparePeerModel(const PreparedModel& model, double voxel_size,
                                                  double ppf_sampling, int threads,
                                                  std::vector<double>& prepared_ms) {
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  OmpThreads team(threadCount(threads));
  auto peer = std::make_shared<PeerModel>();
  auto start = Clock::now();
  peer->dense = std::make_shared<o3g::PointCloud>();
  for (const auto& p : *model.dense_normals) {
    peer->dense->points_.push_back(p.getVector3fMap().cast<double>());
    peer->dense->normals_.push_back(p.getNormalVector3fMap().cast<double>());
  }
  peer->down = peer->dense->VoxelDownSample(voxel_size);  // averages the face normals too
  peer->down->NormalizeNormals();
  peer->fpfh = fpfhOf(*peer->down, voxel_size);
  prepared_ms = {msSince(start)};
  start = Clock::now();
  peer->samples = withNormals(*model.dense_normals);
  peer->detector = std::make_unique<ppf::PPF3DDetector>(ppf_sampling, 0.05);
  peer->detector->trainModel(peer->samples);
  prepared_ms.push_back(msSince(start));
  return peer;
}

MethodRun runPeer(const std::string& method, const CloudXYZ::Ptr& cluster,
                  const PreparedModel& model, double voxel_size, int seed, int threads) {
  if (!model.peers)
    throw std::logic_error("runPeer: the model's peer data were not prepared");
  if (method == "o3d-ransac+icp" || method == "o3d-fgr+icp")
    return runOpen3d(method == "o3d-fgr+icp", cluster, *model.peers, voxel_size, seed, threads);
  if (method == "ppf+icp")
    return runPpf(cluster, *model.peers, threads);
  throw std::logic_error("runPeer: unknown method " + method);
}

}  // namespace bench
}  // namespace pcl_icf_tools
