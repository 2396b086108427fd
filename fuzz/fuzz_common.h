/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Shared by the libFuzzer targets: a scratch file for the loaders (they take paths), a check
// that aborts on a wrong answer, and the invariants every loaded cloud and mesh must hold.
// A documented exception (FileError, InvalidMeshError) is an accepted outcome; anything else
// escaping, a sanitizer report, a hang or a failed invariant is a finding.
#pragma once

#include <pcl/console/print.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/face_mesh.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

/** A wrong answer given without an error: print what and abort, so libFuzzer keeps the input. */
#define PCL_ICF_FUZZ_CHECK(condition, what)                                                   \
  do {                                                                                        \
    if (!(condition)) {                                                                       \
      std::fprintf(stderr, "pcl_icf fuzz check failed: %s (%s) at %s:%d\n", #condition, what, \
                   __FILE__, __LINE__);                                                       \
      std::abort();                                                                           \
    }                                                                                         \
  } while (false)

namespace pcl_icf_fuzz {

/** Silences PCL's console (its readers print every parse error). Call once per process. */
inline void quiet() {
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
}

/** A file of the given extension in a per-process folder, rewritten for every input and
 * removed at exit. The folder is in /dev/shm when there is one: on ext4 a file truncated and
 * rewritten is flushed to disk on close (auto_da_alloc), which made the loaders' targets 15
 * times slower. The file is unlinked, not truncated, before each write for the same reason. */
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& extension) {
    std::error_code ec;
    const std::filesystem::path shm("/dev/shm");
    const std::filesystem::path base =
        std::filesystem::is_directory(shm, ec) && ::access("/dev/shm", W_OK) == 0
            ? shm
            : std::filesystem::temp_directory_path();
    dir_ = base / ("pcl_icf_fuzz_" + std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(dir_);
    path_ = (dir_ / ("input." + extension)).string();
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  const std::string& write(const std::uint8_t* data, std::size_t size) const {
    std::error_code ec;
    std::filesystem::remove(path_, ec);
    std::ofstream out(path_, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    PCL_ICF_FUZZ_CHECK(out.good(), "cannot write the scratch file");
    return path_;
  }

 private:
  std::filesystem::path dir_;
  std::string path_;
};

/** Invariants of a cloud loadSceneCloud returned without throwing. */
inline void checkScene(const pcl::PointCloud<pcl::PointXYZRGBA>& cloud,
                       const pcl::icf::io::SceneFileInfo& info) {
  PCL_ICF_FUZZ_CHECK(!cloud.empty(), "a returned cloud has points");
  PCL_ICF_FUZZ_CHECK(static_cast<std::size_t>(cloud.width) * cloud.height == cloud.size(),
                     "width x height = size");
  PCL_ICF_FUZZ_CHECK(info.points == cloud.size(), "info.points");
  PCL_ICF_FUZZ_CHECK(info.finite_points >= 1 && info.finite_points <= info.points,
                     "info.finite_points");
  PCL_ICF_FUZZ_CHECK(info.organized == (cloud.height > 1), "info.organized");
  PCL_ICF_FUZZ_CHECK(cloud.size() <= pcl::icf::io::kMaxScenePoints, "kMaxScenePoints");
  PCL_ICF_FUZZ_CHECK(
      cloud.sensor_origin_.allFinite() && cloud.sensor_orientation_.coeffs().allFinite(),
      "finite viewpoint");
  std::size_t finite = 0;
  for (const auto& p : cloud)
    finite += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
  PCL_ICF_FUZZ_CHECK(finite == info.finite_points, "info.finite_points counts the finite points");
  PCL_ICF_FUZZ_CHECK(!cloud.is_dense || finite == cloud.size(), "is_dense only when all finite");
}

/** Loads a scene file of the given extension; a FileError is an accepted outcome. */
inline void fuzzSceneFile(const ScratchFile& file, const std::uint8_t* data, std::size_t size) {
  const std::string& path = file.write(data, size);
  try {
    pcl::icf::io::SceneFileInfo info;
    const auto cloud = pcl::icf::io::loadSceneCloud(path, &info);
    PCL_ICF_FUZZ_CHECK(cloud != nullptr, "loadSceneCloud returns a cloud or throws");
    checkScene(*cloud, info);
  } catch (const pcl::icf::io::FileError&) {
  }
}

/** Invariants of a FaceMesh that FaceMesh::build returned; on small meshes also the Embree
 * index against brute force at a few query points (a wrong distance is a finding too). */
inline void checkFaceMesh(const pcl::icf::FaceMesh& mesh) {
  using pcl::icf::Face;
  PCL_ICF_FUZZ_CHECK(mesh.size() >= 1, "a built mesh has faces");
  const auto& indices = mesh.faceVertexIndices();
  for (const Face& f : mesh.faces()) {
    PCL_ICF_FUZZ_CHECK(f.count >= 3, "faces have 3 or more vertices");
    PCL_ICF_FUZZ_CHECK(std::size_t(f.first) + f.count <= indices.size(), "face index range");
    PCL_ICF_FUZZ_CHECK(std::isfinite(f.area) && f.area > 0.f, "positive finite area");
    PCL_ICF_FUZZ_CHECK(f.normal.allFinite() && std::abs(f.normal.norm() - 1.f) < 1e-3f,
                       "unit normal");
    for (std::uint32_t k = 0; k < f.count; ++k) {
      PCL_ICF_FUZZ_CHECK(indices[f.first + k] < mesh.vertices().size(), "vertex index");
      PCL_ICF_FUZZ_CHECK(mesh.vertices()[indices[f.first + k]].allFinite(), "finite vertex");
    }
  }
  PCL_ICF_FUZZ_CHECK(std::isfinite(mesh.totalArea()) && mesh.totalArea() > 0.0, "total area");
  PCL_ICF_FUZZ_CHECK((mesh.boundsMin().array() <= mesh.boundsMax().array()).all(), "bounds");

  const Eigen::Vector3f extent = mesh.boundsMax() - mesh.boundsMin();
  if (mesh.size() > 2000 || !extent.allFinite() || !(extent.norm() < 1e6f))
    return;
  const pcl::icf::EmbreeClosestFaceIndex index(mesh);
  const pcl::icf::BruteForceClosestFace brute(mesh);
  const float scale = std::max(1e-3f, extent.norm());
  const Eigen::Vector3f queries[] = {mesh.surfaceCentroid(), mesh.boundsMin() - 0.1f * extent,
                                     mesh.boundsMax() + 0.3f * extent,
                                     mesh.faceVertex(0, 0) + Eigen::Vector3f(0.01f, 0.f, 0.f)};
  for (const Eigen::Vector3f& q : queries) {
    if (!q.allFinite())
      continue;
    const pcl::icf::ClosestFace e = index.closestFace(q);
    const pcl::icf::ClosestFace b = brute.closestFace(q);
    PCL_ICF_FUZZ_CHECK(e.found() && b.found(), "a query finds a face");
    PCL_ICF_FUZZ_CHECK(std::abs(e.distance - b.distance) <= 1e-4f * scale,
                       "Embree and brute force agree");
  }
}

/** Loads a mesh file of the given extension and builds its FaceMesh; FileError and
 * InvalidMeshError are accepted outcomes. */
inline void fuzzMeshFile(const ScratchFile& file, const std::uint8_t* data, std::size_t size) {
  const std::string& path = file.write(data, size);
  pcl::PolygonMesh mesh;
  try {
    mesh = pcl::icf::io::loadPolygonMesh(path);
  } catch (const pcl::icf::io::FileError&) {
    return;
  }
  PCL_ICF_FUZZ_CHECK(mesh.cloud.width * mesh.cloud.height > 0, "a loaded mesh has vertices");
  try {
    checkFaceMesh(pcl::icf::FaceMesh::build(mesh));
  } catch (const pcl::icf::InvalidMeshError&) {
  }
}

}  // namespace pcl_icf_fuzz

/** \brief The two entry points of a file-format target: each input is written to a scratch file
 * with extension \a ext (the loaders take paths and pick the format by it) and loaded by
 * pcl_icf_fuzz::\a fuzz (fuzzMeshFile or fuzzSceneFile). */
#define PCL_ICF_FILE_FUZZ_TARGET(ext, fuzz)                                           \
  extern "C" int LLVMFuzzerInitialize(int*, char***) {                                \
    pcl_icf_fuzz::quiet();                                                            \
    return 0;                                                                         \
  }                                                                                   \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    static const pcl_icf_fuzz::ScratchFile file(ext);                                 \
    pcl_icf_fuzz::fuzz(file, data, size);                                             \
    return 0;                                                                         \
  }
