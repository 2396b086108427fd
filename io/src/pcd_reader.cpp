/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/io/lzf.h>
#include <pcl_icf_internal/point_field.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

namespace pcl {
namespace icf {
namespace io {
namespace detail {
namespace {

constexpr std::size_t kMaxHeaderBytes = 65536;
/** Largest point accepted, in bytes (a 308-bin descriptor of doubles is 2.5 KB). */
constexpr std::uint64_t kMaxPointBytes = 1 << 20;
/** LZF turns 3 bytes into at most 264 (a back reference of maximal length). */
constexpr std::uint64_t kMaxLzfRatio = 88;

template <typename T>
bool parseNumber(const std::string& word, T& value) {
  const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc() && ptr == word.data() + word.size();
}

std::uint8_t pclType(char type, int size) {
  if (type == 'F')
    return size == 8 ? pcl::PCLPointField::FLOAT64 : pcl::PCLPointField::FLOAT32;
  const bool is_signed = type == 'I';
  switch (size) {
    case 1:
      return is_signed ? pcl::PCLPointField::INT8 : pcl::PCLPointField::UINT8;
    case 2:
      return is_signed ? pcl::PCLPointField::INT16 : pcl::PCLPointField::UINT16;
    default:
      return is_signed ? pcl::PCLPointField::INT32 : pcl::PCLPointField::UINT32;
  }
}

/** A float of \a size 4 or 8 bytes stored at \a out; beyond the type's range: +-inf. */
template <typename T>
bool parseAsciiFloat(const char* begin, const char* end, std::uint8_t* out) {
  T v;
  const auto [ptr, ec] = std::from_chars(begin, end, v);
  if (ec == std::errc::result_out_of_range && ptr == end)
    v = *begin == '-' ? -INFINITY : INFINITY;
  else if (ec != std::errc() || ptr != end)
    return false;
  std::memcpy(out, &v, sizeof v);
  return true;
}

/** One ascii value of a field of type \a type and \a size, stored at \a out. */
bool parseAscii(const char* begin, const char* end, char type, int size, std::uint8_t* out) {
  if (end - begin > 1 && *begin == '+')
    ++begin;
  if (type == 'F')
    return size == 4 ? parseAsciiFloat<float>(begin, end, out)
                     : parseAsciiFloat<double>(begin, end, out);
  // Integers: PCL writes them as integers; a value out of the type's range is an error.
  long long v;
  const auto [ptr, ec] = std::from_chars(begin, end, v);
  if (ec != std::errc() || ptr != end)
    return false;
  const int bits = 8 * size;
  const long long lo = type == 'I' ? -(1LL << (bits - 1)) : 0;
  const long long hi = type == 'I' ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
  if (v < lo || v > hi)
    return false;
  internal::writeFieldValue(static_cast<double>(v), pclType(type, size), out);
  return true;
}

struct Field {
  std::string name;
  char type = 'F';
  int size = 4;
  std::uint32_t count = 1;
  std::uint32_t offset = 0;
};

/** What a PCD header says, checked: the point layout, the size, the data's encoding. */
struct PcdHeader {
  std::vector<Field> layout;
  std::uint64_t width = 0, height = 0, points = 0;
  std::uint64_t point_step = 0, values_per_point = 0;
  std::string data;  ///< "ascii", "binary" or "binary_compressed"
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  std::size_t body = 0;  ///< offset of the first byte after the DATA line
};

/** The header's lines as they are written (one entry per line, comments and blank lines too, so
 * that messages give the line's number), up to and including the DATA line, which must start
 * in the first 64 KiB. \throws FileError "not a PCD file" when there is no DATA line. */
std::vector<std::string> pcdHeaderLines(const std::string& file, const std::string& path,
                                        std::size_t& body) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (true) {
    const std::size_t eol = file.find('\n', pos);
    if (pos >= kMaxHeaderBytes || pos >= file.size() ||
        (eol == std::string::npos && file.size() - pos > kMaxHeaderBytes))
      throw FileError(path + ": not a PCD file (no DATA line in its header)");
    const std::size_t stop = eol == std::string::npos ? file.size() : eol;
    lines.push_back(file.substr(pos, stop - pos));
    pos = stop + 1;
    // The first line that starts with DATA ends the header, as PCL writes it (a misspelt
    // "DATA9ascii" too, so that the line parser names it rather than reading on into the data).
    if (lines.back().compare(0, 4, "DATA") == 0) {
      body = pos;
      return lines;
    }
  }
}

/** Stores \a rest as the entries of a FIELDS, SIZE, TYPE or COUNT line. */
void pcdListLine(const std::string& key, const std::vector<std::string>& rest,
                 const std::string& where, std::vector<std::string> (&lists)[4]) {
  std::vector<std::string>& fields = lists[0];
  if (key == "FIELDS" || key == "COLUMNS") {
    if (rest.empty() || !fields.empty())
      throw FileError(where + "(FIELDS: one or more names, once)");
    fields = rest;
    return;
  }
  std::vector<std::string>& target = lists[key == "SIZE" ? 1 : key == "TYPE" ? 2 : 3];
  if (fields.empty() || rest.size() != fields.size() || !target.empty())
    throw FileError(where + "(" + key + ": one entry per field, after FIELDS, once)");
  target = rest;
}

/** The field layout of FIELDS, SIZE, TYPE [, COUNT]: offsets, PCL types, the point's size. */
void pcdLayout(const std::vector<std::string> (&lists)[4], const std::string& path, PcdHeader& h) {
  const auto& [fields, sizes, types, counts] = lists;
  if (fields.empty() || sizes.empty() || types.empty())
    throw FileError(path + ": PCD header lacks a FIELDS, SIZE or TYPE line (malformed PCD file)");
  for (std::size_t i = 0; i < fields.size(); ++i) {
    Field f;
    f.name = fields[i];
    std::uint64_t count = 1;
    const bool ok =
        (sizes[i] == "1" || sizes[i] == "2" || sizes[i] == "4" || sizes[i] == "8") &&
        (types[i] == "I" || types[i] == "U" ||
         (types[i] == "F" && (sizes[i] == "4" || sizes[i] == "8"))) &&
        (sizes[i] != "8" || types[i] == "F") &&
        (counts.empty() || (parseNumber(counts[i], count) && count >= 1 && count <= 100000));
    if (!ok)
      throw FileError(path + ": PCD field '" + printable(fields[i]) + "' has SIZE " +
                      printable(sizes[i]) + ", TYPE " + printable(types[i]) +
                      (counts.empty() ? std::string() : ", COUNT " + printable(counts[i])) +
                      " (sizes 1, 2, 4, 8; types I, U with 1, 2, 4, F with 4, 8; count >= 1)");
    f.type = types[i][0];
    f.size = sizes[i][0] - '0';
    f.count = static_cast<std::uint32_t>(count);
    f.offset = static_cast<std::uint32_t>(h.point_step);
    h.point_step += count * static_cast<std::uint64_t>(f.size);
    h.values_per_point += count;
    if (h.point_step > kMaxPointBytes)
      throw FileError(path + ": PCD points of more than " + std::to_string(kMaxPointBytes) +
                      " bytes, more than this reader accepts");
    h.layout.push_back(f);
  }
}

/** WIDTH x HEIGHT = POINTS, within \a max_points and rows of at most 4 GiB. */
void pcdSize(bool has_width, bool has_height, bool has_points, std::uint64_t max_points,
             const std::string& path, PcdHeader& h) {
  if (!has_points || (!has_width && has_height))
    throw FileError(path + ": PCD header lacks POINTS or WIDTH (malformed PCD file)");
  if (!has_width)
    h.width = h.points;
  if (!has_height)
    h.height = 1;
  if (h.width > max_points || h.height > max_points || h.points > max_points)
    throw FileError(
        path + ": header claims " + std::to_string(std::max({h.width, h.height, h.points})) +
        " points, more than the " + std::to_string(max_points) + " this reader accepts");
  if (h.width * h.height != h.points)
    throw FileError(path + ": PCD header's WIDTH " + std::to_string(h.width) + " x HEIGHT " +
                    std::to_string(h.height) + " differs from its POINTS " +
                    std::to_string(h.points) + " (malformed PCD file)");
  if (h.width * h.point_step > 0xffffffffu)
    throw FileError(path + ": PCD rows of more than 4 GiB, more than this reader accepts");
}

/** The one PCD header parser: printable ASCII lines (comments excepted), each a known keyword
 * with well-formed values, then the layout and the size checked (file_formats.h's readPcdFile
 * lists the rules). */
PcdHeader parsePcdHeader(const std::string& file, const std::string& path,
                         std::uint64_t max_points) {
  PcdHeader h;
  const std::vector<std::string> lines = pcdHeaderLines(file, path, h.body);
  std::vector<std::string> lists[4];    // FIELDS, SIZE, TYPE, COUNT
  bool has[3] = {false, false, false};  // WIDTH, HEIGHT, POINTS
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::string& line = lines[n];
    const std::string where =
        path + ": PCD header line " + std::to_string(n + 1) + " '" + printable(line) + "' ";
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;  // a comment may hold any text (UTF-8 names, say)
    for (const char c : line)
      if (!((c >= 32 && c < 127) || c == '\t' || c == '\r'))
        throw FileError(where + "has a byte that is not printable text (malformed PCD file)");
    const auto words = splitWords(line);
    const std::string& key = words[0];
    const std::vector<std::string> rest(words.begin() + 1, words.end());
    if (key == "VERSION")
      continue;
    if (key == "FIELDS" || key == "COLUMNS" || key == "SIZE" || key == "TYPE" || key == "COUNT") {
      pcdListLine(key, rest, where, lists);
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      const int k = key == "WIDTH" ? 0 : key == "HEIGHT" ? 1 : 2;
      if (rest.size() != 1 || !parseNumber(rest[0], k == 0   ? h.width
                                                    : k == 1 ? h.height
                                                             : h.points))
        throw FileError(where + "(" + key + ": one non-negative integer)");
      has[k] = true;
    } else if (key == "VIEWPOINT") {
      float v[7];
      bool ok = rest.size() == 7;
      for (std::size_t i = 0; ok && i < 7; ++i)
        ok = parseNumber(rest[i], v[i]);
      if (!ok)
        throw FileError(where + "(VIEWPOINT: 7 numbers, tx ty tz qw qx qy qz)");
      h.origin = Eigen::Vector4f(v[0], v[1], v[2], 0.f);
      h.orientation = Eigen::Quaternionf(v[3], v[4], v[5], v[6]);
    } else if (key == "DATA") {
      if (rest.size() != 1)
        throw FileError(where + "(DATA: ascii, binary or binary_compressed)");
      h.data = rest[0];
    } else
      throw FileError(where + "is not a PCD header line (malformed PCD file)");
  }
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
    throw FileError(path + ": PCD header has an unknown DATA type '" + printable(h.data) + "'");
  pcdLayout(lists, path, h);
  pcdSize(has[0], has[1], has[2], max_points, path, h);
  return h;
}

/** The body checked against the header before anything is allocated: binary data as long as
 * the points need, compressed sizes that the file and the points agree with, ascii text with
 * room for enough numbers. \a compressed, \a uncompressed: binary_compressed's size words. */
void checkPcdBody(const PcdHeader& h, const std::string& file, const std::string& path,
                  std::uint32_t& compressed, std::uint32_t& uncompressed) {
  const std::uint64_t bytes = h.points * h.point_step;
  const std::uint64_t body = file.size() - std::min(h.body, file.size());
  const char* start = file.data() + std::min(h.body, file.size());
  if (h.data == "binary" && body < bytes)
    throw FileError(path + ": binary PCD data is " + std::to_string(body) + " bytes, its " +
                    std::to_string(h.points) + " points need " + std::to_string(bytes) +
                    " (truncated file)");
  if (h.data == "binary_compressed") {
    if (body < 8)
      throw FileError(path + ": compressed PCD data has no size words (truncated file)");
    std::memcpy(&compressed, start, 4);
    std::memcpy(&uncompressed, start + 4, 4);
    if (compressed > body - 8)
      throw FileError(path + ": compressed PCD data claims " + std::to_string(compressed) +
                      " bytes, the file holds " + std::to_string(body - 8) + " (truncated file)");
    if (uncompressed != bytes)
      throw FileError(path + ": compressed PCD data unpacks to " + std::to_string(uncompressed) +
                      " bytes, its " + std::to_string(h.points) + " points need " +
                      std::to_string(bytes) + " (malformed PCD file)");
    if (bytes > kMaxLzfRatio * compressed + 64)
      throw FileError(path + ": " + std::to_string(compressed) + " compressed bytes cannot hold " +
                      std::to_string(h.points) + " points of " + std::to_string(h.point_step) +
                      " bytes (truncated file or a lying header)");
  }
  if (h.data == "ascii" && h.points * h.values_per_point > (body + 1) / 2)
    throw FileError(path + ": ascii PCD data of " + std::to_string(body) + " bytes cannot hold " +
                    std::to_string(h.points) + " points of " + std::to_string(h.values_per_point) +
                    " numbers (truncated file or a lying header)");
}

/** An empty cloud of the header's layout and size (data allocated, zero). */
void allocatePcdCloud(const PcdHeader& h, pcl::PCLPointCloud2& cloud) {
  cloud = pcl::PCLPointCloud2();
  for (const Field& f : h.layout) {
    pcl::PCLPointField pf;
    pf.name = f.name;
    pf.offset = f.offset;
    pf.datatype = pclType(f.type, f.size);
    pf.count = f.count;
    cloud.fields.push_back(pf);
  }
  cloud.width = static_cast<std::uint32_t>(h.width);
  cloud.height = static_cast<std::uint32_t>(h.height);
  cloud.point_step = static_cast<std::uint32_t>(h.point_step);
  cloud.row_step = static_cast<std::uint32_t>(h.width * h.point_step);
  cloud.is_bigendian = false;
  cloud.is_dense = false;
  cloud.data.resize(static_cast<std::size_t>(h.points * h.point_step));
}

/** binary_compressed: LZF of every field's values for all points in turn (structure of arrays,
 * PCL's layout), unpacked into PCL's point after point. */
void readPcdCompressed(const PcdHeader& h, const char* start, std::uint32_t compressed,
                       const std::string& path, pcl::PCLPointCloud2& cloud) {
  const std::size_t bytes = cloud.data.size();
  std::vector<char> soa(bytes);
  const unsigned int got =
      pcl::lzfDecompress(start + 8, compressed, soa.data(), static_cast<unsigned int>(bytes));
  if (got != bytes)
    throw FileError(path + ": compressed PCD data does not unpack to its " + std::to_string(bytes) +
                    " bytes (corrupt or truncated file)");
  std::size_t offset = 0;
  for (const Field& f : h.layout) {
    const std::size_t field_bytes = static_cast<std::size_t>(f.size) * f.count;
    for (std::uint64_t i = 0; i < h.points; ++i)
      std::memcpy(cloud.data.data() + i * h.point_step + f.offset,
                  soa.data() + offset + i * field_bytes, field_bytes);
    offset += static_cast<std::size_t>(h.points) * field_bytes;
  }
}

/** ascii: whitespace-separated numbers, point after point ("nan" for a float is NaN). */
void readPcdAscii(const PcdHeader& h, const char* p, const char* end, const std::string& path,
                  pcl::PCLPointCloud2& cloud) {
  auto space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  };
  for (std::uint64_t i = 0; i < h.points; ++i)
    for (const Field& f : h.layout)
      for (std::uint32_t k = 0; k < f.count; ++k) {
        while (p < end && space(*p))
          ++p;
        const char* token = p;
        while (p < end && !space(*p))
          ++p;
        if (token == p)
          throw FileError(path + ": ascii PCD data ends at point " + std::to_string(i) + " of " +
                          std::to_string(h.points) + " (truncated file)");
        if (!parseAscii(token, p, f.type, f.size,
                        cloud.data.data() + i * h.point_step + f.offset + k * f.size))
          throw FileError(path + ": '" + printable(std::string(token, p)) + "' at point " +
                          std::to_string(i) + " is not a value of field '" + printable(f.name) +
                          "' (" + std::string(1, f.type) + std::to_string(f.size) +
                          "; malformed PCD file)");
      }
}

}  // namespace

void readPcdFile(const std::string& path, std::uint64_t max_points, pcl::PCLPointCloud2& cloud,
                 Eigen::Vector4f& origin, Eigen::Quaternionf& orientation) {
  const std::string file = readWholeFile(path);
  origin = Eigen::Vector4f::Zero();
  orientation = Eigen::Quaternionf::Identity();
  const PcdHeader header = parsePcdHeader(file, path, max_points);
  origin = header.origin;
  orientation = header.orientation;
  std::uint32_t compressed = 0, uncompressed = 0;
  checkPcdBody(header, file, path, compressed, uncompressed);
  allocatePcdCloud(header, cloud);
  if (cloud.data.empty())
    return;
  const char* start = file.data() + std::min(header.body, file.size());
  if (header.data == "binary")
    std::memcpy(cloud.data.data(), start, cloud.data.size());
  else if (header.data == "binary_compressed")
    readPcdCompressed(header, start, compressed, path, cloud);
  else
    readPcdAscii(header, start, file.data() + file.size(), path, cloud);
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
