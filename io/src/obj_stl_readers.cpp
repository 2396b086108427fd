/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <unordered_map>

namespace pcl {
namespace icf {
namespace io {
namespace detail {
namespace {

using Token = std::pair<const char*, const char*>;

/** The words of one line (split at spaces and tabs), after a '#' comment is cut off when
 * \a comments. */
void splitLine(const char* begin, const char* end, bool comments, std::vector<Token>& words) {
  words.clear();
  if (comments)
    end = std::find(begin, end, '#');
  const char* p = begin;
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\v' || *p == '\f'))
      ++p;
    const char* start = p;
    while (p < end && !(*p == ' ' || *p == '\t' || *p == '\r' || *p == '\v' || *p == '\f'))
      ++p;
    if (p > start)
      words.emplace_back(start, p);
  }
}

bool equals(const Token& t, const char* word) {
  const std::size_t n = std::strlen(word);
  return static_cast<std::size_t>(t.second - t.first) == n && std::memcmp(t.first, word, n) == 0;
}

bool parseDouble(const Token& t, double& v) {
  const char* first = (t.second - t.first > 1 && *t.first == '+') ? t.first + 1 : t.first;
  const auto [ptr, ec] = std::from_chars(first, t.second, v);
  if (ec == std::errc::result_out_of_range && ptr == t.second) {
    v = *first == '-' ? -INFINITY : INFINITY;  // kept as a non-finite vertex: FaceMesh drops it
    return true;
  }
  return ec == std::errc() && ptr == t.second;
}

bool parseInteger(const char* begin, const char* end, long long& v) {
  const auto [ptr, ec] = std::from_chars(begin, end, v);
  return ec == std::errc() && ptr == end && begin < end;
}

/** A face vertex: v, v/t, v//n or v/t/n with integers (t and n are read and ignored). */
bool parseFaceVertex(const Token& t, long long& v) {
  const char* s1 = std::find(t.first, t.second, '/');
  if (!parseInteger(t.first, s1, v) || v == 0)
    return false;
  if (s1 == t.second)
    return true;
  long long ignored;
  const char* s2 = std::find(s1 + 1, t.second, '/');
  if (s2 == t.second)
    return parseInteger(s1 + 1, s2, ignored);
  return (s2 == s1 + 1 || parseInteger(s1 + 1, s2, ignored)) &&
         parseInteger(s2 + 1, t.second, ignored);
}

/** Visits the lines of \a data: f(line_number, begin, end) without the line break. */
template <typename F>
void forEachLine(const std::string& data, F f) {
  std::size_t pos = 0, line = 0;
  while (pos < data.size()) {
    std::size_t eol = data.find('\n', pos);
    if (eol == std::string::npos)
      eol = data.size();
    f(++line, data.data() + pos, data.data() + eol);
    pos = eol + 1;
  }
}

pcl::PolygonMesh toMesh(const pcl::PointCloud<pcl::PointXYZ>& vertices,
                        std::vector<pcl::Vertices> polygons) {
  pcl::PolygonMesh mesh;
  pcl::toPCLPointCloud2(vertices, mesh.cloud);
  mesh.polygons = std::move(polygons);
  return mesh;
}

void checkElementCount(const std::string& path, std::size_t count, const char* what) {
  if (count >= kMaxMeshElements)
    throw FileError(path + ": more than " + std::to_string(kMaxMeshElements) + " " + what +
                    ", more than this reader accepts");
}

/** The binary STL header: an 80-byte comment, then the triangle count (little-endian uint32);
 * false when the file is shorter than 84 bytes. */
bool binaryStlHeader(const std::string& data, std::uint32_t& triangles) {
  if (data.size() < 84)
    return false;
  std::memcpy(&triangles, data.data() + 80, 4);
  return true;
}

pcl::PolygonMesh readBinaryStl(const std::string& path, const std::string& data) {
  std::uint32_t triangles;
  if (!binaryStlHeader(data, triangles))
    throw FileError(path + ": binary STL shorter than its 84-byte header (truncated file)");
  if (triangles > (data.size() - 84) / 50)
    throw FileError(path + ": binary STL claims " + std::to_string(triangles) +
                    " triangles but holds " + std::to_string((data.size() - 84) / 50) +
                    " (truncated file or not an STL file)");
  checkElementCount(path, triangles, "triangles");
  pcl::PointCloud<pcl::PointXYZ> vertices;
  std::vector<pcl::Vertices> polygons(triangles);
  std::unordered_map<std::string, pcl::index_t> seen;  // 12 bytes of a vertex -> index
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const char* record = data.data() + 84 + 50 * std::size_t(t);
    for (int k = 0; k < 3; ++k) {
      const char* xyz = record + 12 + 12 * k;
      const auto inserted =
          seen.emplace(std::string(xyz, 12), static_cast<pcl::index_t>(vertices.size()));
      if (inserted.second) {
        pcl::PointXYZ p;
        std::memcpy(&p.x, xyz, 4);
        std::memcpy(&p.y, xyz + 4, 4);
        std::memcpy(&p.z, xyz + 8, 4);
        vertices.push_back(p);
      }
      polygons[t].vertices.push_back(inserted.first->second);
    }
  }
  return toMesh(vertices, std::move(polygons));
}

pcl::PolygonMesh readAsciiStl(const std::string& path, const std::string& data) {
  pcl::PointCloud<pcl::PointXYZ> vertices;
  std::vector<pcl::Vertices> polygons;
  std::unordered_map<std::string, pcl::index_t> seen;
  std::vector<Token> words;
  bool in_facet = false, in_solid = false;
  std::size_t last_line = 0;
  forEachLine(data, [&](std::size_t line, const char* begin, const char* end) {
    last_line = line;
    splitLine(begin, end, false, words);
    if (words.empty())
      return;
    const std::string where = path + ":" + std::to_string(line) + ": ";
    const Token& key = words[0];
    if (equals(key, "solid")) {
      in_solid = true;
      return;  // the name is free text
    }
    if (equals(key, "endsolid")) {
      if (in_facet)
        throw FileError(where + "endsolid inside a facet (malformed STL file)");
      in_solid = false;
      return;
    }
    if (!in_solid)
      throw FileError(where + "'" + printable(std::string(key.first, key.second)) +
                      "' outside 'solid' ... 'endsolid' (malformed STL file)");
    if (equals(key, "facet")) {
      if (in_facet)
        throw FileError(where + "facet inside a facet (malformed STL file)");
      in_facet = true;
      polygons.emplace_back();
      checkElementCount(path, polygons.size(), "facets");
    } else if (equals(key, "vertex")) {
      double v[3];
      if (!in_facet || words.size() != 4 || !parseDouble(words[1], v[0]) ||
          !parseDouble(words[2], v[1]) || !parseDouble(words[3], v[2]))
        throw FileError(where + "expected 'vertex x y z' inside a facet (malformed STL file)");
      pcl::PointXYZ p;
      p.x = static_cast<float>(v[0]);
      p.y = static_cast<float>(v[1]);
      p.z = static_cast<float>(v[2]);
      char key_bytes[12];
      std::memcpy(key_bytes, &p.x, 4);
      std::memcpy(key_bytes + 4, &p.y, 4);
      std::memcpy(key_bytes + 8, &p.z, 4);
      const auto inserted =
          seen.emplace(std::string(key_bytes, 12), static_cast<pcl::index_t>(vertices.size()));
      if (inserted.second)
        vertices.push_back(p);
      polygons.back().vertices.push_back(inserted.first->second);
      checkElementCount(path, polygons.back().vertices.size(), "vertices in a facet");
    } else if (equals(key, "endfacet")) {
      if (!in_facet)
        throw FileError(where + "endfacet outside a facet (malformed STL file)");
      if (polygons.back().vertices.size() < 3)
        throw FileError(where + "a facet with " + std::to_string(polygons.back().vertices.size()) +
                        " vertices (malformed STL file)");
      in_facet = false;
    } else if (!equals(key, "outer") && !equals(key, "endloop"))
      throw FileError(where + "'" + printable(std::string(key.first, key.second)) +
                      "' is not an ascii STL keyword (malformed STL file)");
  });
  if (in_facet || in_solid)
    throw FileError(path + ":" + std::to_string(last_line) + ": the file ends inside a " +
                    (in_facet ? "facet" : "solid") + " (truncated STL file)");
  return toMesh(vertices, std::move(polygons));
}

}  // namespace

pcl::PolygonMesh readStlFile(const std::string& path) {
  const std::string data = readWholeFile(path);
  // A binary file whose size matches its triangle count is binary, whatever its first bytes
  // (some exporters start the 80-byte header with "solid" too).
  std::uint32_t triangles;
  if (binaryStlHeader(data, triangles) && data.size() == 84 + 50 * std::uint64_t(triangles))
    return readBinaryStl(path, data);
  const std::size_t first = data.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && data.compare(first, 5, "solid") == 0)
    return readAsciiStl(path, data);
  return readBinaryStl(path, data);
}

pcl::PolygonMesh readObjFile(const std::string& path) {
  const std::string data = readWholeFile(path);
  pcl::PointCloud<pcl::PointXYZ> vertices;
  std::vector<pcl::Vertices> polygons;
  std::vector<std::size_t> polygon_lines;  // for messages about positive indices
  std::vector<Token> words;
  forEachLine(data, [&](std::size_t line, const char* begin, const char* end) {
    splitLine(begin, end, true, words);
    if (words.empty())
      return;
    const std::string where = path + ":" + std::to_string(line) + ": ";
    if (equals(words[0], "v")) {
      double v[3];
      if (words.size() < 4 || words.size() > 8)
        throw FileError(where + "expected 'v x y z [w | r g b [a]]' (malformed OBJ file)");
      for (std::size_t i = 1; i < words.size(); ++i) {
        double x;
        if (!parseDouble(words[i], x))
          throw FileError(where + "'" + printable(std::string(words[i].first, words[i].second)) +
                          "' is not a number (malformed OBJ file)");
        if (i <= 3)
          v[i - 1] = x;
      }
      checkElementCount(path, vertices.size(), "vertices");
      vertices.push_back(pcl::PointXYZ(static_cast<float>(v[0]), static_cast<float>(v[1]),
                                       static_cast<float>(v[2])));
      return;
    }
    if (!equals(words[0], "f"))
      return;  // vt, vn, l, p, g, o, s, usemtl, mtllib, ...: not faces
    if (words.size() < 4)
      throw FileError(where + "a face needs at least 3 vertices (malformed OBJ file)");
    pcl::Vertices face;
    for (std::size_t i = 1; i < words.size(); ++i) {
      long long index = 0;
      const bool ok = parseFaceVertex(words[i], index);
      if (!ok)
        throw FileError(where + "'" + printable(std::string(words[i].first, words[i].second)) +
                        "' is not a face vertex (v, v/t, v//n or v/t/n) (malformed OBJ file)");
      const long long count = static_cast<long long>(vertices.size());
      if (index < 0) {
        index += count + 1;  // relative to the vertices read so far
        if (index < 1)
          throw FileError(where + "face vertex " +
                          std::string(words[i].first, words[i].second).substr(0, 32) +
                          " refers before the first vertex (malformed OBJ file)");
      }
      if (index > static_cast<long long>(kMaxMeshElements))
        throw FileError(where + "face vertex index " + std::to_string(index) +
                        " is out of range (malformed OBJ file)");
      face.vertices.push_back(static_cast<pcl::index_t>(index - 1));
    }
    checkElementCount(path, polygons.size(), "faces");
    polygons.push_back(std::move(face));
    polygon_lines.push_back(line);
  });
  // Positive indices may refer to vertices defined later in the file.
  for (std::size_t f = 0; f < polygons.size(); ++f)
    for (const pcl::index_t i : polygons[f].vertices)
      if (static_cast<std::size_t>(i) >= vertices.size())
        throw FileError(path + ":" + std::to_string(polygon_lines[f]) + ": face refers to vertex " +
                        std::to_string(i + 1) + ", but the file has " +
                        std::to_string(vertices.size()) + " vertices (malformed OBJ file)");
  return toMesh(vertices, std::move(polygons));
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
