/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Datasets in the BOP benchmark's layout (bop_toolkit's docs/bop_datasets_format.md):
 * the JSON files of a dataset's models, scenes and targets, and its depth images as the
 * organized clouds the library takes.
 *
 * Lengths as BOP writes them, in millimetres (poses' translations, diameters, symmetries' offsets),
 * except the clouds, which are in metres. Every reader throws FileError naming the file, and
 * the key where one is missing or malformed. */

#include <pcl/icf/io/mesh_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace io {

/** \brief One image's camera (scene_camera.json): intrinsics, the depth unit, and the camera's
 * pose in the world where given (cam_R_w2c, cam_t_w2c, millimetres). */
struct BopCamera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  double depth_scale = 1.0;  ///< millimetres per depth PNG unit
  std::optional<Eigen::Isometry3d> world_to_camera;
  int width = 0, height = 0;  ///< the image's size where known (camera.json), else 0
};

/** \brief One annotated object instance of an image (scene_gt.json): its pose, model to camera,
 * translation in millimetres. */
struct BopPose {
  int obj_id = 0;
  Eigen::Isometry3d model_to_camera = Eigen::Isometry3d::Identity();
};

/** \brief An object's entry of models_info.json: its diameter and box (millimetres) and its
 * symmetries: discrete ones as 4x4 transforms, continuous ones as an axis through an offset. */
struct BopModelInfo {
  double diameter = 0.0;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), size = Eigen::Vector3d::Zero();
  std::vector<Eigen::Isometry3d> symmetries_discrete;
  struct Continuous {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  };
  std::vector<Continuous> symmetries_continuous;
};

/** \brief One entry of a targets file (test_targets_bop19.json): an object to find in an
 * image, at most inst_count times. */
struct BopTarget {
  int scene_id = 0, im_id = 0, obj_id = 0, inst_count = 1;
};

/** \brief models_info.json: object id -> its entry. */
std::map<int, BopModelInfo> readBopModelsInfo(const std::string& path);

/** \brief A targets file, in its order. */
std::vector<BopTarget> readBopTargets(const std::string& path);

/** \brief A dataset's camera.json: fx, fy, cx, cy, width, height, depth_scale. */
BopCamera readBopDatasetCamera(const std::string& path);

/** \brief scene_camera.json: image id -> its camera (cam_K, depth_scale, cam_R_w2c and cam_t_w2c
 * where given), of \a width x \a height where known (0: unknown). */
std::map<int, BopCamera> readBopSceneCamera(const std::string& path, int width = 0, int height = 0);

/** \brief scene_gt.json: image id -> its annotated instances, in the file's order (the
 * instances' ids). */
std::map<int, std::vector<BopPose>> readBopSceneGt(const std::string& path);

/** \brief scene_gt_info.json: image id -> each instance's visible fraction (visib_fract). */
std::map<int, std::vector<double>> readBopSceneVisibility(const std::string& path);

/** \brief A 16-bit depth PNG (0 where the sensor gave no depth) as an organized cloud in
 * metres in the camera's frame (x right, y down, z forward): pixel (u, v) of depth d becomes
 * z = d depth_scale / 1000, x = (u - cx) z / fx, y = (v - cy) z / fy; NaN where d is 0. With
 * \a rgb_png (8-bit RGB or RGBA of the same size) the points take its colours, else white.
 * Read by libpng. \throws FileError for a missing or unreadable PNG, one that is not
 * 16-bit single-channel or not of the camera's size (where known), a colour image of another
 * size, or a depth_scale <= 0. */
pcl::PointCloud<pcl::PointXYZRGBA>::Ptr readBopDepthImage(const std::string& depth_png,
                                                          const BopCamera& camera,
                                                          const std::string& rgb_png = "");

}  // namespace io
}  // namespace icf
}  // namespace pcl
