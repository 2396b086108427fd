/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PolygonMesh.h>

#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace io {

/** \brief Thrown when a file cannot be read as asked: missing, unreadable, empty, of an unknown
 * extension, malformed or truncated. The message names the file and the reason. */
class FileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/** \brief Load a polygon mesh from .ply (ascii or binary, any property types), .obj, .stl
 * (ascii or binary) or .vtk, chosen by the extension (case-insensitive). PLY, OBJ and STL are
 * read by our own readers, which check every size against the file before allocating (PCL's
 * and VTK's crashed on fuzzed files: doc/HOSTILE_INPUTS.md); .vtk by VTK's legacy reader.
 *
 * \throws FileError when the file is missing, empty, of another extension, or the reader
 * fails or returns no vertices. A mesh without polygons loads (a point-only PLY is a valid
 * file); FaceMesh::build is where "no faces" is an error. */
pcl::PolygonMesh loadPolygonMesh(const std::string& path);

/** \brief Lower-case extension of \a path without the dot ("" when there is none). */
std::string fileExtension(const std::string& path);

/** \brief Throws FileError unless \a path names a readable, non-empty regular file. */
void requireReadableFile(const std::string& path);

}  // namespace io
}  // namespace icf
}  // namespace pcl
