/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/icf/io/mesh_io.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace pcl {
namespace icf {
namespace io {

std::string fileExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.')
    ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void requireReadableFile(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    throw FileError(path + ": no such file");
  if (!std::filesystem::is_regular_file(status))
    throw FileError(path + ": not a regular file");
  if (std::filesystem::file_size(path, ec) == 0 || ec)
    throw FileError(path + ": file is empty");
  std::ifstream probe(path, std::ios::binary);
  if (!probe)
    throw FileError(path + ": cannot be opened for reading");
}

pcl::PolygonMesh loadPolygonMesh(const std::string& path) {
  requireReadableFile(path);
  const std::string ext = fileExtension(path);
  pcl::PolygonMesh mesh;
  // Our readers (file_formats.h) for every format; PCL's and VTK's crash on malformed files.
  if (ext == "ply") {
    detail::PlyContents ply = detail::readPlyFile(path, true, detail::kMaxMeshElements);
    mesh.cloud = std::move(ply.vertices);
    mesh.polygons = std::move(ply.polygons);
  } else if (ext == "obj")
    mesh = detail::readObjFile(path);
  else if (ext == "stl")
    mesh = detail::readStlFile(path);
  else if (ext == "vtk")
    mesh = detail::readVtkFile(path);
  else
    throw FileError(path + ": unknown mesh extension '." + ext +
                    "' (expected .ply, .obj, .stl or .vtk)");
  if (mesh.cloud.width * mesh.cloud.height == 0 || mesh.cloud.data.empty())
    throw FileError(path + ": no vertices could be read (malformed, truncated or empty ." + ext +
                    " file)");
  const std::size_t expected =
      static_cast<std::size_t>(mesh.cloud.width) * mesh.cloud.height * mesh.cloud.point_step;
  if (mesh.cloud.data.size() < expected)
    throw FileError(path + ": vertex data shorter than its header claims (truncated file)");
  return mesh;
}

}  // namespace io
}  // namespace icf
}  // namespace pcl
