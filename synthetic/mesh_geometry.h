/**
 * \file mesh_geometry.h
 * \brief Small geometric helpers on pcl::PolygonMesh used by the synthetic scenes.
 *
 * Meshes store their vertices as pcl::PointXYZ in mesh.cloud (metres) and their faces as
 * pcl::Vertices (indices into the cloud), counter-clockwise seen from outside.
 */
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief A polygon as a list of vertex indices (pcl::index_t, as in pcl::Vertices). */
using Face = std::vector<pcl::index_t>;

/** \brief A triangle as three vertex indices. */
using Triangle = std::array<pcl::index_t, 3>;

/** \brief A mesh written by hand: \a vertices (metres) and \a faces, each a list of indices
 *  into \a vertices, kept as given (no check: tests feed broken meshes on purpose). */
pcl::PolygonMesh meshOf(const std::vector<Eigen::Vector3f>& vertices,
                        const std::vector<Face>& faces);

/** \brief Builds a mesh from vertex positions (metres) and faces (vertex indices).
 *  \throws std::invalid_argument if a face has fewer than 3 vertices or an index is out of range.
 */
pcl::PolygonMesh makeMesh(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Face>& faces);

/** \brief Vertex positions of a mesh (metres), read from its cloud (pcl::PointXYZ fields). */
std::vector<Eigen::Vector3d> meshVertices(const pcl::PolygonMesh& mesh);

/** \brief Splits every polygon into a triangle fan around its first vertex, keeping the winding.
 *  Faces with fewer than 3 indices are skipped. */
std::vector<Triangle> triangulateFaces(const pcl::PolygonMesh& mesh);

/** \brief Signed volume (m^3) by the divergence theorem; positive for a closed mesh with outward
 *  (counter-clockwise seen from outside) faces. */
double signedVolume(const pcl::PolygonMesh& mesh);

/** \brief Sum over faces of area * unit normal (m^2); the zero vector for a closed mesh. */
Eigen::Vector3d vectorArea(const pcl::PolygonMesh& mesh);

/** \brief Total surface area (m^2). */
double surfaceArea(const pcl::PolygonMesh& mesh);

/** \brief Axis-aligned bounding box of the vertices (metres); empty box for an empty mesh. */
Eigen::AlignedBox3d boundingBox(const pcl::PolygonMesh& mesh);

/** \brief Appends the vertices and faces of b to a (faces of b are re-indexed). */
void appendMesh(pcl::PolygonMesh& a, const pcl::PolygonMesh& b);

/** \brief Returns a copy of the mesh with every vertex transformed by pose. */
pcl::PolygonMesh transformMesh(const pcl::PolygonMesh& mesh, const Eigen::Isometry3d& pose);

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
