/**
 * \file pose_error.h
 * \brief Symmetry-aware pose error metrics for synthetic ground-truth tests.
 *
 * Units: translations and distances in metres, angles in degrees unless stated.
 * A pose "model_to_scene" maps model-frame coordinates to scene (camera) coordinates:
 * x_scene = pose * x_model.
 */
#pragma once

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief Rotational self-symmetry of a model, expressed in the model frame.
 *
 * All symmetries are rotations about the model origin (the centre of the model's bounding box
 * for the synthetic models), so they never change the position of the model origin.
 */
struct Symmetry {
  enum class Kind {
    None,      ///< no symmetry: the pose is unique
    Discrete,  ///< a finite rotation group, see group
    Axial      ///< continuous rotation about axis (a body of revolution)
  };

  Kind kind = Kind::None;

  /** \brief For Kind::Discrete: all rotations S (identity included) with model(S x) == model(x).
   *  The set is a group, so it is closed under inversion and composition. */
  std::vector<Eigen::Matrix3d> group;

  /** \brief For Kind::Axial: the symmetry axis in the model frame (unit length). */
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();

  /** \brief For Kind::Axial: true if the model is also symmetric under a 180-degree turn about an
   *  axis perpendicular to axis (a closed straight cylinder); false for e.g. a cone or a cup. */
  bool axial_flip = true;

  /** \brief No symmetry. */
  static Symmetry none();

  /** \brief Symmetry group of an axis-aligned box with side lengths sx, sy, sz (metres).
   *
   * All proper rotations that permute the coordinate axes (with signs) and map the box onto itself:
   * 4 elements {I, Rx(180), Ry(180), Rz(180)} for three distinct sides, 8 when two sides are equal
   * (a square prism), 24 for a cube. Sides are compared with a relative tolerance of 1e-9.
   */
  static Symmetry box(double sx, double sy, double sz);

  /** \brief Symmetry group of a right regular n-gonal prism about z, centred at the origin, with a
   *  vertex on the +x axis: the n rotations Rz(2 pi k / n) times {I, Rx(180)} (2n elements).
   *  \throws std::invalid_argument if n < 1. */
  static Symmetry prism(int n);

  /** \brief Continuous symmetry about z; flip = true for a closed straight cylinder. */
  static Symmetry cylinder(bool flip = true);
};

/** \brief Error of an estimated pose with respect to the ground truth. */
struct PoseError {
  double translation = 0.0;   ///< metres: distance between the estimated and true model origins
  double rotation_deg = 0.0;  ///< degrees in [0, 180]: symmetry-aware rotation error
};

/** \brief Geodesic angle (degrees, in [0, 180]) of a rotation matrix, numerically stable near 0
 *  and near 180 degrees (computed from the quaternion as 2 atan2(|v|, |w|)). */
double rotationAngleDeg(const Eigen::Matrix3d& rotation);

/** \brief Angle in degrees ([0, 180]) between two (not necessarily unit) vectors. */
double angleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/** \brief Symmetry-aware pose error.
 *
 * - None: angle of R_true^T R_est.
 * - Discrete: min over S in symmetry.group of the angle of R_true^T R_est S. An estimate
 *   est = truth * S (i.e. R_est = R_true S for some S in the group) gives 0, because S^-1 is in the
 *   group as well.
 * - Axial: angle between the estimated and the true symmetry axis in the scene frame
 *   (R_est a vs R_true a); with axial_flip the result is min(angle, 180 - angle). Rotation about
 * the axis is ignored.
 *
 * \param[in] estimated_model_to_scene estimated pose (model -> scene)
 * \param[in] true_model_to_scene ground-truth pose (model -> scene)
 * \param[in] symmetry the model's symmetry in the model frame
 */
PoseError poseError(const Eigen::Isometry3d& estimated_model_to_scene,
                    const Eigen::Isometry3d& true_model_to_scene, const Symmetry& symmetry);

/** \brief ADD-S (average closest-point distance), in metres.
 *
 * Mean over all mesh vertices v of min_w |truth * v - est * w| with w ranging over the mesh
 * vertices. Uses a brute-force O(N^2) search, which is fine for the small synthetic meshes (a few
 * hundred vertices) and avoids a dependency on pcl_kdtree. Duplicate vertices (unshared faces) are
 * counted as they are stored. Returns 0 for an empty mesh.
 */
double addS(const pcl::PolygonMesh& mesh, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth);

/** \brief Largest distance between two vertices of the mesh, in metres (brute force O(N^2)). */
double modelDiameter(const pcl::PolygonMesh& mesh);

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
