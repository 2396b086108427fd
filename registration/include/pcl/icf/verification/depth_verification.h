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

#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/verification/depth_image.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
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
  /** Neighbouring pixels of one smooth surface differ in depth by at most edge_sigmas x
   * sigma(z) plus the depth change of a 63-degree slope over one pixel; a larger step is a
   * depth edge between surfaces (silhouette_continuation). */
  float edge_sigmas = 6.f;
  /** Where the image has colour: neighbouring pixels of one surface differ in colour by at
   * most this (Euclidean distance of RGB in [0, 1]); a larger step is a colour edge where
   * silhouette_continuation stops (an object in contact is usually another material). 35/255,
   * the default point colour threshold of PCL's RegionGrowingRGB. */
  float max_colour_step = 35.f / 255.f;
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
  /** A right pose conflicts with the depth almost nowhere; the confidence falls linearly with
   * the conflicting share, 1 - visible_support, and reaches 0 at this share (calibration:
   * doc/TUNING.md, "The depth verification"). */
  double max_conflict = 0.1;
  /** The confidence falls linearly with silhouette_continuation (a model posed on part of a
   * bigger look-alike: the look-alike's surface goes on beyond the silhouette) and reaches 0
   * at this share. */
  double max_continuation = 0.2;
  /** Share of the model's rendered pixels that must be supported for full evidence; fewer
   * lower the confidence in proportion (a target 15% visible at 0.3 keeps half of it), so a
   * pose is accepted (min_confidence 0.875) only with 26% of its pixels supported. */
  double full_evidence = 0.3;
  /** The part of the model beyond the image's border raises the share needed: full evidence
   * at full_evidence x (1 + out_of_view_evidence x out_of_view). An occluded part is bounded
   * by the occluder's edge in the image; a part beyond the border by nothing, so a pose
   * mostly outside the image (a box laid on a face the image cuts off) needs more support. */
  double out_of_view_evidence = 1.0;
  /** A right pose fits the measured depth about as closely as the sensor measures and the mesh
   * is made (fitSigma), a model laid on an object of another size or shape (a 5 cm can posed
   * on a 4.5 cm one) inside the support tolerance but further off. Up to fit_residual
   * (DepthExplanation::residual, the RMS offset in units of fitSigma(z)) the confidence does
   * not depend on the residual; beyond, it falls linearly and reaches 0 at max_residual
   * (infinity: off). One rule for every mesh and sensor: the mesh's accuracy and the sensor's
   * low-frequency error are in fitSigma (doc/TUNING.md, "The depth verification"). */
  double fit_residual = 0.8;
  double max_residual = 1.6;
  /** Where the scene's occluding edge lies beside the model's silhouette, averaged over the
   * silhouette (DepthExplanation::silhouette_offset, pixels): a right pose puts it on the
   * silhouette within the sensor's and the rasterisation's uncertainty of an edge, about half
   * a pixel; a model posed on a look-alike a few millimetres larger or smaller all round
   * (a 4.5 cm can on a 5 cm one) a pixel or more off on every side. Up to edge_offset_pixels
   * plus the mesh's own error (mesh_accuracy at the model's depth, in pixels) and two standard
   * errors of the mean the confidence does not depend on it; beyond, it falls linearly and
   * reaches 0 at twice that. Judged only with at least min_edge_pixels silhouette pixels whose
   * edge was found. */
  double edge_offset_pixels = 0.5;
  std::size_t min_edge_pixels = 10;
  /** How deep a model may sink into the surface it stands on (DepthImage::setSupportPlane,
   * DepthExplanation::sunk_into_support), in support tolerances (supportTolerance at the
   * model's deepest point): the support's plane is measured by the same sensor as the model's
   * surface, so its error adds to theirs. Beyond it the confidence falls linearly and reaches
   * 0 one support tolerance deeper: a model posed on a shorter look-alike whose foot is hidden
   * behind an occluder (a 15 cm can on a 10 cm one) reaches through the table. */
  double sink_tolerances = 2.0;
  /** How far the mesh's surface may lie from the real object's, in metres (a CAD model of a
   * manufactured part about 0, a scanned YCB mesh 1-2 mm): it adds to the sensor's noise where
   * the fit is judged (fitSigma: a right pose fits the depth that much less closely) and to
   * where the silhouette may lie (allowedEdgeOffset). */
  float mesh_accuracy = 0.f;
  /** A right pose is hidden by the surface that supports it almost nowhere
   * (DepthExplanation::occluded_by_support; an object in contact meets it at a crease); a
   * model tilted against a flat face it is posed on dips behind that face. Up to this share of
   * the model's pixels the confidence does not depend on it; beyond, it falls linearly and
   * reaches 0 at twice the share (calibration: doc/TUNING.md, "The depth verification"). */
  double support_occlusion = 0.01;
  /** A right pose fits the depth everywhere, not only on average; a model laid on a look-alike
   * (two stacked cylinders posed as one taller can) can fit most of its pixels while one part
   * of it lies a steady few millimetres off. The supported pixels are cut in square tiles of
   * misfit_tile x the diameter (at the model's nearest depth, 4-40 pixels; two tilings half a
   * tile apart); a tile of at least kMinTilePixels gives its mean offset along the normal in
   * units of its own uncertainty, sqrt(sigma(z)^2 / n + systematic(z)^2 + mesh_accuracy^2)
   * (the random noise averages out over the tile, the camera's low-frequency error and the
   * mesh's do not): DepthExplanation::local_misfit is the largest. Up to local_misfit the
   * confidence does not depend on it; beyond, it falls linearly and reaches 0 at twice it
   * (calibration: doc/TUNING.md, "The depth verification"). The uncertainty needs the
   * camera's low-frequency error: with noise.systematic 0 (a simulated camera) the right pose
   * on a real camera's depth reads far beyond the limit. Infinity: not measured. */
  double local_misfit = 6.0;
  /** The side of local_misfit's tiles, as a share of the model's diameter at its nearest depth
   * (4-40 pixels). */
  float misfit_tile = 0.15f;
  /** The supported pixels a tile needs to count: fewer give a mean too noisy to judge. */
  static constexpr std::size_t kMinTilePixels = 12;
  /** The window of the planes that tell a surface carried on from a crease
   * (DepthExplanation::occluded_by_support), as a share of the model's diameter at its
   * nearest depth (4-24 pixels). */
  float crease_window = 0.08f;

  /** The support tolerance at depth \a z for a model of \a diameter: noise_sigmas x sigma(z)
   * + size_tolerance x diameter. A measured depth this close to the model's surface (along
   * its normal) supports it. */
  float supportTolerance(float z, float diameter) const {
    return noise_sigmas * noise.sigma(z) + size_tolerance * diameter;
  }

  /** The spread of a right pose's surface about the measured depth at depth \a z: the sensor's
   * pixel noise, its low-frequency error and the mesh's own error together, sqrt(sigma(z)^2 +
   * systematicError(z)^2 + mesh_accuracy^2) (what DepthExplanation::residual is measured
   * in). */
  float fitSigma(float z) const {
    const float s = noise.sigma(z), d = noise.systematicError(z);
    return std::sqrt(s * s + d * d + mesh_accuracy * mesh_accuracy);
  }

  /** The confidence's factor for a pose whose \a supported share of pixels the depth supports
   * while \a out_of_view of them lie beyond the image's border: min(1, supported /
   * (full_evidence x (1 + out_of_view_evidence x out_of_view))). */
  double evidenceFactor(double supported, double out_of_view) const {
    return std::min(1.0, supported / (full_evidence * (1.0 + out_of_view_evidence * out_of_view)));
  }

  /** The confidence's factor for a pose of \a residual (DepthExplanation::residual): 1 up to
   * fit_residual, falling linearly to 0 at max_residual. */
  double residualFactor(double residual) const {
    if (residual <= fit_residual)
      return 1.0;
    return std::max(0.0, 1.0 - (residual - fit_residual) / (max_residual - fit_residual));
  }

  /** The silhouette offset (pixels) up to which the confidence does not depend on it, for a
   * model whose silhouette lies at depth \a z in an image of focal length \a focal (pixels):
   * edge_offset_pixels + mesh_accuracy x focal / z. */
  double allowedEdgeOffset(float z, float focal) const {
    return edge_offset_pixels + static_cast<double>(mesh_accuracy * focal / z);
  }
  /** The confidence's factor for \a explanation's silhouette offset: 1 up to \a allowed
   * (allowedEdgeOffset), falling linearly to 0 at twice it; 1 when fewer than min_edge_pixels
   * edges were found. */
  double edgeOffsetFactor(double offset, std::size_t edges, double allowed) const {
    if (edges < min_edge_pixels || std::abs(offset) <= allowed)
      return 1.0;
    return std::max(0.0, 2.0 - std::abs(offset) / allowed);
  }

  /** The confidence's factor for a model sunk \a sunk metres into its support where the support
   * tolerance is \a support_tolerance: 1 up to sink_tolerances of them, falling linearly to 0
   * one more deeper. */
  double sinkFactor(double sunk, double support_tolerance) const {
    const double allowed = sink_tolerances * support_tolerance;
    if (sunk <= allowed)
      return 1.0;
    return std::max(0.0, 1.0 - (sunk - allowed) / support_tolerance);
  }

  /** The confidence's factor for a pose whose \a share of pixels is hidden by the surface
   * that supports it: 1 up to support_occlusion, falling linearly to 0 at twice it. */
  double supportOcclusionFactor(double share) const {
    if (share <= support_occlusion)
      return 1.0;
    return std::max(0.0, 2.0 - share / support_occlusion);
  }

  /** The confidence's factor for a largest tile offset of \a misfit (DepthExplanation::
   * local_misfit): 1 up to local_misfit, 0 at twice it. */
  double localMisfitFactor(double misfit) const {
    if (misfit <= local_misfit)
      return 1.0;
    return std::max(0.0, 2.0 - misfit / local_misfit);
  }

  /** These tolerances for a camera with \a depth_noise and a mesh whose surface lies up to
   * \a accuracy metres off the object's (the two a user sets; LocalizerParams and IcfParams
   * carry them). */
  DepthVerificationParams forSensor(const DepthNoiseModel& depth_noise, float accuracy) const {
    DepthVerificationParams p = *this;
    p.noise = depth_noise;
    p.mesh_accuracy = accuracy;
    return p;
  }

  /** These tolerances for a pose refined only roughly (a ranked candidate, a start the
   * refinement may skip): without the local misfit, which judges a finished fit, where a coarse
   * pose of the right object lies a steady millimetre off. */
  DepthVerificationParams forRoughPoses() const {
    DepthVerificationParams p = *this;
    p.local_misfit = std::numeric_limits<double>::infinity();
    return p;
  }

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** At most this many pixels beyond an image's border are drawn to count a model's part out of
 * view (ModelDepth::out_of_view_cosines): 640 holds a model twice the width of a VGA image. */
constexpr int kMaxOutOfViewPad = 640;

/** \brief The posed model as the camera would see it: per pixel the depth of its nearest
 * camera-facing surface, the cosine between the ray and that surface's normal (0 where the
 * model is absent). Same size and intrinsics as the depth image it is rendered for; it holds
 * only the window of that image the model's projection can reach, so a small model in a large
 * image costs its own pixels, not the image's (read through depthAt, cosineAt, covers). */
struct ModelDepth {
  int width = 0, height = 0;  ///< the image's size
  /** The window held: pixels [window_u0, window_u0 + window_width) x [window_v0, ...). */
  int window_u0 = 0, window_v0 = 0, window_width = 0, window_height = 0;
  /** Per pixel of the window, row by row (index): DepthImage::kEmpty where the model does not
   * cover the pixel. */
  std::vector<float> depth;
  std::vector<float> cosine;           ///< ray-normal cosine of the visible face, per window pixel
  std::size_t pixels = 0;              ///< covered pixels
  float nearest = DepthImage::kEmpty;  ///< smallest depth of the covered pixels
  /** Bounding box of the covered pixels (empty when u_min > u_max). */
  int u_min = 0, v_min = 0, u_max = -1, v_max = -1;
  /** Ray-normal cosines of the model's pixels beyond the image's border (drawn on a grid over
   * the model's projection, at most kMaxOutOfViewPad pixels past each border): a part of the
   * model the image cannot show. Empty when the model lies inside the image, or when
   * renderModelDepth was asked not to count them. */
  std::vector<float> out_of_view_cosines;

  bool inWindow(int u, int v) const {
    return u >= window_u0 && v >= window_v0 && u < window_u0 + window_width &&
           v < window_v0 + window_height;
  }
  /** The slot of pixel (u, v) in depth and cosine; (u, v) must lie in the window. */
  std::size_t index(int u, int v) const {
    return static_cast<std::size_t>(v - window_v0) * static_cast<std::size_t>(window_width) +
           static_cast<std::size_t>(u - window_u0);
  }
  float depthAt(int u, int v) const {
    return inWindow(u, v) ? depth[index(u, v)] : DepthImage::kEmpty;
  }
  float cosineAt(int u, int v) const { return inWindow(u, v) ? cosine[index(u, v)] : 0.f; }
  bool covers(int u, int v) const { return depthAt(u, v) < DepthImage::kEmpty; }
};

/** \brief Renders \a model at \a model_to_camera into \a image's pixel grid with a z-buffer:
 * every camera-facing face, exact depth where the pixel's ray meets the face's plane. With
 * \a out_of_view, also the cosines of the model's pixels beyond the image's border
 * (ModelDepth::out_of_view_cosines; explainDepth's out_of_view); callers that read only the
 * image's pixels leave it false and pay nothing for a model crossing the border. */
ModelDepth renderModelDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                            const PinholeIntrinsics& image, bool out_of_view = true);

/** \brief How a posed model explains the depth image. Shares are of the judged pixels: the
 * model's pixels away from its silhouette (border_pixels) on faces not seen at a grazing
 * angle. */
struct DepthExplanation {
  std::size_t model_pixels = 0;  ///< judged model pixels, out_of_view ones included
  /** Measured depth on the model surface (within the noise-scaled tolerance): explained. */
  double supported = 0.0;
  /** Measured depth behind the model surface: the camera saw through where the model would
   * be. A conflict: a right pose has next to none. */
  double seen_through = 0.0;
  /** Measured depth in front of the model surface: something else occludes it. Allowed, but it
   * explains nothing. */
  double occluded = 0.0;
  /** Measured depth in front of the model surface where the measurement is the background (the
   * table): the model would lie beneath the surface it stands on. A conflict, like
   * seen_through: a table's top cannot hide an object resting on it from a camera above it. */
  double below_support = 0.0;
  /** Measured depth behind the model surface, or the table in front of it, at a pixel with
   * fewer than 2 of its 4 neighbours in the same conflict: an isolated outlier (a flying
   * pixel, a speckle), noise rather than a conflict. Not in seen_through or below_support. */
  double isolated_conflicts = 0.0;
  /** No measurement (the sensor's holes, black or shiny surfaces): neither for nor against. */
  double missing = 0.0;
  /** The model beyond the image's border (ModelDepth::out_of_view_cosines, faces not seen at a
   * grazing angle): nothing measured there either, but a model mostly out of view is mostly
   * unexplained (a cropped cloud of a 2 cm patch cannot confirm a 14 cm box laid on it). */
  double out_of_view = 0.0;
  /** Measured depth on the model surface, but the measurement belongs to the background (the
   * table): the table explains it, so it is no evidence for the model (a box laid flat into
   * the table's surface would otherwise be "supported" everywhere). */
  double on_background = 0.0;
  /** RMS over the supported pixels of the measured depth's offset from the model surface
   * (along its normal) in units of fitSigma(z), the sensor's noise and the mesh's accuracy
   * together: about 1 when the model fits as well as the sensor measures and the mesh is
   * made, more when the pose is off within the tolerance or the model is laid on an object of
   * another size. Breaks ties between poses of equal confidence (a near-symmetric turn). */
  double residual = 0.0;
  /** supported / (supported + seen_through + below_support): of the model's
   * pixels where the camera could have seen the model, the share where it did. */
  double visible_support = 0.0;
  /** Where the model explains only part of a bigger surface. The scene's surface is grown from
   * the supported pixels through neighbouring pixels without a depth edge (a step larger than
   * edge_sigmas x sigma(z) plus a 63-degree slope) or a colour edge (max_colour_step, where
   * the image has colour); the background and missing depth stop it.
   * Of the band around the silhouette (from border_pixels + 1 to the silhouette margin + 1
   * pixels out), the share it reaches: a silhouette where the scene shows no depth step. */
  double silhouette_continuation = 0.0;
  std::size_t silhouette_pixels = 0;  ///< pixels of the band around the silhouette
  /** Where the scene's occluding edge lies from the model's silhouette, in pixels, averaged
   * over the silhouette pixels where it was found (silhouette_edges): positive where the
   * scene's surface goes on beyond the silhouette before it drops behind or ends, negative
   * where it ends inside it. From each silhouette pixel along the outward normal: inside, the
   * outermost pixel whose measured depth lies on the model's surface; outside, the scene's
   * surface followed without a depth edge up to where it steps back or has no depth. Where
   * something lies in front (an occluder) or the surface goes on past the look's reach, the
   * edge is not found. About 0 for a right pose; the size difference of a look-alike, in
   * pixels, for a model posed on it. */
  double silhouette_offset = 0.0;
  std::size_t silhouette_edges = 0;  ///< silhouette pixels whose edge was found
  /** The offset up to which the confidence does not depend on it: allowedEdgeOffset plus two
   * standard errors of the mean (a mean of few, scattered edges is known only so well). */
  double allowed_offset = 0.0;
  /** How deep (metres) the model's camera-facing surface goes beneath the surface the scene's
   * objects stand on (DepthImage::setSupportPlane), where that surface extends (its hull):
   * measured from the plane through the support's pixels around the model, so that the
   * sensor's low-frequency depth error (a real table near 1 m lies a few millimetres off its
   * own best plane) does not count. 0 when the model stays above it or the image has none. */
  double sunk_into_support = 0.0;
  /** The support tolerance at the model's deepest point (sinkFactor's \a support_tolerance). */
  double support_tolerance = 0.0;
  /** Of the model's occluded pixels, the share the same grown surface reaches: the
   * "occluder" is the scene surface carrying on in front of the model (a taller can around a
   * shorter model) or an object in contact with it (a can standing on a box; its colour
   * does not always stop the growth, so this is reported, not in the confidence). */
  double occluder_continuation = 0.0;
  /** Of the model's pixels, the share hidden by the very surface that supports it: occluded
   * pixels that the supported surface reaches (as occluder_continuation), some pixels away
   * from the supported ones (half a crease window), whose depth lies within noise_sigmas x
   * sigma(z) of the plane fitted to the supported pixels within the window
   * (DepthVerificationParams::crease_window). A model tilted against a flat face it is posed
   * on dips behind that face with no crease between; a real object in contact with the
   * model (a can standing on a box) meets it at a crease. */
  double occluded_by_support = 0.0;
  /** The largest mean offset of the supported pixels' depth from the model's surface over a
   * tile of the footprint, in units of that mean's uncertainty
   * (DepthVerificationParams::local_misfit): a few for a right pose, more where part of the
   * model lies steadily off the surface it is laid on; 0 when not measured (an infinite limit,
   * DepthVerificationParams::forRoughPoses). */
  double local_misfit = 0.0;
  /** In [0, 1]: max(0, 1 - (1 - visible_support) / max_conflict) x max(0, 1 -
   * silhouette_continuation / max_continuation) x evidenceFactor(supported, out_of_view) x
   * residualFactor(residual) x edgeOffsetFactor(silhouette_offset) x
   * sinkFactor(sunk_into_support) x supportOcclusionFactor(occluded_by_support) x
   * localMisfitFactor(local_misfit). What the
   * localizer ranks and accepts by
   * (doc/localizer.md). */
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

/** \brief Why a pose whose \a explanation falls short of \a min_confidence is refused, in one
 * sentence: "confidence 0.62 < 0.875: explains 81% of the visible model, 2% seen through, 0%
 * beneath the table, 90% of its silhouette continues, 97% of it supported", then the share beyond
 * the image's border when there is one, and how the fit lowered the confidence when it did ("and
 * fits the depth at 1.41 sigma, full confidence up to 0.8", \a params' fit_residual). Every refusal
 * of a depth explanation (the localizer's, the tracker's) says it in these words. */
std::string describeRefusal(const DepthExplanation& explanation, double min_confidence,
                            const DepthVerificationParams& params);

/** \brief The indices of \a points (camera frame) that \a model at \a model_to_camera explains:
 * their pixel in \a image is covered by the rendered model and their depth lies on its surface
 * within the verification's support tolerance (noise_sigmas x sigma(z) + size_tolerance x
 * diameter, along the surface normal), as explainDepth judges a pixel "supported". A caller
 * that has accepted this pose marks them explained (DepthImage::markExplained) before
 * verifying another object beside it: a touching neighbour's surface is then explained, and
 * stops silhouette continuation as the table does. Ascending. */
std::vector<int> pointsExplainedBy(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                                   const DepthImage& image,
                                   const std::vector<Eigen::Vector3f>& points,
                                   const DepthVerificationParams& params = {});

}  // namespace icf
}  // namespace pcl
