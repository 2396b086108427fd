/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The scene as the camera saw it: a depth image with its pinhole intrinsics, built from
 * an organized cloud (its own pixel grid, the intrinsics fitted to its points) or from any
 * cloud projected through given or virtual intrinsics. The verification (depth_verification.h)
 * compares a posed model with it pixel by pixel.
 *
 * Frames: points are in the camera's frame (x right, y down, z forward, PCL's and every depth
 * driver's convention); a point (x, y, z) falls on pixel (fx x / z + cx, fy y / z + cy), pixel
 * centres at integer coordinates. */

#include <pcl/types.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace pcl {
namespace icf {

/** \brief Pinhole intrinsics of a depth image, in pixels. */
struct PinholeIntrinsics {
  float fx = 525.f, fy = 525.f;    ///< focal lengths (Kinect v1 at 640 x 480: 525)
  float cx = 319.5f, cy = 239.5f;  ///< principal point
  int width = 640, height = 480;

  /** \throws std::invalid_argument naming the field when a focal length or the size is <= 0 or
   * anything is not finite. */
  void validate() const;
};

/** \brief The depth noise of the sensor: the standard deviation of a depth measurement at
 * depth z, sigma(z) = max(floor, coefficient * z^2), and its low-frequency error over an
 * object's extent, systematic * z^2. Structured-light and stereo sensors
 * (Kinect v1, Xtion, RealSense) grow with z^2: Khoshelham and Elberink (2012) measure about
 * 1.4e-3 z^2 m for the Kinect v1, whose disparity is quantised in 1/8 pixel steps of about
 * 2.9e-3 z^2 m. Lengths in metres. */
struct DepthNoiseModel {
  float coefficient = 1.4e-3f;  ///< per metre: sigma = coefficient * z^2
  float floor = 5e-4f;          ///< smallest sigma (time-of-flight sensors: use a constant)
  /** Per metre: the sensor's low-frequency depth error at depth z, systematic * z^2, over an
   * object's extent (its calibration's residual distortion: a real table near 1 m bends by
   * millimetres, and a right pose's surface differs from the measured one by as much). It
   * does not widen what a pixel's depth supports (sigma); it is what a right pose's fit may
   * show beyond the pixel noise (DepthVerificationParams::fitSigma). 2.5e-3: the right poses
   * of the real YCB-Video frames (an Xtion, 0.55 m and 1 m; doc/TUNING.md); a simulated
   * sensor without such an error: 0. */
  float systematic = 2.5e-3f;

  float sigma(float z) const { return std::max(floor, coefficient * z * z); }
  /** The low-frequency error at depth \a z: systematic * z^2. */
  float systematicError(float z) const { return systematic * z * z; }
  void validate() const;
};

/** \brief A depth image: z of the nearest measurement per pixel (+inf where the sensor saw
 * nothing), and which pixels hold background (the table) that silhouette checks ignore. */
class DepthImage {
 public:
  static constexpr float kEmpty = std::numeric_limits<float>::infinity();

  DepthImage() = default;
  /** \brief Projects \a points (camera frame; NaN ones skipped) through \a intrinsics, keeping
   * the nearest z per pixel. */
  DepthImage(const std::vector<Eigen::Vector3f>& points, const PinholeIntrinsics& intrinsics);

  /** \brief The intrinsics of an organized cloud (\a width x \a height, row-major, NaN where
   * nothing was measured), fitted by least squares to its finite points' pixel positions. Sets
   * \a rms_pixels to the fit's residual: near 0 for a cloud made by a pinhole camera, large for
   * a cloud that is not in the camera's frame. */
  static PinholeIntrinsics fitIntrinsics(const std::vector<Eigen::Vector3f>& points, int width,
                                         int height, double& rms_pixels);

  /** \brief Intrinsics of a virtual camera at the origin that sees every point of \a points in
   * pixels of \a pixel_angle radians (about one scan point per pixel when \a pixel_angle is
   * the points' angular spacing; see angularSpacing). At most \a max_side pixels a side. */
  static PinholeIntrinsics virtualCamera(const std::vector<Eigen::Vector3f>& points,
                                         float pixel_angle, int max_side = 2048);

  /** \brief Median angular spacing (radians) of neighbouring points as seen from the origin,
   * on a deterministic subset of at most \a sample points. */
  static float angularSpacing(const std::vector<Eigen::Vector3f>& points,
                              std::size_t sample = 2000);

  /** \brief Pixel angle of an unorganized cloud's virtual camera: kVirtualPixelPitch x the
   * points' angular spacing (angularSpacing on at most \a sample points). */
  static float virtualPixelAngle(const std::vector<Eigen::Vector3f>& points,
                                 std::size_t sample = 2000);
  /** Pixels of a virtual camera per point spacing. At 1 a regularly sampled surface aliases:
   * where its points fall on pixel borders, whole rows and columns stay empty, and an empty
   * pixel stops the verification's surface growth (a 40 cm wall seen at its own grid pitch
   * had half the silhouette band around a box posed on it unreached, and which half depended
   * on the compiler's rounding). 1.5 leaves no pixel of a regular grid empty. */
  static constexpr float kVirtualPixelPitch = 1.5f;

  /** \brief The camera an image of a scene's \a points is made with: \a given when set; else,
   * for an organized cloud (\a width x \a height, width 0: unorganized), its own pinhole
   * (fitIntrinsics) when that fits within half a pixel; else a virtual camera at the origin
   * with pixels of virtualPixelAngle. */
  static PinholeIntrinsics sceneCamera(const std::vector<Eigen::Vector3f>& points, int width,
                                       int height,
                                       const std::optional<PinholeIntrinsics>& given = {});

  const PinholeIntrinsics& intrinsics() const { return k_; }
  int width() const { return k_.width; }
  int height() const { return k_.height; }
  bool empty() const { return depth_.empty(); }

  /** \brief Depth at pixel (u, v); kEmpty outside the image or where nothing was seen. */
  float depth(int u, int v) const {
    return inside(u, v) ? depth_[static_cast<std::size_t>(v) * k_.width + u] : kEmpty;
  }
  /** \brief True when pixel (u, v) holds a background point (markBackground or markExplained):
   * no evidence for a model, and the end of a surface's continuation. */
  bool background(int u, int v) const {
    return inside(u, v) && background_[static_cast<std::size_t>(v) * k_.width + u] != 0;
  }
  /** \brief True when pixel (u, v) holds a point of the supporting surface (markBackground, the
   * table): a model it lies in front of would be beneath it. */
  bool supportSurface(int u, int v) const {
    return inside(u, v) && background_[static_cast<std::size_t>(v) * k_.width + u] == kSupport;
  }
  bool inside(int u, int v) const { return u >= 0 && v >= 0 && u < k_.width && v < k_.height; }
  /** \brief True when colours were set (setColours). */
  bool hasColour() const { return !colour_.empty(); }
  /** \brief RGB in [0, 1] of the nearest measurement at pixel (u, v) (black without one);
   * only when hasColour(). */
  Eigen::Vector3f colour(int u, int v) const {
    return inside(u, v) ? colour_[static_cast<std::size_t>(v) * k_.width + u]
                        : Eigen::Vector3f::Zero();
  }
  /** \brief Gives every pixel the colour (RGB in [0, 1]) of its nearest measurement among \a
   * points; \a colours[i] belongs to \a points[i]. \throws std::invalid_argument when the
   * sizes differ. */
  void setColours(const std::vector<Eigen::Vector3f>& points,
                  const std::vector<Eigen::Vector3f>& colours);

  /** \brief Marks the pixels of \a points[indices] as background (where they are the nearest
   * measurement of their pixel). */
  void markBackground(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices);

  /** \brief Marks the pixels of \a points[indices] as background explained by something else
   * (another object's accepted pose): like the table, no evidence and the end of a continuation,
   * but, unlike it, allowed in front of a model (an occluder, not a support). A pixel already
   * marked as the table stays the table. */
  void markExplained(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices);

  /** \brief Pixel (rounded) of a camera-frame point; false when it is behind the camera or
   * outside the image. */
  bool pixelOf(const Eigen::Vector3f& p, int& u, int& v) const;
  /** \brief The camera-frame point at depth \a z on pixel (u, v)'s ray. */
  Eigen::Vector3f pointAt(int u, int v, float z) const {
    return {(static_cast<float>(u) - k_.cx) / k_.fx * z,
            (static_cast<float>(v) - k_.cy) / k_.fy * z, z};
  }

  /** \brief The surface the scene's objects stand on: its \a plane (a x + b y + c z + d = 0 in
   * the camera's frame, (a, b, c) a unit normal) and the convex polygon it extends over on it
   * (\a hull: its vertices in order, at least 3). A model that sinks into it where it extends
   * cannot be there (DepthExplanation::sunk_into_support); its pixels are marked with
   * markBackground. The normal is turned towards the camera.
   * \throws std::invalid_argument for a normal that is not of unit length, a plane or vertex
   * that is not finite, or fewer than 3 vertices. */
  void setSupportPlane(const Eigen::Vector4f& plane, const std::vector<Eigen::Vector3f>& hull);
  bool hasSupportPlane() const { return !hull_.empty(); }
  /** \brief The support plane, its normal towards the camera (setSupportPlane). */
  const Eigen::Vector4f& supportPlane() const { return plane_; }
  /** \brief True when the foot of camera-frame point \a p on the support plane lies inside the
   * support's hull (false without a support plane). */
  bool overSupport(const Eigen::Vector3f& p) const;

 private:
  PinholeIntrinsics k_;
  std::vector<float> depth_;
  static constexpr std::uint8_t kSupport = 1, kExplained = 2;
  void mark(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices,
            std::uint8_t kind);
  std::vector<std::uint8_t> background_;  ///< 0, kSupport or kExplained per pixel
  std::vector<Eigen::Vector3f> colour_;
  Eigen::Vector4f plane_ = Eigen::Vector4f::Zero();  ///< the support plane (setSupportPlane)
  Eigen::Vector3f plane_x_ = Eigen::Vector3f::Zero(), plane_y_ = Eigen::Vector3f::Zero();
  std::vector<Eigen::Vector2f> hull_;  ///< the support's hull in (plane_x_, plane_y_), ccw
};

}  // namespace icf
}  // namespace pcl
