/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Thrown when a mesh cannot serve as a model: no vertices, no faces, vertex indices out
 * of range, non-finite coordinates in every face, or nothing left after degenerate faces are
 * dropped. The message names what is wrong. */
class InvalidMeshError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/** \brief One face of a FaceMesh: a planar convex polygon (3 or more vertices, counter-
 * clockwise around \c normal). */
struct Face {
  std::uint32_t first = 0;  ///< offset of its first vertex index in FaceMesh::faceVertexIndices()
  std::uint32_t count = 0;  ///< number of vertices (3 for triangles, 4 for rectangles, ...)
  Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  ///< unit normal (Newell's method)
  float area = 0.f;                                   ///< in squared mesh units
};

/** \brief What FaceMesh::build kept and dropped, for the caller to report. */
struct FaceMeshReport {
  std::size_t input_polygons = 0;         ///< polygons in the PolygonMesh
  std::size_t kept_faces = 0;             ///< faces kept as they were
  std::size_t triangulated_polygons = 0;  ///< non-planar or concave polygons split in triangles
  std::size_t degenerate_dropped = 0;     ///< fewer than 3 distinct vertices, or zero area
  std::size_t duplicate_dropped = 0;      ///< same vertex set as an earlier face
  std::size_t nonfinite_dropped = 0;      ///< a vertex with a NaN or Inf coordinate
};

/** \brief Options of FaceMesh::build. */
struct FaceMeshOptions {
  /** A polygon of more than 3 vertices is planar when every vertex lies within
   * planarity_tolerance * (its longest diagonal or edge) of its Newell plane. */
  float planarity_tolerance = 1e-4f;
  /** A face whose area is below area_tolerance * (bounding-box diagonal)^2 is degenerate. */
  float area_tolerance = 1e-12f;
  /** Multiply every vertex coordinate by this (1e-3 turns a millimetre CAD file into metres). */
  float scale = 1.f;
};

/** \brief A polygon mesh prepared for point-to-face queries: vertices, convex planar faces
 * with unit normals and areas.
 *
 * Built from a pcl::PolygonMesh (any field layout with x, y, z). Triangles, rectangles and any
 * planar convex polygon stay single faces; non-planar or concave polygons are ear-clipped
 * into triangles. Zero-area and duplicate faces (same vertex set) are dropped and counted in
 * report(); unreferenced vertices are kept but never queried. Immutable after construction,
 * so it is safe to share between threads. */
class FaceMesh {
 public:
  using Ptr = std::shared_ptr<FaceMesh>;
  using ConstPtr = std::shared_ptr<const FaceMesh>;

  /** \brief Build from a PCL mesh. \throws InvalidMeshError when no usable face remains. */
  static FaceMesh build(const pcl::PolygonMesh& mesh, const FaceMeshOptions& options = {});

  const std::vector<Eigen::Vector3f>& vertices() const { return vertices_; }
  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<std::uint32_t>& faceVertexIndices() const { return indices_; }
  const FaceMeshReport& report() const { return report_; }

  std::size_t size() const { return faces_.size(); }
  /** \brief Vertex \a k (0 <= k < count) of face \a f. */
  const Eigen::Vector3f& faceVertex(std::size_t f, std::size_t k) const {
    return vertices_[indices_[faces_[f].first + k]];
  }
  /** \brief Total surface area in squared mesh units. */
  double totalArea() const { return total_area_; }
  /** \brief Axis-aligned bounds of the referenced vertices. */
  const Eigen::Vector3f& boundsMin() const { return min_; }
  const Eigen::Vector3f& boundsMax() const { return max_; }
  /** \brief Area-weighted centroid of the surface. */
  const Eigen::Vector3f& surfaceCentroid() const { return centroid_; }
  /** \brief Number of faces with 3, 4 and more vertices. */
  std::size_t countFacesWithVertices(std::uint32_t count) const;

 private:
  FaceMesh() = default;
  void addFace(const std::vector<std::uint32_t>& polygon, const Eigen::Vector3f& normal,
               float area);
  void finish();

  std::vector<Eigen::Vector3f> vertices_;
  std::vector<Face> faces_;
  std::vector<std::uint32_t> indices_;
  FaceMeshReport report_;
  double total_area_ = 0.0;
  Eigen::Vector3f min_ = Eigen::Vector3f::Zero(), max_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f centroid_ = Eigen::Vector3f::Zero();
};

/** \brief Area-weighted random points on the surface with their face normals, for the base
 * Registration's target cloud and for coverage checks. Deterministic for a given seed. */
struct SurfaceSample {
  Eigen::Vector3f point;
  Eigen::Vector3f normal;
  std::uint32_t face;
};
std::vector<SurfaceSample> sampleSurface(const FaceMesh& mesh, std::size_t count,
                                         std::uint64_t seed);

}  // namespace icf
}  // namespace pcl
