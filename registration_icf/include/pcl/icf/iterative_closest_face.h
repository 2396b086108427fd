/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/icf/estimate_pose.h>
#include <pcl/icf/icf_model.h>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>

namespace pcl {

/** \brief Iterative Closest Face: registers a scene cluster (the source) to a polygon mesh (the
 * target) without an initial guess, by point-to-face distance (doc/icf.md; the method of
 * Valentina Armenise's 2013 KTH master's thesis, supervised by Renaud Detry, made fast).
 *
 * A pcl::Registration<PointSource, PointSource>, so it stands beside
 * pcl::IterativeClosestPoint<PointSource, PointSource> behind the same pcl::Registration::Ptr.
 * (The target point type is PointSource, not PointXYZ: PCL 1.13's Registration::initCompute
 * does not compile when the source and target types differ, because
 * CorrespondenceEstimationBase types its reciprocal kd-tree on the target. The base's target
 * cloud holds the mesh's surface samples, xyz and, where the type has them, normals.)
 * getFinalTransformation() maps the source into the model frame, as PCL defines registration;
 * getObjectPose() is its inverse, the model's pose in the scene, which is usually what a grasp
 * planner wants.
 *
 * - align(output): global search (setSearchStrategy: fast by default, or the thesis's), then
 *   refinement by iterative closest face. align(output, guess) with a guess other than the
 *   identity refines from the guess only (align(output) passes the identity, so the identity
 *   means "no guess" unless setGuessPolicy says otherwise).
 * - hasConverged() is true only when the pose passes the acceptance test (getResult().status
 *   == Accepted: enough of the model's camera-facing surface is covered by the scan, see
 *   icf::AcceptanceParams), never merely because the iterations ran out.
 * - getFitnessScore() is the base class's: mean squared distance from the source to the
 *   nearest *surface sample* of the mesh (the base's target cloud, area-weighted samples). The
 *   point-to-face measures are in getResult().quality.
 * - setMaximumIterations, setTransformationEpsilon (squared translation of a step),
 *   setTransformationRotationEpsilon (cosine of a step's angle) and
 *   setEuclideanFitnessEpsilon drive the refinement; registerVisualizationCallback is called
 *   after each refinement iteration with the source in the model frame (PCL's base calls it
 *   once at registration with the source and target: set both before registering it).
 * - NaN points of organized clouds are skipped. An empty or all-NaN source gives status
 *   TooFewPoints; no mesh gives NoModel (and PCL's own error from initCompute).
 *
 * \code
 * pcl::IterativeClosestFace<pcl::PointXYZ> icf;
 * icf.setInputTarget(mesh);        // pcl::PolygonMesh::ConstPtr, scene units
 * icf.setInputSource(cluster);
 * pcl::PointCloud<pcl::PointXYZ> aligned;
 * icf.align(aligned);
 * if (icf.hasConverged())
 *   std::cout << icf.getObjectPose() << "\n";
 * \endcode
 *
 * Not thread-safe as an object (like every PCL Registration); the work inside align runs on
 * setNumberOfThreads threads with results independent of the count. */
template <typename PointSource, typename Scalar = float>
class IterativeClosestFace : public Registration<PointSource, PointSource, Scalar> {
 public:
  using Base = Registration<PointSource, PointSource, Scalar>;
  using typename Base::Matrix4;
  using typename Base::PointCloudSource;
  using typename Base::PointCloudTargetConstPtr;
  using Ptr = shared_ptr<IterativeClosestFace<PointSource, Scalar>>;
  using ConstPtr = shared_ptr<const IterativeClosestFace<PointSource, Scalar>>;

  /** \brief How the guess passed to align is used. */
  enum class GuessPolicy {
    IdentityMeansNone,  ///< default: an identity guess runs the global search
    Always,             ///< always refine from the guess, never search
    Never,              ///< always search, ignore the guess
  };

  IterativeClosestFace();
  ~IterativeClosestFace() override = default;

  /** \brief The CAD model, in scene units (see icf::FaceMeshOptions::scale for millimetre
   * files). Builds the model (faces, exact index, field, samples) and fills the base class's
   * target cloud with its surface samples. \throws icf::InvalidMeshError for a mesh that
   * cannot be a model. */
  void setInputTarget(const pcl::PolygonMesh::ConstPtr& mesh);

  /** \brief Use a model that is already built (shared between several registrations). */
  void setInputModel(const icf::IcfModel::ConstPtr& model);

  /** \brief A point cloud is not a mesh target. \throws std::invalid_argument always. */
  void setInputTarget(const PointCloudTargetConstPtr& cloud) override;

  /** \brief Options used by the next setInputTarget(mesh). */
  void setModelParams(const icf::IcfModelParams& params) { model_params_ = params; }
  /** \brief All algorithm parameters (search, refinement, acceptance). Validated at align. */
  void setParams(const icf::IcfParams& params) { params_ = params; }
  const icf::IcfParams& getParams() const { return params_; }

  void setSearchStrategy(icf::SearchStrategy s) { params_.strategy = s; }
  /** \brief Threads for the search and refinement (0: all cores). */
  void setNumberOfThreads(int threads) {
    if (threads < 0)
      throw std::invalid_argument(
          "IterativeClosestFace::setNumberOfThreads: " + std::to_string(threads) + " < 0");
    params_.threads = threads;
  }
  void setSeed(std::uint64_t seed) { params_.seed = seed; }
  void setGuessPolicy(GuessPolicy policy) { guess_policy_ = policy; }
  /** \brief Camera position in the source frame; by default the source's sensor_origin_. */
  void setCameraOrigin(const Eigen::Vector3f& origin) {
    camera_ = origin;
    camera_set_ = true;
  }

  const icf::IcfModel::ConstPtr& getModel() const { return model_; }
  /** \brief Scores, status and timing of the last align. */
  const icf::IcfResult& getResult() const { return result_; }
  /** \brief The model's pose in the scene: the inverse of getFinalTransformation(). */
  Eigen::Matrix4f getObjectPose() const { return result_.object_pose; }

 protected:
  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override;

  using Base::converged_;
  using Base::euclidean_fitness_epsilon_;
  using Base::final_transformation_;
  using Base::indices_;
  using Base::input_;
  using Base::max_iterations_;
  using Base::nr_iterations_;
  using Base::previous_transformation_;
  using Base::reg_name_;
  using Base::target_;
  using Base::transformation_;
  using Base::transformation_epsilon_;
  using Base::transformation_rotation_epsilon_;
  using Base::update_visualizer_;

 private:
  icf::IcfModelParams model_params_;
  icf::IcfParams params_;
  icf::IcfModel::ConstPtr model_;
  icf::IcfResult result_;
  GuessPolicy guess_policy_ = GuessPolicy::IdentityMeansNone;
  Eigen::Vector3f camera_ = Eigen::Vector3f::Zero();
  bool camera_set_ = false;
};

}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl/icf/impl/iterative_closest_face.hpp>
#endif
