/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// libFuzzer target: the whole pipeline on tiny inputs. The bytes decode into a mesh of a few
// faces and a cloud of a few hundred points at most; then FaceMesh::build -> IcfModel::build
// (a small field) -> estimatePose on a tiny budget. InvalidMeshError and std::invalid_argument
// from IcfModel::build are the documented outcomes for a mesh that cannot be a model;
// estimatePose with valid parameters must not throw, and must return a finite pose.
//
// Layout (every read past the end gives zeros):
//   flags (1 byte): bit 0 raw float vertices (NaN, Inf, 1e30 reachable), bit 1 raw float scene
//     points, bit 2 scene = samples of the mesh under a pose read from the bytes, bit 3 the
//     thesis search, bit 4 the SampleConsensus fallback (Always), bit 5 also run with 2 threads
//     and require the same result, bit 6 millimetre mesh (scale 1e-3)
//   vertices (1 byte: 3 + b % 30), faces (1 byte: 1 + b % 40)
//   each vertex: 3 x int8 x 5 mm, or 3 x float32
//   each face: 1 byte (3 + b % 3 vertices), then one byte per vertex index (b % (vertices + 1):
//     one past the end is reachable)
//   scene: 1 byte point count (bit 2) + 6 pose bytes, or the remaining bytes as points
//     (3 x int8 x 5 mm, or 3 x float32), at most 400
#include "fuzz_common.h"

#include <pcl/conversions.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/point_types.h>

#include <cstring>
#include <vector>

namespace {

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  float quantized() { return 0.005f * static_cast<float>(static_cast<std::int8_t>(byte())); }
  float raw() {
    std::uint8_t b[4] = {byte(), byte(), byte(), byte()};
    float v;
    std::memcpy(&v, b, 4);
    return v;
  }
  std::size_t left() const { return size_ - std::min(pos_, size_); }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

pcl::PolygonMesh decodeMesh(Bytes& in, bool raw) {
  const std::size_t vertices = 3 + in.byte() % 30, faces = 1 + in.byte() % 40;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  for (std::size_t v = 0; v < vertices; ++v) {
    pcl::PointXYZ p;
    p.x = raw ? in.raw() : in.quantized();
    p.y = raw ? in.raw() : in.quantized();
    p.z = raw ? in.raw() : in.quantized();
    cloud.push_back(p);
  }
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(cloud, mesh.cloud);
  for (std::size_t f = 0; f < faces; ++f) {
    pcl::Vertices face;
    const std::size_t count = 3 + in.byte() % 3;
    for (std::size_t k = 0; k < count; ++k)
      face.vertices.push_back(static_cast<pcl::index_t>(in.byte() % (vertices + 1)));
    mesh.polygons.push_back(face);
  }
  return mesh;
}

pcl::icf::IcfParams tinyBudget(std::uint8_t flags, int threads) {
  pcl::icf::IcfParams p;
  p.strategy = (flags & 8) ? pcl::icf::SearchStrategy::Thesis : pcl::icf::SearchStrategy::Fast;
  p.tuning().global.rotations = 24;
  p.tuning().global.subsample = 32;
  p.tuning().global.centroid_samples = 32;
  p.tuning().global.keep = 2;
  p.tuning().global.max_anchors = 4;
  p.tuning().global.field_refinement.max_iterations = 3;
  p.tuning().thesis.outer_iterations = 2;
  p.tuning().thesis.orientation_iterations = 3;
  p.tuning().thesis.samples_per_kernel = 3;
  p.tuning().exact_candidates = 1;
  p.tuning().candidate_points = 64;
  p.tuning().refinement.max_iterations = 4;
  p.acceptance.min_inliers = 10;
  p.fallback = (flags & 16) ? pcl::icf::FallbackPolicy::Always : pcl::icf::FallbackPolicy::Off;
  p.tuning().sac.model_samples = 2000;
  p.tuning().sac.max_iterations = 200;
  p.threads = threads;
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  pcl_icf_fuzz::quiet();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  const std::uint8_t flags = in.byte();
  const pcl::PolygonMesh mesh = decodeMesh(in, flags & 1);

  pcl::icf::IcfModelParams model_params;
  model_params.field.resolution = 8;
  model_params.field.threads = 1;
  model_params.surface_samples = 100;
  model_params.mesh.scale = (flags & 64) ? 1e-3f : 1.f;
  pcl::icf::IcfModel::ConstPtr model;
  try {
    model = pcl::icf::IcfModel::build(mesh, model_params);
  } catch (const std::invalid_argument&) {  // InvalidMeshError is one
    return 0;
  }
  pcl_icf_fuzz::checkFaceMesh(model->mesh());
  PCL_ICF_FUZZ_CHECK(model->samples().size() == 100, "surface samples");
  PCL_ICF_FUZZ_CHECK(std::isfinite(model->radius()), "finite model radius");

  std::vector<Eigen::Vector3f> scene;
  if (flags & 4) {
    const std::size_t count = 10 + in.byte() % 200;
    Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
    pose.rotate(Eigen::AngleAxisf(0.05f * in.byte(), Eigen::Vector3f::UnitZ()));
    pose.rotate(Eigen::AngleAxisf(0.05f * in.byte(), Eigen::Vector3f::UnitX()));
    pose.translation() = Eigen::Vector3f(in.quantized(), in.quantized(), 0.5f + in.quantized());
    for (const auto& s : pcl::icf::sampleSurface(model->mesh(), count, in.byte()))
      scene.push_back(pose * s.point);
  } else {
    const bool raw = flags & 2;
    while (scene.size() < 400 && in.left() >= (raw ? 12u : 3u))
      scene.emplace_back(raw ? in.raw() : in.quantized(), raw ? in.raw() : in.quantized(),
                         raw ? in.raw() : in.quantized());
  }

  const Eigen::Vector3f camera = Eigen::Vector3f::Zero();
  const pcl::icf::IcfResult result =
      pcl::icf::estimatePose(*model, scene, camera, tinyBudget(flags, 1));
  PCL_ICF_FUZZ_CHECK(result.status != pcl::icf::IcfStatus::NotRun, "a status");
  if (result.status == pcl::icf::IcfStatus::TooFewPoints) {
    PCL_ICF_FUZZ_CHECK(result.points < 10, "TooFewPoints only below min_inliers");
    return 0;
  }
  PCL_ICF_FUZZ_CHECK(result.object_pose.allFinite() && result.scene_to_model.allFinite(),
                     "a finite pose");
  const Eigen::Matrix3f r = result.object_pose.topLeftCorner<3, 3>();
  PCL_ICF_FUZZ_CHECK((r * r.transpose() - Eigen::Matrix3f::Identity()).norm() < 1e-3f,
                     "a rotation");
  PCL_ICF_FUZZ_CHECK(
      std::isfinite(result.quality.rmse) && std::isfinite(result.quality.surface_coverage),
      "finite quality");
  if (result.accepted())
    PCL_ICF_FUZZ_CHECK(result.quality.inliers >= 10, "accepted with enough inliers");
  if (flags & 32) {
    const pcl::icf::IcfResult two =
        pcl::icf::estimatePose(*model, scene, camera, tinyBudget(flags, 2));
    PCL_ICF_FUZZ_CHECK(two.status == result.status && two.object_pose == result.object_pose,
                       "the same result with 1 and 2 threads");
  }
  return 0;
}
