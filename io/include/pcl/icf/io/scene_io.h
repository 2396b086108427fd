/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/io/mesh_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstddef>
#include <string>

namespace pcl {
namespace icf {
namespace io {

/** \brief Thrown when a scene file was read correctly but holds no usable point: no points at
 * all, or only points with a NaN or infinite coordinate. A FileError, so one catch handles
 * every unusable input; the message names the file and says which case it is. */
class EmptyCloudError : public FileError {
 public:
  using FileError::FileError;
};

/** \brief What loadSceneCloud found in the file besides the points. */
struct SceneFileInfo {
  std::string format;             ///< "pcd", "ply" or "xyz" (.asc files too)
  bool has_colour = false;        ///< the file had rgb / rgba (or red, green, blue) fields
  bool organized = false;         ///< height > 1 (a depth image's grid, kept as it was)
  std::size_t points = 0;         ///< width * height
  std::size_t finite_points = 0;  ///< points whose x, y and z are all finite
};

/** \brief Largest cloud loadSceneCloud accepts (points), to fail fast on absurd headers or
 * files: 50 million, about 25 Kinect frames. */
constexpr std::size_t kMaxScenePoints = 50000000;

/** \brief Load a scene point cloud, chosen by the extension (case-insensitive):
 *
 * - .pcd: ascii, binary, binary_compressed, as PCL writes them. An organized cloud stays
 *   organized (width x height, NaN where the sensor saw nothing) and the file's VIEWPOINT becomes
 *   sensor_origin_ / sensor_orientation_.
 * - .ply: ascii or binary; the vertices are the points (faces, if any, are ignored).
 * - .xyz / .asc: plain text as the thesis's capture program wrote it, one point per line:
 *   three numbers "x y z", or six "x y z r g b" with r, g, b integers in [0, 255]; numbers
 *   are separated by spaces, tabs or commas; blank lines and lines starting with '#' are
 *   skipped; "nan" is read as NaN. Any other line is an error naming its line number.
 *
 * PCD and PLY are read by our own readers, which check every size against the file before
 * allocating (PCL's crashed on fuzzed files: doc/HOSTILE_INPUTS.md); the result is what PCL's
 * readers give for valid files.
 *
 * Without colour in the file every point gets white (r = g = b = a = 255) and
 * info->has_colour is false. Units are whatever the file holds (PCL's convention: metres).
 *
 * \param[in] path the file
 * \param[out] info optional: format, colour, organisation and point counts
 * \throws FileError when the file is missing, empty, unreadable, of an unknown extension,
 * malformed, truncated, or larger than kMaxScenePoints
 * \throws EmptyCloudError when the file has no points or no finite point */
pcl::PointCloud<pcl::PointXYZRGBA>::Ptr loadSceneCloud(const std::string& path,
                                                       SceneFileInfo* info = nullptr);

/** \brief Parse .xyz / .asc text that is already in memory (received over a socket, read from
 * an archive or a capture program's pipe) by the rules loadSceneCloud gives for .xyz files,
 * without writing it to a file first; loadSceneCloud reads .xyz files with it.
 *
 * \code
 * bool colour = false;
 * const auto cloud = pcl::icf::io::parseXyzText(received_bytes, "camera stream", &colour);
 * \endcode
 *
 * \param[in] text the text, lines ended by '\n' or "\r\n"
 * \param[in] name what error messages call the text ("scan.xyz" gives "scan.xyz:12: ...")
 * \param[out] has_colour optional: true when the lines have six numbers (x y z r g b)
 * \return an unorganized cloud (height 1) in the text's order and units, is_dense when every
 * coordinate is finite; without colour every point is white
 * \throws FileError naming the line for a malformed line, or when the text holds more than
 * kMaxScenePoints points
 * \throws EmptyCloudError when the text holds no point (only blank or comment lines). Unlike
 * loadSceneCloud it returns a cloud whose points are all NaN: check is_dense or the points. */
pcl::PointCloud<pcl::PointXYZRGBA>::Ptr parseXyzText(const std::string& text,
                                                     const std::string& name,
                                                     bool* has_colour = nullptr);

}  // namespace io
}  // namespace icf
}  // namespace pcl
