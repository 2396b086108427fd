/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/icf/io/scene_io.h>
#include <pcl_icf_internal/point_field.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <vector>

namespace pcl {
namespace icf {
namespace io {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZRGBA>;
using detail::printable;

/** Text files larger than this are refused before reading (4 GiB of "x y z" lines is well
 * above kMaxScenePoints anyway). */
constexpr std::uintmax_t kMaxTextBytes = std::uintmax_t(4) << 30;

/** The first field named \a name (pcl::getFieldIndex), nullptr when there is none. */
const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob, const std::string& name) {
  const int index = pcl::getFieldIndex(blob, name);
  return index < 0 ? nullptr : &blob.fields[static_cast<std::size_t>(index)];
}

/** The fields of a PCLPointCloud2 that make a PointXYZRGBA: x, y, z (any numeric type) and the
 * colour, packed (rgba or rgb, 4 bytes) or separate (red, green, blue). */
struct BlobFields {
  const pcl::PCLPointField* axes[3] = {nullptr, nullptr, nullptr};
  const pcl::PCLPointField* packed = nullptr;
  const pcl::PCLPointField* channels[3] = {nullptr, nullptr, nullptr};
  bool separate = false;  ///< red, green and blue, used when there is no packed colour
};

/** Finds the fields and checks that each lies inside a point. */
BlobFields blobFields(const pcl::PCLPointCloud2& blob, const std::string& path) {
  BlobFields b;
  for (int i = 0; i < 3; ++i) {
    b.axes[i] = findField(blob, std::string(1, char('x' + i)));
    if (!b.axes[i])
      throw FileError(path + ": the file has no '" + std::string(1, char('x' + i)) +
                      "' field, so it holds no 3D points");
  }
  b.packed = findField(blob, "rgba");
  if (!b.packed)
    b.packed = findField(blob, "rgb");
  const char* names[3] = {"red", "green", "blue"};
  for (int i = 0; i < 3; ++i)
    b.channels[i] = findField(blob, names[i]);
  b.separate = b.channels[0] && b.channels[1] && b.channels[2];
  if (b.packed && pcl::getFieldSize(b.packed->datatype) != 4)
    b.packed = nullptr;
  std::vector<const pcl::PCLPointField*> used(b.axes, b.axes + 3);
  if (b.packed)
    used.push_back(b.packed);
  if (b.separate && !b.packed)
    used.insert(used.end(), b.channels, b.channels + 3);
  for (const auto* f : used)
    if (f->offset + static_cast<std::size_t>(pcl::getFieldSize(f->datatype)) > blob.point_step)
      throw FileError(path + ": field '" + f->name + "' lies outside the point (malformed)");
  return b;
}

double readField(const std::uint8_t* p, const pcl::PCLPointField& f) {
  return internal::readFieldValue(p + f.offset, f.datatype);
}

/** The point at \a p as a PointXYZRGBA: white without colour fields. */
pcl::PointXYZRGBA readPoint(const std::uint8_t* p, const BlobFields& b) {
  pcl::PointXYZRGBA q;
  q.x = static_cast<float>(readField(p, *b.axes[0]));
  q.y = static_cast<float>(readField(p, *b.axes[1]));
  q.z = static_cast<float>(readField(p, *b.axes[2]));
  q.r = q.g = q.b = q.a = 255;
  if (b.packed) {
    std::uint32_t rgba;
    std::memcpy(&rgba, p + b.packed->offset, 4);
    q.r = static_cast<std::uint8_t>((rgba >> 16) & 0xff);
    q.g = static_cast<std::uint8_t>((rgba >> 8) & 0xff);
    q.b = static_cast<std::uint8_t>(rgba & 0xff);
  } else if (b.separate) {
    auto channel = [&](const pcl::PCLPointField* f) {
      const double v = readField(p, *f);
      // Float colours in [0, 1] (some PLY writers) or integers in [0, 255].
      const double scaled = (f->datatype == pcl::PCLPointField::FLOAT32 ||
                             f->datatype == pcl::PCLPointField::FLOAT64) &&
                                    v <= 1.0
                                ? 255.0 * v
                                : v;
      return static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, std::round(scaled))));
    };
    q.r = channel(b.channels[0]);
    q.g = channel(b.channels[1]);
    q.b = channel(b.channels[2]);
  }
  return q;
}

/** Copies x, y, z and the colour of a PCLPointCloud2 into a PointXYZRGBA cloud of the same
 * width and height. */
Cloud::Ptr fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path, bool& has_colour) {
  const BlobFields fields = blobFields(blob, path);
  has_colour = fields.packed || fields.separate;
  const std::size_t n = static_cast<std::size_t>(blob.width) * blob.height;
  const std::size_t step = blob.point_step;
  if (n == 0)
    throw EmptyCloudError(path + ": the cloud has no points");
  if (blob.data.size() < n * step || (blob.height > 1 && blob.row_step < blob.width * step))
    throw FileError(path + ": point data shorter than the header claims (truncated file)");

  auto cloud = pcl::make_shared<Cloud>();
  cloud->width = blob.width;
  cloud->height = blob.height;
  cloud->resize(n);
  bool dense = true;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t row = blob.height > 1 ? i / blob.width : 0;
    const std::size_t col = blob.height > 1 ? i % blob.width : i;
    pcl::PointXYZRGBA& q = (*cloud)[i];
    q = readPoint(blob.data.data() + row * blob.row_step + col * step, fields);
    dense = dense && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
  }
  cloud->is_dense = dense;
  return cloud;
}

Cloud::Ptr loadPcd(const std::string& path, bool& has_colour) {
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  // Our reader, not pcl::PCDReader, which crashes on malformed headers and parses binary data
  // as header lines (file_formats.h).
  detail::readPcdFile(path, kMaxScenePoints, blob, origin, orientation);
  auto cloud = fromBlob(blob, path, has_colour);
  // A VIEWPOINT that is not a pose (NaN, a zero quaternion) is treated as the identity.
  if (!origin.allFinite() || !orientation.coeffs().allFinite() ||
      std::abs(orientation.norm() - 1.f) > 1e-3f) {
    PCL_WARN(
        "[pcl::icf::io::loadSceneCloud] %s: VIEWPOINT is not a valid pose; using the "
        "identity\n",
        path.c_str());
    origin.setZero();
    orientation.setIdentity();
  }
  cloud->sensor_origin_ = origin;
  cloud->sensor_origin_[3] = 0.f;
  cloud->sensor_orientation_ = orientation.normalized();
  return cloud;
}

Cloud::Ptr loadPly(const std::string& path, bool& has_colour) {
  // Our reader, not pcl::PLYReader, which asserts and overruns on malformed files
  // (file_formats.h).
  const pcl::PCLPointCloud2 blob = detail::readPlyFile(path, false, kMaxScenePoints).vertices;
  return fromBlob(blob, path, has_colour);
}

/** Splits \a line at spaces, tabs and commas. */
void splitTokens(const char* begin, const char* end,
                 std::vector<std::pair<const char*, const char*>>& out) {
  out.clear();
  const char* p = begin;
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == ','))
      ++p;
    const char* start = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != ',')
      ++p;
    if (p > start)
      out.emplace_back(start, p);
  }
}

bool parseNumber(const char* begin, const char* end, double& value) {
  if (begin < end && *begin == '+')
    ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

Cloud::Ptr parseXyzText(const std::string& text, const std::string& name, bool* has_colour) {
  auto cloud = pcl::make_shared<Cloud>();
  std::vector<std::pair<const char*, const char*>> tokens;
  int columns = 0;  // 3 or 6, fixed by the first point line
  std::size_t line_number = 0;
  std::size_t pos = 0;
  bool dense = true;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos)
      eol = text.size();
    ++line_number;
    std::size_t stop = eol;
    if (stop > pos && text[stop - 1] == '\r')
      --stop;
    // Comments: a '#' and everything after it.
    const char* p = text.data() + pos;
    const char* line_end = std::find(p, text.data() + stop, '#');
    splitTokens(p, line_end, tokens);
    const std::string where = name + ":" + std::to_string(line_number) + ": ";
    pos = eol + 1;
    if (tokens.empty())
      continue;
    const int count = static_cast<int>(tokens.size());
    if (count != 3 && count != 6)
      throw FileError(where + "expected 3 numbers (x y z) or 6 (x y z r g b), found " +
                      std::to_string(count) + " fields (malformed or truncated file)");
    if (columns == 0)
      columns = count;
    else if (count != columns)
      throw FileError(where + "found " + std::to_string(count) +
                      " fields where earlier lines have " + std::to_string(columns) +
                      " (malformed or truncated file)");
    double v[6];
    for (int i = 0; i < count; ++i)
      if (!parseNumber(tokens[i].first, tokens[i].second, v[i]))
        throw FileError(where + "'" + printable(std::string(tokens[i].first, tokens[i].second)) +
                        "' is not a number (malformed file)");
    if (cloud->size() >= kMaxScenePoints)
      throw FileError(name + ": more than " + std::to_string(kMaxScenePoints) +
                      " points, more than this reader accepts");
    pcl::PointXYZRGBA q;
    q.x = static_cast<float>(v[0]);
    q.y = static_cast<float>(v[1]);
    q.z = static_cast<float>(v[2]);
    q.r = q.g = q.b = q.a = 255;
    if (count == 6) {
      for (int i = 3; i < 6; ++i)
        if (!(v[i] >= 0.0 && v[i] <= 255.0 && v[i] == std::floor(v[i])))
          throw FileError(where + "colour '" +
                          printable(std::string(tokens[i].first, tokens[i].second)) +
                          "' is not an integer in [0, 255]");
      q.r = static_cast<std::uint8_t>(v[3]);
      q.g = static_cast<std::uint8_t>(v[4]);
      q.b = static_cast<std::uint8_t>(v[5]);
    }
    dense = dense && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
    cloud->push_back(q);
  }
  cloud->is_dense = dense;
  if (has_colour)
    *has_colour = columns == 6;
  if (cloud->empty())
    throw EmptyCloudError(name + ": the file holds no points (only blank or comment lines)");
  return cloud;
}

Cloud::Ptr loadSceneCloud(const std::string& path, SceneFileInfo* info) {
  requireReadableFile(path);
  const std::string ext = fileExtension(path);
  SceneFileInfo local;
  Cloud::Ptr cloud;
  if (ext == "pcd") {
    local.format = "pcd";
    cloud = loadPcd(path, local.has_colour);
  } else if (ext == "ply") {
    local.format = "ply";
    cloud = loadPly(path, local.has_colour);
  } else if (ext == "xyz" || ext == "asc") {
    local.format = "xyz";
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) > kMaxTextBytes)
      throw FileError(path + ": text file larger than 4 GiB, more than this reader accepts");
    cloud = parseXyzText(detail::readWholeFile(path), path, &local.has_colour);
  } else
    throw FileError(path + ": unknown scene extension '." + ext +
                    "' (expected .pcd, .ply, .xyz or .asc)");

  local.points = cloud->size();
  local.organized = cloud->height > 1;
  for (const auto& q : *cloud)
    local.finite_points += std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
  if (local.points == 0)
    throw EmptyCloudError(path + ": the cloud has no points");
  if (local.finite_points == 0)
    throw EmptyCloudError(path + ": all " + std::to_string(local.points) +
                          " points have a NaN or infinite coordinate (no usable point)");
  if (info)
    *info = local;
  return cloud;
}

}  // namespace io
}  // namespace icf
}  // namespace pcl
