/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Which of PCL's feature-based sample-consensus aligners runs. */
enum class SacMethod {
  /** pcl::SampleConsensusPrerejective (Buch et al. 2013): polygonal pre-rejection of each
   * 3-point hypothesis, scored by inliers. The default. */
  Prerejective,
  /** pcl::SampleConsensusInitialAlignment (SAC-IA, Rusu et al. 2009): every hypothesis scored
   * on all points by a truncated error. Slower; offered for comparison. */
  InitialAlignment,
};

/** \brief Parse "prerejective" / "ia"; throws std::invalid_argument otherwise. */
SacMethod parseSacMethod(const std::string& name);
std::string toString(SacMethod method);

/** \brief Parameters of the feature-based initial alignment. Lengths in scene units; the
 * defaults are in metres and suit objects of 5-30 cm seen by a Kinect-class sensor at about
 * 1 m (point spacing about 2 mm). They follow PCL's "robust pose estimation of rigid objects"
 * tutorial scaled to that size: the radii are 2x and 5x the voxel size, the correspondence
 * distance 2.5x. */
struct SacParams {
  SacMethod method = SacMethod::Prerejective;
  /** Both the scene cluster and the model's dense samples are reduced to one point per voxel of
   * this size (pcl::VoxelGrid); features are computed on these keypoints. */
  float voxel_size = 0.005f;
  /** Area-weighted samples drawn on the model's faces (seeded with \c seed) before the voxel
   * reduction: dense enough that every voxel of the surface holds several. */
  std::size_t model_samples = 50000;
  /** Radius of the normal estimation (scene: over the full cluster, oriented towards the camera;
   * model: over the dense samples, oriented outwards by the nearest face). */
  float normal_radius = 0.01f;
  /** Radius of the FPFH descriptor (pcl::FPFHEstimationOMP), larger than normal_radius. */
  float feature_radius = 0.025f;
  /** Hypotheses drawn. Prerejective rejects most of them in O(1); InitialAlignment scores each
   * on every keypoint, so about 1000 is its usual budget. */
  int max_iterations = 20000;
  /** Correspondences per hypothesis (PCL's setNumberOfSamples; 3 is the minimum). */
  int samples_per_hypothesis = 3;
  /** A scene feature's correspondence is drawn among its k nearest model features. */
  int correspondence_randomness = 5;
  /** Prerejective: edge-length similarity of the sample polygons in [0, 1). */
  float similarity_threshold = 0.9f;
  /** A transformed scene keypoint within this distance of a model keypoint is an inlier
   * (both methods; for InitialAlignment we pass it squared, see the .cpp). */
  float max_correspondence_distance = 0.0125f;
  /** Prerejective: a hypothesis needs at least this share of scene keypoints as inliers. The
   * scene is a partial view of the model, so most of its keypoints have a partner. */
  float inlier_fraction = 0.25f;
  /** InitialAlignment: minimum distance between the sampled scene keypoints. */
  float min_sample_distance = 0.02f;
  /** Seeds the model sampling and, through srand, PCL's draws (see sampleConsensusAlign). */
  std::uint64_t seed = 42;

  /** \throws std::invalid_argument naming the field and value. */
  void validate() const;
};

/** \brief A model's keypoints with normals and FPFH descriptors, one feature per point. Built
 * once per model and parameter set (prepareSacModel) and shared by every call; immutable. */
struct SacModelFeatures {
  using ConstPtr = std::shared_ptr<const SacModelFeatures>;
  pcl::PointCloud<pcl::PointNormal>::ConstPtr points;        ///< model frame, outward normals
  pcl::PointCloud<pcl::FPFHSignature33>::ConstPtr features;  ///< same size as points
  /** The parameters the features were built with (voxel, radii, samples, seed). */
  SacParams params;
};

/** \brief Sample the model's faces (area-weighted, seeded), reduce to voxel_size, estimate
 * normals and FPFH. Keypoints whose normal or descriptor is not finite are dropped.
 * Costs 0.1-1 s for a 16k-face mesh. \throws std::invalid_argument for bad params. */
SacModelFeatures::ConstPtr prepareSacModel(const FaceMesh& mesh, const SacParams& params,
                                           int threads = 1);

/** \brief prepareSacModel through a cache that is process-wide global state: one cache for the
 * whole process, shared by every caller (estimatePose's fallback, sampleConsensusAlign on an
 * IcfModel, the localizer, the tracker), not owned by any object.
 *
 * - Key: a hash of the mesh's vertices and faces (not its address, so two IcfModels of the same
 *   mesh share one entry) and of the feature parameters (voxel_size, normal_radius,
 *   feature_radius, model_samples, seed). The features are built on the first call for a key.
 * - Bounded: at most 8 entries; the least recently used is dropped beyond that. An entry holds
 *   a few thousand keypoints with FPFH descriptors (about 1 MB); a returned pointer stays valid
 *   after its entry is dropped or cleared.
 * - Thread-safe: one mutex; a missing entry is built under it, so concurrent callers asking for
 *   the same new model build it once (and others wait for it).
 * - Results do not depend on it: the features are a deterministic function of the key, so a
 *   hit returns what a rebuild would. It only saves the 0.1-1 s of prepareSacModel.
 * - Cleared by clearSacModelCache(); callers who want no global state call prepareSacModel
 *   themselves and the sampleConsensusAlign overload that takes SacModelFeatures. */
SacModelFeatures::ConstPtr cachedSacModel(const IcfModel& model, const SacParams& params,
                                          int threads = 1);

/** \brief Drop every entry of cachedSacModel's cache (thread-safe). Pointers handed out before
 * stay valid; the next call for a model builds its features again. */
void clearSacModelCache();

/** \brief Outcome of one sample-consensus alignment. */
enum class SacStatus {
  NotRun,        ///< nothing run yet
  Found,         ///< a hypothesis met the acceptance of the method (Prerejective: the inlier
                 ///< fraction; InitialAlignment: any hypothesis, it always "converges")
  NotFound,      ///< no hypothesis met it; scene_to_model is the identity
  TooFewPoints,  ///< fewer scene keypoints with finite features than needed (see keypoints)
};
std::string toString(SacStatus status);

/** \brief The result of sampleConsensusAlign. */
struct SacResult {
  SacStatus status = SacStatus::NotRun;
  /** Registration transform: scene points into the model frame (PCL's source -> target). */
  Eigen::Matrix4f scene_to_model = Eigen::Matrix4f::Identity();
  /** Mean squared distance (scene units^2) from the inlier scene keypoints to their nearest
   * model keypoint, at scene_to_model (PCL's prerejective fitness; we measure it the same way
   * for both methods). */
  double fitness = 0.0;
  /** Scene keypoints within max_correspondence_distance of a model keypoint. */
  std::size_t inliers = 0;
  std::size_t keypoints = 0;     ///< scene keypoints used
  double inlier_fraction = 0.0;  ///< inliers / keypoints
  double feature_ms = 0.0;       ///< downsampling, normals and FPFH of the scene
  double time_ms = 0.0;          ///< everything (scene features, lock wait, alignment, scoring;
                                 ///< not the model features)

  bool found() const { return status == SacStatus::Found; }
};

/** \brief Feature-based initial alignment of a scene cluster to a model: the scene is reduced
 * to keypoints (voxel_size), normals are estimated over the full cluster and oriented towards
 * \a camera, FPFH descriptors computed, and PCL's sample-consensus aligner (params.method)
 * matched against \a model. No initial guess is needed or used.
 *
 * PCL's aligners draw with the C library's global rand(). This function seeds it with
 * srand(params.seed) and runs the aligner under a process-wide mutex, so the result is
 * reproducible and calls from several threads are serialised (they do not run in parallel).
 * Any other code that calls rand() or srand() concurrently (in this process, outside this
 * function) breaks the reproducibility, not the memory safety. The feature computation runs
 * outside the lock on \a threads threads (0: all cores); the result does not depend on it.
 *
 * \param scene_points finite points of one cluster, scene frame (non-finite ones are skipped)
 * \throws std::invalid_argument for bad params or features built with other parameters. */
SacResult sampleConsensusAlign(const SacModelFeatures& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Vector3f& camera, const SacParams& params,
                               int threads = 1);

/** \brief The same with the model's features from cachedSacModel. */
SacResult sampleConsensusAlign(const IcfModel& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Vector3f& camera, const SacParams& params,
                               int threads = 1);

/** \brief Scene keypoints, normals and FPFH as sampleConsensusAlign computes them, for pipelines
 * that run PCL's aligners (or their own matching) on the same features. Keypoints with a
 * non-finite normal or descriptor are dropped. */
void computeSacSceneFeatures(const std::vector<Eigen::Vector3f>& scene_points,
                             const Eigen::Vector3f& camera, const SacParams& params, int threads,
                             pcl::PointCloud<pcl::PointNormal>& keypoints,
                             pcl::PointCloud<pcl::FPFHSignature33>& features);

}  // namespace icf
}  // namespace pcl
