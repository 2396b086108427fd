/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief One verification of a pose hypothesis: does the posed model explain the depth image?
 *
 * The posed mesh is rendered into the camera's pixel grid (renderModelDepth) and compared with
 * the measured depth pixel by pixel (explainDepth), as hypothesis verification in object
 * recognition does (Aldoma et al., "A global hypotheses verification method for 3D object
 * recognition", ECCV 2012, PCL's GlobalHypothesesVerification; the thesis's gate, section 6.2,
 * asks the same of a cluster's points only). Every tolerance scales with the sensor's depth
 * noise at the pixel's depth and with the model's size (doc/localizer.md, "Verification"). */

#include <pcl/icf/depth_image.h>
#include <pcl/icf/icf_model.h>

#include <Eigen/Geometry>

#include <vector>

namespace pcl {
namespace icf {

/** \brief Tolerances of explainDepth. Depths in metres. */
struct DepthVerificationParams {
  DepthNoiseModel noise;
  /** A measured depth within noise_sigmas x sigma(z) + size_tolerance x diameter of the model
   * surface (along the surface normal) supports it. 3 sigma: 99.7% of a right surface's
   * pixels. */
  float noise_sigmas = 3.f;
  /** Share of the model's diameter added to every depth tolerance: the pose's own error after
   * refinement and the mesh's difference from the real object (a scanned YCB mesh: 1-3 mm on
   * 10-20 cm objects). */
  float size_tolerance = 0.015f;
  /** The scene "carries on" past the model's silhouette where a pixel just outside it has a
   * depth within edge_sigmas x sigma(z) + size_tolerance x diameter of the model's border. */
  float edge_sigmas = 6.f;
  /** Model pixels this close (in pixels) to the silhouette are not judged: depth edges smear
   * (flying pixels, missing depth at edges) and a pose error of a pixel moves them. The ring
   * of pixels judged for continuation lies this far outside. */
  int border_pixels = 2;
  /** The same margin as a share of the model's diameter (the pose's and the mesh's lateral
   * error), converted to pixels at the model's depth; the larger of the two is used, so a
   * high-resolution camera does not judge the silhouette closer than the pose is known. */
  float silhouette_margin = 0.03f;
  /** Faces seen more obliquely than this (cosine between ray and normal) hide what lies
   * behind them but are not judged: a depth camera returns little there. */
  float min_view_cosine = 0.25f;
  /** A right pose is seen through almost nowhere (noise, the mesh's error); the confidence
   * falls linearly with the share seen through, seen_through / (supported + seen_through),
   * and reaches 0 at this share. */
  double max_seen_through = 0.2;
  /** Share of the model's rendered pixels that must be supported for full evidence; fewer
   * lower the confidence in proportion (a target 25% visible at 0.5 keeps half of it). */
  double full_evidence = 0.5;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief The posed model as the camera would see it: per pixel the depth of its nearest
 * camera-facing surface, the cosine between the ray and that surface's normal (0 where the
 * model is absent). Same size and intrinsics as the depth image it is rendered for. */
struct ModelDepth {
  int width = 0, height = 0;
  std::vector<float> depth;   ///< DepthImage::kEmpty where the model does not cover the pixel
  std::vector<float> cosine;  ///< ray-normal cosine of the visible face
  std::size_t pixels = 0;     ///< covered pixels
  float nearest = DepthImage::kEmpty;  ///< smallest depth of the covered pixels
  /** Bounding box of the covered pixels (empty when u_min > u_max). */
  int u_min = 0, v_min = 0, u_max = -1, v_max = -1;

  bool covers(int u, int v) const {
    return u >= 0 && v >= 0 && u < width && v < height &&
           depth[static_cast<std::size_t>(v) * width + u] < DepthImage::kEmpty;
  }
};

/** \brief Renders \a model at \a model_to_camera into \a image's pixel grid with a z-buffer:
 * every camera-facing face, exact depth where the pixel's ray meets the face's plane. */
ModelDepth renderModelDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                            const PinholeIntrinsics& image);

/** \brief How a posed model explains the depth image. Shares are of the judged pixels: the
 * model's pixels away from its silhouette (border_pixels) on faces not seen at a grazing
 * angle. */
struct DepthExplanation {
  std::size_t model_pixels = 0;  ///< judged model pixels
  /** Measured depth on the model surface (within the noise-scaled tolerance): explained. */
  double supported = 0.0;
  /** Measured depth behind the model surface: the camera saw through where the model would
   * be. A conflict: a right pose has next to none. */
  double seen_through = 0.0;
  /** Measured depth in front of the model surface: something else occludes it. Allowed, but it
   * explains nothing. */
  double occluded = 0.0;
  /** No measurement (the sensor's holes, black or shiny surfaces): neither for nor against. */
  double missing = 0.0;
  /** Measured depth on the model surface, but the measurement belongs to the background (the
   * table): the table explains it, so it is no evidence for the model (a box laid flat into
   * the table's surface would otherwise be "supported" everywhere). */
  double on_background = 0.0;
  /** supported / (supported + seen_through): of the model's pixels where the camera could
   * have seen the model, the share where it did. */
  double visible_support = 0.0;
  /** Of the pixels just outside the silhouette whose depth was measured (and is not
   * background such as the table), the share where the scene's surface carries on at the
   * model's depth: a silhouette where the scene shows no depth step, so the model explains
   * only part of a bigger surface. */
  double silhouette_continuation = 0.0;
  std::size_t silhouette_pixels = 0;  ///< ring pixels judged
  /** In [0, 1]: max(0, 1 - (1 - visible_support) / max_seen_through) x (1 -
   * silhouette_continuation) x min(1, supported / full_evidence). What the localizer ranks
   * and accepts by (doc/localizer.md). */
  double confidence = 0.0;
};

/** \brief Compares \a model at \a model_to_camera with \a image pixel by pixel (see
 * DepthExplanation). \a image must be in the camera's frame. Deterministic. */
DepthExplanation explainDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                              const DepthImage& image, const DepthVerificationParams& params = {});

/** \brief The same comparison for a model already rendered (renderModelDepth with \a image's
 * intrinsics) whose diameter is \a diameter. */
DepthExplanation explainDepth(const ModelDepth& rendered, const DepthImage& image, float diameter,
                              const DepthVerificationParams& params = {});

/** \brief The silhouette margin in pixels for a model of \a diameter rendered in \a rendered
 * (see DepthVerificationParams::silhouette_margin). */
int silhouetteMarginPixels(const ModelDepth& rendered, const PinholeIntrinsics& intrinsics,
                           float diameter, const DepthVerificationParams& params);

}  // namespace icf
}  // namespace pcl
