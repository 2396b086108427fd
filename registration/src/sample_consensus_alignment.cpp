/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/features/fpfh_omp.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/icf/registration/sample_consensus_alignment.h>
#include <pcl/registration/ia_ransac.h>
#include <pcl/registration/sample_consensus_prerejective.h>
#include <pcl/search/kdtree.h>
#include <pcl_icf_internal/parameter_check.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <list>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace pcl {
namespace icf {

using Clock = std::chrono::steady_clock;
using PointCloudN = pcl::PointCloud<pcl::PointNormal>;
using FeatureCloud = pcl::PointCloud<pcl::FPFHSignature33>;

SacMethod parseSacMethod(const std::string& name) {
  if (name == "prerejective")
    return SacMethod::Prerejective;
  if (name == "ia")
    return SacMethod::InitialAlignment;
  throw std::invalid_argument("unknown sample-consensus method '" + name +
                              "' (expected prerejective or ia)");
}

std::string toString(SacMethod method) {
  return method == SacMethod::Prerejective ? "prerejective" : "ia";
}

std::string toString(SacStatus status) {
  switch (status) {
    case SacStatus::NotRun:
      return "not run";
    case SacStatus::Found:
      return "found";
    case SacStatus::NotFound:
      return "not found";
    case SacStatus::TooFewPoints:
      return "too few points";
  }
  return "unknown";
}

void SacParams::validate() const {
  const internal::ParameterCheck fail("SacParams");
  auto positive = [&fail](const char* field, float value) {
    if (!(value > 0.f) || !std::isfinite(value))
      fail(field, value, "must be positive and finite");
  };
  positive("voxel_size", voxel_size);
  positive("normal_radius", normal_radius);
  positive("feature_radius", feature_radius);
  positive("max_correspondence_distance", max_correspondence_distance);
  if (feature_radius <= normal_radius)
    fail("feature_radius", feature_radius, "must exceed normal_radius");
  if (model_samples < 100 || model_samples > 10000000)
    fail("model_samples", static_cast<double>(model_samples), "must lie in [100, 1e7]");
  if (max_iterations < 1)
    fail("max_iterations", max_iterations, "must be at least 1");
  if (samples_per_hypothesis < 3)
    fail("samples_per_hypothesis", samples_per_hypothesis, "must be at least 3");
  if (correspondence_randomness < 1)
    fail("correspondence_randomness", correspondence_randomness, "must be at least 1");
  if (!(similarity_threshold >= 0.f && similarity_threshold < 1.f))
    fail("similarity_threshold", similarity_threshold, "must lie in [0, 1)");
  if (!(inlier_fraction >= 0.f && inlier_fraction <= 1.f))
    fail("inlier_fraction", inlier_fraction, "must lie in [0, 1]");
  if (!(min_sample_distance >= 0.f) || !std::isfinite(min_sample_distance))
    fail("min_sample_distance", min_sample_distance, "must be finite and >= 0");
}

namespace {

int resolveThreads(int threads) {
  if (threads < 0)
    throw std::invalid_argument("sampleConsensusAlign: threads = " + std::to_string(threads) +
                                " < 0");
  return threads > 0 ? threads : omp_get_num_procs();
}

/** The parameters the model's features depend on are equal. */
bool sameFeatureParams(const SacParams& a, const SacParams& b) {
  return a.voxel_size == b.voxel_size && a.normal_radius == b.normal_radius &&
         a.feature_radius == b.feature_radius && a.model_samples == b.model_samples &&
         a.seed == b.seed;
}

PointCloudN::Ptr voxelReduce(const PointCloudN::ConstPtr& cloud, float leaf) {
  auto reduced = pcl::make_shared<PointCloudN>();
  pcl::VoxelGrid<pcl::PointNormal> grid;
  grid.setInputCloud(cloud);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(*reduced);
  return reduced;
}

/** FPFH of \a keypoints (with normals) over themselves; keeps the pairs with finite normal and
 * descriptor. */
void describe(const PointCloudN::Ptr& keypoints, float radius, int threads,
              PointCloudN& kept_points, FeatureCloud& kept_features) {
  kept_points.clear();
  kept_features.clear();
  auto finite = pcl::make_shared<PointCloudN>();
  for (const auto& p : *keypoints)
    if (p.getNormalVector3fMap().allFinite() && p.getVector3fMap().allFinite())
      finite->push_back(p);
  if (finite->empty())
    return;
  FeatureCloud features;
  pcl::FPFHEstimationOMP<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> fpfh(
      static_cast<unsigned>(threads));
  fpfh.setInputCloud(finite);
  fpfh.setInputNormals(finite);
  fpfh.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointNormal>>());
  fpfh.setRadiusSearch(radius);
  fpfh.compute(features);
  for (std::size_t i = 0; i < finite->size(); ++i) {
    const auto& h = features[i].histogram;
    bool ok = true;
    float sum = 0.f;
    for (float v : h) {
      ok = ok && std::isfinite(v);
      sum += v;
    }
    if (ok && sum > 0.f) {
      kept_points.push_back((*finite)[i]);
      kept_features.push_back(features[i]);
    }
  }
}

std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    hash ^= p[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

std::uint64_t modelKey(const FaceMesh& mesh, const SacParams& params) {
  std::uint64_t h = 14695981039346656037ull;
  for (const auto& v : mesh.vertices())
    h = fnv1a(h, v.data(), 3 * sizeof(float));
  const auto& indices = mesh.faceVertexIndices();
  h = fnv1a(h, indices.data(), indices.size() * sizeof(std::uint32_t));
  for (const auto& f : mesh.faces())
    h = fnv1a(h, &f.count, sizeof(f.count));
  const float radii[3] = {params.voxel_size, params.normal_radius, params.feature_radius};
  h = fnv1a(h, radii, sizeof(radii));
  const std::uint64_t counts[2] = {params.model_samples, params.seed};
  return fnv1a(h, counts, sizeof(counts));
}

/** PCL's aligners draw with the global rand(): one at a time, each after srand(seed). */
std::mutex& randMutex() {
  static std::mutex mutex;
  return mutex;
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

SacModelFeatures::ConstPtr prepareSacModel(const FaceMesh& mesh, const SacParams& params,
                                           int threads) {
  params.validate();
  threads = resolveThreads(threads);
  const std::vector<SurfaceSample> samples = sampleSurface(mesh, params.model_samples, params.seed);
  auto dense = pcl::make_shared<PointCloudN>();
  dense->reserve(samples.size());
  for (const auto& s : samples) {
    pcl::PointNormal p;
    p.getVector3fMap() = s.point;
    p.getNormalVector3fMap() = s.normal;
    dense->push_back(p);
  }
  // Keypoints: one per voxel. Their normals are estimated over the dense samples as the
  // scene's are over the full cluster (the same smoothing at edges), then turned outwards to
  // agree with the face of the nearest sample (the scene's face the camera).
  const PointCloudN::Ptr keypoints = voxelReduce(dense, params.voxel_size);
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointNormal>>();
  pcl::NormalEstimationOMP<pcl::PointNormal, pcl::PointNormal> normals(
      static_cast<unsigned>(threads));
  normals.setInputCloud(keypoints);
  normals.setSearchSurface(dense);
  normals.setSearchMethod(tree);
  normals.setRadiusSearch(params.normal_radius);
  PointCloudN estimated;
  normals.compute(estimated);
  pcl::search::KdTree<pcl::PointNormal> nearest;
  nearest.setInputCloud(dense);
  pcl::Indices index(1);
  std::vector<float> sqr(1);
  for (std::size_t i = 0; i < keypoints->size(); ++i) {
    auto& k = (*keypoints)[i];
    Eigen::Vector3f n = estimated[i].getNormalVector3fMap();
    if (nearest.nearestKSearch(k, 1, index, sqr) == 1 &&
        n.dot((*dense)[static_cast<std::size_t>(index[0])].getNormalVector3fMap()) < 0.f)
      n = -n;
    k.getNormalVector3fMap() = n;
    k.curvature = estimated[i].curvature;
  }
  auto points = pcl::make_shared<PointCloudN>();
  auto features = pcl::make_shared<FeatureCloud>();
  describe(keypoints, params.feature_radius, threads, *points, *features);
  auto result = std::make_shared<SacModelFeatures>();
  result->points = points;
  result->features = features;
  result->params = params;
  return result;
}

namespace {

/** The process-wide cache behind cachedSacModel: model features, most recently used first,
 * keyed by modelKey. */
struct SacModelCache {
  static constexpr std::size_t kCapacity = 8;
  std::mutex mutex;
  std::list<std::pair<std::uint64_t, SacModelFeatures::ConstPtr>> entries;  // MRU first
};

SacModelCache& sacModelCache() {
  static SacModelCache cache;
  return cache;
}

}  // namespace

SacModelFeatures::ConstPtr cachedSacModel(const IcfModel& model, const SacParams& params,
                                          int threads) {
  params.validate();
  SacModelCache& cache = sacModelCache();
  const std::uint64_t key = modelKey(model.mesh(), params);
  std::lock_guard<std::mutex> lock(cache.mutex);
  for (auto it = cache.entries.begin(); it != cache.entries.end(); ++it)
    if (it->first == key) {
      cache.entries.splice(cache.entries.begin(), cache.entries, it);
      return cache.entries.front().second;
    }
  // Built under the lock: two threads asking for the same new model build it once.
  SacModelFeatures::ConstPtr built = prepareSacModel(model.mesh(), params, threads);
  cache.entries.emplace_front(key, built);
  if (cache.entries.size() > SacModelCache::kCapacity)
    cache.entries.pop_back();
  return built;
}

void clearSacModelCache() {
  SacModelCache& cache = sacModelCache();
  std::lock_guard<std::mutex> lock(cache.mutex);
  cache.entries.clear();
}

void computeSacSceneFeatures(const std::vector<Eigen::Vector3f>& scene_points,
                             const Eigen::Vector3f& camera, const SacParams& params, int threads,
                             pcl::PointCloud<pcl::PointNormal>& keypoints,
                             pcl::PointCloud<pcl::FPFHSignature33>& features) {
  params.validate();
  threads = resolveThreads(threads);
  auto full = pcl::make_shared<PointCloudN>();
  full->reserve(scene_points.size());
  for (const auto& x : scene_points)
    if (x.allFinite()) {
      pcl::PointNormal p;
      p.getVector3fMap() = x;
      p.getNormalVector3fMap().setZero();
      full->push_back(p);
    }
  keypoints.clear();
  features.clear();
  if (full->empty())
    return;
  const PointCloudN::Ptr reduced = voxelReduce(full, params.voxel_size);
  pcl::NormalEstimationOMP<pcl::PointNormal, pcl::PointNormal> normals(
      static_cast<unsigned>(threads));
  normals.setInputCloud(reduced);
  normals.setSearchSurface(full);
  normals.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointNormal>>());
  normals.setRadiusSearch(params.normal_radius);
  normals.setViewPoint(camera.x(), camera.y(), camera.z());
  PointCloudN estimated;
  normals.compute(estimated);
  for (std::size_t i = 0; i < reduced->size(); ++i) {
    (*reduced)[i].getNormalVector3fMap() = estimated[i].getNormalVector3fMap();
    (*reduced)[i].curvature = estimated[i].curvature;
  }
  describe(reduced, params.feature_radius, threads, keypoints, features);
}

namespace {

/** \throws std::invalid_argument when \a model's features are missing, inconsistent or built
 * with other feature parameters than \a params. */
void checkModelFeatures(const SacModelFeatures& model, const SacParams& params) {
  if (!model.points || !model.features || model.points->size() != model.features->size())
    throw std::invalid_argument("sampleConsensusAlign: model features are empty or inconsistent");
  if (!sameFeatureParams(model.params, params))
    throw std::invalid_argument(
        "sampleConsensusAlign: the model's features were built with other voxel_size, radii, "
        "model_samples or seed than params");
}

/** PCL's aligner (params.method) from the scene keypoints to the model's, under the rand()
 * mutex after srand(seed); false when it did not converge. */
bool runPclAligner(const PointCloudN::Ptr& keypoints, const FeatureCloud::Ptr& features,
                   const SacModelFeatures& model, const SacParams& params,
                   Eigen::Matrix4f& transform) {
  bool found = false;
  PointCloudN aligned;
  std::lock_guard<std::mutex> lock(randMutex());
  std::srand(static_cast<unsigned>(params.seed ^ (params.seed >> 32)));
  // What both classes share; then each one's own settings, align, and its answer.
  const auto run = [&](auto& sac) {
    sac.setInputSource(keypoints);
    sac.setSourceFeatures(features);
    sac.setInputTarget(model.points);
    sac.setTargetFeatures(model.features);
    sac.setMaximumIterations(params.max_iterations);
    sac.setNumberOfSamples(params.samples_per_hypothesis);
    sac.setCorrespondenceRandomness(params.correspondence_randomness);
    sac.align(aligned);
    found = sac.hasConverged();
    transform = sac.getFinalTransformation();
  };
  if (params.method == SacMethod::Prerejective) {
    pcl::SampleConsensusPrerejective<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> sac;
    sac.setSimilarityThreshold(params.similarity_threshold);
    sac.setMaxCorrespondenceDistance(params.max_correspondence_distance);
    sac.setInlierFraction(params.inlier_fraction);
    run(sac);
  } else {
    pcl::SampleConsensusInitialAlignment<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33>
        sac;
    sac.setMinSampleDistance(params.min_sample_distance);
    // SAC-IA's TruncatedError compares the *squared* nearest-neighbour distance with this
    // threshold (PCL 1.13, ia_ransac.h): pass the distance squared, as PCL's tutorial does.
    sac.setMaxCorrespondenceDistance(params.max_correspondence_distance *
                                     params.max_correspondence_distance);
    run(sac);
  }
  return found;
}

/** Inliers, fitness and inlier fraction of \a result.scene_to_model, measured the same way for
 * both methods (prerejective's definition): scene keypoints within max_correspondence_distance
 * of a model keypoint, and their mean squared distance. */
void measureInliers(const PointCloudN& keypoints, const SacModelFeatures& model,
                    const SacParams& params, SacResult& result) {
  pcl::search::KdTree<pcl::PointNormal> tree;
  tree.setInputCloud(model.points);
  pcl::Indices index(1);
  std::vector<float> sqr(1);
  const float max_sqr = params.max_correspondence_distance * params.max_correspondence_distance;
  double sum = 0.0;
  for (const auto& k : keypoints) {
    pcl::PointNormal moved;
    moved.getVector3fMap() = (result.scene_to_model * k.getVector3fMap().homogeneous()).head<3>();
    if (tree.nearestKSearch(moved, 1, index, sqr) == 1 && sqr[0] < max_sqr) {
      ++result.inliers;
      sum += sqr[0];
    }
  }
  result.fitness = result.inliers > 0 ? sum / static_cast<double>(result.inliers) : 0.0;
  result.inlier_fraction =
      static_cast<double>(result.inliers) / static_cast<double>(keypoints.size());
}

}  // namespace

SacResult sampleConsensusAlign(const SacModelFeatures& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Vector3f& camera, const SacParams& params,
                               int threads) {
  params.validate();
  checkModelFeatures(model, params);
  const auto start = Clock::now();
  SacResult result;
  auto keypoints = pcl::make_shared<PointCloudN>();
  auto features = pcl::make_shared<FeatureCloud>();
  computeSacSceneFeatures(scene_points, camera, params, threads, *keypoints, *features);
  result.feature_ms = msSince(start);
  result.keypoints = keypoints->size();
  const std::size_t needed = static_cast<std::size_t>(std::max(params.samples_per_hypothesis, 10));
  if (keypoints->size() < needed || model.points->size() < needed) {
    result.status = SacStatus::TooFewPoints;
    result.time_ms = msSince(start);
    return result;
  }
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();
  const bool found = runPclAligner(keypoints, features, model, params, transform);
  if (!found || !transform.allFinite()) {
    result.status = SacStatus::NotFound;
    result.time_ms = msSince(start);
    return result;
  }
  result.status = SacStatus::Found;
  result.scene_to_model = transform;
  measureInliers(*keypoints, model, params, result);
  result.time_ms = msSince(start);
  return result;
}

SacResult sampleConsensusAlign(const IcfModel& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Vector3f& camera, const SacParams& params,
                               int threads) {
  const SacModelFeatures::ConstPtr features = cachedSacModel(model, params, threads);
  return sampleConsensusAlign(*features, scene_points, camera, params, threads);
}

}  // namespace icf
}  // namespace pcl
