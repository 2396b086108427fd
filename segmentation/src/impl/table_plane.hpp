/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): the body of table_plane.h's
 * templates, instantiated in src/table_plane.cpp for PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/console/print.h>
#include <pcl/icf/segmentation/table_plane.h>
#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_plane.h>
#include "segmentation_common.hpp"

#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace pcl::icf::segmentation::detail {

/** pcl::SampleConsensusModelPlane whose sample generator is seeded by the caller. The base
 * constructor seeds the protected boost::mt19937 `rng_alg_` with 12345 (or the clock); reseeding
 * it afterwards is enough because the variate generator holds it by reference. */
template <typename PointT>
class SeededPlaneModel : public pcl::SampleConsensusModelPlane<PointT> {
 public:
  SeededPlaneModel(const typename pcl::PointCloud<PointT>::ConstPtr& cloud, std::uint32_t seed)
      : pcl::SampleConsensusModelPlane<PointT>(cloud, false) {
    this->rng_alg_.seed(seed);
  }
};

/** pcl::RandomSampleConsensus that reports how many hypotheses it drew. */
template <typename PointT>
class CountingRansac : public pcl::RandomSampleConsensus<PointT> {
 public:
  using pcl::RandomSampleConsensus<PointT>::RandomSampleConsensus;

  int hypotheses() const { return this->iterations_; }
};

}  // namespace pcl::icf::segmentation::detail

template <typename PointT>
pcl::icf::segmentation::TablePlane pcl::icf::segmentation::findTablePlane(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
    const TablePlaneParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::findTablePlane");

  TablePlane result;
  auto usable = std::make_shared<pcl::Indices>(detail::finiteSubset(cloud, indices));
  if (usable->size() < 3 || !detail::spansPlane(cloud, *usable)) {
    PCL_DEBUG("[pcl::icf::segmentation::findTablePlane] %zu usable points do not span a plane\n",
              usable->size());
    return result;
  }

  auto model =
      std::make_shared<detail::SeededPlaneModel<PointT>>(detail::nonOwning(cloud), params.seed);
  model->setIndices(usable);
  detail::CountingRansac<PointT> ransac(model, params.distance_threshold);
  ransac.setMaxIterations(params.max_iterations);
  ransac.setProbability(params.probability);
  const bool ok = ransac.computeModel();
  result.iterations = ransac.hypotheses();
  if (!ok) {
    PCL_DEBUG("[pcl::icf::segmentation::findTablePlane] RANSAC found no plane among %zu points\n",
              usable->size());
    return result;
  }

  Eigen::VectorXf best;
  ransac.getModelCoefficients(best);
  if (best.size() != 4 || !best.allFinite() || !(best.head<3>().norm() > 0.0f))
    return result;
  Eigen::Vector4f plane = best.head<4>() / best.head<3>().norm();
  pcl::Indices inliers;
  ransac.getInliers(inliers);
  if (params.refine) {
    Eigen::Vector4f refined;
    if (detail::fitPlane(cloud, inliers, refined)) {
      plane = refined;
      inliers = planeInliers(cloud, *usable, plane, params.distance_threshold);
    }
  }

  result.coefficients =
      detail::orientTowards(plane, cloud.sensor_origin_.template head<3>().eval());
  result.inliers = std::move(inliers);
  result.status = result.inliers.size() >= params.min_inliers ? TablePlaneStatus::Found
                                                              : TablePlaneStatus::TooFewInliers;
  return result;
}

template <typename PointT>
pcl::icf::segmentation::TablePlane pcl::icf::segmentation::refineTablePlane(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, const TablePlane& plane,
    const TablePlaneParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::refineTablePlane");
  TablePlane result = plane;
  result.inliers.clear();
  if (plane.status == TablePlaneStatus::NoPlane)
    return result;
  result.inliers = planeInliers(cloud, indices, plane.coefficients, params.distance_threshold);
  Eigen::Vector4f refined;
  if (params.refine && detail::fitPlane(cloud, result.inliers, refined)) {
    result.coefficients =
        detail::orientTowards(refined, cloud.sensor_origin_.template head<3>().eval());
    result.inliers = planeInliers(cloud, indices, result.coefficients, params.distance_threshold);
  }
  return result;
}

template <typename PointT>
pcl::Indices pcl::icf::segmentation::planeInliers(const pcl::PointCloud<PointT>& cloud,
                                                  const pcl::Indices& indices,
                                                  const Eigen::Vector4f& coefficients,
                                                  double distance_threshold) {
  if (!(distance_threshold > 0.0) || !std::isfinite(distance_threshold)) {
    std::ostringstream msg;
    msg << "[pcl::icf::segmentation::planeInliers] distance_threshold = " << distance_threshold
        << " must be finite and > 0";
    throw std::invalid_argument(msg.str());
  }
  detail::requireIndicesInRange(cloud, indices, "segmentation::planeInliers");
  const Eigen::Vector3f n = coefficients.head<3>();
  const float d = coefficients[3];
  const auto threshold = static_cast<float>(distance_threshold);
  pcl::Indices out;
  out.reserve(indices.size());
  for (const pcl::index_t i : indices) {
    const auto& p = cloud[i];
    if (!pcl::isXYZFinite(p))
      continue;
    if (std::abs(n.dot(p.getVector3fMap()) + d) < threshold)
      out.push_back(i);
  }
  return out;
}

#define PCL_INSTANTIATE_IcfFindTablePlane(T)                                             \
  template pcl::icf::segmentation::TablePlane pcl::icf::segmentation::findTablePlane<T>( \
      const pcl::PointCloud<T>&, const pcl::Indices&,                                    \
      const pcl::icf::segmentation::TablePlaneParams&);
#define PCL_INSTANTIATE_IcfRefineTablePlane(T)                                                   \
  template pcl::icf::segmentation::TablePlane pcl::icf::segmentation::refineTablePlane<T>(       \
      const pcl::PointCloud<T>&, const pcl::Indices&, const pcl::icf::segmentation::TablePlane&, \
      const pcl::icf::segmentation::TablePlaneParams&);
#define PCL_INSTANTIATE_IcfPlaneInliers(T)                       \
  template pcl::Indices pcl::icf::segmentation::planeInliers<T>( \
      const pcl::PointCloud<T>&, const pcl::Indices&, const Eigen::Vector4f&, double);
