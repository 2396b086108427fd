/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/closest_face_query.h>
#include <pcl/icf/registration/distance_field.h>
#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/registration/point_pair_voting.h>

#include <memory>

namespace pcl {
namespace icf {

/** \brief Options for preparing a model. */
struct IcfModelParams {
  FaceMeshOptions mesh;       ///< unit scale and tolerances of the faces
  DistanceFieldParams field;  ///< the scoring field
  std::size_t surface_samples =
      4000;                ///< area-weighted samples (visibility, coverage, base target)
  std::uint64_t seed = 1;  ///< for the samples
  /** The table the scene's point pairs vote with (point_pair_voting.h); a calibration
   * constant of the localizer's whole-scene hypotheses. */
  PointPairModelParams point_pairs;
};

/** \brief A model ready for pose estimation: the faces, the exact index, the closest-point
 * field, surface samples with normals and the point pair table, built once and shared by every
 * cluster and thread.
 *
 * Building costs about a second for 100k faces (the field dominates); queries are const and
 * thread-safe. Non-copyable (the index refers to the faces); hold it by shared_ptr. */
class IcfModel {
 public:
  using Ptr = std::shared_ptr<IcfModel>;
  using ConstPtr = std::shared_ptr<const IcfModel>;

  /** \throws InvalidMeshError for a mesh that cannot be a model, std::invalid_argument for
   * absurd parameters. */
  static ConstPtr build(const pcl::PolygonMesh& mesh, const IcfModelParams& params = {});

  const FaceMesh& mesh() const { return *mesh_; }
  /** \brief Exact closest faces, each query bounded by the field first (FieldBoundedClosestFace).
   */
  const ClosestFaceQuery& index() const { return *index_; }
  const ClosestPointField& field() const { return *field_; }
  const std::vector<SurfaceSample>& samples() const { return samples_; }
  /** \brief The model's point pair table (whole-scene hypotheses, voteForPoses). */
  const PointPairModel& pointPairs() const { return point_pairs_; }
  /** \brief Radius of the bounding sphere about the surface centroid. */
  float radius() const { return radius_; }

  IcfModel(const IcfModel&) = delete;
  IcfModel& operator=(const IcfModel&) = delete;

 private:
  friend struct ModelFileAccess;
  IcfModel() = default;
  /** build, with the field and the table given (read from a prepared file) where not null. */
  static ConstPtr assemble(const pcl::PolygonMesh& mesh, const IcfModelParams& params,
                           std::unique_ptr<ClosestPointField> field,
                           std::unique_ptr<PointPairModel> pairs);
  std::unique_ptr<FaceMesh> mesh_;
  std::unique_ptr<ClosestFaceQuery> exact_index_;  // the BVH; the field is built from it
  std::unique_ptr<ClosestPointField> field_;
  std::unique_ptr<ClosestFaceQuery> index_;  // exact_index_ bounded by field_
  std::vector<SurfaceSample> samples_;
  PointPairModel point_pairs_;
  float radius_ = 0.f;
};

}  // namespace icf
}  // namespace pcl
