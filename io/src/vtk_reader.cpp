/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Our reader of legacy VTK polygon meshes (DATASET POLYDATA), replacing VTK's
// vtkPolyDataReader (through pcl::io::loadPolygonFileVTK), which crashed (SIGSEGV in
// vtkDataReader::ReadString) on a file cut after its POLYGONS line. See file_formats.h.
#include "file_formats.h"

#include <pcl/conversions.h>
#include <pcl/icf/io/mesh_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

namespace pcl {
namespace icf {
namespace io {
namespace detail {
namespace {

/** A data type of the legacy format: its name, its size in binary files, how to read it. */
struct ValueType {
  const char* name;
  int bytes;
  bool is_float;
  bool is_signed;
};

// "long" is 8 bytes in VTK's binary files on LP64 (Linux), as VTK writes sizeof(long).
constexpr ValueType kValueTypes[] = {{"char", 1, false, true},
                                     {"signed_char", 1, false, true},
                                     {"unsigned_char", 1, false, false},
                                     {"short", 2, false, true},
                                     {"unsigned_short", 2, false, false},
                                     {"int", 4, false, true},
                                     {"unsigned_int", 4, false, false},
                                     {"long", 8, false, true},
                                     {"unsigned_long", 8, false, false},
                                     {"vtkidtype", 8, false, true},
                                     {"vtktypeint8", 1, false, true},
                                     {"vtktypeuint8", 1, false, false},
                                     {"vtktypeint16", 2, false, true},
                                     {"vtktypeuint16", 2, false, false},
                                     {"vtktypeint32", 4, false, true},
                                     {"vtktypeuint32", 4, false, false},
                                     {"vtktypeint64", 8, false, true},
                                     {"vtktypeuint64", 8, false, false},
                                     {"float", 4, true, true},
                                     {"double", 8, true, true}};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/** One cell section (POLYGONS, TRIANGLE_STRIPS) as offsets into its connectivity. */
struct CellSection {
  std::string name;
  std::size_t pos = 0;  // of its keyword, for messages
  std::vector<std::uint64_t> offsets{0};
  std::vector<std::int64_t> connectivity;
};

class VtkParser {
 public:
  VtkParser(const std::string& path, const std::string& data) : path_(path), data_(data) {}

  pcl::PolygonMesh read() {
    readHeader();
    pcl::PointCloud<pcl::PointXYZ> points;
    bool have_points = false;
    std::vector<CellSection> faces;
    std::string word;
    while (nextWord(word)) {
      const std::string key = lower(word);
      const std::size_t keyword = pos_;
      if (key == "points") {
        if (have_points)
          fail("a second POINTS section");
        readPoints(points);
        have_points = true;
      } else if (key == "polygons" || key == "triangle_strips" || key == "vertices" ||
                 key == "lines") {
        CellSection cells = readCells(word);
        cells.pos = keyword;
        if (key == "polygons" || key == "triangle_strips")
          faces.push_back(std::move(cells));
      } else if (key == "metadata") {
        skipMetadata();
      } else if (key == "field") {
        skipField();
      } else if (key == "point_data" || key == "cell_data") {
        break;  // attributes: not needed for a mesh
      } else {
        fail("'" + printable(word) + "' is not a POLYDATA section keyword");
      }
    }
    if (!have_points)
      fail("no POINTS section (truncated or not a polygon mesh)");
    pcl::PolygonMesh mesh;
    for (const CellSection& cells : faces)
      addFaces(cells, points.size(), mesh.polygons);
    pcl::toPCLPointCloud2(points, mesh.cloud);
    return mesh;
  }

 private:
  [[noreturn]] void fail(const std::string& why, std::size_t at = std::string::npos) const {
    throw FileError(path_ + ":" + std::to_string(lineAt(at == std::string::npos ? pos_ : at)) +
                    ": " + why + " (malformed VTK file)");
  }

  std::size_t lineAt(std::size_t pos) const {
    pos = std::min(pos, data_.size());
    return 1 + static_cast<std::size_t>(std::count(data_.begin(), data_.begin() + pos, '\n'));
  }

  static bool blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  }

  /** The next whitespace-separated word; false at the end of the file. */
  bool nextWord(std::string& word) {
    while (pos_ < data_.size() && blank(data_[pos_]))
      ++pos_;
    const std::size_t start = pos_;
    while (pos_ < data_.size() && !blank(data_[pos_]))
      ++pos_;
    word.assign(data_, start, pos_ - start);
    return pos_ > start;
  }

  std::string requireWord(const std::string& what) {
    std::string word;
    if (!nextWord(word))
      fail("the file ends before " + what + " (truncated file)");
    return word;
  }

  /** The rest of the current line, without its line break; moves past the break. */
  std::string restOfLine() {
    std::size_t eol = data_.find('\n', pos_);
    const bool found = eol != std::string::npos;
    if (!found)
      eol = data_.size();
    std::string line = data_.substr(pos_, eol - pos_);
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    pos_ = found ? eol + 1 : eol;
    return line;
  }

  std::uint64_t requireCount(const std::string& what) {
    const std::string word = requireWord(what);
    std::uint64_t n = 0;
    const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), n);
    if (ec != std::errc() || ptr != word.data() + word.size())
      fail("'" + printable(word) + "' is not a count of " + what);
    return n;
  }

  const ValueType& requireType(const std::string& section) {
    const std::string word = requireWord("the data type of " + section);
    const std::string name = lower(word);
    for (const ValueType& t : kValueTypes)
      if (name == t.name)
        return t;
    fail("'" + printable(word) + "' is not a data type this reader reads in " + section);
  }

  void readHeader() {
    const std::string magic = "# vtk DataFile Version";
    if (data_.compare(0, magic.size(), magic) != 0)
      fail("not a legacy VTK file (no '# vtk DataFile Version' line)", 0);
    pos_ = magic.size();
    const std::string version = restOfLine();
    const std::size_t digit = version.find_first_not_of(" \t");
    int major = 0;
    if (digit == std::string::npos ||
        std::from_chars(version.data() + digit, version.data() + version.size(), major).ec !=
            std::errc())
      fail("'" + printable(version) + "' is not a version number");
    new_cells_ = major >= 5;
    if (pos_ >= data_.size())
      fail("the file ends before its title line (truncated file)");
    restOfLine();  // the title: free text
    const std::string format = lower(requireWord("ASCII or BINARY"));
    if (format != "ascii" && format != "binary")
      fail("'" + printable(format) + "' is neither ASCII nor BINARY");
    binary_ = format == "binary";
    const std::string dataset = requireWord("DATASET");
    if (lower(dataset) != "dataset")
      fail("expected 'DATASET POLYDATA', found '" + printable(dataset) + "'");
    const std::string kind = requireWord("the DATASET kind");
    if (lower(kind) != "polydata")
      fail("DATASET " + printable(kind) +
           " is not a polygon mesh (this reader reads DATASET POLYDATA only)");
  }

  /** Checks that \a count values of \a type can be in the rest of the file, before anything
   * is allocated; in binary files, moves past the line break before the data. */
  void startValues(std::uint64_t count, const ValueType& type, const std::string& section) {
    if (binary_) {
      restOfLine();
      const std::uint64_t left = data_.size() - pos_;
      if (count > left / static_cast<std::uint64_t>(type.bytes))
        fail(section + " claims " + std::to_string(count) + " values of " + type.name +
             ", the file holds " + std::to_string(left / type.bytes) +
             " (truncated file or a lying count)");
    } else {
      const std::uint64_t left = data_.size() - pos_;
      if (count > (left + 1) / 2)
        fail(section + " claims " + std::to_string(count) +
             " values, more than the rest of the file can hold (truncated file or a lying "
             "count)");
    }
  }

  /** Big-endian bytes of one binary value, as an unsigned integer. */
  std::uint64_t binaryBits(int bytes) {
    // startValues checks each section's room; this guards the reads themselves.
    if (static_cast<std::uint64_t>(bytes) > data_.size() - pos_)
      fail("binary data ends inside a value (truncated file)");
    std::uint64_t bits = 0;
    for (int i = 0; i < bytes; ++i)
      bits = (bits << 8) | static_cast<unsigned char>(data_[pos_ + i]);
    pos_ += bytes;
    return bits;
  }

  static std::int64_t signExtend(std::uint64_t bits, int bytes) {
    if (bytes == 8)
      return static_cast<std::int64_t>(bits);
    const std::uint64_t sign = std::uint64_t(1) << (8 * bytes - 1);
    return static_cast<std::int64_t>((bits ^ sign) - sign);
  }

  /** One value as a double (points). The size was checked by startValues. */
  double readReal(const ValueType& type, const std::string& section) {
    if (binary_) {
      const std::uint64_t bits = binaryBits(type.bytes);
      if (type.is_float && type.bytes == 4) {
        const std::uint32_t b32 = static_cast<std::uint32_t>(bits);
        float f;
        std::memcpy(&f, &b32, 4);
        return f;
      }
      if (type.is_float) {
        double d;
        std::memcpy(&d, &bits, 8);
        return d;
      }
      return type.is_signed ? static_cast<double>(signExtend(bits, type.bytes))
                            : static_cast<double>(bits);
    }
    const std::string word = requireWord("the end of " + section);
    const char* first = word.data();
    const char* last = word.data() + word.size();
    if (word.size() > 1 && *first == '+')
      ++first;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (ec == std::errc::result_out_of_range && ptr == last)
      return *first == '-' ? -INFINITY : INFINITY;  // a non-finite vertex: FaceMesh drops it
    if (ec != std::errc() || ptr != last)
      fail("'" + printable(word) + "' is not a number in " + section);
    return v;
  }

  /** One value as an integer (cells): integer types only. */
  std::int64_t readInteger(const ValueType& type, const std::string& section) {
    if (binary_) {
      const std::uint64_t bits = binaryBits(type.bytes);
      if (!type.is_signed && bits > std::uint64_t(INT64_MAX))
        fail("a value of " + section + " is out of range");
      return type.is_signed ? signExtend(bits, type.bytes) : static_cast<std::int64_t>(bits);
    }
    const std::string word = requireWord("the end of " + section);
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || ptr != word.data() + word.size())
      fail("'" + printable(word) + "' is not an integer in " + section);
    return v;
  }

  void readPoints(pcl::PointCloud<pcl::PointXYZ>& points) {
    const std::uint64_t n = requireCount("POINTS");
    if (n > kMaxMeshElements)
      fail("POINTS claims " + std::to_string(n) + " points, more than the " +
           std::to_string(kMaxMeshElements) + " this reader accepts");
    const ValueType& type = requireType("POINTS");
    startValues(3 * n, type, "POINTS");
    points.resize(n);
    for (pcl::PointXYZ& p : points.points) {
      p.x = static_cast<float>(readReal(type, "POINTS"));
      p.y = static_cast<float>(readReal(type, "POINTS"));
      p.z = static_cast<float>(readReal(type, "POINTS"));
    }
    points.width = static_cast<std::uint32_t>(n);
    points.height = 1;
  }

  CellSection readCells(const std::string& name) {
    CellSection cells;
    cells.name = printable(name);
    const std::uint64_t first = requireCount(cells.name);
    const std::uint64_t second = requireCount(cells.name);
    if (first > kMaxMeshElements || second > kMaxMeshElements)
      fail(cells.name + " claims " + std::to_string(std::max(first, second)) +
           " values, more than the " + std::to_string(kMaxMeshElements) + " this reader accepts");
    if (new_cells_)
      readNewCells(cells, first, second);
    else
      readClassicCells(cells, first, second);
    return cells;
  }

  /** Versions < 5: "NAME cells size", then per cell "count i0 i1 ...", int in binary files. */
  void readClassicCells(CellSection& cells, std::uint64_t n, std::uint64_t size) {
    static const ValueType& int32 = kValueTypes[5];
    startValues(size, int32, cells.name);
    if (n > size)
      fail(cells.name + " claims " + std::to_string(n) + " cells in " + std::to_string(size) +
           " values");
    cells.offsets.reserve(n + 1);
    cells.connectivity.reserve(size - n);
    std::uint64_t used = 0;
    for (std::uint64_t c = 0; c < n; ++c) {
      // startValues checked room for size values only: no count is read beyond them.
      if (used >= size)
        fail(cells.name + " claims " + std::to_string(n) + " cells, its " + std::to_string(size) +
             " values end at cell " + std::to_string(c));
      const std::int64_t count = readInteger(int32, cells.name);
      if (count < 0 || static_cast<std::uint64_t>(count) > size - used - 1)
        fail(cells.name + " cell " + std::to_string(c) + " claims " + std::to_string(count) +
             " points, more than its size " + std::to_string(size) + " leaves");
      used += 1 + static_cast<std::uint64_t>(count);
      for (std::int64_t k = 0; k < count; ++k)
        cells.connectivity.push_back(readInteger(int32, cells.name));
      cells.offsets.push_back(cells.connectivity.size());
    }
    if (used != size)
      fail(cells.name + " cells hold " + std::to_string(used) + " values, its size says " +
           std::to_string(size));
  }

  /** Version 5.x: "NAME offsets connectivity", "OFFSETS type" and "CONNECTIVITY type" arrays. */
  void readNewCells(CellSection& cells, std::uint64_t n_offsets, std::uint64_t n_connectivity) {
    const std::string offsets_word = requireWord("OFFSETS");
    if (lower(offsets_word) != "offsets")
      fail("expected OFFSETS in " + cells.name + ", found '" + printable(offsets_word) + "'");
    const ValueType& offsets_type = requireType(cells.name + " OFFSETS");
    if (offsets_type.is_float)
      fail(cells.name + " OFFSETS of type " + offsets_type.name + " (an integer type needed)");
    startValues(n_offsets, offsets_type, cells.name + " OFFSETS");
    cells.offsets.clear();
    cells.offsets.reserve(n_offsets);
    for (std::uint64_t i = 0; i < n_offsets; ++i) {
      const std::int64_t o = readInteger(offsets_type, cells.name + " OFFSETS");
      const std::uint64_t previous = cells.offsets.empty() ? 0 : cells.offsets.back();
      if (o < 0 || static_cast<std::uint64_t>(o) < previous ||
          static_cast<std::uint64_t>(o) > n_connectivity || (i == 0 && o != 0))
        fail(cells.name + " OFFSETS value " + std::to_string(i) + " is " + std::to_string(o) +
             " (offsets start at 0, never decrease and end at the connectivity size " +
             std::to_string(n_connectivity) + ")");
      cells.offsets.push_back(static_cast<std::uint64_t>(o));
    }
    if ((n_offsets == 0 && n_connectivity != 0) ||
        (n_offsets > 0 && cells.offsets.back() != n_connectivity))
      fail(cells.name + " OFFSETS end at " +
           std::to_string(cells.offsets.empty() ? 0 : cells.offsets.back()) +
           ", not at the connectivity size " + std::to_string(n_connectivity));
    if (cells.offsets.empty())
      cells.offsets.push_back(0);
    const std::string connectivity_word = requireWord("CONNECTIVITY");
    if (lower(connectivity_word) != "connectivity")
      fail("expected CONNECTIVITY in " + cells.name + ", found '" + printable(connectivity_word) +
           "'");
    const ValueType& type = requireType(cells.name + " CONNECTIVITY");
    if (type.is_float)
      fail(cells.name + " CONNECTIVITY of type " + type.name + " (an integer type needed)");
    startValues(n_connectivity, type, cells.name + " CONNECTIVITY");
    cells.connectivity.reserve(n_connectivity);
    for (std::uint64_t i = 0; i < n_connectivity; ++i)
      cells.connectivity.push_back(readInteger(type, cells.name + " CONNECTIVITY"));
  }

  /** Dataset-level field data, which VTK writes before POINTS: "FIELD name arrays", then per
   * array "name components tuples type" and its values (a NULL_ARRAY has none), each maybe
   * followed by METADATA. Read past; string arrays are refused. */
  void skipField() {
    requireWord("the FIELD name");
    const std::uint64_t arrays = requireCount("FIELD arrays");
    for (std::uint64_t a = 0; a < arrays; ++a) {
      std::string name = requireWord("a FIELD array");
      if (lower(name) == "metadata") {
        skipMetadata();
        name = requireWord("a FIELD array");
      }
      if (name == "NULL_ARRAY")
        continue;
      const std::string section = "FIELD array " + printable(name);
      const std::uint64_t components = requireCount(section + " components");
      const std::uint64_t tuples = requireCount(section + " tuples");
      if (components > kMaxMeshElements || tuples > kMaxMeshElements ||
          components * tuples > 4 * kMaxMeshElements)
        fail(section + " claims " + std::to_string(components) + " x " + std::to_string(tuples) +
             " values, more than this reader accepts");
      const ValueType& type = requireType(section);
      const std::uint64_t count = components * tuples;
      startValues(count, type, section);
      if (binary_) {
        pos_ += count * static_cast<std::uint64_t>(type.bytes);
        continue;
      }
      for (std::uint64_t i = 0; i < count; ++i)
        requireWord("the end of " + section);
    }
  }

  /** METADATA (VTK 8+ array information): lines up to the first empty one. */
  void skipMetadata() {
    restOfLine();
    while (pos_ < data_.size()) {
      const std::string line = restOfLine();
      if (line.find_first_not_of(" \t") == std::string::npos)
        return;
    }
  }

  /** Polygons as they are; triangle strips split into triangles of alternating winding as
   * VTK's vtkTriangleStrip::DecomposeStrip does. Indices checked against the points. */
  void addFaces(const CellSection& cells, std::size_t n_points,
                std::vector<pcl::Vertices>& polygons) const {
    const bool strips = lower(cells.name) == "triangle_strips";
    for (std::size_t c = 0; c + 1 < cells.offsets.size(); ++c) {
      const std::int64_t* p = cells.connectivity.data() + cells.offsets[c];
      const std::size_t count = cells.offsets[c + 1] - cells.offsets[c];
      for (std::size_t k = 0; k < count; ++k)
        if (p[k] < 0 || static_cast<std::uint64_t>(p[k]) >= n_points)
          fail(cells.name + " cell " + std::to_string(c) + " refers to point " +
                   std::to_string(p[k]) + ", but the file has " + std::to_string(n_points) +
                   " points",
               cells.pos);
      if (!strips) {
        pcl::Vertices face;
        face.vertices.assign(p, p + count);
        polygons.push_back(std::move(face));
        continue;
      }
      for (std::size_t i = 0; i + 2 < count; ++i) {
        pcl::Vertices face;
        const bool odd = i % 2 == 1;
        face.vertices = {static_cast<pcl::index_t>(p[i]),
                         static_cast<pcl::index_t>(p[odd ? i + 2 : i + 1]),
                         static_cast<pcl::index_t>(p[odd ? i + 1 : i + 2])};
        polygons.push_back(std::move(face));
      }
    }
  }

  const std::string& path_;
  const std::string& data_;
  std::size_t pos_ = 0;
  bool binary_ = false;
  bool new_cells_ = false;
};

}  // namespace

pcl::PolygonMesh readVtkFile(const std::string& path) {
  const std::string data = readWholeFile(path);
  return VtkParser(path, data).read();
}

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
