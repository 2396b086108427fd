/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief What pcl_icf_bench --bop knows of a BOP dataset: its camera, its targets grouped by
 * image, the targets' objects (model, points, symmetries) and each image's truth, read through
 * pcl/icf/io/bop_dataset.h. */

#include <pcl/icf/evaluation/bop_pose_errors.h>
#include <pcl/icf/io/bop_dataset.h>
#include <pcl/icf/registration/icf_model.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pcl_icf_bench {

/** A dataset's object: its model (metres), its mesh's vertices, symmetries and diameter (mm). */
struct BopObject {
  pcl::icf::IcfModel::ConstPtr model;
  std::vector<Eigen::Vector3d> vertices;                 ///< mm
  std::vector<Eigen::Isometry3d> symmetries;             ///< mm, the identity first
  Eigen::Vector3d box_centre = Eigen::Vector3d::Zero();  ///< of the vertices, mm
  double diameter_mm = 0.0;
  /** BOP's ADD(-S): ADD-S for an object with symmetries in models_info.json, ADD otherwise. */
  bool symmetric() const { return symmetries.size() > 1; }
};

/** (scene_id, im_id). */
using BopImage = std::pair<int, int>;

/** One image's truth: its camera, its instances and their visible fractions. */
struct BopImageTruth {
  pcl::icf::io::BopCamera camera;
  std::vector<pcl::icf::io::BopPose> gt;
  std::vector<double> visib;
  /** The scene has scene_gt.json and scene_gt_info.json (BOP withholds them for some test
   * splits: those are run, not scored). */
  bool annotated = false;
};

/** A BOP dataset's split as the bench runs it. */
class BopBenchData {
 public:
  /** Reads ROOT/camera.json, ROOT/MODELS/models_info.json and \a targets, and prepares every
   * targeted object from ROOT/MODELS/obj_NNNNNN.ply (models through the model cache); the
   * errors' points are the vertices of ROOT/models_eval/ where the dataset has it (as the BOP
   * toolkit scores), of ROOT/MODELS/ otherwise. \throws pcl::icf::io::FileError for a bad
   * file or a target whose object has no models_info.json entry. */
  BopBenchData(const std::filesystem::path& root, const std::string& split,
               const std::filesystem::path& targets, const std::string& models = "models");

  /** The dataset's folder name (BOP's DATASET in METHOD_DATASET-SPLIT.csv). */
  const std::string& name() const { return name_; }
  const std::string& split() const { return split_; }
  const std::filesystem::path& root() const { return root_; }
  const pcl::icf::io::BopCamera& camera() const { return camera_; }
  /** The targets by image, in (scene, image) order. */
  const std::map<BopImage, std::vector<pcl::icf::io::BopTarget>>& targets() const {
    return by_image_;
  }
  const std::map<int, BopObject>& objects() const { return objects_; }

  /** The image's camera, instances and visibility (the scene's JSON read once; no instances
   * and not annotated where the scene has no scene_gt.json). \throws
   * pcl::icf::io::FileError when the image is missing from one of them or they disagree. */
  const BopImageTruth& truth(const BopImage& image);
  /** The image's depth PNG (with its colour PNG when there is one) as an organized cloud in
   * metres. */
  pcl::PointCloud<pcl::PointXYZRGBA>::Ptr cloud(const BopImage& image);

 private:
  std::string sceneFolder(int scene_id) const;
  void readScene(int scene_id);

  std::filesystem::path root_;
  std::string split_, name_;
  pcl::icf::io::BopCamera camera_;
  std::map<BopImage, std::vector<pcl::icf::io::BopTarget>> by_image_;
  std::map<int, BopObject> objects_;
  std::map<BopImage, BopImageTruth> truth_;
  std::map<int, bool> scenes_read_;
};

/** The camera-frame depth in metres of an organized cloud, 0 where NaN. */
pcl::icf::evaluation::DepthMap depthOf(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud);

}  // namespace pcl_icf_bench
