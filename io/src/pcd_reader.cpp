/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/icf/io/mesh_io.h>
#include <pcl/io/lzf.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>

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

/** One ascii value of a field of type \a type and \a size, stored at \a out. */
bool parseAscii(const char* begin, const char* end, char type, int size, std::uint8_t* out) {
  if (end - begin > 1 && *begin == '+')
    ++begin;
  if (type == 'F') {
    if (size == 4) {
      float v;
      const auto [ptr, ec] = std::from_chars(begin, end, v);
      if (ec == std::errc::result_out_of_range && ptr == end)
        v = *begin == '-' ? -INFINITY : INFINITY;
      else if (ec != std::errc() || ptr != end)
        return false;
      std::memcpy(out, &v, 4);
      return true;
    }
    double v;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    if (ec == std::errc::result_out_of_range && ptr == end)
      v = *begin == '-' ? -INFINITY : INFINITY;
    else if (ec != std::errc() || ptr != end)
      return false;
    std::memcpy(out, &v, 8);
    return true;
  }
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
  if (type == 'I') {
    const auto x = static_cast<std::int64_t>(v);
    const std::int8_t b8 = static_cast<std::int8_t>(x);
    const std::int16_t b16 = static_cast<std::int16_t>(x);
    const std::int32_t b32 = static_cast<std::int32_t>(x);
    std::memcpy(out,
                size == 1   ? static_cast<const void*>(&b8)
                : size == 2 ? static_cast<const void*>(&b16)
                            : static_cast<const void*>(&b32),
                static_cast<std::size_t>(size));
  } else {
    const auto x = static_cast<std::uint64_t>(v);
    const std::uint8_t b8 = static_cast<std::uint8_t>(x);
    const std::uint16_t b16 = static_cast<std::uint16_t>(x);
    const std::uint32_t b32 = static_cast<std::uint32_t>(x);
    std::memcpy(out,
                size == 1   ? static_cast<const void*>(&b8)
                : size == 2 ? static_cast<const void*>(&b16)
                            : static_cast<const void*>(&b32),
                static_cast<std::size_t>(size));
  }
  return true;
}

struct Field {
  std::string name;
  char type = 'F';
  int size = 4;
  std::uint32_t count = 1;
  std::uint32_t offset = 0;
};

}  // namespace

void readPcdFile(const std::string& path, std::uint64_t max_points, pcl::PCLPointCloud2& cloud,
                 Eigen::Vector4f& origin, Eigen::Quaternionf& orientation) {
  std::ifstream in(path, std::ios::binary);
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.eof() && in.fail())
    throw FileError(path + ": read error");

  // ---- Header: line by line up to and including DATA.
  std::vector<std::string> fields, sizes, types, counts;
  bool has_width = false, has_height = false, has_points = false, has_data = false;
  std::uint64_t width = 0, height = 0, points = 0;
  std::string data;
  origin = Eigen::Vector4f::Zero();
  orientation = Eigen::Quaternionf::Identity();
  std::size_t pos = 0, line_number = 0;
  while (!has_data) {
    const std::size_t eol = file.find('\n', pos);
    if (pos >= kMaxHeaderBytes || pos >= file.size() ||
        (eol == std::string::npos && file.size() - pos > kMaxHeaderBytes))
      throw FileError(path + ": not a PCD file (no DATA line in its header)");
    const std::size_t stop = eol == std::string::npos ? file.size() : eol;
    const std::string line = file.substr(pos, stop - pos);
    pos = stop + 1;
    ++line_number;
    const std::string where =
        path + ": PCD header line " + std::to_string(line_number) + " '" + printable(line) + "' ";
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#')
      continue;  // a comment may hold any text (UTF-8 names, say)
    for (const char c : line)
      if (!((c >= 32 && c < 127) || c == '\t' || c == '\r'))
        throw FileError(where + "has a byte that is not printable text (malformed PCD file)");
    const auto words = splitWords(line);
    if (words[0] == "VERSION")
      continue;
    const std::string& key = words[0];
    const std::vector<std::string> rest(words.begin() + 1, words.end());
    if (key == "FIELDS" || key == "COLUMNS") {
      if (rest.empty() || !fields.empty())
        throw FileError(where + "(FIELDS: one or more names, once)");
      fields = rest;
    } else if (key == "SIZE" || key == "TYPE" || key == "COUNT") {
      std::vector<std::string>& target = key == "SIZE" ? sizes : key == "TYPE" ? types : counts;
      if (fields.empty() || rest.size() != fields.size() || !target.empty())
        throw FileError(where + "(" + key + ": one entry per field, after FIELDS, once)");
      target = rest;
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::uint64_t v = 0;
      if (rest.size() != 1 || !parseNumber(rest[0], v))
        throw FileError(where + "(" + key + ": one non-negative integer)");
      (key == "WIDTH" ? width : key == "HEIGHT" ? height : points) = v;
      (key == "WIDTH" ? has_width : key == "HEIGHT" ? has_height : has_points) = true;
    } else if (key == "VIEWPOINT") {
      float v[7];
      bool ok = rest.size() == 7;
      for (std::size_t i = 0; ok && i < 7; ++i)
        ok = parseNumber(rest[i], v[i]);
      if (!ok)
        throw FileError(where + "(VIEWPOINT: 7 numbers, tx ty tz qw qx qy qz)");
      origin = Eigen::Vector4f(v[0], v[1], v[2], 0.f);
      orientation = Eigen::Quaternionf(v[3], v[4], v[5], v[6]);
    } else if (key == "DATA") {
      if (rest.size() != 1)
        throw FileError(where + "(DATA: ascii, binary or binary_compressed)");
      data = rest[0];
      has_data = true;
    } else
      throw FileError(where + "is not a PCD header line (malformed PCD file)");
  }
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    throw FileError(path + ": PCD header has an unknown DATA type '" + printable(data) + "'");
  if (fields.empty() || sizes.empty() || types.empty())
    throw FileError(path + ": PCD header lacks a FIELDS, SIZE or TYPE line (malformed PCD file)");
  std::vector<Field> layout;
  std::uint64_t point_step = 0, values_per_point = 0;
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
    f.offset = static_cast<std::uint32_t>(point_step);
    point_step += count * static_cast<std::uint64_t>(f.size);
    values_per_point += count;
    if (point_step > kMaxPointBytes)
      throw FileError(path + ": PCD points of more than " + std::to_string(kMaxPointBytes) +
                      " bytes, more than this reader accepts");
    layout.push_back(f);
  }
  if (!has_points || (!has_width && has_height))
    throw FileError(path + ": PCD header lacks POINTS or WIDTH (malformed PCD file)");
  if (!has_width)
    width = points;
  if (!has_height)
    height = 1;
  if (width > max_points || height > max_points || points > max_points)
    throw FileError(path + ": header claims " + std::to_string(std::max({width, height, points})) +
                    " points, more than the " + std::to_string(max_points) +
                    " this reader accepts");
  if (width * height != points)
    throw FileError(path + ": PCD header's WIDTH " + std::to_string(width) + " x HEIGHT " +
                    std::to_string(height) + " differs from its POINTS " + std::to_string(points) +
                    " (malformed PCD file)");
  const std::uint64_t bytes = points * point_step;
  if (width * point_step > 0xffffffffu)
    throw FileError(path + ": PCD rows of more than 4 GiB, more than this reader accepts");

  // ---- Body: checked against the header before anything is allocated.
  const std::uint64_t body = file.size() - std::min(pos, file.size());
  const char* start = file.data() + std::min(pos, file.size());
  if (data == "binary" && body < bytes)
    throw FileError(path + ": binary PCD data is " + std::to_string(body) + " bytes, its " +
                    std::to_string(points) + " points need " + std::to_string(bytes) +
                    " (truncated file)");
  std::uint32_t compressed = 0, uncompressed = 0;
  if (data == "binary_compressed") {
    if (body < 8)
      throw FileError(path + ": compressed PCD data has no size words (truncated file)");
    std::memcpy(&compressed, start, 4);
    std::memcpy(&uncompressed, start + 4, 4);
    if (compressed > body - 8)
      throw FileError(path + ": compressed PCD data claims " + std::to_string(compressed) +
                      " bytes, the file holds " + std::to_string(body - 8) + " (truncated file)");
    if (uncompressed != bytes)
      throw FileError(path + ": compressed PCD data unpacks to " + std::to_string(uncompressed) +
                      " bytes, its " + std::to_string(points) + " points need " +
                      std::to_string(bytes) + " (malformed PCD file)");
    if (bytes > kMaxLzfRatio * compressed + 64)
      throw FileError(path + ": " + std::to_string(compressed) + " compressed bytes cannot hold " +
                      std::to_string(points) + " points of " + std::to_string(point_step) +
                      " bytes (truncated file or a lying header)");
  }
  if (data == "ascii" && points * values_per_point > (body + 1) / 2)
    throw FileError(path + ": ascii PCD data of " + std::to_string(body) + " bytes cannot hold " +
                    std::to_string(points) + " points of " + std::to_string(values_per_point) +
                    " numbers (truncated file or a lying header)");

  cloud = pcl::PCLPointCloud2();
  for (const Field& f : layout) {
    pcl::PCLPointField pf;
    pf.name = f.name;
    pf.offset = f.offset;
    pf.datatype = pclType(f.type, f.size);
    pf.count = f.count;
    cloud.fields.push_back(pf);
  }
  cloud.width = static_cast<std::uint32_t>(width);
  cloud.height = static_cast<std::uint32_t>(height);
  cloud.point_step = static_cast<std::uint32_t>(point_step);
  cloud.row_step = static_cast<std::uint32_t>(width * point_step);
  cloud.is_bigendian = false;
  cloud.is_dense = false;
  cloud.data.resize(static_cast<std::size_t>(bytes));
  if (bytes == 0)
    return;

  if (data == "binary") {
    std::memcpy(cloud.data.data(), start, static_cast<std::size_t>(bytes));
    return;
  }
  if (data == "binary_compressed") {
    // PCL's layout: every field's values for all points in turn (structure of arrays).
    std::vector<char> soa(static_cast<std::size_t>(bytes));
    const unsigned int got =
        pcl::lzfDecompress(start + 8, compressed, soa.data(), static_cast<unsigned int>(bytes));
    if (got != bytes)
      throw FileError(path + ": compressed PCD data does not unpack to its " +
                      std::to_string(bytes) + " bytes (corrupt or truncated file)");
    std::size_t offset = 0;
    for (const Field& f : layout) {
      const std::size_t field_bytes = static_cast<std::size_t>(f.size) * f.count;
      for (std::uint64_t i = 0; i < points; ++i)
        std::memcpy(cloud.data.data() + i * point_step + f.offset,
                    soa.data() + offset + i * field_bytes, field_bytes);
      offset += static_cast<std::size_t>(points) * field_bytes;
    }
    return;
  }
  // ascii: whitespace-separated numbers, point after point ("nan" for a float is NaN).
  const char* p = start;
  const char* end = file.data() + file.size();
  auto space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  };
  for (std::uint64_t i = 0; i < points; ++i)
    for (const Field& f : layout)
      for (std::uint32_t k = 0; k < f.count; ++k) {
        while (p < end && space(*p))
          ++p;
        const char* token = p;
        while (p < end && !space(*p))
          ++p;
        if (token == p)
          throw FileError(path + ": ascii PCD data ends at point " + std::to_string(i) + " of " +
                          std::to_string(points) + " (truncated file)");
        if (!parseAscii(token, p, f.type, f.size,
                        cloud.data.data() + i * point_step + f.offset + k * f.size))
          throw FileError(path + ": '" + printable(std::string(token, p)) + "' at point " +
                          std::to_string(i) + " is not a value of field '" + printable(f.name) +
                          "' (" + std::string(1, f.type) + std::to_string(f.size) +
                          "; malformed PCD file)");
      }
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
