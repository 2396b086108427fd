/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/common/io.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl_icf_internal/point_field.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <utility>

namespace pcl {
namespace icf {
namespace io {
namespace detail {
namespace {

/** A PLY scalar type, as the pcl::PCLPointField datatype of the same C++ type. */
using Scalar = std::uint8_t;
enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
  std::string name;
  Scalar type = pcl::PCLPointField::FLOAT32;
  bool list = false;
  Scalar count_type = pcl::PCLPointField::UINT8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

constexpr std::size_t kMaxHeaderBytes = 65536;

std::size_t scalarSize(Scalar t) {
  return static_cast<std::size_t>(pcl::getFieldSize(t));
}

bool isInteger(Scalar t) {
  return t != pcl::PCLPointField::FLOAT32 && t != pcl::PCLPointField::FLOAT64;
}

bool parseScalar(const std::string& name, Scalar& t) {
  using F = pcl::PCLPointField;
  static const std::pair<const char*, Scalar> names[] = {
      {"char", F::INT8},      {"int8", F::INT8},       {"uchar", F::UINT8},
      {"uint8", F::UINT8},    {"short", F::INT16},     {"int16", F::INT16},
      {"ushort", F::UINT16},  {"uint16", F::UINT16},   {"int", F::INT32},
      {"int32", F::INT32},    {"uint", F::UINT32},     {"uint32", F::UINT32},
      {"float", F::FLOAT32},  {"float32", F::FLOAT32}, {"double", F::FLOAT64},
      {"float64", F::FLOAT64}};
  for (const auto& n : names)
    if (name == n.first) {
      t = n.second;
      return true;
    }
  return false;
}

template <typename T>
std::pair<double, double> limitsOf() {
  return {static_cast<double>(std::numeric_limits<T>::lowest()),
          static_cast<double>(std::numeric_limits<T>::max())};
}

/** Lowest and highest value of an integer type (the last of parseScalar's, UINT32, by default). */
std::pair<double, double> integerRange(Scalar t) {
  using F = pcl::PCLPointField;
  static const std::pair<Scalar, std::pair<double, double>> ranges[] = {
      {F::INT8, limitsOf<std::int8_t>()},
      {F::UINT8, limitsOf<std::uint8_t>()},
      {F::INT16, limitsOf<std::int16_t>()},
      {F::UINT16, limitsOf<std::uint16_t>()},
      {F::INT32, limitsOf<std::int32_t>()}};
  for (const auto& r : ranges)
    if (r.first == t)
      return r.second;
  return limitsOf<std::uint32_t>();
}

/** The bytes of the PLY body as typed values: ascii tokens or binary fields. */
class Body {
 public:
  Body(const std::string& data, std::size_t pos, Format format, const std::string& path)
      : data_(data), pos_(pos), format_(format), path_(path) {}

  std::size_t remaining() const { return data_.size() - std::min(pos_, data_.size()); }

  /** Next value of type \a t as a double (any type converts exactly). */
  double value(Scalar t, const char* what) {
    if (format_ == Format::Ascii)
      return asciiValue(t, what);
    std::uint8_t bytes[8];
    binaryValue(t, bytes, what);
    return internal::readFieldValue(bytes, t);
  }

  /** Next value of type \a t written to \a out in the machine's byte order. */
  void store(Scalar t, std::uint8_t* out, const char* what) {
    if (format_ != Format::Ascii)
      binaryValue(t, out, what);
    else  // beyond float's range: +-inf, as IEEE says
      internal::writeFieldValue(asciiValue(t, what), t, out);
  }

  /** Skips \a bytes of binary data (a row of fixed size). */
  void skip(std::uint64_t bytes, const char* what) {
    if (bytes > remaining())
      truncated(what);
    pos_ += static_cast<std::size_t>(bytes);
  }

  [[noreturn]] void truncated(const char* what) const {
    throw FileError(path_ + ": PLY data ends inside the " + what + " (truncated file)");
  }

 private:
  void binaryValue(Scalar t, std::uint8_t* out, const char* what) {
    const std::size_t n = scalarSize(t);
    if (n > remaining())
      truncated(what);
    std::memcpy(out, data_.data() + pos_, n);
    pos_ += n;
    if (format_ == Format::BinaryBig)
      std::reverse(out, out + n);
  }

  double asciiValue(Scalar t, const char* what) {
    const char* end = data_.data() + data_.size();
    const char* p = data_.data() + pos_;
    while (p < end &&
           (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '\v' || *p == '\f'))
      ++p;
    const char* start = p;
    while (p < end &&
           !(*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == '\v' || *p == '\f'))
      ++p;
    pos_ = static_cast<std::size_t>(p - data_.data());
    if (p == start)
      truncated(what);
    const char* first = (*start == '+' && p - start > 1) ? start + 1 : start;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, p, v);
    const bool number = ec == std::errc() && ptr == p;
    const bool out_of_range = ec == std::errc::result_out_of_range && ptr == p;
    if (!number && !(out_of_range && !isInteger(t)))
      throw FileError(path_ + ": '" + printable(std::string(start, p)) + "' in the " + what +
                      " is not a number (malformed PLY file)");
    if (out_of_range)  // beyond double: keep the sign, let the float conversion give +-inf
      v = (*first == '-') ? -INFINITY : INFINITY;
    if (isInteger(t)) {
      const auto [lo, hi] = integerRange(t);
      if (!(v >= lo && v <= hi && v == std::floor(v)))
        throw FileError(path_ + ": '" + printable(std::string(start, p)) + "' in the " + what +
                        " is not an integer of its declared type (malformed PLY file)");
    }
    return v;
  }

  const std::string& data_;
  std::size_t pos_;
  Format format_;
  const std::string& path_;
};

/** Least number of bytes a row of \a e can take. */
std::uint64_t minimumRowBytes(const Element& e, Format format) {
  std::uint64_t bytes = 0;
  for (const Property& p : e.properties)
    bytes += format == Format::Ascii ? 2 : scalarSize(p.list ? p.count_type : p.type);
  return bytes;
}

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t body = 0;  ///< offset of the first byte after end_header's line
};

/** Adds the element or the property of an "element" or "property" line to \a h. */
void plyDeclaration(const std::vector<std::string>& words, const std::string& bad, Header& h) {
  if (words[0] == "element") {
    Element e;
    if (words.size() != 3)
      throw FileError(bad + "is not 'element <name> <count>'");
    e.name = words[1];
    const char* end = words[2].data() + words[2].size();
    const auto [ptr, ec] = std::from_chars(words[2].data(), end, e.count);
    if (ec != std::errc() || ptr != end)
      throw FileError(bad + "has no valid element count");
    h.elements.push_back(e);
    return;
  }
  if (h.elements.empty())
    throw FileError(bad + "comes before any element");
  Property p;
  const bool list = words.size() == 5 && words[1] == "list";
  if (!(list || words.size() == 3))
    throw FileError(bad +
                    "is not 'property <type> <name>' or 'property list <count "
                    "type> <type> <name>'");
  p.list = list;
  if (list && (!parseScalar(words[2], p.count_type) || !isInteger(p.count_type)))
    throw FileError(bad + "has no integer list count type");
  if (!parseScalar(words[list ? 3 : 1], p.type))
    throw FileError(bad + "has an unknown type");
  p.name = words.back();
  h.elements.back().properties.push_back(p);
}

/** The one PLY header parser: magic, format, elements and their properties up to end_header
 * (at most 64 KiB); comments and obj_info are skipped. */
Header parseHeader(const std::string& data, const std::string& path) {
  if (data.compare(0, 3, "ply") != 0 || (data.size() > 3 && data[3] != '\n' && data[3] != '\r'))
    throw FileError(path + ": not a PLY file (no 'ply' header line)");
  Header h;
  bool format_seen = false;
  std::size_t pos = 0;
  while (true) {
    const std::size_t eol = data.find('\n', pos);
    if (eol == std::string::npos || eol >= kMaxHeaderBytes)
      throw FileError(path + ": PLY header has no end_header line (malformed or truncated)");
    std::string line = data.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    const auto words = splitWords(line);
    if (words.empty() || words[0] == "ply" || words[0] == "comment" || words[0] == "obj_info")
      continue;
    const std::string bad = path + ": PLY header line '" + printable(line) + "' ";
    if (words[0] == "end_header") {
      h.body = pos;
      break;
    }
    if (words[0] == "format") {
      if (words.size() != 3 || words[2].compare(0, 1, "1") != 0)
        throw FileError(bad + "is not 'format <type> 1.0'");
      if (words[1] == "ascii")
        h.format = Format::Ascii;
      else if (words[1] == "binary_little_endian")
        h.format = Format::BinaryLittle;
      else if (words[1] == "binary_big_endian")
        h.format = Format::BinaryBig;
      else
        throw FileError(bad + "names an unknown format");
      format_seen = true;
    } else if (words[0] == "element" || words[0] == "property")
      plyDeclaration(words, bad, h);
    else
      throw FileError(bad + "is not a PLY header line (malformed file)");
  }
  if (!format_seen)
    throw FileError(path + ": PLY header has no format line (malformed file)");
  return h;
}

/** The first "vertex" element, its count within \a max_vertices, and every element's rows within
 * the body's bytes: a header that claims more rows than the body can hold fails here, before
 * any allocation. */
const Element& checkPlySizes(const Header& header, std::uint64_t body_bytes,
                             std::uint64_t max_vertices, const std::string& path) {
  const Element* vertex = nullptr;
  for (const Element& e : header.elements)
    if (e.name == "vertex" && !vertex)
      vertex = &e;
  if (!vertex)
    throw FileError(path + ": PLY header declares no vertex element");
  if (vertex->count > max_vertices)
    throw FileError(path + ": header claims " + std::to_string(vertex->count) +
                    " vertices, more than the " + std::to_string(max_vertices) +
                    " this reader accepts");
  std::uint64_t needed = 0;
  for (const Element& e : header.elements) {
    const std::uint64_t row = minimumRowBytes(e, header.format);
    if (row > 0 && (e.count > body_bytes / row + 1 || (needed += e.count * row) > body_bytes + 1))
      throw FileError(path + ": PLY file is shorter than its " + std::to_string(e.count) + " " +
                      printable(e.name) + " elements need (truncated or a lying header)");
  }
  return *vertex;
}

/** Where each vertex property goes in the cloud's point: scalar properties in order, red,
 * green, blue [, alpha] of type uchar packed into one rgb / rgba field as PCL's reader does. */
struct VertexLayout {
  std::vector<int> offset_of;        ///< byte offset per property, -1: not a field of its own
  int colour[4] = {-1, -1, -1, -1};  ///< property index of red, green, blue, alpha
  bool packed = false;               ///< red, green and blue are packed
  std::uint32_t colour_offset = 0;   ///< offset of the packed field
  std::uint32_t step = 0;            ///< bytes per point

  /** 0..3 for red, green, blue, alpha when property \a i is packed, else -1. */
  int channel(std::size_t i) const {
    if (!packed)
      return -1;
    const int* c = std::find(colour, colour + 4, static_cast<int>(i));
    return c == colour + 4 ? -1 : static_cast<int>(c - colour);
  }
};

/** The layout of \a vertex and the cloud's fields, width and steps (no data yet). */
VertexLayout vertexLayout(const Element& vertex, pcl::PCLPointCloud2& cloud) {
  VertexLayout l;
  l.offset_of.assign(vertex.properties.size(), -1);
  const char* names[4] = {"red", "green", "blue", "alpha"};
  for (std::size_t i = 0; i < vertex.properties.size(); ++i)
    for (int c = 0; c < 4; ++c)
      if (!vertex.properties[i].list && vertex.properties[i].type == pcl::PCLPointField::UINT8 &&
          vertex.properties[i].name == names[c] && l.colour[c] < 0)
        l.colour[c] = static_cast<int>(i);
  l.packed = l.colour[0] >= 0 && l.colour[1] >= 0 && l.colour[2] >= 0;
  auto addField = [&](const std::string& name, std::uint8_t datatype) {
    pcl::PCLPointField f;
    f.name = name;
    f.offset = l.step;
    f.datatype = datatype;
    f.count = 1;
    cloud.fields.push_back(f);
  };
  for (std::size_t i = 0; i < vertex.properties.size(); ++i) {
    const Property& p = vertex.properties[i];
    if (p.list || l.channel(i) >= 0)
      continue;
    addField(p.name, p.type);
    l.offset_of[i] = static_cast<int>(l.step);
    l.step += static_cast<std::uint32_t>(scalarSize(p.type));
  }
  if (l.packed) {
    const bool alpha = l.colour[3] >= 0;
    addField(alpha ? "rgba" : "rgb",
             alpha ? pcl::PCLPointField::UINT32 : pcl::PCLPointField::FLOAT32);
    l.colour_offset = l.step;
    l.step += 4;
  }
  cloud.width = static_cast<std::uint32_t>(vertex.count);
  cloud.height = 1;
  cloud.point_step = l.step;
  cloud.row_step = static_cast<std::uint32_t>(std::min<std::uint64_t>(
      std::uint64_t(l.step) * vertex.count, std::numeric_limits<std::uint32_t>::max()));
  cloud.is_bigendian = false;
  cloud.is_dense = false;
  return l;
}

/** What the rows of one element are read into. */
struct RowTarget {
  const VertexLayout* vertex = nullptr;  ///< the vertex element: its layout
  std::uint8_t* point = nullptr;         ///< the vertex element: this row's point
  const Property* indices = nullptr;     ///< the face element: the list kept as a polygon
  pcl::Vertices* polygon = nullptr;      ///< the face element: this row's polygon
};

/** Reads one list property: its length, then its items; the face's vertex indices are kept in
 * the polygon, each checked against the \a vertices count. */
void readList(Body& body, const Property& p, Format format, const RowTarget& target,
              std::uint64_t row, std::uint64_t vertices, const std::string& what_s,
              const std::string& path) {
  const char* what = what_s.c_str();
  const double count = body.value(p.count_type, what);
  if (count < 0)
    throw FileError(path + ": negative list length in the " + what_s + " (malformed PLY file)");
  const std::uint64_t n = static_cast<std::uint64_t>(count);
  const std::uint64_t item = format == Format::Ascii ? 2 : scalarSize(p.type);
  if (n > 0 && n > (body.remaining() + 1) / item)
    body.truncated(what);
  const bool keep = target.polygon && &p == target.indices;
  for (std::uint64_t k = 0; k < n; ++k) {
    const double v = body.value(p.type, what);
    if (!keep)
      continue;
    target.polygon->vertices.push_back(
        v >= 0.0 && v < static_cast<double>(vertices) ? static_cast<pcl::index_t>(v) : -1);
    if (target.polygon->vertices.back() < 0)
      throw FileError(path + ": PLY face " + std::to_string(row) + " refers to vertex " +
                      std::to_string(static_cast<long long>(v)) + ", but the file has " +
                      std::to_string(vertices) + " vertices");
  }
}

/** Reads one row of \a e: a vertex's values into its point (colours packed, b, g, r, a in
 * memory as PCL does: little-endian 0xAARRGGBB), a face's indices into its polygon, anything
 * else read and dropped. */
void readRow(Body& body, const Element& e, Format format, const RowTarget& target,
             std::uint64_t row, std::uint64_t vertices, const std::string& what_s,
             const std::string& path) {
  const char* what = what_s.c_str();
  const VertexLayout* layout = target.vertex;
  for (std::size_t i = 0; i < e.properties.size(); ++i) {
    const Property& p = e.properties[i];
    if (p.list) {
      readList(body, p, format, target, row, vertices, what_s, path);
      continue;
    }
    const int channel = layout ? layout->channel(i) : -1;
    if (layout && layout->offset_of[i] >= 0)
      body.store(p.type, target.point + layout->offset_of[i], what);
    else if (channel >= 0)
      body.store(pcl::PCLPointField::UINT8,
                 target.point + layout->colour_offset + (channel == 3 ? 3 : 2 - channel), what);
    else
      body.value(p.type, what);
  }
  if (layout && layout->packed && layout->colour[3] < 0)
    target.point[layout->colour_offset + 3] = 255;
}

}  // namespace

std::string readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.eof() && in.fail())
    throw FileError(path + ": read error");
  return data;
}

PlyContents readPlyFile(const std::string& path, bool read_faces, std::uint64_t max_vertices) {
  const std::string data = readWholeFile(path);
  const Header header = parseHeader(data, path);
  const Element& vertex = checkPlySizes(header, data.size() - header.body, max_vertices, path);
  PlyContents out;
  const VertexLayout layout = vertexLayout(vertex, out.vertices);
  Body body(data, header.body, header.format, path);
  bool vertices_read = false;
  for (const Element& e : header.elements) {
    const bool is_vertex = &e == &vertex;
    const bool is_face = read_faces && e.name == "face";
    if (!is_vertex && !is_face && vertices_read && !read_faces)
      break;  // a scene needs nothing after its vertices
    if (e.properties.empty())
      continue;
    const std::string what = printable(e.name) + " element";
    const bool fixed = std::none_of(e.properties.begin(), e.properties.end(),
                                    [](const Property& p) { return p.list; });
    if (!is_vertex && !is_face && fixed && header.format != Format::Ascii) {
      body.skip(e.count * minimumRowBytes(e, header.format), what.c_str());
      continue;
    }
    RowTarget target;
    if (is_vertex) {
      out.vertices.data.resize(static_cast<std::size_t>(e.count) * layout.step);
      target.vertex = &layout;
    }
    if (is_face) {
      for (const Property& p : e.properties)
        if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && !target.indices)
          target.indices = &p;
      if (target.indices && !isInteger(target.indices->type))
        throw FileError(path + ": PLY face indices are not of an integer type");
      out.polygons.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(
          e.count, body.remaining() / minimumRowBytes(e, header.format) + 1)));
    }
    for (std::uint64_t row = 0; row < e.count; ++row) {
      if (is_vertex)
        target.point = out.vertices.data.data() + row * layout.step;
      if (is_face)
        target.polygon = &out.polygons.emplace_back();
      readRow(body, e, header.format, target, row, vertex.count, what, path);
    }
    vertices_read = vertices_read || is_vertex;
  }
  return out;
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
