/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "tool_output.h"

#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <unistd.h>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace fs = std::filesystem;

namespace pcl_icf_tool {

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec))
    return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

void checkOutputPath(const std::string& what, const std::string& output,
                     const std::vector<std::string>& inputs, bool force) {
  if (output.empty())
    throw OutputError(what + ": empty file name");
  for (const std::string& input : inputs)
    if (!input.empty() && samePath(output, input))
      throw OutputError(what + " " + output + " is an input file; refusing to overwrite it");
  std::error_code ec;
  const fs::path path(output);
  if (fs::is_directory(path, ec))
    throw OutputError(what + " " + output + " is a directory");
  if (fs::exists(path, ec) && !force)
    throw OutputError(what + " " + output + " exists; use --force to replace it");
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw OutputError(what + " " + output + ": folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw OutputError(what + " " + output + ": folder " + dir.string() + " is not writable");
}

void writeAtomically(const std::string& target, bool force,
                     const std::function<void(const std::string&)>& write) {
  const fs::path path(target);
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const fs::path temporary = dir / ("." + path.stem().string() + ".tmp-" +
                                    std::to_string(::getpid()) + path.extension().string());
  std::error_code ec;
  try {
    write(temporary.string());
  } catch (const std::exception& e) {
    fs::remove(temporary, ec);
    throw OutputError("could not write " + target + ": " + e.what());
  }
  if (!fs::exists(temporary, ec)) {
    throw OutputError("could not write " + target);
  }
  if (force) {
    fs::rename(temporary, path, ec);
    if (ec) {
      fs::remove(temporary, ec);
      throw OutputError("could not write " + target + ": " + ec.message());
    }
    return;
  }
  // link() fails when the target exists: no check-then-write race.
  if (::link(temporary.c_str(), path.c_str()) != 0) {
    const int err = errno;
    if (err == EEXIST) {
      fs::remove(temporary, ec);
      throw OutputError(target + " appeared while working; use --force to replace it");
    }
    // File systems without hard links: fall back to check + rename.
    if (fs::exists(path, ec)) {
      fs::remove(temporary, ec);
      throw OutputError(target + " exists; use --force to replace it");
    }
    fs::rename(temporary, path, ec);
    if (ec) {
      fs::remove(temporary, ec);
      throw OutputError("could not write " + target + ": " + ec.message());
    }
    return;
  }
  fs::remove(temporary, ec);
}

namespace {

/** x, y, z of vertex \a i of a mesh's cloud (FLOAT32 or FLOAT64 fields). */
Eigen::Vector3d vertex(const pcl::PCLPointCloud2& cloud, const int offsets[3],
                       const bool doubles[3], std::size_t i) {
  Eigen::Vector3d v;
  const std::uint8_t* p = cloud.data.data() + i * cloud.point_step;
  for (int k = 0; k < 3; ++k) {
    if (doubles[k]) {
      double d;
      std::memcpy(&d, p + offsets[k], sizeof d);
      v[k] = d;
    } else {
      float f;
      std::memcpy(&f, p + offsets[k], sizeof f);
      v[k] = f;
    }
  }
  return v;
}

bool xyzLayout(const pcl::PCLPointCloud2& cloud, int offsets[3], bool doubles[3]) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    offsets[k] = -1;
    for (const auto& f : cloud.fields)
      if (f.name == names[k] && (f.datatype == pcl::PCLPointField::FLOAT32 ||
                                 f.datatype == pcl::PCLPointField::FLOAT64)) {
        offsets[k] = static_cast<int>(f.offset);
        doubles[k] = f.datatype == pcl::PCLPointField::FLOAT64;
      }
    if (offsets[k] < 0)
      return false;
  }
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  return cloud.data.size() >= n * cloud.point_step;
}

}  // namespace

pcl::PolygonMesh posedMesh(const pcl::PolygonMesh& mesh, const Eigen::Matrix4d& pose,
                           double scale) {
  int offsets[3];
  bool doubles[3];
  if (!xyzLayout(mesh.cloud, offsets, doubles))
    throw OutputError("the mesh has no float x, y, z vertex fields");
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  pcl::PointCloud<pcl::PointXYZ> vertices;
  vertices.resize(n);
  const Eigen::Matrix3d r = pose.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = pose.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = r * (scale * vertex(mesh.cloud, offsets, doubles, i)) + t;
    vertices[i].getVector3fMap() = v.cast<float>();
  }
  pcl::PolygonMesh out;
  pcl::toPCLPointCloud2(vertices, out.cloud);
  out.polygons = mesh.polygons;
  return out;
}

double meshExtent(const pcl::PolygonMesh& mesh) {
  int offsets[3];
  bool doubles[3];
  if (!xyzLayout(mesh.cloud, offsets, doubles))
    return 0.0;
  const std::size_t n = static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d v = vertex(mesh.cloud, offsets, doubles, i);
    if (!v.allFinite())
      continue;
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
    any = true;
  }
  return any ? (hi - lo).norm() : 0.0;
}

}  // namespace pcl_icf_tool
