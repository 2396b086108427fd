/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl_icf_bench's methods: ICF with each strategy and fallback, and PCL's pipelines, run on
// the same cluster against a model prepared once.
#pragma once

#include "bench_manifest.h"

#include <pcl/PolygonMesh.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/iterative_closest_face.h>
#include <pcl/icf/registration/sample_consensus_alignment.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <Eigen/StdVector>

#include <chrono>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

using CloudXYZ = pcl::PointCloud<pcl::PointXYZ>;
using CloudN = pcl::PointCloud<pcl::PointNormal>;

struct PeerModel;  // bench_peers.cpp: Open3D's and OpenCV's per-model data

/** Everything prepared once per model (not timed). */
struct PreparedModel {
  pcl::PolygonMesh::Ptr mesh;        ///< in metres
  pcl::icf::IcfModel::ConstPtr icf;  ///< faces, index, field, samples
  CloudXYZ::Ptr dense;               ///< 20000 area-weighted samples (ICP targets)
  CloudN::Ptr dense_normals;         ///< the same with face normals
  CloudXYZ::Ptr adds_samples;        ///< 2000 samples for ADD-S
  double diameter = 0.0;             ///< largest distance between two vertices, metres
  Eigen::Vector3d box_centre = Eigen::Vector3d::Zero();  ///< of the vertices' bounding box
  double icf_build_ms = 0.0, sac_build_ms = 0.0;
  /** The non-PCL peers' data (bench_peers.h), when a peer method runs; their build times
   * (Open3D, OpenCV). */
  std::shared_ptr<const PeerModel> peers;
  std::vector<double> peer_build_ms;
};

/** Loads the model (scaled to metres) and prepares everything the methods share; the
 * SampleConsensus features go to pcl::icf::cachedSacModel. */
std::shared_ptr<PreparedModel> prepareModel(const std::filesystem::path& path, double scale,
                                            const pcl::icf::SacParams& sac, int threads,
                                            const pcl::icf::IcfModelParams& params = {});

/** ADD-S (metres): the mean, over the model's 2000 surface samples posed by the truth, of the
 * exact distance to the surface of the model posed by the estimate (point-to-face through the
 * model's index, so there is no sample-spacing floor: a pose that differs from the truth by a
 * symmetry scores 0). */
double addS(const PreparedModel& model, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth);

/** The case's cluster: finite scene points selected by the cluster spec; \a camera receives
 * the sensor position (the manifest's camera= or the PCD's sensor origin). */
CloudXYZ::Ptr loadCluster(const CaseSpec& c, const PreparedModel& model, Eigen::Vector3f& camera);

/** One method's answer on one cluster. */
struct MethodRun {
  Eigen::Matrix4f object_pose = Eigen::Matrix4f::Identity();  ///< model -> scene
  double ms = 0.0;
  bool converged = false;  ///< the method's own verdict (ICF: accepted; SAC: found; ICP: PCL's)
  std::string detail;
  /** icf-scene: the top hypothesis's verification confidence and terms (NaN / empty for the
   * other methods and when no hypothesis was verified). */
  double confidence = std::numeric_limits<double>::quiet_NaN();
  std::string verification;
  /** icf-scene: the poses reported as explaining the depth as well (model -> scene). */
  std::vector<Eigen::Matrix4f, Eigen::aligned_allocator<Eigen::Matrix4f>> alternative_poses;
};

/** pcl::IterativeClosestFace with \a params (strategy, fallback, threads). */
MethodRun runIcf(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                 const pcl::icf::IcfParams& params);

/** Milliseconds since \a start (steady clock). */
double msSince(std::chrono::steady_clock::time_point start);

/** The cluster's points with PCL's normals (NormalEstimationOMP over the \a k nearest
 * neighbours, or within \a radius when \a k is 0) turned towards the sensor origin; points
 * without a normal (isolated outliers, which would poison a point-to-plane system) left out. */
CloudN::Ptr clusterWithNormals(const CloudXYZ::Ptr& cluster, int k, double radius, int threads);

/** PCL's ICP from the centroid start (model surface centroid on the cluster centroid, no
 * rotation) on the dense samples: point-to-point, or point-to-plane with scene normals. */
MethodRun runIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model, bool plane, int threads);

/** FPFH + PCL's sample consensus (\a params.method), then point-to-point ICP (2 cm). */
MethodRun runSacIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                    const pcl::icf::SacParams& params, int threads);

}  // namespace bench
}  // namespace pcl_icf_tools
