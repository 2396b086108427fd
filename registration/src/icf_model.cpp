/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/icf_model.h>

#include <pcl/icf/registration/field_bounded_closest_face.h>

namespace pcl {
namespace icf {

IcfModel::ConstPtr IcfModel::build(const pcl::PolygonMesh& mesh, const IcfModelParams& params) {
  return assemble(mesh, params, nullptr, nullptr);
}

IcfModel::ConstPtr IcfModel::assemble(const pcl::PolygonMesh& mesh, const IcfModelParams& params,
                                      std::unique_ptr<ClosestPointField> field,
                                      std::unique_ptr<PointPairModel> pairs) {
  params.field.validate();
  params.point_pairs.validate();
  if (params.surface_samples < 100 || params.surface_samples > 10000000)
    throw std::invalid_argument(
        "IcfModelParams::surface_samples = " + std::to_string(params.surface_samples) +
        ": must lie in [100, 1e7]");
  std::shared_ptr<IcfModel> model(new IcfModel());
  model->mesh_ = std::make_unique<FaceMesh>(FaceMesh::build(mesh, params.mesh));
  model->exact_index_ = std::make_unique<EmbreeClosestFaceIndex>(*model->mesh_);
  model->field_ = field ? std::move(field)
                        : std::make_unique<ClosestPointField>(*model->exact_index_, params.field);
  model->index_ = std::make_unique<FieldBoundedClosestFace>(*model->exact_index_, *model->field_);
  model->samples_ = sampleSurface(*model->mesh_, params.surface_samples, params.seed);
  model->point_pairs_ =
      pairs ? std::move(*pairs) : PointPairModel::build(*model->mesh_, params.point_pairs);
  const Eigen::Vector3f& c = model->mesh_->surfaceCentroid();
  for (const Eigen::Vector3f& v : model->mesh_->vertices())
    if (v.allFinite())
      model->radius_ = std::max(model->radius_, (v - c).norm());
  return model;
}

}  // namespace icf
}  // namespace pcl
