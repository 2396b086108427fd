/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Internal to pcl_icf::io: our own readers for PCD, PLY, OBJ, STL and legacy VTK.
//
// Why not PCL's and VTK's readers: fuzzing them through our loaders (fuzz/) found a
// SIGSEGV in pcl::PCDReader on a FIELDS line of control bytes and a 100 TB allocation when
// binary data after DATA happened to read as a header line, an assert() in pcl::PLYReader
// on a list property inside the vertex element, a SIGSEGV in vtkOBJReader on a malformed face
// line and a 7 GB allocation in vtkSTLReader from a binary STL whose triangle count lies;
// VTK's legacy vtkPolyDataReader crashed (SIGSEGV in vtkDataReader::ReadString) on a .vtk
// file cut right after its POLYGONS line.
// These readers check every size against the bytes actually present, never allocate more
// than the file can hold, and throw FileError naming the file (and the line, for text) and
// the reason. doc/HOSTILE_INPUTS.md lists the inputs tried.
//
// Each format has one header parser, in its reader's source, used by every path that reads the
// format (loadSceneCloud and loadPolygonMesh alike): a file gets the same message whichever
// loader reads it. Field values are decoded by pcl_icf_internal/point_field.h.
#pragma once

#include <pcl/PCLPointCloud2.h>
#include <pcl/PolygonMesh.h>
#include <pcl/Vertices.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace io {
namespace detail {

/** The bytes of a file; FileError when it cannot be read. */
std::string readWholeFile(const std::string& path);

/** A token for an error message: at most 32 characters, bytes that are not printable ASCII
 * shown as '?'. */
inline std::string printable(const std::string& token) {
  std::string out;
  for (const char c : token.substr(0, 32))
    out += (c >= 32 && c < 127) ? c : '?';
  if (token.size() > 32)
    out += "...";
  return out;
}

/** The words of a header line, split at spaces, tabs and carriage returns (CRLF files). */
inline std::vector<std::string> splitWords(const std::string& line) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i]))
      ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i]))
      ++i;
    if (i > start)
      words.push_back(line.substr(start, i - start));
  }
  return words;
}

/** Largest number of vertices or faces the mesh readers accept (a lying header fails fast). */
constexpr std::uint64_t kMaxMeshElements = 100000000;

/** What readPlyFile found: the vertex element as a cloud, and the faces when asked. */
struct PlyContents {
  /** Every scalar vertex property as a field of its own type (x, y, z as declared: float or
   * double), except red, green, blue [, alpha] of type uchar, which are packed into one "rgb"
   * (FLOAT32) or "rgba" (UINT32) field as PCL's PLY reader does. width = vertices, height = 1.
   * List properties of the vertex element are read and dropped. */
  pcl::PCLPointCloud2 vertices;
  /** The "vertex_indices" (or "vertex_index") lists of the "face" element, each index checked
   * against the vertex count. Empty unless asked for. */
  std::vector<pcl::Vertices> polygons;
};

/** Reads a PLY file: ascii, binary_little_endian or binary_big_endian, any element order,
 * any property types; elements other than "vertex" and "face" are read past.
 * \param max_vertices a vertex count above this fails before anything is allocated
 * \throws FileError for a missing magic, a malformed header, an element count the file is too
 * short to hold, a non-number, truncated data or a face index out of range */
PlyContents readPlyFile(const std::string& path, bool read_faces, std::uint64_t max_vertices);

/** Reads a Wavefront OBJ file: "v x y z [w | r g b]" vertices and "f" polygons (v, v/t, v//n,
 * v/t/n, negative indices relative to the vertices read so far); texture coordinates,
 * normals, lines, points, groups, materials and unknown statements are ignored.
 * \throws FileError naming the line for a malformed vertex or face, or a face index out of
 * range */
pcl::PolygonMesh readObjFile(const std::string& path);

/** Reads an STL file, binary (84-byte header, 50 bytes per triangle: chosen when the size
 * matches the triangle count, or when the file does not start with "solid") or ascii.
 * Identical vertices are merged. \throws FileError for a file shorter than its triangle count
 * says, a malformed ascii line, or ascii data that ends inside a facet */
pcl::PolygonMesh readStlFile(const std::string& path);

/** Reads a legacy VTK polygon mesh ("# vtk DataFile Version X.Y", a title, ASCII or BINARY
 * (big-endian), DATASET POLYDATA), as VTK's vtkPolyDataReader does: POINTS of any VTK number
 * type, POLYGONS and TRIANGLE_STRIPS (split into triangles of alternating winding), VERTICES
 * and LINES read past, in the classic cell layout (versions < 5: "count i0 i1 ..." records) or
 * version 5's OFFSETS / CONNECTIVITY arrays; FIELD data and METADATA are read past, reading
 * stops at POINT_DATA or CELL_DATA. Vertices as float x, y, z, as readObjFile gives them.
 * \throws FileError naming the line for another DATASET kind, a count the rest of the file
 * cannot hold (checked before allocating), a non-number, truncated data or an index out of
 * range */
pcl::PolygonMesh readVtkFile(const std::string& path);

/** Reads a PCD file (ascii, binary or binary_compressed) into a PCLPointCloud2, as PCL's
 * reader would, with a strict header that ends at the first line starting with DATA (none in
 * the first 64 KiB: "not a PCD file"): printable ASCII lines (comments excepted); FIELDS, SIZE,
 * TYPE [, COUNT] with one entry per field; TYPE I or U with SIZE 1, 2 or 4, F with 4 or 8;
 * COUNT >= 1;
 * WIDTH x HEIGHT = POINTS at most \a max_points; DATA ascii, binary or binary_compressed.
 * The body is checked against the header before anything is allocated: binary data as long
 * as the points need, compressed sizes that the file and the points agree with (LZF cannot
 * expand more than 88 times), ascii text with enough numbers. (pcl::PCDReader reads on past
 * the DATA line: binary data that looks like a header line is parsed as one.)
 * \param[out] origin, orientation the VIEWPOINT (identity without one), unchecked
 * \throws FileError naming the file and the first problem */
void readPcdFile(const std::string& path, std::uint64_t max_points, pcl::PCLPointCloud2& cloud,
                 Eigen::Vector4f& origin, Eigen::Quaternionf& orientation);

}  // namespace detail
}  // namespace io
}  // namespace icf
}  // namespace pcl
