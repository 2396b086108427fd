/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_localization's sources (not installed): the body of
 * object_localizer.h's templates (a thin shell that moves the scene into the camera's frame)
 * and the non-template core they call, defined in src/object_localizer.cpp, which instantiates
 * them for PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/common/transforms.h>
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/localization/objects_localizer.h>
#include <pcl/icf/segmentation/tabletop_segmentation.h>
#include <pcl_icf_internal/scene_view.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace localization {
namespace detail {

using internal::makeSceneView;
using internal::SceneView;

/** Everything localizeObjects does after the segmentation, on a scene in the camera's frame:
 * every object's hypotheses (votes, clusters, the rests accepted poses leave), each judged by
 * the depth verification, and the one selection over all objects. */
ObjectsLocalization localizeObjectsInView(const SceneView& view,
                                          segmentation::TabletopSegmentation segmentation,
                                          const std::vector<ObjectQuery>& objects,
                                          const LocalizerParams& params, double segmentation_ms);

/** Share of the finite points of \a points at positive depth (z > 0, camera frame); 1 when
 * there is none. */
double shareInFront(const std::vector<Eigen::Vector3f>& points);

/** Maps a localization made in the camera's frame into the scene's: poses, registration
 * transforms and the table plane. Indices are unchanged. */
void toSceneFrame(Localization& loc, const Eigen::Isometry3f& camera_to_scene);

/** \a objects checked: not empty, no null model, counts of at least 1, no colour cue for
 * several. \throws std::invalid_argument. */
void validateQueries(const std::vector<ObjectQuery>& objects, const LocalizerParams& params);

/** Everything localizeObjects does, on a cloud in the camera's frame (camera at the origin,
 * looking along +z): the scene's view and segmentation, then localizeObjectsInView, or status
 * BadScene for every object when the scene lies behind the camera. */
template <typename PointT>
ObjectsLocalization localizeObjectsInCameraFrame(const pcl::PointCloud<PointT>& scene,
                                                 const std::vector<ObjectQuery>& objects,
                                                 const LocalizerParams& params) {
  const auto start = std::chrono::steady_clock::now();
  SceneView view = makeSceneView(scene);
  const double in_front = shareInFront(view.points);
  if (in_front < params.tuning().min_points_in_front) {
    ObjectsLocalization all;
    all.status = LocalizationStatus::BadScene;
    all.message = "the scene lies behind the camera: only " +
                  std::to_string(static_cast<int>(std::lround(100.0 * in_front))) +
                  "% of its finite points are in front of it (check the camera pose or the "
                  "cloud's VIEWPOINT)";
    Localization behind;
    behind.status = all.status;
    behind.message = all.message;
    all.objects.assign(objects.size(), behind);
    return all;
  }
  segmentation::TabletopSegmentation segmentation;
  if (params.segment)
    segmentation = segmentation::segmentTabletop(scene, params.segmentationParams());
  const double segmentation_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return localizeObjectsInView(view, std::move(segmentation), objects, params, segmentation_ms);
}

}  // namespace detail

template <typename PointT>
Eigen::Isometry3f cameraPoseOf(const pcl::PointCloud<PointT>& scene,
                               const LocalizerParams& params) {
  if (params.camera_pose)
    return *params.camera_pose;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = scene.sensor_origin_.template head<3>();
  const Eigen::Quaternionf& q = scene.sensor_orientation_;
  if (!(q.coeffs().allFinite() && std::abs(q.norm() - 1.f) < 1e-3f))
    throw std::invalid_argument(
        "[pcl::icf::localization::cameraPoseOf] the cloud's "
        "sensor_orientation_ (VIEWPOINT) is not a unit quaternion");
  pose.linear() = q.normalized().toRotationMatrix();
  return pose;
}

template <typename PointT>
ObjectsLocalization localizeObjects(const pcl::PointCloud<PointT>& scene,
                                    const std::vector<ObjectQuery>& objects,
                                    const LocalizerParams& params) {
  params.validate();
  detail::validateQueries(objects, params);
  const Eigen::Isometry3f camera_to_scene = cameraPoseOf(scene, params);
  validateRigidTransform(camera_to_scene.matrix().cast<double>(),
                         "[pcl::icf::localization::localizeObjects] the camera pose");
  if (camera_to_scene.matrix() == Eigen::Matrix4f::Identity())
    return detail::localizeObjectsInCameraFrame(scene, objects, params);
  const auto start = std::chrono::steady_clock::now();
  pcl::PointCloud<PointT> in_camera;
  pcl::transformPointCloud(scene, in_camera, camera_to_scene.inverse(Eigen::Isometry).matrix());
  in_camera.sensor_origin_.setZero();
  in_camera.sensor_orientation_.setIdentity();
  const double transform_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ObjectsLocalization all = detail::localizeObjectsInCameraFrame(in_camera, objects, params);
  for (Localization& loc : all.objects) {
    detail::toSceneFrame(loc, camera_to_scene);
    loc.segmentation_ms += transform_ms;
    loc.total_ms += transform_ms;
  }
  if (!all.objects.empty())
    all.segmentation.plane = all.objects.front().segmentation.plane;
  all.camera_pose = camera_to_scene;
  all.scene_ms += transform_ms;
  all.total_ms += transform_ms;
  return all;
}

template <typename PointT>
Localization localizeObject(const pcl::PointCloud<PointT>& scene, const IcfModel& model,
                            const LocalizerParams& params) {
  // The one-object case; the model is the caller's (an aliasing pointer that owns nothing).
  ObjectsLocalization all = localizeObjects(
      scene, {{IcfModel::ConstPtr(IcfModel::ConstPtr(), &model), "", params.max_instances}},
      params);
  Localization loc = std::move(all.objects.front());
  loc.segmentation = std::move(all.segmentation);
  return loc;
}

}  // namespace localization
}  // namespace icf
}  // namespace pcl
