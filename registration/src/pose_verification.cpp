/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/verification/pose_verification.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/parameter_check.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace pcl {
namespace icf {

void VisibilityParams::validate() const {
  const internal::ParameterCheck fail("VisibilityParams");
  if (!(bin_angle > 0.f && bin_angle < 0.5f))
    fail("bin_angle", bin_angle, "must lie in (0, 0.5) radians");
  if (!(depth_tolerance >= 0.f) || !std::isfinite(depth_tolerance))
    fail("depth_tolerance", depth_tolerance, "must be finite and >= 0");
  if (!(min_view_cosine >= 0.f && min_view_cosine < 1.f))
    fail("min_view_cosine", min_view_cosine, "must lie in [0, 1)");
}

std::vector<std::size_t> visibleSamples(const IcfModel& model,
                                        const Eigen::Isometry3f& model_to_scene,
                                        const Eigen::Vector3f& camera,
                                        const VisibilityParams& params) {
  params.validate();
  // View frame: z from the camera towards the model's centre.
  const Eigen::Vector3f centre = model_to_scene * model.mesh().surfaceCentroid();
  Eigen::Vector3f axis = centre - camera;
  if (!(axis.norm() > 1e-9f))
    axis = Eigen::Vector3f::UnitZ();
  axis.normalize();
  const Eigen::Vector3f side = axis.unitOrthogonal();
  const Eigen::Vector3f up = axis.cross(side);

  struct Candidate {
    std::size_t sample;
    std::int64_t bin;
    float depth;
  };
  std::vector<Candidate> facing;
  std::unordered_map<std::int64_t, float> nearest;  // bin -> smallest depth
  const auto& samples = model.samples();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Vector3f p = model_to_scene * samples[i].point - camera;
    const float depth = p.norm();
    if (!(depth > 1e-6f))
      continue;
    const Eigen::Vector3f n = model_to_scene.linear() * samples[i].normal;
    if (-n.dot(p) / depth < params.min_view_cosine)
      continue;
    const float along = p.dot(axis);
    if (!(along > 1e-6f))
      continue;
    const auto bx = static_cast<std::int64_t>(std::floor(p.dot(side) / along / params.bin_angle));
    const auto by = static_cast<std::int64_t>(std::floor(p.dot(up) / along / params.bin_angle));
    const std::int64_t bin = bx * 1000003 + by;
    auto it = nearest.find(bin);
    if (it == nearest.end())
      nearest.emplace(bin, depth);
    else
      it->second = std::min(it->second, depth);
    facing.push_back({i, bin, depth});
  }
  std::vector<std::size_t> visible;
  for (const Candidate& c : facing)
    if (c.depth <= nearest[c.bin] + params.depth_tolerance)
      visible.push_back(c.sample);
  return visible;
}

PoseQuality measurePoseQuality(const IcfModel& model,
                               const std::vector<Eigen::Vector3f>& scene_points,
                               const Eigen::Isometry3f& scene_to_model,
                               const Eigen::Vector3f& camera, float inlier_distance,
                               float gate_distance, const ObjectiveParams& objective,
                               const VisibilityParams& visibility, int threads) {
  PoseQuality q;
  if (scene_points.empty())
    return q;
  const int n = static_cast<int>(scene_points.size());
  std::vector<float> distances(scene_points.size());
  const float search = std::max(objective.cutoff / objective.far_factor, gate_distance) * 1.01f;
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
  for (int i = 0; i < n; ++i)
    distances[static_cast<std::size_t>(i)] =
        model.index()
            .closestFace(scene_to_model * scene_points[static_cast<std::size_t>(i)], search)
            .distance;  // +inf beyond the search radius: f = 0 there anyway
  double sq = 0.0;
  for (float d : distances) {
    q.thesis_score += objectivePointScore(d, objective);
    if (d > gate_distance)
      ++q.far_points;
    if (d <= inlier_distance) {
      ++q.inliers;
      sq += static_cast<double>(d) * d;
    }
  }
  q.points = n;
  q.inlier_ratio = static_cast<double>(q.inliers) / static_cast<double>(n);
  q.rmse = q.inliers > 0 ? std::sqrt(sq / static_cast<double>(q.inliers)) : 0.0;

  const Eigen::Isometry3f model_to_scene = scene_to_model.inverse();
  const std::vector<std::size_t> visible =
      visibleSamples(model, model_to_scene, camera, visibility);
  q.visible_samples = visible.size();
  if (visible.empty())
    return q;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->reserve(scene_points.size());
  for (const auto& p : scene_points)
    cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  long covered = 0;  // a count: the same for any thread count
  const int visible_count = static_cast<int>(visible.size());
#pragma omp parallel num_threads(std::max(1, threads))
  {
    pcl::Indices index(1);
    std::vector<float> sq_dist(1);
#pragma omp for schedule(static) reduction(+ : covered)
    for (int k = 0; k < visible_count; ++k) {
      const Eigen::Vector3f p =
          model_to_scene * model.samples()[visible[static_cast<std::size_t>(k)]].point;
      if (tree.nearestKSearch(pcl::PointXYZ(p.x(), p.y(), p.z()), 1, index, sq_dist) > 0 &&
          sq_dist[0] <= inlier_distance * inlier_distance)
        ++covered;
    }
  }
  q.surface_coverage = static_cast<double>(covered) / static_cast<double>(visible.size());
  return q;
}

}  // namespace icf
}  // namespace pcl
