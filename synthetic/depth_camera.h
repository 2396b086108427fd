/**
 * \file depth_camera.h
 * \brief A pinhole depth-camera simulator (Kinect-like) producing synthetic scans with ground
 * truth.
 *
 * Camera frame: x right, y down, z forward (optical axis), metres, origin at the optical centre.
 * Pixel (u, v) (column, row; integer coordinates are pixel centres) sees the ray
 * d = ((u - cx) / fx, (v - cy) / fy, 1); the depth of a hit is its z coordinate.
 * All randomness comes from std::mt19937_64 seeded explicitly: the same inputs and seed give
 * bit-identical output (with the same standard library).
 */
#pragma once

#include "synthetic/synthetic_models.h"

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace synthetic {

/** \brief Pinhole intrinsics in pixels (defaults: a 640 x 480 Kinect-like camera). */
struct CameraIntrinsics {
  int width = 640;    ///< image width, pixels
  int height = 480;   ///< image height, pixels
  double fx = 525.0;  ///< focal length along x, pixels
  double fy = 525.0;  ///< focal length along y, pixels
  double cx = 319.5;  ///< principal point x, pixels
  double cy = 239.5;  ///< principal point y, pixels
};

/** \brief A mesh placed in the camera frame. The mesh is not owned and must outlive the render. */
struct SceneObject {
  const pcl::PolygonMesh* mesh = nullptr;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< model -> camera frame (metres)
  Eigen::Vector3f rgb = Eigen::Vector3f::Ones();           ///< flat colour, channels in [0, 1]
  int label = 0;                                           ///< copied into Scan::labels
};

/** \brief Depth noise model.
 *
 * Every valid pixel's point is moved along its viewing ray by a Gaussian offset with standard
 * deviation sigma = sigma_at_1m * z^2 (z = true depth in metres), truncated at +-4 sigma
 * (resampled), so that every point is within 4 sigma + outlier_range of the true surface.
 * Each valid pixel independently becomes an outlier with probability outlier_ratio (so the expected
 * fraction of outliers is outlier_ratio) and then gets an additional offset along the ray, uniform
 * in [-outlier_range, +outlier_range]. Pixels are processed in row-major order with one
 * std::mt19937_64 seeded with seed.
 */
struct ScanNoise {
  double sigma_at_1m = 0.0015;  ///< metres at 1 m depth; grows with depth^2
  double outlier_ratio = 0.05;  ///< probability in [0, 1] that a valid pixel is an outlier
  double outlier_range = 0.05;  ///< metres along the ray, uniform +-
  /** Structured-light quantisation (Kinect v1, Asus Xtion): the sensor measures the disparity
   * d = focal_baseline / z in steps of disparity_step pixels, so the noisy depth is rounded to
   * focal_baseline / (d rounded to a step): steps of z^2 disparity_step / focal_baseline
   * metres, 2.9 mm at 1 m and 7.5 mm at 1.6 m for a Kinect v1 (focal_baseline 0 turns it
   * off). */
  double focal_baseline = 0.0;    ///< pixels x metres (Kinect v1: 580 px x 0.075 m)
  double disparity_step = 0.125;  ///< pixels (Kinect v1: 1/8)
  std::uint64_t seed = 1;         ///< random seed

  /** \brief No noise and no outliers (exact ray-cast depths). */
  static ScanNoise none();
  /** \brief A Kinect v1 or Xtion (PrimeSense structured light): disparity quantised in 1/8
   * pixel steps of a 580 px x 7.5 cm baseline, Gaussian disparity noise of 1 mm at 1 m
   * (growing with z^2) before it, 2% outliers within +-5 cm: together about 1.4 mm at 1 m, as
   * Khoshelham and Elberink (2012) measure for the Kinect v1. */
  static ScanNoise structuredLight();
};

/** \brief A rendered scan. */
struct Scan {
  /** Organized width x height cloud in the camera frame (metres); x = y = z = NaN and rgb = 0 where
   *  no surface was hit; is_dense = false; sensor origin 0, orientation identity. */
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud;
  /** Per pixel, row-major (index v * width + u): -1 where nothing was hit, else the
   *  SceneObject::label of the nearest hit object. */
  std::vector<int> labels;
};

/** \brief Ray-casts every pixel against every face of every object and keeps the nearest hit.
 *
 * Polygons are triangulated as fans; hits are two-sided (Moeller-Trumbore). Objects entirely
 * behind the camera or outside the image (bounding sphere / projected bounding box) are skipped
 * and each triangle is only tested against the pixels in its projected bounding box.
 * \throws std::invalid_argument for non-positive image size or focal lengths, a null mesh, or
 * invalid noise parameters.
 */
Scan renderScan(const std::vector<SceneObject>& objects, const CameraIntrinsics& intrinsics,
                const ScanNoise& noise);

/** \brief Renders a single mesh alone and returns its visible points (the "cluster") as an
 *  unorganized, dense cloud in the camera frame (metres), in row-major pixel order.
 *  Same noise model and determinism as renderScan. */
pcl::PointCloud<pcl::PointXYZ>::Ptr renderCluster(const pcl::PolygonMesh& mesh,
                                                  const Eigen::Isometry3d& model_to_camera,
                                                  const CameraIntrinsics& intrinsics,
                                                  const ScanNoise& noise);

/** \brief The scan's cloud as points, one per pixel, row-major (NaN where nothing was hit). */
std::vector<Eigen::Vector3f> scanPoints(const Scan& scan);

/** \brief The points of a scan whose pixel label equals label, as an unorganized dense cloud. */
pcl::PointCloud<pcl::PointXYZ>::Ptr extractLabelCloud(const Scan& scan, int label);

/** \brief A rotation uniformly distributed on SO(3) (normalised 4D Gaussian quaternion). */
Eigen::Matrix3d randomRotation(std::mt19937_64& rng);

/** \brief A uniformly random rotation with a position in front of the camera:
 *  x, y uniform in [-0.15, 0.15] m and z uniform in [distance_min, distance_max] m. */
Eigen::Isometry3d randomTabletopPose(std::mt19937_64& rng, double distance_min = 0.7,
                                     double distance_max = 1.1);

/** \brief A model alone at a seeded random pose, and its noisy view. */
struct RandomView {
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();  ///< model -> camera (metres)
  pcl::PointCloud<pcl::PointXYZ>::Ptr cluster;              ///< renderCluster's points
};

/** \brief randomTabletopPose from std::mt19937_64(seed) and renderCluster with the default
 *  camera and noise (ScanNoise::seed = seed), drawn again while fewer than min_points show
 *  (a thin box seen edge-on). Same seed, same view. */
RandomView randomView(const pcl::PolygonMesh& mesh, std::uint64_t seed,
                      std::size_t min_points = 200);

/** \brief A synthetic table-top scene with ground truth. */
struct TabletopScene {
  Scan scan;                             ///< labels: 0 table, i + 1 for objects[i], -1 background
  std::vector<Eigen::Isometry3d> poses;  ///< model -> camera per object (metres)
  std::vector<std::string> names;        ///< SyntheticModel::name per object
  /** Table plane (a, b, c, d) in the camera frame: a x + b y + c z + d = 0 with (a, b, c) a unit
   *  normal pointing up, towards the camera (so d = camera height above the table > 0). */
  Eigen::Vector4f table_plane = Eigen::Vector4f::Zero();
  /** Table frame -> camera frame. Table frame: z up, surface z = 0, centred on the table. */
  Eigen::Isometry3d table_to_camera = Eigen::Isometry3d::Identity();
};

/** \brief Model -> table frame of a mesh standing upright at (x, y) = xy_yaw.head<2>() (metres),
 *  turned by yaw xy_yaw.z() (radians) about the table normal, its lowest vertex on the surface
 *  (as makeTabletopScene places its objects). */
Eigen::Isometry3d standOnTable(const pcl::PolygonMesh& mesh, const Eigen::Vector3d& xy_yaw);

/** \brief Table frame -> camera frame of the table-top camera: \a camera_height (m) above the
 *  table, looking at the table centre with its optical axis tilted \a camera_tilt_deg below the
 *  horizontal, the image x axis along the table's x axis (as makeTabletopScene places it).
 *  \throws std::invalid_argument if the height is not positive or the tilt is not in (0, 90]. */
Eigen::Isometry3d tableToCamera(double camera_height, double camera_tilt_deg);

/** \brief Share of \a object's pixels inside the image, rendered alone without noise, that
 *  carry \a label in \a scene, in [0, 1]: occlusion counted, the part beyond the image's
 *  border not (an unoccluded object half out of the frame gives 1). Times inViewShare: the
 *  visible share of the whole object. */
double visibleShare(const Scan& scene, int label, const SceneObject& object,
                    const CameraIntrinsics& intrinsics);

/** \brief Share of \a object's projection, rendered alone, that falls inside the image, in
 *  [0, 1]: its pixels in the image over its pixels in the image widened by \a pad pixels on
 *  every side (same focal length and rays). 1 for an object wholly in view; 0 when none of it
 *  projects into either. The default pad holds an object three image widths across.
 *  \throws std::invalid_argument if \a pad is negative. */
double inViewShare(const SceneObject& object, const CameraIntrinsics& intrinsics, int pad = 640);

/** \brief What a Kinect v1 does at depth edges, beyond ScanNoise. A pixel is on an edge when a
 *  4-neighbour's depth differs by more than edge_step; there its depth is lost with probability
 *  dropout (NaN, the sensor's holes along silhouettes), else with probability flying it is a
 *  flying pixel: moved along its ray to a uniform point between its own depth and the
 *  neighbour's (the two surfaces' returns mixed). Pixels off edges are not touched. */
struct EdgeArtefacts {
  double edge_step = 0.03;  ///< metres
  double dropout = 0.5;     ///< probability in [0, 1]
  double flying = 0.3;      ///< probability in [0, 1], of the pixels not dropped
  std::uint64_t seed = 1;   ///< random seed (pixels in row-major order)
};

/** \brief Applies \a artefacts to \a scan's cloud (labels unchanged: the render's truth).
 *  Edges are found on the cloud as it is (after ScanNoise). Same scan and seed, same output. */
void addEdgeArtefacts(Scan& scan, const EdgeArtefacts& artefacts);

/** \brief Renders objects standing upright on a 1.2 x 0.8 m table.
 *
 * The table lies in the z = 0 plane of the table frame (x along its 1.2 m side). The camera is
 * at height camera_height (m) above the table, looking at the table centre with its optical axis
 * tilted camera_tilt_deg below the horizontal (90 = straight down), the image x axis parallel to
 * the table's x axis. Object i stands at (x, y) = table_xy_yaw[i].head<2>() (metres, table frame),
 * turned by yaw table_xy_yaw[i].z() (radians) about the table normal, with its lowest vertex on the
 * table surface (model z axis = table normal).
 * \throws std::invalid_argument if the sizes of objects and table_xy_yaw differ, the height is not
 * positive or the tilt is not in (0, 90].
 */
TabletopScene makeTabletopScene(const std::vector<SyntheticModel>& objects,
                                const std::vector<Eigen::Vector3d>& table_xy_yaw,
                                const CameraIntrinsics& intrinsics, const ScanNoise& noise,
                                double camera_height = 0.6, double camera_tilt_deg = 45.0);

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
