/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/icf/io/scene_io.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
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

/** The header lines of a text header (PCD, PLY) up to and including the line that starts with
 * \a last_keyword, at most 64 KiB; empty when that line is not found. */
std::vector<std::string> headerLines(const std::string& path, const std::string& last_keyword) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> lines;
  std::string line;
  std::size_t bytes = 0;
  while (bytes < 65536 && std::getline(in, line)) {
    bytes += line.size() + 1;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    lines.push_back(line);
    if (line.compare(0, last_keyword.size(), last_keyword) == 0)
      return lines;
  }
  return {};
}

/** First whitespace-separated word of \a line and the rest as a stream. */
std::istringstream words(const std::string& line, std::string& keyword) {
  std::istringstream in(line);
  in >> keyword;
  return in;
}

void checkPointCount(const std::string& path, double count) {
  if (!(count <= static_cast<double>(kMaxScenePoints)))
    throw FileError(path + ": header claims " + std::to_string(static_cast<long double>(count)) +
                    " points, more than the " + std::to_string(kMaxScenePoints) +
                    " this reader accepts");
}

/** Checks a PCD header before PCL's reader allocates what it claims. */
void checkPcdHeader(const std::string& path) {
  const auto lines = headerLines(path, "DATA");
  if (lines.empty())
    throw FileError(path + ": not a PCD file (no DATA line in its header)");
  double width = 0, height = 1, points = -1;
  std::string data;
  for (const std::string& line : lines) {
    std::string key;
    auto rest = words(line, key);
    if (key == "WIDTH")
      rest >> width;
    else if (key == "HEIGHT")
      rest >> height;
    else if (key == "POINTS")
      rest >> points;
    else if (key == "DATA")
      rest >> data;
  }
  checkPointCount(path, width * height);
  checkPointCount(path, points);
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    throw FileError(path + ": PCD header has an unknown DATA type '" + printable(data) + "'");
}

/** Checks a PLY header: magic, a vertex element, and a size the file can hold. */
void checkPlyHeader(const std::string& path) {
  {
    std::ifstream in(path, std::ios::binary);
    char magic[3] = {0, 0, 0};
    in.read(magic, 3);
    if (std::string(magic, 3) != "ply")
      throw FileError(path + ": not a PLY file (no 'ply' header line)");
  }
  const auto lines = headerLines(path, "end_header");
  if (lines.empty())
    throw FileError(path + ": PLY header has no end_header line (malformed or truncated)");
  std::uintmax_t header_bytes = 0;
  for (const std::string& line : lines)
    header_bytes += line.size() + 1;
  std::string format;
  double vertices = -1;
  bool in_vertex = false, fixed_size = true;
  std::uintmax_t vertex_bytes = 0;
  for (const std::string& line : lines) {
    std::string key;
    auto rest = words(line, key);
    if (key == "format")
      rest >> format;
    else if (key == "element") {
      std::string name;
      double count = -1;
      rest >> name >> count;
      in_vertex = name == "vertex";
      if (in_vertex)
        vertices = count;
    } else if (key == "property" && in_vertex) {
      std::string type;
      rest >> type;
      if (type == "list")
        fixed_size = false;
      else if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
        vertex_bytes += 1;
      else if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
        vertex_bytes += 2;
      else if (type == "double" || type == "float64")
        vertex_bytes += 8;
      else
        vertex_bytes += 4;
    }
  }
  if (vertices < 0)
    throw FileError(path + ": PLY header declares no vertex element");
  checkPointCount(path, vertices);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  const std::uintmax_t body = size > header_bytes ? size - header_bytes : 0;
  const std::uintmax_t per_vertex = format == "ascii" ? 6 : (fixed_size ? vertex_bytes : 1);
  if (static_cast<double>(body) < vertices * static_cast<double>(per_vertex))
    throw FileError(path + ": PLY file is shorter than its " +
                    std::to_string(static_cast<std::uintmax_t>(vertices)) +
                    " vertices need (truncated)");
}

/** Reads one numeric field of a PCLPointCloud2 point as double. */
double readField(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case pcl::PCLPointField::UINT8:
      return *p;
    case pcl::PCLPointField::INT16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::UINT16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::INT32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::UINT32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

std::size_t fieldSize(std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8:
      return 1;
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16:
      return 2;
    case pcl::PCLPointField::FLOAT64:
      return 8;
    default:
      return 4;
  }
}

const pcl::PCLPointField* findField(const pcl::PCLPointCloud2& blob, const std::string& name) {
  for (const auto& f : blob.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

/** Copies x, y, z (any numeric type) and the colour (packed rgb / rgba, or red, green, blue)
 * of a PCLPointCloud2 into a PointXYZRGBA cloud of the same width and height. */
Cloud::Ptr fromBlob(const pcl::PCLPointCloud2& blob, const std::string& path, bool& has_colour) {
  const pcl::PCLPointField* axes[3] = {findField(blob, "x"), findField(blob, "y"),
                                       findField(blob, "z")};
  for (int i = 0; i < 3; ++i)
    if (!axes[i])
      throw FileError(path + ": the file has no '" + std::string(1, char('x' + i)) +
                      "' field, so it holds no 3D points");
  const pcl::PCLPointField* packed = findField(blob, "rgba");
  if (!packed)
    packed = findField(blob, "rgb");
  const pcl::PCLPointField* channels[3] = {findField(blob, "red"), findField(blob, "green"),
                                           findField(blob, "blue")};
  const bool separate = channels[0] && channels[1] && channels[2];
  if (packed && fieldSize(packed->datatype) != 4)
    packed = nullptr;
  has_colour = packed || separate;

  const std::size_t n = static_cast<std::size_t>(blob.width) * blob.height;
  const std::size_t step = blob.point_step;
  // Every field must lie inside a point, and the data must hold every point.
  std::vector<const pcl::PCLPointField*> used(axes, axes + 3);
  if (packed)
    used.push_back(packed);
  if (separate && !packed)
    used.insert(used.end(), channels, channels + 3);
  for (const auto* f : used)
    if (f->offset + fieldSize(f->datatype) > step)
      throw FileError(path + ": field '" + f->name + "' lies outside the point (malformed)");
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
    const std::uint8_t* p = blob.data.data() + row * blob.row_step + col * step;
    pcl::PointXYZRGBA& q = (*cloud)[i];
    q.x = static_cast<float>(readField(p + axes[0]->offset, axes[0]->datatype));
    q.y = static_cast<float>(readField(p + axes[1]->offset, axes[1]->datatype));
    q.z = static_cast<float>(readField(p + axes[2]->offset, axes[2]->datatype));
    dense = dense && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
    if (packed) {
      std::uint32_t rgba;
      std::memcpy(&rgba, p + packed->offset, 4);
      q.r = static_cast<std::uint8_t>((rgba >> 16) & 0xff);
      q.g = static_cast<std::uint8_t>((rgba >> 8) & 0xff);
      q.b = static_cast<std::uint8_t>(rgba & 0xff);
      q.a = 255;
    } else if (separate) {
      auto channel = [&](const pcl::PCLPointField* f) {
        const double v = readField(p + f->offset, f->datatype);
        // Float colours in [0, 1] (some PLY writers) or integers in [0, 255].
        const double scaled = (f->datatype == pcl::PCLPointField::FLOAT32 ||
                               f->datatype == pcl::PCLPointField::FLOAT64) &&
                                      v <= 1.0
                                  ? 255.0 * v
                                  : v;
        return static_cast<std::uint8_t>(std::min(255.0, std::max(0.0, std::round(scaled))));
      };
      q.r = channel(channels[0]);
      q.g = channel(channels[1]);
      q.b = channel(channels[2]);
      q.a = 255;
    } else {
      q.r = q.g = q.b = q.a = 255;
    }
  }
  cloud->is_dense = dense;
  return cloud;
}

Cloud::Ptr loadPcd(const std::string& path, bool& has_colour) {
  checkPcdHeader(path);
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
  checkPlyHeader(path);
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
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && in.fail())
      throw FileError(path + ": read error");
    cloud = parseXyzText(text, path, &local.has_colour);
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
