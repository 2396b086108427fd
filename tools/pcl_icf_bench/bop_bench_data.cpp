/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "bop_bench_data.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/model_file.h>

#include <cmath>
#include <cstdio>

namespace pcl_icf_bench {

namespace {

namespace fs = std::filesystem;
namespace bop = pcl::icf::io;
namespace eval = pcl::icf::evaluation;

std::string objectFile(int obj_id) {
  char name[32];
  std::snprintf(name, sizeof name, "obj_%06d.ply", obj_id);
  return name;
}

BopObject loadObject(const fs::path& root, const std::string& models, int obj_id,
                     const bop::BopModelInfo& info) {
  BopObject o;
  const pcl::PolygonMesh mesh = bop::loadPolygonMesh((root / models / objectFile(obj_id)).string());
  pcl::icf::IcfModelParams params;
  params.mesh.scale = 1e-3f;  // BOP's models are in millimetres
  o.model = pcl::icf::buildModelCached(mesh, params, pcl::icf::defaultModelCacheFolder()).model;
  // The errors' points: the vertices of the evaluation model where the dataset has one, of the
  // model otherwise, as a model reads them (any vertex type), in mm.
  const fs::path eval_path = root / "models_eval" / objectFile(obj_id);
  pcl::icf::FaceMeshOptions eval_options;  // in mm, as BOP's files
  const pcl::icf::FaceMesh eval_mesh =
      fs::exists(eval_path)
          ? pcl::icf::FaceMesh::build(bop::loadPolygonMesh(eval_path.string()), eval_options)
          : pcl::icf::FaceMesh::build(mesh, eval_options);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const Eigen::Vector3f& v : eval_mesh.vertices()) {
    o.vertices.push_back(v.cast<double>());
    lo = lo.cwiseMin(o.vertices.back());
    hi = hi.cwiseMax(o.vertices.back());
  }
  o.box_centre = 0.5 * (lo + hi);
  std::vector<eval::ContinuousSymmetry> continuous;
  for (const auto& c : info.symmetries_continuous)
    continuous.push_back({c.axis, c.offset});
  o.symmetries = eval::symmetryTransformations(info.symmetries_discrete, continuous, 0.01);
  o.diameter_mm = info.diameter;
  return o;
}

std::string imageFile(const std::string& scene, const char* kind, int im_id) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.png", im_id);
  return (fs::path(scene) / kind / name).string();
}

}  // namespace

BopBenchData::BopBenchData(const fs::path& root, const std::string& split, const fs::path& targets,
                           const std::string& models)
    : root_(root), split_(split) {
  // BOP's name: the dataset's folder name (ROOT/ or ROOT alike).
  const fs::path normal = root.lexically_normal();
  name_ =
      (normal.filename().empty() ? normal.parent_path().filename() : normal.filename()).string();
  camera_ = bop::readBopDatasetCamera((root / "camera.json").string());
  const auto infos = bop::readBopModelsInfo((root / models / "models_info.json").string());
  for (const auto& t : bop::readBopTargets(targets.string())) {
    if (!infos.count(t.obj_id))
      throw bop::FileError(targets.string() + ": object " + std::to_string(t.obj_id) +
                           " has no entry in models_info.json");
    by_image_[{t.scene_id, t.im_id}].push_back(t);
    if (!objects_.count(t.obj_id))
      objects_[t.obj_id] = loadObject(root, models, t.obj_id, infos.at(t.obj_id));
  }
}

std::string BopBenchData::sceneFolder(int scene_id) const {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", scene_id);
  return (root_ / split_ / name).string();
}

void BopBenchData::readScene(int scene_id) {
  const std::string scene = sceneFolder(scene_id);
  const auto cameras =
      bop::readBopSceneCamera(scene + "/scene_camera.json", camera_.width, camera_.height);
  // Test splits whose truth BOP withholds have neither file: run, not scored.
  const bool annotated = fs::exists(scene + "/scene_gt.json");
  std::map<int, std::vector<bop::BopPose>> gts;
  std::map<int, std::vector<double>> visibs;
  if (annotated) {
    gts = bop::readBopSceneGt(scene + "/scene_gt.json");
    visibs = bop::readBopSceneVisibility(scene + "/scene_gt_info.json");
  }
  for (const auto& [image, targets] : by_image_) {
    if (image.first != scene_id)
      continue;
    const int im_id = image.second;
    const std::string im = std::to_string(im_id);
    if (!cameras.count(im_id))
      throw bop::FileError(scene + "/scene_camera.json: image " + im + " is missing");
    BopImageTruth& t = truth_[image];
    t.camera = cameras.at(im_id);
    t.annotated = annotated;
    if (!annotated)
      continue;
    if (!gts.count(im_id) || !visibs.count(im_id))
      throw bop::FileError(scene + ": image " + im +
                           " is missing from scene_gt.json or scene_gt_info.json");
    t.gt = gts.at(im_id);
    t.visib = visibs.at(im_id);
    if (t.gt.size() != t.visib.size())
      throw bop::FileError(scene + ": image " + im + " has " + std::to_string(t.gt.size()) +
                           " instances in scene_gt.json and " + std::to_string(t.visib.size()) +
                           " in scene_gt_info.json");
  }
  scenes_read_[scene_id] = true;
}

const BopImageTruth& BopBenchData::truth(const BopImage& image) {
  if (!scenes_read_.count(image.first))
    readScene(image.first);
  const auto it = truth_.find(image);
  if (it == truth_.end())
    throw bop::FileError(sceneFolder(image.first) + ": image " + std::to_string(image.second) +
                         " is not among the targets");
  return it->second;
}

pcl::PointCloud<pcl::PointXYZRGBA>::Ptr BopBenchData::cloud(const BopImage& image) {
  const BopImageTruth& t = truth(image);
  const std::string scene = sceneFolder(image.first);
  const std::string rgb = imageFile(scene, "rgb", image.second);
  return bop::readBopDepthImage(imageFile(scene, "depth", image.second), t.camera,
                                fs::exists(rgb) ? rgb : "");
}

eval::DepthMap depthOf(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud) {
  eval::DepthMap d{static_cast<int>(cloud.width), static_cast<int>(cloud.height), {}};
  d.z.reserve(cloud.size());
  for (const auto& p : cloud)
    d.z.push_back(std::isfinite(p.z) ? p.z : 0.f);
  return d;
}

}  // namespace pcl_icf_bench
