/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "file_formats.h"

#include <pcl/icf/io/mesh_io.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

namespace pcl {
namespace icf {
namespace io {
namespace detail {
namespace {

enum class Scalar : std::uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Format { Ascii, BinaryLittle, BinaryBig };

struct Property {
  std::string name;
  Scalar type = Scalar::F32;
  bool list = false;
  Scalar count_type = Scalar::U8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

constexpr std::size_t kMaxHeaderBytes = 65536;

std::size_t scalarSize(Scalar t) {
  switch (t) {
    case Scalar::I8:
    case Scalar::U8:
      return 1;
    case Scalar::I16:
    case Scalar::U16:
      return 2;
    case Scalar::F64:
      return 8;
    default:
      return 4;
  }
}

bool isInteger(Scalar t) {
  return t != Scalar::F32 && t != Scalar::F64;
}

bool parseScalar(const std::string& name, Scalar& t) {
  static const std::pair<const char*, Scalar> names[] = {
      {"char", Scalar::I8},    {"int8", Scalar::I8},     {"uchar", Scalar::U8},
      {"uint8", Scalar::U8},   {"short", Scalar::I16},   {"int16", Scalar::I16},
      {"ushort", Scalar::U16}, {"uint16", Scalar::U16},  {"int", Scalar::I32},
      {"int32", Scalar::I32},  {"uint", Scalar::U32},    {"uint32", Scalar::U32},
      {"float", Scalar::F32},  {"float32", Scalar::F32}, {"double", Scalar::F64},
      {"float64", Scalar::F64}};
  for (const auto& n : names)
    if (name == n.first) {
      t = n.second;
      return true;
    }
  return false;
}

std::uint8_t pclType(Scalar t) {
  switch (t) {
    case Scalar::I8:
      return pcl::PCLPointField::INT8;
    case Scalar::U8:
      return pcl::PCLPointField::UINT8;
    case Scalar::I16:
      return pcl::PCLPointField::INT16;
    case Scalar::U16:
      return pcl::PCLPointField::UINT16;
    case Scalar::I32:
      return pcl::PCLPointField::INT32;
    case Scalar::U32:
      return pcl::PCLPointField::UINT32;
    case Scalar::F64:
      return pcl::PCLPointField::FLOAT64;
    default:
      return pcl::PCLPointField::FLOAT32;
  }
}

/** Lowest and highest value of an integer type. */
void integerRange(Scalar t, double& lo, double& hi) {
  switch (t) {
    case Scalar::I8:
      lo = -128.0, hi = 127.0;
      return;
    case Scalar::U8:
      lo = 0.0, hi = 255.0;
      return;
    case Scalar::I16:
      lo = -32768.0, hi = 32767.0;
      return;
    case Scalar::U16:
      lo = 0.0, hi = 65535.0;
      return;
    case Scalar::I32:
      lo = -2147483648.0, hi = 2147483647.0;
      return;
    default:
      lo = 0.0, hi = 4294967295.0;
  }
}

/** The bytes of the PLY body as typed values: ascii tokens or binary fields. */
class Body {
 public:
  Body(const std::string& data, std::size_t pos, Format format, const std::string& path)
      : data_(data), pos_(pos), format_(format), path_(path) {}

  std::size_t remaining() const { return data_.size() - std::min(pos_, data_.size()); }

  /** Next value of type \a t as a double (any type converts exactly, but uint64). */
  double value(Scalar t, const char* what) {
    if (format_ == Format::Ascii)
      return asciiValue(t, what);
    std::uint8_t bytes[8];
    binaryValue(t, bytes, what);
    return decode(t, bytes);
  }

  /** Next value of type \a t written to \a out in the machine's byte order. */
  void store(Scalar t, std::uint8_t* out, const char* what) {
    if (format_ != Format::Ascii) {
      binaryValue(t, out, what);
      return;
    }
    const double v = asciiValue(t, what);
    switch (t) {
      case Scalar::I8: {
        const auto x = static_cast<std::int8_t>(v);
        std::memcpy(out, &x, 1);
        return;
      }
      case Scalar::U8: {
        const auto x = static_cast<std::uint8_t>(v);
        std::memcpy(out, &x, 1);
        return;
      }
      case Scalar::I16: {
        const auto x = static_cast<std::int16_t>(v);
        std::memcpy(out, &x, 2);
        return;
      }
      case Scalar::U16: {
        const auto x = static_cast<std::uint16_t>(v);
        std::memcpy(out, &x, 2);
        return;
      }
      case Scalar::I32: {
        const auto x = static_cast<std::int32_t>(v);
        std::memcpy(out, &x, 4);
        return;
      }
      case Scalar::U32: {
        const auto x = static_cast<std::uint32_t>(v);
        std::memcpy(out, &x, 4);
        return;
      }
      case Scalar::F32: {
        const float x = static_cast<float>(v);  // beyond float's range: +-inf, as IEEE says
        std::memcpy(out, &x, 4);
        return;
      }
      case Scalar::F64:
        std::memcpy(out, &v, 8);
        return;
    }
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

  static double decode(Scalar t, const std::uint8_t* b) {
    switch (t) {
      case Scalar::I8:
        return static_cast<std::int8_t>(b[0]);
      case Scalar::U8:
        return b[0];
      case Scalar::I16: {
        std::int16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case Scalar::U16: {
        std::uint16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case Scalar::I32: {
        std::int32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Scalar::U32: {
        std::uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Scalar::F32: {
        float v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Scalar::F64: {
        double v;
        std::memcpy(&v, b, 8);
        return v;
      }
    }
    return 0.0;
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
      double lo, hi;
      integerRange(t, lo, hi);
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
    } else if (words[0] == "element") {
      Element e;
      if (words.size() != 3)
        throw FileError(bad + "is not 'element <name> <count>'");
      e.name = words[1];
      const char* end = words[2].data() + words[2].size();
      const auto [ptr, ec] = std::from_chars(words[2].data(), end, e.count);
      if (ec != std::errc() || ptr != end)
        throw FileError(bad + "has no valid element count");
      h.elements.push_back(e);
    } else if (words[0] == "property") {
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
    } else
      throw FileError(bad + "is not a PLY header line (malformed file)");
  }
  if (!format_seen)
    throw FileError(path + ": PLY header has no format line (malformed file)");
  return h;
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
  // Every element's rows need a least number of bytes: a header that claims more rows than
  // the body can hold fails here, before any allocation.
  const std::uint64_t body_bytes = data.size() - header.body;
  std::uint64_t needed = 0;
  for (const Element& e : header.elements) {
    const std::uint64_t row = minimumRowBytes(e, header.format);
    if (row > 0 && (e.count > body_bytes / row + 1 || (needed += e.count * row) > body_bytes + 1))
      throw FileError(path + ": PLY file is shorter than its " + std::to_string(e.count) + " " +
                      printable(e.name) + " elements need (truncated or a lying header)");
  }

  PlyContents out;
  pcl::PCLPointCloud2& cloud = out.vertices;
  // Vertex layout: scalar properties in order, red/green/blue[/alpha] uchar packed.
  std::vector<int> offset_of(vertex->properties.size(), -1);
  int colour[4] = {-1, -1, -1, -1};  // property index of red, green, blue, alpha
  {
    const char* names[4] = {"red", "green", "blue", "alpha"};
    for (std::size_t i = 0; i < vertex->properties.size(); ++i)
      for (int c = 0; c < 4; ++c)
        if (!vertex->properties[i].list && vertex->properties[i].type == Scalar::U8 &&
            vertex->properties[i].name == names[c] && colour[c] < 0)
          colour[c] = static_cast<int>(i);
  }
  const bool packed = colour[0] >= 0 && colour[1] >= 0 && colour[2] >= 0;
  std::uint32_t step = 0;
  for (std::size_t i = 0; i < vertex->properties.size(); ++i) {
    const Property& p = vertex->properties[i];
    const bool is_colour =
        packed && std::find(colour, colour + 4, static_cast<int>(i)) != colour + 4;
    if (p.list || is_colour)
      continue;
    pcl::PCLPointField f;
    f.name = p.name;
    f.offset = step;
    f.datatype = pclType(p.type);
    f.count = 1;
    cloud.fields.push_back(f);
    offset_of[i] = static_cast<int>(step);
    step += static_cast<std::uint32_t>(scalarSize(p.type));
  }
  std::uint32_t colour_offset = 0;
  if (packed) {
    pcl::PCLPointField f;
    f.name = colour[3] >= 0 ? "rgba" : "rgb";
    f.offset = colour_offset = step;
    f.datatype = colour[3] >= 0 ? pcl::PCLPointField::UINT32 : pcl::PCLPointField::FLOAT32;
    f.count = 1;
    cloud.fields.push_back(f);
    step += 4;
  }
  cloud.width = static_cast<std::uint32_t>(vertex->count);
  cloud.height = 1;
  cloud.point_step = step;
  cloud.row_step = static_cast<std::uint32_t>(std::min<std::uint64_t>(
      std::uint64_t(step) * vertex->count, std::numeric_limits<std::uint32_t>::max()));
  cloud.is_bigendian = false;
  cloud.is_dense = false;

  Body body(data, header.body, header.format, path);
  bool vertices_read = false;
  for (const Element& e : header.elements) {
    const bool is_vertex = &e == vertex;
    const bool is_face = read_faces && e.name == "face";
    if (!is_vertex && !is_face && vertices_read && !read_faces)
      break;  // a scene needs nothing after its vertices
    if (e.properties.empty())
      continue;
    const std::string what_s = printable(e.name) + " element";
    const char* what = what_s.c_str();
    bool fixed = true;
    for (const Property& p : e.properties)
      fixed = fixed && !p.list;
    if (!is_vertex && !is_face && fixed && header.format != Format::Ascii) {
      body.skip(e.count * minimumRowBytes(e, header.format), what);
      continue;
    }
    if (is_vertex)
      cloud.data.resize(static_cast<std::size_t>(e.count) * step);
    const Property* indices = nullptr;
    if (is_face)
      for (const Property& p : e.properties)
        if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index") && !indices)
          indices = &p;
    if (is_face && indices && !isInteger(indices->type))
      throw FileError(path + ": PLY face indices are not of an integer type");
    if (is_face)
      out.polygons.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(
          e.count, body.remaining() / minimumRowBytes(e, header.format) + 1)));
    const std::uint64_t item_bytes_min = header.format == Format::Ascii ? 2 : 0;
    for (std::uint64_t row = 0; row < e.count; ++row) {
      std::uint8_t* point = is_vertex ? cloud.data.data() + row * step : nullptr;
      if (is_face)
        out.polygons.emplace_back();
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const Property& p = e.properties[i];
        if (!p.list) {
          if (is_vertex && offset_of[i] >= 0)
            body.store(p.type, point + offset_of[i], what);
          else if (is_vertex && packed &&
                   std::find(colour, colour + 4, static_cast<int>(i)) != colour + 4) {
            const int c =
                static_cast<int>(std::find(colour, colour + 4, static_cast<int>(i)) - colour);
            // Packed as PCL does: b, g, r, a in memory (little-endian 0xAARRGGBB).
            const int byte = c == 3 ? 3 : 2 - c;
            body.store(Scalar::U8, point + colour_offset + byte, what);
          } else
            body.value(p.type, what);
          continue;
        }
        const double count = body.value(p.count_type, what);
        if (count < 0)
          throw FileError(path + ": negative list length in the " + what_s +
                          " (malformed PLY file)");
        const std::uint64_t n = static_cast<std::uint64_t>(count);
        const std::uint64_t item =
            header.format == Format::Ascii ? item_bytes_min : scalarSize(p.type);
        if (n > 0 && n > (body.remaining() + 1) / item)
          body.truncated(what);
        const bool keep = is_face && &p == indices;
        for (std::uint64_t k = 0; k < n; ++k) {
          const double v = body.value(p.type, what);
          if (keep)
            out.polygons.back().vertices.push_back(
                v >= 0.0 && v < static_cast<double>(vertex->count) ? static_cast<pcl::index_t>(v)
                                                                   : -1);
          if (keep && out.polygons.back().vertices.back() < 0)
            throw FileError(path + ": PLY face " + std::to_string(row) + " refers to vertex " +
                            std::to_string(static_cast<long long>(v)) + ", but the file has " +
                            std::to_string(vertex->count) + " vertices");
        }
      }
      if (packed && is_vertex && colour[3] < 0)
        point[colour_offset + 3] = 255;
    }
    vertices_read = vertices_read || is_vertex;
  }
  return out;
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
