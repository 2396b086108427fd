/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// The peer selection (ghv_selection.h): PCL's own pcl::GlobalHypothesesVerification, given the
// hypotheses localizeObjects judged, as posed point clouds of the models.
#include "ghv_selection.h"

#include <pcl/common/io.h>
#include <pcl/common/transforms.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/verification/depth_image.h>
#include <pcl/recognition/hv/hv_go.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>

namespace pcl_icf_bench {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using pcl::icf::localization::ObjectQuery;
using pcl::icf::localization::ObjectsLocalization;

/** The model's surface: area-weighted samples with their normals, thinned to one per voxel
 * of \a leaf (the first sample in each). */
std::vector<pcl::icf::SurfaceSample> modelSamples(const pcl::icf::IcfModel& model,
                                                  std::size_t samples, float leaf) {
  std::vector<pcl::icf::SurfaceSample> kept;
  std::set<std::array<long, 3>> voxels;
  for (const auto& s : pcl::icf::sampleSurface(model.mesh(), samples, 1)) {
    const std::array<long, 3> voxel = {std::lround(std::floor(s.point.x() / leaf)),
                                       std::lround(std::floor(s.point.y() / leaf)),
                                       std::lround(std::floor(s.point.z() / leaf))};
    if (voxels.insert(voxel).second)
      kept.push_back(s);
  }
  return kept;
}

/** The samples the camera sees at \a pose (model -> camera): facing it, inside the image and
 * not behind the frame's surface by more than \a occlusion_threshold (a pixel without depth
 * hides nothing), with the frame's own intrinsics. A hypothesis none of whose points is seen
 * is not given to GHV. */
Cloud::Ptr visiblePart(const std::vector<pcl::icf::SurfaceSample>& samples,
                       const Eigen::Matrix4f& pose, const Cloud& scene,
                       const pcl::icf::PinholeIntrinsics& k, float occlusion_threshold) {
  auto cloud = pcl::make_shared<Cloud>();
  const Eigen::Matrix3f rotation = pose.topLeftCorner<3, 3>();
  const Eigen::Vector3f translation = pose.topRightCorner<3, 1>();
  for (const auto& s : samples) {
    const Eigen::Vector3f p = rotation * s.point + translation;
    if (!(p.z() > 0.f) || (rotation * s.normal).dot(p) >= 0.f)
      continue;
    const int u = static_cast<int>(std::lround(k.fx * p.x() / p.z() + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y() / p.z() + k.cy));
    if (u < 0 || v < 0 || u >= static_cast<int>(scene.width) || v >= static_cast<int>(scene.height))
      continue;
    const float z = scene.at(u, v).z;
    if (std::isfinite(z) && p.z() > z + occlusion_threshold)
      continue;
    cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  }
  return cloud;
}

/** The frame's finite points (\a only, when not empty). */
Cloud::Ptr finitePoints(const Cloud& scene, const pcl::Indices& only) {
  auto cloud = pcl::make_shared<Cloud>();
  auto add = [&](const pcl::PointXYZ& p) {
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      cloud->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  };
  if (only.empty())
    for (const auto& p : scene)
      add(p);
  else
    for (const auto i : only)
      add(scene[static_cast<std::size_t>(i)]);
  return cloud;
}

/** The organized frame's points, NaN where a pixel has no depth (fitIntrinsics's input). */
std::vector<Eigen::Vector3f> organizedPoints(const Cloud& scene) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(scene.size());
  for (const auto& p : scene)
    points.push_back(p.getVector3fMap());
  return points;
}

/** The frame as GHV's occlusion reasoning reads an organized cloud: PCL 1.13 projects with a
 * 525-pixel focal length at the image's centre (Kinect v1's), whatever the camera. So the frame
 * is redrawn for that camera (640 x 480, the nearest point per pixel): a point GHV projects
 * then lands where the frame's surface is. (Its other path, an unorganized cloud, kept no
 * model point on these frames; addModels without occlusion reasoning sets no complete models
 * and verify() then fails.) */
Cloud::Ptr asKinectView(const Cloud& scene) {
  constexpr int kWidth = 640, kHeight = 480;
  constexpr float kFocal = 525.f, kCx = kWidth / 2.f - 0.5f, kCy = kHeight / 2.f - 0.5f;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto view = pcl::make_shared<Cloud>(kWidth, kHeight, pcl::PointXYZ(nan, nan, nan));
  for (const auto& p : scene) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !(p.z > 0.f))
      continue;
    const int u = static_cast<int>(kFocal * p.x / p.z + kCx);
    const int v = static_cast<int>(kFocal * p.y / p.z + kCy);
    if (u < 0 || v < 0 || u >= kWidth || v >= kHeight)
      continue;
    auto& q = view->at(u, v);
    if (!(q.z <= p.z))
      q = pcl::PointXYZ(p.x, p.y, p.z);
  }
  return view;
}

struct Candidate {
  std::size_t object;
  int hypothesis;
};

/** Each object's best \a per_object hypotheses with a finite pose, by score (ties: lower
 * index). */
std::vector<Candidate> candidates(const ObjectsLocalization& found, std::size_t per_object) {
  std::vector<Candidate> out;
  for (std::size_t k = 0; k < found.objects.size(); ++k) {
    const auto& clusters = found.objects[k].clusters;
    std::vector<int> order(clusters.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return clusters[static_cast<std::size_t>(a)].score >
             clusters[static_cast<std::size_t>(b)].score;
    });
    std::size_t taken = 0;
    for (const int h : order) {
      if (taken == per_object)
        break;
      if (!clusters[static_cast<std::size_t>(h)].icf.object_pose.allFinite())
        continue;
      out.push_back({k, h});
      ++taken;
    }
  }
  return out;
}

}  // namespace

std::vector<std::vector<int>> ghvSelect(const pcl::PointCloud<pcl::PointXYZRGBA>& scene,
                                        const ObjectsLocalization& found,
                                        const std::vector<ObjectQuery>& queries,
                                        const GhvParams& params) {
  std::vector<std::vector<int>> kept(found.objects.size());
  const std::vector<Candidate> hypotheses = candidates(found, params.per_object);
  if (hypotheses.empty())
    return kept;
  // Everything GHV is given is in the camera's frame (its occlusion reasoning puts the camera
  // at the origin); the frame stays organized, pixel for pixel.
  Cloud camera_view;
  pcl::copyPointCloud(scene, camera_view);
  const Eigen::Affine3f to_camera(found.camera_pose.inverse().matrix());
  pcl::transformPointCloud(camera_view, camera_view, to_camera);
  const bool table = found.segmentation.plane.found() && !found.segmentation.above_table.empty();
  const Cloud::Ptr explained =
      finitePoints(camera_view, table ? found.segmentation.above_table : pcl::Indices{});
  if (explained->empty())
    return kept;

  // The frame's camera: the organized cloud's own pixel grid.
  double rms = 0.0;
  const pcl::icf::PinholeIntrinsics k = pcl::icf::DepthImage::fitIntrinsics(
      organizedPoints(camera_view), static_cast<int>(scene.width), static_cast<int>(scene.height),
      rms);
  if (!(rms <= 0.5))
    throw std::invalid_argument(
        "--selection ghv: the frame is not one pinhole camera's image "
        "(its pixels fit one to " +
        std::to_string(rms) + " px)");
  std::vector<std::vector<pcl::icf::SurfaceSample>> samples(queries.size());
  std::vector<Cloud::ConstPtr> posed;
  std::vector<Candidate> seen;
  for (const Candidate& c : hypotheses) {
    if (samples[c.object].empty())
      samples[c.object] =
          modelSamples(*queries[c.object].model, params.model_points, params.resolution);
    const auto& pose =
        found.objects[c.object].clusters[static_cast<std::size_t>(c.hypothesis)].icf.object_pose;
    const Eigen::Matrix4f in_camera = found.camera_pose.inverse() * pose;
    if (visiblePart(samples[c.object], in_camera, camera_view, k, params.occlusion_threshold)
            ->empty())
      continue;  // nothing of it would be seen: GHV would refuse it (and fails on none at all)
    auto whole = pcl::make_shared<Cloud>();
    for (const auto& sample : samples[c.object]) {
      const Eigen::Vector3f q =
          in_camera.topLeftCorner<3, 3>() * sample.point + in_camera.topRightCorner<3, 1>();
      whole->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
    }
    posed.push_back(whole);
    seen.push_back(c);
  }
  if (posed.empty())
    return kept;

  pcl::GlobalHypothesesVerification<pcl::PointXYZ, pcl::PointXYZ> ghv;
  ghv.setResolution(params.resolution);
  ghv.setInlierThreshold(params.inlier_threshold);
  ghv.setOcclusionThreshold(params.occlusion_threshold);
  ghv.setRadiusClutter(params.clutter_radius);
  ghv.setRegularizer(params.regularizer);
  ghv.setClutterRegularizer(params.clutter_regularizer);
  ghv.setDetectClutter(true);
  ghv.setSceneCloud(explained);
  ghv.setOcclusionCloud(asKinectView(camera_view));
  ghv.addModels(posed, true);
  ghv.verify();
  std::vector<bool> mask;
  ghv.getMask(mask);

  for (std::size_t i = 0; i < seen.size() && i < mask.size(); ++i)
    if (mask[i] && kept[seen[i].object].size() <
                       static_cast<std::size_t>(queries[seen[i].object].max_instances))
      kept[seen[i].object].push_back(seen[i].hypothesis);
  return kept;
}

}  // namespace pcl_icf_bench
