/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// pcl::IterativeClosestFace, a drop-in for pcl::IterativeClosestPoint with a mesh target
// (doc/icf.md section 8). In short:
// - align(out, guess), guess not the identity: refined from the guess, as ICP; hasConverged()
//   is ICP's (>= 3 points within the correspondence distance at the end).
// - align(out): the identity is refined first when the source already lies on the model and
//   kept if accepted; otherwise a global search, no guess needed. hasConverged() then means the
//   pose passed the acceptance test. setGuessPolicy(Always) is pure ICP.
// - The acceptance verdict and its measures are in getResult() either way.
#pragma once

#include <pcl/PolygonMesh.h>
#include <pcl/icf/registration/estimate_pose.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/rigid_transform.h>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>
#include <pcl/search/kdtree.h>

#include <limits>
#include <optional>
#include <string>

namespace pcl {
namespace icf {

/** \brief How many of \a points lie within \a radius of the model's surface after
 * \a scene_to_model (exact point-to-face distance, radius-bounded queries; OpenMP over
 * \a threads, 0: all cores). */
std::size_t countPointsNearSurface(const ClosestFaceQuery& index,
                                   const std::vector<Eigen::Vector3f>& points,
                                   const Eigen::Isometry3f& scene_to_model, float radius,
                                   int threads);

/** \brief The target search method of IterativeClosestFace: a pcl::search::KdTree over the
 * model's surface samples whose single-nearest-neighbour answer (k = 1) carries the exact
 * squared point-to-face distance to the model (doc/icf.md eq. 3) instead of the squared
 * distance to the returned sample. pcl::Registration::getFitnessScore is not virtual and asks
 * its target tree for one neighbour per source point, so through this tree the base's fitness
 * is point-to-face, also when called through a pcl::Registration pointer. The index returned
 * is the nearest sample's (-1 without a model); k > 1 and radius searches are the kd-tree's own.
 * Non-finite query points report +infinity. Queries are const and thread-safe; the model is
 * shared, not copied. */
template <typename PointT>
class MeshSurfaceSearch : public pcl::search::KdTree<PointT> {
 public:
  using Base = pcl::search::KdTree<PointT>;
  using Base::nearestKSearch;
  using typename Base::IndicesConstPtr;
  using typename Base::PointCloudConstPtr;

  /** \param model in the target (model) frame; null: every distance is +infinity. */
  explicit MeshSurfaceSearch(IcfModel::ConstPtr model) : model_(std::move(model)) {}

  /** \brief Builds the kd-tree over \a cloud (the surface samples); an empty cloud (no model
   * yet) is kept without a kd-tree, where PCL's would log an error. */
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override;

  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override;

 private:
  IcfModel::ConstPtr model_;
};

}  // namespace icf

/** \brief Iterative Closest Face: registers a scan (the source) to a polygon mesh (the target)
 * by exact point-to-face distance, as a drop-in for pcl::IterativeClosestPoint.
 *
 * **Guess policy** (setGuessPolicy; default GuessPolicy::IdentityRefinedFirst):
 * - align(output, guess) with a guess other than the identity refines from the guess only,
 *   like ICP;
 * - align(output) (PCL passes the identity) first refines from the identity, as ICP would, when
 *   the source already lies on the model (at least min_inliers points within the
 *   correspondence distance); when that pose passes the acceptance test it is the answer (a
 *   pre-aligned source stays put, method "identity+icf"). Otherwise the global search runs
 *   (doc/icf.md sections 4-7: no initial guess needed).
 * - GuessPolicy::Always: every call refines from its guess (pure ICP); Never: always search;
 *   IdentityMeansNone: an identity guess searches at once.
 *
 * **hasConverged()**: after a refinement from a guess (method "guess+icf"), ICP's meaning: the
 * refinement ended (by a criterion or at setMaximumIterations, as ICP's default) with at least
 * min_number_correspondences_ (3, PCL's) source points within the correspondence distance of
 * the mesh. After a global search ("fast+icf", "thesis+icf", "sac+icf") or the identity-first
 * attempt ("identity+icf"): the pose passed the acceptance test (enough of the model's
 * camera-facing surface covered, icf::AcceptanceParams) — a searched pose is only worth
 * something when it is verified. In every case the acceptance verdict is getResult().status
 * (Accepted / Rejected) and its measures (coverage of the visible surface, the confidence;
 * inliers, RMSE) are getResult().quality.
 *
 * The rest follows ICP where the APIs overlap (table in doc/icf.md section 8):
 * - getFinalTransformation() maps the source into the model frame (PCL's source -> target);
 *   getObjectPose() is its inverse, the model's pose in the scene.
 * - align's output is the whole source (NaN points included, as ICP) moved by the final
 *   transformation; normals, where the point type has them, are rotated.
 * - getFitnessScore(max_range): the mean squared *point-to-face* distance of the source points
 *   moved by the final transformation, over the points counted by PCL's rule (squared distance
 *   <= max_range; PCL compares the squared distance with max_range); NaN points are not
 *   counted; no point counted gives std::numeric_limits<double>::max(), PCL's value. Through a
 *   Registration pointer the base's function computes it via MeshSurfaceSearch (do not replace
 *   the target search method with setSearchMethodTarget, or it becomes point-to-sample).
 * - setMaxCorrespondenceDistance(d): the refinement's first search radius and Tukey radius
 *   (RefinementParams::initial_inlier_distance = d; the final radius is min(d,
 *   final_inlier_distance)); default 2 cm, not ICP's unbounded default.
 * - setMaximumIterations, setTransformationEpsilon (squared translation of a step),
 *   setTransformationRotationEpsilon (cosine of a step's angle; 0: 1 - transformation epsilon,
 *   ICP's rule), setEuclideanFitnessEpsilon (relative change of the mean squared residual, as
 *   ICP; negative: off) are the refinement's. They and setParams() share one store: the base
 *   setters write icf::IcfParams::refinement's fields, setParams() writes the base's members,
 *   getParams() reads both; the last call wins.
 * - registerVisualizationCallback is called after each refinement iteration with the source
 *   in the model frame (PCL's base calls it once at registration: set source and target first).
 *
 * **Bad input**: a point cloud as the target (also through a Registration pointer, where
 * setInputTarget is virtual): std::invalid_argument. A guess with a NaN or infinite entry or
 * that is not a rigid motion: std::invalid_argument from align. getFitnessScore(max_range)
 * with max_range <= 0 or NaN: std::invalid_argument (through a Registration pointer PCL's
 * non-virtual function runs: no point counted, std::numeric_limits<double>::max()). Nonsense
 * parameters (base setters included, e.g. setMaxCorrespondenceDistance(-1)):
 * std::invalid_argument from align naming the field and value. No mesh: align returns with
 * status NoModel, hasConverged() false, the output the unmoved source. An empty or all-NaN
 * source: status TooFewPoints, hasConverged() false.
 *
 * \code
 * pcl::IterativeClosestFace<pcl::PointNormal> icf;
 * icf.setInputTarget(mesh);        // pcl::PolygonMesh::ConstPtr, scene units
 * pcl::Registration<pcl::PointNormal, pcl::PointNormal>::Ptr reg = ...;  // ICP or ICF
 * reg->setInputSource(cluster);
 * reg->setMaxCorrespondenceDistance(0.02);
 * pcl::PointCloud<pcl::PointNormal> aligned;
 * reg->align(aligned, guess);      // or align(aligned): ICF searches when needed
 * if (reg->hasConverged())
 *   std::cout << reg->getFitnessScore() << "\n";  // mean squared point-to-face distance
 * \endcode
 *
 * The target point type is PointSource: PCL 1.13's Registration::initCompute does not compile
 * when the source and target types differ. The base's target cloud holds the mesh's surface
 * samples (xyz and, where the type has them, normals). Not thread-safe as an object (like
 * every PCL Registration); the work inside align runs on setNumberOfThreads threads with
 * results independent of the count. */
template <typename PointSource, typename Scalar = float>
class IterativeClosestFace : public Registration<PointSource, PointSource, Scalar> {
 public:
  using Base = Registration<PointSource, PointSource, Scalar>;
  using typename Base::Matrix4;
  using typename Base::PointCloudSource;
  using typename Base::PointCloudTargetConstPtr;
  using Ptr = shared_ptr<IterativeClosestFace<PointSource, Scalar>>;
  using ConstPtr = shared_ptr<const IterativeClosestFace<PointSource, Scalar>>;

  /** \brief How the guess passed to align is used (see the class comment). */
  enum class GuessPolicy {
    IdentityRefinedFirst,  ///< default: an identity guess is refined first, searched if rejected
    IdentityMeansNone,     ///< an identity guess runs the global search at once
    Always,                ///< always refine from the guess, never search (ICP)
    Never,                 ///< always search, ignore the guess
  };

  IterativeClosestFace();
  ~IterativeClosestFace() override = default;

  /** \brief The CAD model, in scene units (see icf::FaceMeshOptions::scale for millimetre
   * files). Builds the model (faces, exact index, field, samples) and fills the base class's
   * target cloud with its surface samples. \throws icf::InvalidMeshError for a mesh that
   * cannot be a model, std::invalid_argument for a null pointer. */
  void setInputTarget(const pcl::PolygonMesh::ConstPtr& mesh);

  /** \brief Use a model that is already built (shared between several registrations). */
  void setInputModel(const icf::IcfModel::ConstPtr& model);

  /** \brief A point cloud is not a mesh target. \throws std::invalid_argument always. */
  void setInputTarget(const PointCloudTargetConstPtr& cloud) override;

  /** \brief Options used by the next setInputTarget(mesh). */
  void setModelParams(const icf::IcfModelParams& params) { model_params_ = params; }
  /** \brief All algorithm parameters (search, refinement, acceptance). Validated at align.
   * Also sets the base's iteration count, epsilons and correspondence distance from
   * params.refinement (see the class comment). */
  void setParams(const icf::IcfParams& params);
  /** \brief The parameters align will use: the stored ones with the refinement's iteration
   * count, epsilons and radii taken from the base's members. */
  icf::IcfParams getParams() const;

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
  GuessPolicy getGuessPolicy() const { return guess_policy_; }

  /** \brief The camera's pose in the source frame (camera -> source, as
   * LocalizerParams::camera_pose is camera -> scene); its position decides which side of the
   * model is visible. By default the source's sensor_origin_ / sensor_orientation_.
   * \throws std::invalid_argument when it is not a finite rigid motion. */
  void setCameraPose(const Eigen::Isometry3f& camera_to_source);
  /** \brief The camera's position only (orientation: identity). */
  void setCameraOrigin(const Eigen::Vector3f& origin);
  /** \brief Back to the default: the source's sensor_origin_ / sensor_orientation_. */
  void resetCameraPose() { camera_pose_.reset(); }
  /** \brief The pose align uses: the one set, else the current source's sensor pose (the
   * identity without a source). \throws std::invalid_argument for a non-unit sensor
   * quaternion. */
  Eigen::Isometry3f getCameraPose() const;

  /** \brief Mean squared point-to-face distance of the source moved by the final
   * transformation, over the points whose squared distance is <= \a max_range (PCL's rule);
   * std::numeric_limits<double>::max() when none is. \throws std::invalid_argument when
   * max_range is not positive or there is no source. */
  double getFitnessScore(double max_range = std::numeric_limits<double>::max());
  using Base::getFitnessScore;

  const icf::IcfModel::ConstPtr& getModel() const { return model_; }
  /** \brief Scores, status (the acceptance verdict), method and timing of the last align. */
  const icf::IcfResult& getResult() const { return result_; }
  /** \brief The model's pose in the scene: the inverse of getFinalTransformation(). */
  Eigen::Matrix4f getObjectPose() const { return result_.object_pose; }
  /** \brief Points of the last align's source within its correspondence distance of the mesh
   * at the final pose (0 when no pose was estimated). Counted at align after a guess (it
   * decides hasConverged()), else on the first call. */
  std::size_t getCorrespondenceCount() const;

 protected:
  void computeTransformation(PointCloudSource& output, const Matrix4& guess) override;

  using Base::converged_;
  using Base::corr_dist_threshold_;
  using Base::euclidean_fitness_epsilon_;
  using Base::final_transformation_;
  using Base::indices_;
  using Base::input_;
  using Base::max_iterations_;
  using Base::min_number_correspondences_;
  using Base::nr_iterations_;
  using Base::previous_transformation_;
  using Base::reg_name_;
  using Base::target_;
  using Base::target_cloud_updated_;
  using Base::transformation_;
  using Base::transformation_epsilon_;
  using Base::transformation_rotation_epsilon_;
  using Base::update_visualizer_;

 private:
  /** The finite points of \a cloud (at indices_ when it is the current source), in order. */
  std::vector<Eigen::Vector3f> finitePoints(const PointCloudSource& cloud) const;

  icf::IcfModelParams model_params_;
  icf::IcfParams params_;
  icf::IcfModel::ConstPtr model_;
  icf::IcfResult result_;
  GuessPolicy guess_policy_ = GuessPolicy::IdentityRefinedFirst;
  std::optional<Eigen::Isometry3f> camera_pose_;
  mutable std::optional<std::size_t> correspondences_;
  typename PointCloudSource::ConstPtr aligned_source_;  ///< the last align's source
  float aligned_radius_ = 0.f;                          ///< and its correspondence distance
};

}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl/icf/registration/impl/iterative_closest_face.hpp>
#endif
