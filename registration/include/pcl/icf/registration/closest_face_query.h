/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/point_face_distance.h>

#include <limits>
#include <memory>

namespace pcl {
namespace icf {

/** \brief The closest face of a mesh to a query point (doc/icf.md eq. 3).
 *
 * \c face is -1 when no face lies within the query's radius; then the other fields are
 * meaningless and \c distance is +infinity. */
struct ClosestFace {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();  ///< closest point on the mesh (mesh frame)
  float distance = std::numeric_limits<float>::infinity();  ///< |query - point|, mesh units
  int face = -1;                                            ///< index into FaceMesh::faces()
  FaceFeature feature = FaceFeature::Interior;              ///< interior, edge or vertex
  int feature_index = -1;  ///< edge or vertex index within the face (see ClosestPointOnFace)

  bool found() const { return face >= 0; }
};

/** \brief Exact closest point on face \a f of \a mesh to \a p. */
ClosestPointOnFace<float> closestPointOnMeshFace(const FaceMesh& mesh, std::size_t f,
                                                 const Eigen::Vector3f& p);

/** \brief Unit direction along which the point-to-face residual is measured (doc/icf.md eq. 6):
 * the face normal, signed towards \a p, when the closest point is inside the face or \a p lies
 * on the surface; (p - c) / |p - c| on an edge or at a vertex. */
Eigen::Vector3f residualDirection(const FaceMesh& mesh, const Eigen::Vector3f& p,
                                  const ClosestFace& closest);

/** \brief Closest-face queries on one FaceMesh: a small interface with an exact brute-force
 * reference and an accelerated index behind it.
 *
 * Implementations keep a reference to the mesh: it must outlive them. Queries are const and
 * safe to run from several threads at once. */
class ClosestFaceQuery {
 public:
  using Ptr = std::shared_ptr<ClosestFaceQuery>;
  using ConstPtr = std::shared_ptr<const ClosestFaceQuery>;

  explicit ClosestFaceQuery(const FaceMesh& mesh) : mesh_(mesh) {}
  virtual ~ClosestFaceQuery() = default;
  ClosestFaceQuery(const ClosestFaceQuery&) = delete;
  ClosestFaceQuery& operator=(const ClosestFaceQuery&) = delete;

  /** \brief Exact closest face to \a p among faces within \a max_distance (mesh units); a
   * smaller radius makes the query faster. Ties go to the lowest face index in the brute
   * force; the index returns one of the tied faces with the same distance. */
  virtual ClosestFace closestFace(
      const Eigen::Vector3f& p,
      float max_distance = std::numeric_limits<float>::infinity()) const = 0;

  const FaceMesh& mesh() const { return mesh_; }

 protected:
  const FaceMesh& mesh_;
};

/** \brief Exact by exhaustion, like pcl::search::BruteForce: every face is measured, O(faces) a
 * query and no build. For meshes of a few dozen faces, and the reference an index is checked
 * against. */
class BruteForceClosestFace : public ClosestFaceQuery {
 public:
  using ClosestFaceQuery::ClosestFaceQuery;
  ClosestFace closestFace(
      const Eigen::Vector3f& p,
      float max_distance = std::numeric_limits<float>::infinity()) const override;
};

/** \brief Exact and accelerated: an Embree 3 BVH over the faces' bounding boxes, traversed by a
 * radius-bounded point query that shrinks its radius as closer faces are found, with our
 * closest-point-on-face in the callback. Same answers as BruteForceClosestFace (tested). Builds
 * in O(faces log faces); about 1-2 million queries per second and thread on 100k faces. */
class EmbreeClosestFaceIndex : public ClosestFaceQuery {
 public:
  /** \throws std::runtime_error when Embree cannot create its device or scene. */
  explicit EmbreeClosestFaceIndex(const FaceMesh& mesh);
  ~EmbreeClosestFaceIndex() override;

  ClosestFace closestFace(
      const Eigen::Vector3f& p,
      float max_distance = std::numeric_limits<float>::infinity()) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** \brief The default exact index for \a mesh (Embree). */
ClosestFaceQuery::Ptr makeClosestFaceIndex(const FaceMesh& mesh);

}  // namespace icf
}  // namespace pcl
