/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bench_methods.h"

#include <pcl/common/centroid.h>
#include <pcl/common/io.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

namespace pcl_icf_tools {
namespace bench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

CloudN::Ptr clusterWithNormals(const CloudXYZ::Ptr& cluster, int k, double radius, int threads) {
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::PointNormal> estimation(
      static_cast<unsigned>(threads));
  estimation.setInputCloud(cluster);
  if (k > 0)
    estimation.setKSearch(k);
  else
    estimation.setRadiusSearch(radius);
  const Eigen::Vector3f c = cluster->sensor_origin_.head<3>();
  estimation.setViewPoint(c.x(), c.y(), c.z());
  auto out = pcl::make_shared<CloudN>();
  estimation.compute(*out);
  for (std::size_t i = 0; i < out->size(); ++i)
    (*out)[i].getVector3fMap() = (*cluster)[i].getVector3fMap();
  out->erase(std::remove_if(
                 out->begin(), out->end(),
                 [](const pcl::PointNormal& p) { return !p.getNormalVector3fMap().allFinite(); }),
             out->end());
  return out;
}

namespace {

/** PCL's point-to-plane LLS, except that a singular system (NaN step: PCL inverts it without a
 * rank check) gives no step instead of poisoning the cloud, which would abort in the kd-tree.
 * Otherwise stock PCL behaviour. */
class GuardedPointToPlaneLLS
    : public pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal,
                                                                        pcl::PointNormal> {
 public:
  using Base = pcl::registration::TransformationEstimationPointToPlaneLLS<pcl::PointNormal,
                                                                          pcl::PointNormal>;
  using Base::estimateRigidTransformation;
  void estimateRigidTransformation(const CloudN& source, const CloudN& target,
                                   const pcl::Correspondences& correspondences,
                                   Matrix4& transform) const override {
    Base::estimateRigidTransformation(source, target, correspondences, transform);
    if (!transform.allFinite())
      transform.setIdentity();
  }
};

Eigen::Matrix4f centroidStart(const CloudXYZ& cluster, const PreparedModel& model) {
  Eigen::Vector4f c;
  pcl::compute3DCentroid(cluster, c);
  Eigen::Matrix4f guess = Eigen::Matrix4f::Identity();
  guess.block<3, 1>(0, 3) = model.icf->mesh().surfaceCentroid() - c.head<3>();
  return guess;
}

/** Point-to-point ICP from a scene-to-model start. */
Eigen::Matrix4f icpPointToPoint(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                                const Eigen::Matrix4f& guess, double max_distance,
                                bool& converged) {
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setInputSource(cluster);
  icp.setInputTarget(model.dense);
  icp.setMaximumIterations(50);
  icp.setMaxCorrespondenceDistance(max_distance);
  CloudXYZ aligned;
  icp.align(aligned, guess);
  converged = icp.hasConverged();
  return icp.getFinalTransformation();
}

}  // namespace

std::shared_ptr<PreparedModel> prepareModel(const fs::path& path, double scale,
                                            const pcl::icf::SacParams& sac, int threads,
                                            const pcl::icf::IcfModelParams& params) {
  auto m = std::make_shared<PreparedModel>();
  m->mesh = pcl::make_shared<pcl::PolygonMesh>(pcl::icf::io::loadPolygonMesh(path.string()));
  if (scale != 1.0) {
    CloudXYZ vertices;
    pcl::fromPCLPointCloud2(m->mesh->cloud, vertices);
    for (auto& p : vertices)
      p.getVector3fMap() *= static_cast<float>(scale);
    pcl::toPCLPointCloud2(vertices, m->mesh->cloud);
  }
  auto start = Clock::now();
  m->icf = pcl::icf::IcfModel::build(*m->mesh, params);
  m->icf_build_ms = msSince(start);
  start = Clock::now();
  pcl::icf::cachedSacModel(*m->icf, sac, threads);
  m->sac_build_ms = msSince(start);
  m->dense = pcl::make_shared<CloudXYZ>();
  m->dense_normals = pcl::make_shared<CloudN>();
  for (const auto& s : pcl::icf::sampleSurface(m->icf->mesh(), 20000, 11)) {
    m->dense->push_back(pcl::PointXYZ(s.point.x(), s.point.y(), s.point.z()));
    pcl::PointNormal p;
    p.getVector3fMap() = s.point;
    p.getNormalVector3fMap() = s.normal;
    m->dense_normals->push_back(p);
  }
  m->adds_samples = pcl::make_shared<CloudXYZ>();
  for (const auto& s : pcl::icf::sampleSurface(m->icf->mesh(), 2000, 13))
    m->adds_samples->push_back(pcl::PointXYZ(s.point.x(), s.point.y(), s.point.z()));
  m->diameter = pcl::icf::synthetic::modelDiameter(*m->mesh);
  m->box_centre = 0.5 * (m->icf->mesh().boundsMin() + m->icf->mesh().boundsMax()).cast<double>();
  return m;
}

double addS(const PreparedModel& model, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3f to_est_frame = (est.inverse() * truth).cast<float>();
  double sum = 0.0;
  for (const auto& p : *model.adds_samples)
    sum += model.icf->index().closestFace(to_est_frame * p.getVector3fMap()).distance;
  return sum / static_cast<double>(model.adds_samples->size());
}

/** The case's cluster: finite scene points selected by the cluster spec. */
CloudXYZ::Ptr loadCluster(const CaseSpec& c, const PreparedModel& model, Eigen::Vector3f& camera) {
  pcl::icf::io::requireReadableFile(c.scene.string());
  CloudXYZ scene;
  if (pcl::io::loadPCDFile(c.scene.string(), scene) < 0 || scene.empty())
    throw BadInput(c.source + ": " + c.scene.string() + " is not a readable PCD cloud");
  camera = c.camera_set ? c.camera : Eigen::Vector3f(scene.sensor_origin_.head<3>());
  std::vector<bool> keep(scene.size(), c.cluster == "all");
  if (!c.indices.empty()) {
    std::ifstream in(c.indices);
    if (!in)
      throw BadInput(c.source + ": cannot read " + c.indices.string());
    long long i;
    while (in >> i) {
      if (i < 0 || static_cast<std::size_t>(i) >= scene.size())
        throw BadInput(c.source + ": index " + std::to_string(i) + " outside the scene");
      keep[static_cast<std::size_t>(i)] = true;
    }
  }
  if (c.cluster.rfind("crop:", 0) == 0) {
    // Oracle crop: the ground-truth posed bounding box of the model, inflated by the margin.
    const Eigen::Isometry3f to_model = c.truth.inverse().cast<float>();
    const Eigen::Vector3f lo =
        model.icf->mesh().boundsMin() - Eigen::Vector3f::Constant(float(c.crop_margin));
    const Eigen::Vector3f hi =
        model.icf->mesh().boundsMax() + Eigen::Vector3f::Constant(float(c.crop_margin));
    for (std::size_t i = 0; i < scene.size(); ++i) {
      const Eigen::Vector3f x = to_model * scene[i].getVector3fMap();
      keep[i] = (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
    }
  }
  auto cluster = pcl::make_shared<CloudXYZ>();
  for (std::size_t i = 0; i < scene.size(); ++i)
    if (keep[i] && scene[i].getVector3fMap().allFinite())
      cluster->push_back(scene[i]);
  cluster->sensor_origin_.head<3>() = camera;
  if (cluster->size() < 10)
    throw BadInput(c.source + ": the cluster has " + std::to_string(cluster->size()) +
                   " finite points");
  return cluster;
}

MethodRun runIcf(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                 const pcl::icf::IcfParams& params) {
  MethodRun run;
  const auto start = Clock::now();
  pcl::IterativeClosestFace<pcl::PointXYZ> icf;
  icf.setInputModel(model.icf);
  icf.setParams(params);
  icf.setInputSource(cluster);
  CloudXYZ aligned;
  icf.align(aligned);
  run.ms = msSince(start);
  run.object_pose = icf.getObjectPose();
  run.converged = icf.hasConverged();
  const pcl::icf::IcfResult& r = icf.getResult();
  char seen[48];
  std::snprintf(seen, sizeof(seen), ", seen through %.4f", r.quality.seen_through);
  run.detail = r.method + (r.fallback_ran ? " (fallback ran)" : "") + seen;
  return run;
}

MethodRun runIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model, bool plane,
                 int threads) {
  MethodRun run;
  const auto start = Clock::now();
  const Eigen::Matrix4f guess = centroidStart(*cluster, model);
  Eigen::Matrix4f scene_to_model;
  if (!plane) {
    scene_to_model = icpPointToPoint(cluster, model, guess, 0.05, run.converged);
  } else {
    const CloudN::Ptr source = clusterWithNormals(cluster, 0, 0.01, threads);
    pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
    icp.setTransformationEstimation(pcl::make_shared<GuardedPointToPlaneLLS>());
    icp.setInputSource(source);
    icp.setInputTarget(model.dense_normals);
    icp.setMaximumIterations(50);
    icp.setMaxCorrespondenceDistance(0.05);
    CloudN aligned;
    icp.align(aligned, guess);
    run.converged = icp.hasConverged();
    scene_to_model = icp.getFinalTransformation();
  }
  run.ms = msSince(start);
  run.object_pose = scene_to_model.inverse();
  return run;
}

MethodRun runSacIcp(const CloudXYZ::Ptr& cluster, const PreparedModel& model,
                    const pcl::icf::SacParams& params, int threads) {
  MethodRun run;
  const auto start = Clock::now();
  std::vector<Eigen::Vector3f> points;
  points.reserve(cluster->size());
  for (const auto& p : *cluster)
    points.push_back(p.getVector3fMap());
  const auto sac = pcl::icf::sampleConsensusAlign(
      *model.icf, points, cluster->sensor_origin_.head<3>(), params, threads);
  bool icp_converged = false;
  // From SAC's pose (the identity when it found nothing: PCL's own behaviour).
  const Eigen::Matrix4f scene_to_model =
      icpPointToPoint(cluster, model, sac.scene_to_model, 0.02, icp_converged);
  run.ms = msSince(start);
  run.object_pose = scene_to_model.inverse();
  run.converged = sac.found() && icp_converged;
  run.detail =
      "sac " + pcl::icf::toString(sac.status) + ", " + std::to_string(sac.keypoints) + " keypoints";
  return run;
}

}  // namespace bench
}  // namespace pcl_icf_tools
