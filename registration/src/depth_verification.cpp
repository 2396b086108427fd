/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The model is rendered by a small z-buffer rasteriser written here: PCL's own renderer
 * (pcl::simulation) is not in Debian's PCL, and VTK renders only through an X display, which a
 * library called from a robot's process cannot require. Convex planar faces (FaceMesh) make
 * it short: an edge-function test per pixel and the exact ray-plane depth.
 */
#include <pcl/icf/registration/usable_point.h>
#include <pcl/icf/verification/depth_verification.h>
#include <pcl_icf_internal/parameter_check.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace pcl {
namespace icf {

void DepthVerificationParams::validate() const {
  noise.validate();
  const internal::ParameterCheck fail("DepthVerificationParams");
  if (!(noise_sigmas > 0.f) || !std::isfinite(noise_sigmas))
    fail("noise_sigmas", noise_sigmas, "must be positive and finite");
  if (!(edge_sigmas > 0.f) || !std::isfinite(edge_sigmas))
    fail("edge_sigmas", edge_sigmas, "must be positive and finite");
  if (!(size_tolerance >= 0.f && size_tolerance < 1.f))
    fail("size_tolerance", size_tolerance, "must lie in [0, 1)");
  if (border_pixels < 0 || border_pixels > 16)
    fail("border_pixels", border_pixels, "must lie in [0, 16]");
  if (!(silhouette_margin >= 0.f && silhouette_margin < 0.5f))
    fail("silhouette_margin", silhouette_margin, "must lie in [0, 0.5)");
  if (!(max_colour_step > 0.f && max_colour_step <= 2.f))
    fail("max_colour_step", max_colour_step, "must lie in (0, 2]");
  if (!(min_view_cosine >= 0.f && min_view_cosine < 1.f))
    fail("min_view_cosine", min_view_cosine, "must lie in [0, 1)");
  if (!(max_conflict > 0.0 && max_conflict <= 1.0))
    fail("max_conflict", max_conflict, "must lie in (0, 1]");
  if (!(max_continuation > 0.0 && max_continuation <= 1.0))
    fail("max_continuation", max_continuation, "must lie in (0, 1]");
  if (!(full_evidence > 0.0 && full_evidence <= 1.0))
    fail("full_evidence", full_evidence, "must lie in (0, 1]");
  if (!(out_of_view_evidence >= 0.0 && std::isfinite(out_of_view_evidence)))
    fail("out_of_view_evidence", out_of_view_evidence, "must be finite and not negative");
  if (!(fit_residual >= 0.0 && std::isfinite(fit_residual)))
    fail("fit_residual", fit_residual, "must be finite and not negative");
  if (!(max_residual > fit_residual))
    fail("max_residual", max_residual, "must exceed fit_residual (infinity: off)");
  if (!(sink_tolerances > 0.0))
    fail("sink_tolerances", sink_tolerances, "must be positive (infinity: off)");
  if (!(edge_offset_pixels > 0.0))
    fail("edge_offset_pixels", edge_offset_pixels, "must be positive (infinity: off)");
  if (!(mesh_accuracy >= 0.f && std::isfinite(mesh_accuracy)))
    fail("mesh_accuracy", mesh_accuracy, "must be finite and not negative");
  if (!(support_occlusion > 0.0))
    fail("support_occlusion", support_occlusion, "must be positive (infinity: off)");
  if (!(crease_window > 0.f && crease_window <= 1.f))
    fail("crease_window", crease_window, "must lie in (0, 1]");
  if (!(local_misfit > 0.0))
    fail("local_misfit", local_misfit, "must be positive (infinity: off)");
  if (!(misfit_tile > 0.f && misfit_tile <= 1.f))
    fail("misfit_tile", misfit_tile, "must lie in (0, 1]");
}

namespace {

/** One face in the camera's frame, projected: its vertices' pixels are
 * ProjectedFaces::pixels[first, first + count). */
struct ProjectedFace {
  std::uint32_t first = 0, count = 0;
  Eigen::Vector3f normal;
  float offset = 0.f;  // normal . x = offset on the face's plane
};

/** The camera-facing faces of a model, projected; one array of pixels for all (a scanned
 * mesh has tens of thousands of faces: one allocation each cost as much as drawing them). */
struct ProjectedFaces {
  std::vector<ProjectedFace> faces;
  std::vector<Eigen::Vector2f> pixels;
};

/** Draws one convex face (its \a n projected vertices \a pixels, its plane \a normal . x = \a
 * offset in the camera's frame) into \a out (z-buffer). */
void rasterFace(const Eigen::Vector2f* pixels, std::size_t n, const Eigen::Vector3f& normal,
                float offset, const PinholeIntrinsics& k, ModelDepth& out) {
  Eigen::Vector2f lo = pixels[0], hi = pixels[0];
  for (std::size_t i = 0; i < n; ++i) {
    lo = lo.cwiseMin(pixels[i]);
    hi = hi.cwiseMax(pixels[i]);
  }
  if (!(lo.allFinite() && hi.allFinite()))
    return;
  // Clamped as floats first: a vertex just in front of the camera projects far outside.
  const float w = static_cast<float>(k.width), h = static_cast<float>(k.height);
  const int u0 = static_cast<int>(std::ceil(std::clamp(lo.x(), 0.f, w)));
  const int v0 = static_cast<int>(std::ceil(std::clamp(lo.y(), 0.f, h)));
  const int u1 = static_cast<int>(std::floor(std::clamp(hi.x(), -1.f, w - 1.f)));
  const int v1 = static_cast<int>(std::floor(std::clamp(hi.y(), -1.f, h - 1.f)));
  float area = 0.f;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = pixels[i];
    const auto& b = pixels[(i + 1) % n];
    area += a.x() * b.y() - b.x() * a.y();
  }
  if (!(std::abs(area) > 1e-12f))
    return;
  const float sign = area > 0.f ? 1.f : -1.f;
  for (int v = v0; v <= v1; ++v)
    for (int u = u0; u <= u1; ++u) {
      const Eigen::Vector2f q(static_cast<float>(u), static_cast<float>(v));
      bool inside = true;
      for (std::size_t i = 0; i < n && inside; ++i) {
        const Eigen::Vector2f e = pixels[(i + 1) % n] - pixels[i];
        const Eigen::Vector2f w = q - pixels[i];
        inside = sign * (e.x() * w.y() - e.y() * w.x()) >= 0.f;
      }
      if (!inside)
        continue;
      const Eigen::Vector3f ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.f);
      const float along = normal.dot(ray);
      if (!(std::abs(along) > 1e-9f))
        continue;
      const float z = offset / along;
      if (!out.inWindow(u, v))
        continue;
      const std::size_t i = out.index(u, v);
      if (z > 1e-6f && z < out.depth[i]) {
        out.depth[i] = z;
        out.cosine[i] = std::abs(along) / ray.norm();
        out.nearest = std::min(out.nearest, z);
        out.u_min = std::min(out.u_min, u);
        out.v_min = std::min(out.v_min, v);
        out.u_max = std::max(out.u_max, u);
        out.v_max = std::max(out.v_max, v);
      }
    }
}

/** True when every pixel within \a r (4-neighbourhood steps) of (u, v) is covered. */
bool awayFromSilhouette(const ModelDepth& m, int u, int v, int r) {
  for (int d = 1; d <= r; ++d)
    if (!m.covers(u + d, v) || !m.covers(u - d, v) || !m.covers(u, v + d) || !m.covers(u, v - d))
      return false;
  return true;
}

/** The pixels of the model's footprint widened by a band, as a small grid: each pixel's class
 * and whether the scene's surface reaches it from the supported pixels. */
struct Footprint {
  enum Class : std::uint8_t { kOutside, kCovered, kNearBand, kBand };
  int u0 = 0, v0 = 0, w = 0, h = 0;
  std::vector<std::uint8_t> cls;      ///< Class
  std::vector<std::uint8_t> reached;  ///< 1: reached by the surface from a supported pixel
  std::vector<std::size_t> nearest;   ///< index of the (approximately) nearest covered pixel
  std::size_t at(int u, int v) const { return static_cast<std::size_t>(v - v0) * w + (u - u0); }
  int u(std::size_t i) const { return u0 + static_cast<int>(i % static_cast<std::size_t>(w)); }
  int v(std::size_t i) const { return v0 + static_cast<int>(i / static_cast<std::size_t>(w)); }
  bool inside(int u, int v) const { return u >= u0 && v >= v0 && u < u0 + w && v < v0 + h; }
};

/** The model's footprint and the band of \a ring pixels around it; band pixels within \a
 * near of the silhouette (the sensor's smeared edge) are kNearBand, the rest kBand. */
Footprint footprintWithBand(const ModelDepth& m, int ring, int near) {
  Footprint f;
  f.u0 = std::max(0, m.u_min - ring);
  f.v0 = std::max(0, m.v_min - ring);
  f.w = std::min(m.width - 1, m.u_max + ring) - f.u0 + 1;
  f.h = std::min(m.height - 1, m.v_max + ring) - f.v0 + 1;
  // Chessboard distance to the nearest covered pixel, and that pixel: two passes over the
  // grid (Rosenfeld and Pfaltz's sequential distance transform, carrying the source).
  const int far = f.w + f.h;
  std::vector<int> dist(static_cast<std::size_t>(f.w) * f.h, far);
  f.nearest.assign(dist.size(), 0);
  for (int v = f.v0; v < f.v0 + f.h; ++v)
    for (int u = f.u0; u < f.u0 + f.w; ++u)
      if (m.covers(u, v)) {
        dist[f.at(u, v)] = 0;
        f.nearest[f.at(u, v)] = f.at(u, v);
      }
  auto take = [&](std::size_t i, int nu, int nv) {
    if (!f.inside(nu, nv))
      return;
    const std::size_t j = f.at(nu, nv);
    if (dist[j] + 1 < dist[i]) {
      dist[i] = dist[j] + 1;
      f.nearest[i] = f.nearest[j];
    }
  };
  for (int v = f.v0; v < f.v0 + f.h; ++v)
    for (int u = f.u0; u < f.u0 + f.w; ++u)
      for (const auto& [du, dv] : {std::pair{-1, -1}, {0, -1}, {1, -1}, {-1, 0}})
        take(f.at(u, v), u + du, v + dv);
  for (int v = f.v0 + f.h - 1; v >= f.v0; --v)
    for (int u = f.u0 + f.w - 1; u >= f.u0; --u)
      for (const auto& [du, dv] : {std::pair{1, 1}, {0, 1}, {-1, 1}, {1, 0}})
        take(f.at(u, v), u + du, v + dv);
  f.cls.resize(dist.size());
  for (std::size_t i = 0; i < dist.size(); ++i)
    f.cls[i] = dist[i] == 0      ? Footprint::kCovered
               : dist[i] <= near ? Footprint::kNearBand
               : dist[i] <= ring ? Footprint::kBand
                                 : Footprint::kOutside;
  f.reached.assign(f.cls.size(), 0);
  return f;
}

/** Largest depth difference between 4-neighbour pixels of one smooth surface at depth \a z:
 * the sensor's noise, plus the depth change of a surface inclined up to about 63 degrees
 * (twice the pixel's footprint). A larger step is a depth edge between two surfaces. */
float smoothStep(float z, const DepthImage& image, const DepthVerificationParams& params) {
  const PinholeIntrinsics& k = image.intrinsics();
  const float footprint = z / std::min(k.fx, k.fy);
  return params.edge_sigmas * params.noise.sigma(z) + 2.f * footprint;
}

/** True when pixels (u, v) and (nu, nv) show one material: no colour in the image, or colours
 * within max_colour_step (Euclidean, RGB in [0, 1]). */
bool sameColour(const DepthImage& image, int u, int v, int nu, int nv,
                const DepthVerificationParams& params) {
  if (!image.hasColour())
    return true;
  // Against the pixel behind too: a colour edge blurred over two pixels (demosaicing, the
  // colour camera's registration to depth) changes little per pixel.
  const Eigen::Vector3f c = image.colour(nu, nv);
  const int bu = 2 * u - nu, bv = 2 * v - nv;
  return (image.colour(u, v) - c).norm() <= params.max_colour_step &&
         (!image.inside(bu, bv) || image.depth(bu, bv) == DepthImage::kEmpty ||
          (image.colour(bu, bv) - c).norm() <= params.max_colour_step);
}

/** Marks in \a f every footprint or band pixel that the scene's surface reaches from \a
 * seeds (the supported pixels) through 4-neighbours without a depth edge (smoothStep) or, when
 * the image has colour, a colour edge (sameColour: an object in contact, a can standing on a
 * box, is another material; one surface carrying on is not); the background (the table) and
 * pixels without depth stop it. Breadth first: deterministic. */
void growSurface(Footprint& f, const DepthImage& image, const std::vector<std::size_t>& seeds,
                 const DepthVerificationParams& params) {
  std::vector<std::pair<int, int>> queue;
  queue.reserve(seeds.size());
  for (std::size_t s : seeds) {
    const int u = f.u0 + static_cast<int>(s % static_cast<std::size_t>(f.w));
    const int v = f.v0 + static_cast<int>(s / static_cast<std::size_t>(f.w));
    f.reached[s] = 1;
    queue.emplace_back(u, v);
  }
  static constexpr int kStep[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto [u, v] = queue[head];
    const float z = image.depth(u, v);
    for (const auto& d : kStep) {
      const int nu = u + d[0], nv = v + d[1];
      if (!f.inside(nu, nv))
        continue;
      const std::size_t i = f.at(nu, nv);
      if (f.reached[i] || f.cls[i] == Footprint::kOutside)
        continue;
      const float nz = image.depth(nu, nv);
      if (nz == DepthImage::kEmpty || image.background(nu, nv) ||
          std::abs(nz - z) > smoothStep(std::min(z, nz), image, params) ||
          !sameColour(image, u, v, nu, nv, params))
        continue;
      f.reached[i] = 1;
      queue.emplace_back(nu, nv);
    }
  }
}

/** The pixel \a k steps from (\a u, \a v) against the direction (\a du, \a dv) / \a steps
 * (inward from the silhouette, when that direction points out), rounded to the nearest pixel. */
std::pair<int, int> stepInward(int u, int v, int du, int dv, int steps, int k) {
  return {u - static_cast<int>(std::lround(static_cast<double>(du * k) / steps)),
          v - static_cast<int>(std::lround(static_cast<double>(dv * k) / steps))};
}

/** The model pixel where the surface seen at silhouette pixel (\a ue, \a ve) faces the
 * camera: from it, \a walked pixels inward along (-\a du, -\a dv) / \a steps, past the
 * faces seen at a grazing angle (cosine below min_view_cosine; at most \a max_walk pixels).
 * A box's side seen edge-on lines its front face's silhouette; the front face is the surface
 * that may carry on past it. */
std::pair<int, int> facingEdgePixel(const ModelDepth& m, int ue, int ve, int du, int dv, int steps,
                                    int max_walk, const DepthVerificationParams& params,
                                    int& walked) {
  walked = 0;
  for (int in = 0; in <= max_walk; ++in) {
    const auto [u, v] = stepInward(ue, ve, du, dv, steps, in);
    if (!m.covers(u, v))
      break;
    walked = in;
    if (m.cosineAt(u, v) >= params.min_view_cosine)
      return {u, v};
  }
  walked = 0;
  return {ue, ve};
}

/** True when the scene at band pixel \a i lies on the model's surface carried on past the
 * silhouette: the model's depth at the silhouette (at its nearest pixel, or where the surface
 * there faces the camera: facingEdgePixel), extrapolated linearly along the way out from the
 * model's own depth two pixels further in, within the support tolerance (noise_sigmas x
 * sigma(z) + size_tolerance x diameter). One surface carrying on passes (a wall flush with a
 * box's front face, whose sides are seen edge-on); an object in contact meets the model at a
 * fold (a can standing on a box) and does not. */
bool onModelSurfaceExtended(const Footprint& f, const ModelDepth& m, const DepthImage& image,
                            std::size_t i, float diameter, int max_walk,
                            const DepthVerificationParams& params) {
  const int ub = f.u(i), vb = f.v(i);
  const int du = ub - f.u(f.nearest[i]), dv = vb - f.v(f.nearest[i]);
  const int steps = std::max(std::abs(du), std::abs(dv));
  if (steps == 0)
    return false;
  int walked = 0;
  const auto [ue, ve] = facingEdgePixel(m, f.u(f.nearest[i]), f.v(f.nearest[i]), du, dv, steps,
                                        max_walk, params, walked);
  const float edge = m.depthAt(ue, ve);
  for (int back = 2; back >= 1; --back) {
    const auto [ui, vi] = stepInward(ue, ve, du, dv, steps, back);
    if (!m.covers(ui, vi))
      continue;
    const float slope = (edge - m.depthAt(ui, vi)) / static_cast<float>(back);
    const float extended = edge + slope * static_cast<float>(steps + walked);
    return std::abs(image.depth(ub, vb) - extended) <= params.supportTolerance(extended, diameter);
  }
  return false;
}

/** Of the band around the silhouette (beyond the sensor's smeared edge), the share that
 * growSurface reached where the scene lies on the model's surface carried on
 * (onModelSurfaceExtended); \a band_pixels: the band's size. */
double bandReached(const Footprint& f, const ModelDepth& m, const DepthImage& image, float diameter,
                   int max_walk, const DepthVerificationParams& params, std::size_t& band_pixels) {
  std::size_t reached = 0;
  band_pixels = 0;
  for (std::size_t i = 0; i < f.cls.size(); ++i)
    if (f.cls[i] == Footprint::kBand) {
      ++band_pixels;
      reached += f.reached[i] && onModelSurfaceExtended(f, m, image, i, diameter, max_walk, params);
    }
  return band_pixels > 0 ? static_cast<double>(reached) / static_cast<double>(band_pixels) : 0.0;
}

/** The outward unit normal of the model's silhouette at covered pixel (\a u, \a v): the mean
 * direction to its uncovered 8-neighbours; zero when all are covered. */
Eigen::Vector2f silhouetteNormal(const ModelDepth& m, int u, int v) {
  Eigen::Vector2f n = Eigen::Vector2f::Zero();
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du)
      if (!m.covers(u + du, v + dv))
        n += Eigen::Vector2f(static_cast<float>(du), static_cast<float>(dv));
  const float length = n.norm();
  return length > 1e-6f ? Eigen::Vector2f(n / length) : Eigen::Vector2f::Zero();
}

/** Where the scene's occluding edge lies along the line from silhouette pixel (\a u, \a v)
 * along \a normal, in pixels from the silhouette (0 when the scene's object ends where the
 * model does: on the border between the silhouette pixel and the next one out); false when it
 * is not found within \a reach (an occluder in front, the surface going on, the image's
 * border, a hole wider than a pixel where the edge should be).
 * Inside the footprint, the outermost pixel within reach whose depth lies on the model's
 * surface (the table's included: it is no evidence, but no edge either), past pixels seen
 * through or without depth; when that is the silhouette pixel, the scene's surface is followed
 * outward without a depth edge (smoothStep) to where it steps back or reaches the table. A
 * pixel without depth on the way holds the edge, half a pixel either way (a structured-light
 * sensor loses one pixel on either side of an edge); a wider hole leaves it unknown, and a
 * one-pixel hole in a surface that goes on beyond it does not stop it. */
bool edgeAlongNormal(const ModelDepth& m, const DepthImage& image, int u, int v,
                     const Eigen::Vector2f& normal, int reach, float diameter,
                     const DepthVerificationParams& params, double& offset) {
  auto pixel = [&](int t) {
    return std::pair<int, int>{u + static_cast<int>(std::lround(t * normal.x())),
                               v + static_cast<int>(std::lround(t * normal.y()))};
  };
  auto missing = [&](int t) {
    const auto [pu, pv] = pixel(t);
    return image.inside(pu, pv) && image.depth(pu, pv) == DepthImage::kEmpty;
  };
  int anchor = 1;
  for (int t = 0; t >= -reach; --t) {
    const auto [pu, pv] = pixel(t);
    if (!m.covers(pu, pv))
      return false;
    const float z = image.depth(pu, pv);
    if (z == DepthImage::kEmpty)
      continue;
    const std::size_t i = m.index(pu, pv);
    // Along the normal, but a face seen edge-on (a can's limb) still judged by its depth.
    const float off = (z - m.depth[i]) * std::max(m.cosine[i], 0.05f);
    const float tolerance = params.supportTolerance(m.depth[i], diameter);
    if (std::abs(off) <= tolerance) {
      anchor = t;
      break;
    }
    if (off < -tolerance && !image.supportSurface(pu, pv))
      return false;  // an occluder: where the object ends is hidden
  }
  if (anchor > 0)
    return false;
  if (anchor < 0) {  // the scene's object ends inside the model
    if (!missing(anchor + 1)) {
      offset = anchor;
      return true;
    }
    if (anchor + 2 <= 0 && missing(anchor + 2))
      return false;  // a wider hole: the edge lies somewhere in it
    offset = anchor + 0.5;
    return true;
  }
  const auto [su, sv] = pixel(0);
  float last = image.depth(su, sv);
  for (int t = 1; t <= reach; ++t) {
    const auto [pu, pv] = pixel(t);
    if (!image.inside(pu, pv))
      return false;
    float z = image.depth(pu, pv);
    if (z == DepthImage::kEmpty) {
      const auto [nu, nv] = pixel(t + 1);
      const float next = image.depth(nu, nv);
      if (next == DepthImage::kEmpty)
        return false;  // a wider hole
      // A one-pixel hole in a surface that goes on beyond it, or the edge.
      if (t + 1 > reach || image.background(nu, nv) ||
          std::abs(next - last) > 2.f * smoothStep(std::min(next, last), image, params)) {
        offset = t - 0.5;
        return true;
      }
      ++t;
      z = next;
      last = z;
      continue;
    }
    const float step = smoothStep(std::min(z, last), image, params);
    if (image.background(pu, pv) || z - last > step) {
      offset = t - 1;
      return true;
    }
    if (last - z > step)
      return false;  // something in front
    last = z;
  }
  return false;  // the surface goes on (silhouette_continuation judges that)
}

/** The mean silhouette offset (DepthExplanation::silhouette_offset) over the silhouette pixels
 * of \a m whose edge edgeAlongNormal finds within \a reach; their number in \a edges and the
 * mean's standard error in \a error. */
double silhouetteOffset(const ModelDepth& m, const DepthImage& image, int reach, float diameter,
                        const DepthVerificationParams& params, std::size_t& edges, double& error) {
  double sum = 0.0, squares = 0.0;
  edges = 0;
  error = 0.0;
  for (int v = m.v_min; v <= m.v_max; ++v)
    for (int u = m.u_min; u <= m.u_max; ++u) {
      if (!m.covers(u, v))
        continue;
      const Eigen::Vector2f normal = silhouetteNormal(m, u, v);
      double offset = 0.0;
      if (normal.isZero() ||
          !edgeAlongNormal(m, image, u, v, normal, reach, diameter, params, offset))
        continue;
      sum += offset;
      squares += offset * offset;
      ++edges;
    }
  if (edges == 0)
    return 0.0;
  const double n = static_cast<double>(edges), mean = sum / n;
  if (edges > 1)
    error = std::sqrt(std::max(0.0, squares / n - mean * mean) / (n - 1.0));
  return mean;
}

/** The plane (unit normal towards the camera, offset) through the support's pixels in \a m's
 * footprint grown by half its size on every side (at least \a min_pixels of them, at most
 * about 4000 used), least squares; nullopt when there are fewer. */
std::optional<Eigen::Vector4f> localSupportPlane(const ModelDepth& m, const DepthImage& image,
                                                 std::size_t min_pixels) {
  const int gu = std::max(10, (m.u_max - m.u_min) / 2), gv = std::max(10, (m.v_max - m.v_min) / 2);
  const int u0 = std::max(0, m.u_min - gu), u1 = std::min(image.width() - 1, m.u_max + gu);
  const int v0 = std::max(0, m.v_min - gv), v1 = std::min(image.height() - 1, m.v_max + gv);
  const std::size_t area = static_cast<std::size_t>(u1 - u0 + 1) * (v1 - v0 + 1);
  const int stride = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(area) / 4000.0)));
  std::vector<Eigen::Vector3f> points;
  for (int v = v0; v <= v1; v += stride)
    for (int u = u0; u <= u1; u += stride)
      if (image.supportSurface(u, v))
        points.push_back(image.pointAt(u, v, image.depth(u, v)));
  if (points.size() < min_pixels)
    return std::nullopt;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : points)
    centroid += p;
  centroid /= static_cast<float>(points.size());
  Eigen::Matrix3f scatter = Eigen::Matrix3f::Zero();
  for (const auto& p : points)
    scatter += (p - centroid) * (p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> solver(scatter);
  Eigen::Vector3f normal = solver.eigenvectors().col(0);
  if (normal.dot(centroid) > 0.f)
    normal = -normal;  // towards the camera at the origin
  return Eigen::Vector4f(normal.x(), normal.y(), normal.z(), -normal.dot(centroid));
}

/** DepthExplanation::sunk_into_support for \a m; \a deepest_z: the depth of its deepest
 * pixel. Model pixels beneath the support plane where the support extends are measured from
 * the local plane through the support's pixels around the model (localSupportPlane), or from
 * the support plane itself where too few of them are seen. */
double sunkIntoSupport(const ModelDepth& m, const DepthImage& image, float& deepest_z) {
  deepest_z = m.nearest;
  if (!image.hasSupportPlane())
    return 0.0;
  const Eigen::Vector4f& plane = image.supportPlane();
  std::vector<Eigen::Vector3f> beneath;  // model surface points under the support
  for (int v = m.v_min; v <= m.v_max; ++v)
    for (int u = m.u_min; u <= m.u_max; ++u) {
      if (!m.covers(u, v))
        continue;
      const Eigen::Vector3f p = image.pointAt(u, v, m.depthAt(u, v));
      if (plane.head<3>().dot(p) + plane[3] < 0.f && image.overSupport(p))
        beneath.push_back(p);
    }
  if (beneath.empty())
    return 0.0;
  const Eigen::Vector4f local = localSupportPlane(m, image, 30).value_or(plane);
  double sunk = 0.0;
  for (const auto& p : beneath) {
    const double depth = -(local.head<3>().dot(p) + local[3]);
    if (depth > sunk) {
      sunk = depth;
      deepest_z = p.z();
    }
  }
  return sunk;
}

/** What one model pixel's measurement says (DepthExplanation's terms). */
enum Verdict : std::uint8_t {
  kSupported,
  kSeenThrough,
  kBelowSupport,
  kOccluded,
  kMissing,
  kOnBackground,
  kIsolatedConflict,  ///< counted, never a pixel's verdict
  kUnjudged,          ///< near the silhouette or grazing: not counted
  kVerdicts = kUnjudged
};

/** Fewest supported pixels a plane of occludedBySupport is fitted to. */
constexpr std::size_t kMinPlanePixels = 12;

/** The corners, in a summed-area table over \a f's grid (one row and column more), of the
 * window within \a radius (chessboard) of pixel (u, v), cut at the grid's edges. */
struct TableWindow {
  int x0, y0, x1, y1;
  TableWindow(const Footprint& f, int u, int v, int radius)
      : x0(std::max(0, u - f.u0 - radius)),
        y0(std::max(0, v - f.v0 - radius)),
        x1(std::clamp(u - f.u0 + radius + 1, x0, f.w)),
        y1(std::clamp(v - f.v0 + radius + 1, y0, f.h)) {}
};

/** A summed-area table of one verdict over a footprint grid: how many pixels of a window
 * have it, in O(1). */
class VerdictCounts {
 public:
  VerdictCounts(const Footprint& f, const std::vector<std::uint8_t>& verdict, std::uint8_t what)
      : f_(f), w_(f.w + 1), table_(static_cast<std::size_t>(f.w + 1) * (f.h + 1), 0) {
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x)
        table_[static_cast<std::size_t>(y + 1) * w_ + (x + 1)] =
            (verdict[static_cast<std::size_t>(y) * f.w + x] == what ? 1 : 0) + at(x + 1, y) +
            at(x, y + 1) - at(x, y);
  }
  /** How many pixels within \a radius (chessboard) of pixel (u, v) have the verdict. */
  std::int64_t within(int u, int v, int radius) const {
    const TableWindow w(f_, u, v, radius);
    return at(w.x1, w.y1) - at(w.x0, w.y1) - at(w.x1, w.y0) + at(w.x0, w.y0);
  }

 private:
  std::int64_t at(int x, int y) const { return table_[static_cast<std::size_t>(y) * w_ + x]; }
  const Footprint& f_;
  int w_;
  std::vector<std::int64_t> table_;
};

/** Sums over the supported pixels of a footprint grid that lie more than \a clear pixels from
 * every occluded one, for least-squares planes in the image: inverse depth as a linear
 * function of the pixel, w = a u + b v + c, which holds exactly for a plane seen through a
 * pinhole camera. Summed-area tables: any window's sums in O(1). The pixels next to an
 * occluder in contact lie within the support tolerance of the model without being its
 * surface; left out, they do not bend the plane towards the occluder. */
class SupportedPlaneSums {
 public:
  SupportedPlaneSums(const Footprint& f, const std::vector<std::uint8_t>& verdict,
                     const DepthImage& image, std::uint8_t supported, const VerdictCounts& occluded,
                     int clear)
      : f_(f), w_(f.w + 1) {
    table_.assign(static_cast<std::size_t>(f.w + 1) * (f.h + 1), Sums{});
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x) {
        Sums s;
        const std::size_t i = static_cast<std::size_t>(y) * f.w + x;
        if (verdict[i] == supported && occluded.within(f.u0 + x, f.v0 + y, clear) == 0) {
          const double u = x, v = y, w = 1.0 / image.depth(f.u0 + x, f.v0 + y);
          s = Sums{{1.0, u, v, u * u, u * v, v * v, w, u * w, v * w}};
        }
        const Sums &up = at(x + 1, y), &left = at(x, y + 1), &diagonal = at(x, y);
        Sums& out = table_[static_cast<std::size_t>(y + 1) * w_ + (x + 1)];
        for (int k = 0; k < kTerms; ++k)
          out.t[k] = s.t[k] + up.t[k] + left.t[k] - diagonal.t[k];
      }
  }

  /** How many supported pixels lie within \a radius (chessboard) of pixel (u, v). */
  std::size_t supportedWithin(int u, int v, int radius) const {
    return static_cast<std::size_t>(window(u, v, radius).t[0]);
  }

  /** The depth at pixel (u, v) of the plane fitted to the supported pixels within \a radius
   * (chessboard), or nothing with fewer than \a min_pixels of them or a degenerate spread. */
  std::optional<double> predictedDepth(int u, int v, int radius, std::size_t min_pixels) const {
    const Sums s = window(u, v, radius);
    const double n = s.t[0];
    if (n < static_cast<double>(min_pixels))
      return std::nullopt;
    // Centred on the query pixel: well conditioned, and the plane's value there is its
    // intercept.
    const double du = u - f_.u0, dv = v - f_.v0;
    const double su = s.t[1] - du * n, sv = s.t[2] - dv * n;
    const double suu = s.t[3] - 2.0 * du * s.t[1] + du * du * n;
    const double suv = s.t[4] - du * s.t[2] - dv * s.t[1] + du * dv * n;
    const double svv = s.t[5] - 2.0 * dv * s.t[2] + dv * dv * n;
    // Supported pixels along one line fix no plane: their spread must span both directions.
    const double mu = su / n, mv = sv / n;
    if ((suu / n - mu * mu) * (svv / n - mv * mv) - std::pow(suv / n - mu * mv, 2) < 1.0)
      return std::nullopt;
    Eigen::Matrix3d a;
    a << suu, suv, su, suv, svv, sv, su, sv, n;
    const Eigen::Vector3d b(s.t[7] - du * s.t[6], s.t[8] - dv * s.t[6], s.t[6]);
    const double w = a.ldlt().solve(b).z();
    if (!(w > 0.0))
      return std::nullopt;
    return 1.0 / w;
  }

 private:
  static constexpr int kTerms = 9;
  struct Sums {
    double t[kTerms] = {};
  };
  Sums window(int u, int v, int radius) const {
    const TableWindow w(f_, u, v, radius);
    Sums s;
    for (int k = 0; k < kTerms; ++k)
      s.t[k] =
          at(w.x1, w.y1).t[k] - at(w.x0, w.y1).t[k] - at(w.x1, w.y0).t[k] + at(w.x0, w.y0).t[k];
    return s;
  }
  const Sums& at(int x, int y) const { return table_[static_cast<std::size_t>(y) * w_ + x]; }
  const Footprint& f_;
  int w_;
  std::vector<Sums> table_;
};

/** The verdict of model pixel (u, v), \a margin pixels or more inside the silhouette being
 * judged in full; nearer, only the table in front counts (a lateral pose error of a few pixels
 * cannot put the model's edge beneath the table by more than the tolerance). */
Verdict judgePixel(const ModelDepth& m, const DepthImage& image, int u, int v, int margin,
                   float diameter, const DepthVerificationParams& params) {
  const std::size_t i = m.index(u, v);
  if (m.cosine[i] < params.min_view_cosine)
    return kUnjudged;
  const bool judged = awayFromSilhouette(m, u, v, margin);
  const float scene = image.depth(u, v);
  if (scene == DepthImage::kEmpty)
    return judged ? kMissing : kUnjudged;
  const float tolerance = params.supportTolerance(m.depth[i], diameter);
  // Distance along the surface normal: a depth offset on an oblique face is larger.
  const float off = (scene - m.depth[i]) * m.cosine[i];
  const bool background = image.background(u, v);
  if (off < -tolerance && image.supportSurface(u, v))
    return kBelowSupport;  // the table in front of the model: the model lies beneath it
  if (!judged)
    return kUnjudged;
  if (off > tolerance)
    return kSeenThrough;
  if (off < -tolerance)
    return kOccluded;
  return background ? kOnBackground : kSupported;
}

/** The share of the model's \a n pixels occluded by the surface that supports the model
 * (DepthExplanation::occluded_by_support), for \a occluders some of which growSurface reached:
 * of them, those it reached that lie
 * within noise_sigmas x sigma(z) of the plane fitted to the supported pixels within \a radius,
 * the pixel and the plane's pixels each at least \a radius / 2 from the other verdict. */
double occludedBySupport(const Footprint& f, const std::vector<std::uint8_t>& verdict,
                         const DepthImage& image, const std::vector<std::size_t>& occluders,
                         int radius, const DepthVerificationParams& params, double n) {
  const int gap = std::max(1, radius / 2);
  const VerdictCounts occluded(f, verdict, kOccluded);
  const SupportedPlaneSums sums(f, verdict, image, kSupported, occluded, gap);
  std::size_t crossed = 0;
  for (std::size_t i : occluders) {
    if (!f.reached[i])
      continue;
    const int u = f.u(i), v = f.v(i);
    // Near the supported pixels any surface meeting the model passes the test; a crease
    // shows only some pixels away.
    if (sums.supportedWithin(u, v, gap - 1) > 0)
      continue;
    const std::optional<double> z = sums.predictedDepth(u, v, radius, kMinPlanePixels);
    if (!z)
      continue;
    const float measured = image.depth(u, v);
    crossed += std::abs(measured - *z) <= params.noise_sigmas * params.noise.sigma(measured);
  }
  return static_cast<double>(crossed) / n;
}

/** The offset of the measured depth from model pixel (u, v)'s surface along its normal,
 * metres. */
float normalOffset(const ModelDepth& m, const DepthImage& image, int u, int v) {
  const std::size_t i = m.index(u, v);
  return (image.depth(u, v) - m.depth[i]) * m.cosine[i];
}

/** (\a offset along the normal of a model pixel at \a depth / fitSigma)^2. */
double squaredNoiseOffset(double offset, float depth, const DepthVerificationParams& params) {
  const double sigma = params.fitSigma(depth);
  return offset * offset / (sigma * sigma);
}

/** How many of the 4 neighbours of (u, v) share its verdict. */
int sameVerdictNeighbours(const std::vector<std::uint8_t>& verdict, const Footprint& f, int u,
                          int v) {
  const std::uint8_t what = verdict[f.at(u, v)];
  int same = 0;
  for (const auto& [du, dv] :
       {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}})
    same += f.inside(u + du, v + dv) && verdict[f.at(u + du, v + dv)] == what;
  return same;
}

/** The pixels \a length metres span at the model's nearest depth in \a m (where a length spans
 * the most pixels), within [\a lo, \a hi]; \a hi when that is not finite. Clamped as a float,
 * before any conversion to int. */
float pixelsAtNearestDepth(float length, const ModelDepth& m, const PinholeIntrinsics& k, float lo,
                           float hi) {
  const float pixels = length * std::max(k.fx, k.fy) / m.nearest;
  return std::isfinite(pixels) ? std::clamp(pixels, lo, hi) : hi;
}

/** The supported pixels' offsets summed over square tiles of the footprint: one tiling and, for
 * a misfit that straddles its tiles, a second shifted by half a tile both ways. */
class TileOffsets {
 public:
  TileOffsets(const ModelDepth& m, int side) : m_(m), side_(side) {
    columns_ = (m.u_max - m.u_min) / side + 2;
    const int rows = (m.v_max - m.v_min) / side + 2;
    for (auto& tiling : tiles_)
      tiling.assign(static_cast<std::size_t>(columns_) * rows, Tile{});
  }

  /** Adds supported pixel (u, v): \a offset metres off the model along its normal, at
   * \a depth, where the sensor's noise is \a sigma. */
  void add(int u, int v, double offset, double depth, double sigma) {
    for (int t = 0; t < 2; ++t) {
      const int shift = t * side_ / 2;
      const int x = (u - m_.u_min + shift) / side_, y = (v - m_.v_min + shift) / side_;
      Tile& tile = tiles_[t][static_cast<std::size_t>(y) * columns_ + x];
      tile.offset += offset;
      tile.depth += depth;
      tile.variance += sigma * sigma;
      ++tile.pixels;
    }
  }

  /** The largest |mean offset| / its uncertainty over the tiles of at least \a min_pixels. */
  double largestMisfit(const DepthVerificationParams& params, std::size_t min_pixels) const {
    double largest = 0.0;
    for (const auto& tiling : tiles_)
      for (const Tile& tile : tiling) {
        if (tile.pixels < min_pixels)
          continue;
        const double n = static_cast<double>(tile.pixels);
        const double z = tile.depth / n;
        const double systematic = params.noise.systematicError(static_cast<float>(z));
        const double accuracy = params.mesh_accuracy;
        const double uncertainty =
            std::sqrt(tile.variance / (n * n) + systematic * systematic + accuracy * accuracy);
        if (uncertainty > 0.0)
          largest = std::max(largest, std::abs(tile.offset / n) / uncertainty);
      }
    return largest;
  }

 private:
  struct Tile {
    double offset = 0.0, depth = 0.0, variance = 0.0;
    std::size_t pixels = 0;
  };
  const ModelDepth& m_;
  int side_;
  int columns_;
  std::vector<Tile> tiles_[2];
};

/** The side of local misfit's tiles in pixels: misfit_tile x the model's diameter at its
 * nearest depth, within [4, 40]. */
int misfitTilePixels(const ModelDepth& m, const PinholeIntrinsics& k, float diameter,
                     const DepthVerificationParams& params) {
  return static_cast<int>(
      std::round(pixelsAtNearestDepth(params.misfit_tile * diameter, m, k, 4.f, 40.f)));
}

/** The window of occludedBySupport's planes in pixels: crease_window x the model's diameter
 * at its nearest depth, within [4, 24]. */
int creaseWindowPixels(const ModelDepth& m, const PinholeIntrinsics& k, float diameter,
                       const DepthVerificationParams& params) {
  return static_cast<int>(
      std::ceil(pixelsAtNearestDepth(params.crease_window * diameter, m, k, 4.f, 24.f)));
}

/** The silhouette margin in pixels for a model of \a diameter rendered in \a m (see
 * DepthVerificationParams::silhouette_margin). */
int silhouetteMarginPixels(const ModelDepth& m, const PinholeIntrinsics& k, float diameter,
                           const DepthVerificationParams& params) {
  if (m.u_max < m.u_min)
    return params.border_pixels;
  const float pixels = pixelsAtNearestDepth(params.silhouette_margin * diameter, m, k, 0.f, 16.f);
  return std::clamp(static_cast<int>(std::ceil(pixels)), params.border_pixels, 16);
}

/** The camera-facing faces of \a model at \a model_to_camera projected through \a k (faces
 * with a vertex behind the camera left out); \a lo, \a hi: their pixels' bounds. */
ProjectedFaces projectFaces(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                            const PinholeIntrinsics& k, Eigen::Vector2f& lo, Eigen::Vector2f& hi) {
  const FaceMesh& mesh = model.mesh();
  // Every vertex moved and projected once (faces share them).
  const std::vector<Eigen::Vector3f>& vertices = mesh.vertices();
  std::vector<Eigen::Vector3f> camera(vertices.size());
  std::vector<Eigen::Vector2f> pixel(vertices.size());
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const Eigen::Vector3f p = model_to_camera * vertices[v];
    camera[v] = p;
    pixel[v] = Eigen::Vector2f(k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy);
  }
  const std::vector<std::uint32_t>& index = mesh.faceVertexIndices();
  ProjectedFaces out;
  out.faces.reserve(mesh.size() / 2 + 1);
  out.pixels.reserve(3 * (mesh.size() / 2 + 1));
  lo = Eigen::Vector2f::Constant(std::numeric_limits<float>::infinity());
  hi = -lo;
  for (std::size_t i = 0; i < mesh.size(); ++i) {
    const Face& face = mesh.faces()[i];
    ProjectedFace f;
    f.normal = model_to_camera.linear() * face.normal;
    f.offset = f.normal.dot(camera[index[face.first]]);
    if (!(f.offset < 0.f))
      continue;  // facing away from the camera (or seen edge-on)
    bool in_front = true;
    for (std::uint32_t j = 0; j < face.count && in_front; ++j)
      in_front = camera[index[face.first + j]].z() > 1e-3f;
    if (!in_front)
      continue;
    f.first = static_cast<std::uint32_t>(out.pixels.size());
    f.count = face.count;
    for (std::uint32_t j = 0; j < face.count; ++j) {
      const Eigen::Vector2f& q = pixel[index[face.first + j]];
      out.pixels.push_back(q);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    out.faces.push_back(f);
  }
  return out;
}

/** An empty rendering on \a k's grid, holding the whole image. */
ModelDepth emptyRendering(const PinholeIntrinsics& k) {
  ModelDepth out;
  out.width = out.window_width = k.width;
  out.height = out.window_height = k.height;
  out.depth.assign(static_cast<std::size_t>(k.width) * k.height, DepthImage::kEmpty);
  out.cosine.assign(out.depth.size(), 0.f);
  out.u_min = k.width;
  out.v_min = k.height;
  return out;
}

/** An empty rendering on \a k's grid holding only the window a face projected within [\a lo,
 * \a hi] can cover (rasterFace's clamp: as floats first, then rounded inward); the whole image
 * when the bounds are not numbers. */
ModelDepth emptyRenderingWithin(const PinholeIntrinsics& k, const Eigen::Vector2f& lo,
                                const Eigen::Vector2f& hi) {
  if (lo.hasNaN() || hi.hasNaN())
    return emptyRendering(k);
  ModelDepth out;
  out.width = k.width;
  out.height = k.height;
  const float w = static_cast<float>(k.width), h = static_cast<float>(k.height);
  out.window_u0 = static_cast<int>(std::ceil(std::clamp(lo.x(), 0.f, w)));
  out.window_v0 = static_cast<int>(std::ceil(std::clamp(lo.y(), 0.f, h)));
  out.window_width = std::max(
      0, static_cast<int>(std::floor(std::clamp(hi.x(), -1.f, w - 1.f))) + 1 - out.window_u0);
  out.window_height = std::max(
      0, static_cast<int>(std::floor(std::clamp(hi.y(), -1.f, h - 1.f))) + 1 - out.window_v0);
  out.depth.assign(static_cast<std::size_t>(out.window_width) * out.window_height,
                   DepthImage::kEmpty);
  out.cosine.assign(out.depth.size(), 0.f);
  out.u_min = k.width;
  out.v_min = k.height;
  return out;
}

/** The ray-normal cosines of the pixels that \a faces (projected through \a k, pixel bounds
 * \a lo, \a hi) cover beyond \a k's image: drawn on a grid over their projection only, at most
 * kMaxOutOfViewPad pixels past each border. Empty when no pixel centre lies outside. */
std::vector<float> beyondTheImage(const ProjectedFaces& projected, const PinholeIntrinsics& k,
                                  const Eigen::Vector2f& lo, const Eigen::Vector2f& hi) {
  const float pad = static_cast<float>(kMaxOutOfViewPad);
  const float w = static_cast<float>(k.width), h = static_cast<float>(k.height);
  if (!(lo.allFinite() && hi.allFinite()) ||
      (lo.x() > -1.f && lo.y() > -1.f && hi.x() < w && hi.y() < h))
    return {};
  // The grid's first pixel centre and size, in the image's pixel coordinates.
  const int u0 = static_cast<int>(std::ceil(std::max(lo.x(), -pad)));
  const int v0 = static_cast<int>(std::ceil(std::max(lo.y(), -pad)));
  const int u1 = static_cast<int>(std::floor(std::min(hi.x(), w - 1.f + pad)));
  const int v1 = static_cast<int>(std::floor(std::min(hi.y(), h - 1.f + pad)));
  if (u1 < u0 || v1 < v0)
    return {};
  PinholeIntrinsics local = k;
  local.cx -= static_cast<float>(u0);
  local.cy -= static_cast<float>(v0);
  local.width = u1 - u0 + 1;
  local.height = v1 - v0 + 1;
  ModelDepth grid = emptyRendering(local);
  const Eigen::Vector2f shift(static_cast<float>(u0), static_cast<float>(v0));
  std::vector<Eigen::Vector2f> shifted;
  for (const ProjectedFace& f : projected.faces) {
    shifted.assign(projected.pixels.begin() + f.first,
                   projected.pixels.begin() + f.first + f.count);
    for (auto& q : shifted)
      q -= shift;
    rasterFace(shifted.data(), shifted.size(), f.normal, f.offset, local, grid);
  }
  std::vector<float> cosines;
  for (int v = 0; v < local.height; ++v)
    for (int u = 0; u < local.width; ++u) {
      const std::size_t i = grid.index(u, v);
      const int ui = u + u0, vi = v + v0;
      if (grid.depth[i] < DepthImage::kEmpty &&
          (ui < 0 || vi < 0 || ui >= k.width || vi >= k.height))
        cosines.push_back(grid.cosine[i]);
    }
  return cosines;
}

}  // namespace

ModelDepth renderModelDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                            const PinholeIntrinsics& k, bool out_of_view) {
  k.validate();
  Eigen::Vector2f lo, hi;
  const ProjectedFaces projected = projectFaces(model, model_to_camera, k, lo, hi);
  ModelDepth out = emptyRenderingWithin(k, lo, hi);
  for (const ProjectedFace& f : projected.faces)
    rasterFace(projected.pixels.data() + f.first, f.count, f.normal, f.offset, k, out);
  out.pixels = static_cast<std::size_t>(std::count_if(
      out.depth.begin(), out.depth.end(), [](float z) { return z < DepthImage::kEmpty; }));
  if (out_of_view)
    out.out_of_view_cosines = beyondTheImage(projected, k, lo, hi);
  return out;
}

DepthExplanation explainDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                              const DepthImage& image, const DepthVerificationParams& params) {
  if (image.empty())
    return {};
  return explainDepth(renderModelDepth(model, model_to_camera, image.intrinsics()), image,
                      2.f * model.radius(), params);
}

std::vector<int> pointsExplainedBy(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                                   const DepthImage& image,
                                   const std::vector<Eigen::Vector3f>& points,
                                   const DepthVerificationParams& params) {
  params.validate();
  std::vector<int> explained;
  if (image.empty())
    return explained;
  const ModelDepth m = renderModelDepth(model, model_to_camera, image.intrinsics(), false);
  const float diameter = 2.f * model.radius();
  for (std::size_t i = 0; i < points.size(); ++i) {
    int u = 0, v = 0;
    if (!isUsablePoint(points[i]) || !image.pixelOf(points[i], u, v) || !m.covers(u, v))
      continue;
    const std::size_t k = m.index(u, v);
    if (std::abs((points[i].z() - m.depth[k]) * m.cosine[k]) <=
        params.supportTolerance(m.depth[k], diameter))
      explained.push_back(static_cast<int>(i));
  }
  return explained;
}

std::string describeRefusal(const DepthExplanation& e, double min_confidence,
                            const DepthVerificationParams& params) {
  auto percent = [](double share) { return std::to_string(std::lround(100.0 * share)) + "%"; };
  std::ostringstream why;
  why << "confidence " << e.confidence << " < " << min_confidence << ": explains "
      << percent(e.visible_support) << " of the visible model, " << percent(e.seen_through)
      << " seen through, " << percent(e.below_support) << " beneath the table, "
      << percent(e.silhouette_continuation) << " of its silhouette continues, "
      << percent(e.supported) << " of it supported";
  if (e.out_of_view > 0.0)
    why << " (" << percent(e.out_of_view) << " beyond the image's border)";
  if (params.edgeOffsetFactor(e.silhouette_offset, e.silhouette_edges, e.allowed_offset) < 1.0)
    why << ", its edges lie " << std::round(10.0 * e.silhouette_offset) / 10.0
        << " pixels from the scene's (" << std::round(10.0 * e.allowed_offset) / 10.0
        << " allowed)";
  if (params.sinkFactor(e.sunk_into_support, e.support_tolerance) < 1.0)
    why << ", sinks " << std::round(1000.0 * e.sunk_into_support) / 10.0
        << " cm into the surface it stands on";
  if (params.supportOcclusionFactor(e.occluded_by_support) < 1.0)
    why << ", " << percent(e.occluded_by_support)
        << " of it hidden by the surface it lies on (no crease between)";
  if (params.localMisfitFactor(e.local_misfit) < 1.0)
    why << ", part of it lies " << std::round(10.0 * e.local_misfit) / 10.0
        << " uncertainties off the depth (" << params.local_misfit << " allowed)";
  if (params.residualFactor(e.residual) < 1.0)
    why << " and fits the depth at " << std::round(100.0 * e.residual) / 100.0
        << " sigma, full confidence up to " << params.fit_residual;
  return why.str();
}

DepthExplanation explainDepth(const ModelDepth& m, const DepthImage& image, float diameter,
                              const DepthVerificationParams& params) {
  params.validate();
  DepthExplanation e;
  if (image.empty() || m.width != image.width() || m.height != image.height() || m.u_max < m.u_min)
    return e;
  const int margin = silhouetteMarginPixels(m, image.intrinsics(), diameter, params);
  Footprint footprint = footprintWithBand(m, margin + 1, params.border_pixels);
  std::vector<std::uint8_t> verdict(footprint.cls.size(), kUnjudged);
  for (int v = m.v_min; v <= m.v_max; ++v)
    for (int u = m.u_min; u <= m.u_max; ++u)
      if (m.covers(u, v))
        verdict[footprint.at(u, v)] = judgePixel(m, image, u, v, margin, diameter, params);
  std::size_t count[kVerdicts] = {};
  std::vector<std::size_t> seeds, occluders;
  double squared_offsets = 0.0;
  // The tiles only where the local misfit is measured: not for the ranking's rough poses.
  std::optional<TileOffsets> tiles;
  if (std::isfinite(params.local_misfit))
    tiles.emplace(m, misfitTilePixels(m, image.intrinsics(), diameter, params));
  for (int v = m.v_min; v <= m.v_max; ++v)
    for (int u = m.u_min; u <= m.u_max; ++u) {
      const std::size_t i = footprint.at(u, v);
      const std::uint8_t what = verdict[i];
      if (what == kUnjudged)
        continue;
      if (what == kSupported) {
        seeds.push_back(i);
        const float depth = m.depthAt(u, v);
        const double offset = normalOffset(m, image, u, v);
        squared_offsets += squaredNoiseOffset(offset, depth, params);
        if (tiles)
          tiles->add(u, v, offset, depth, params.noise.sigma(depth));
      } else if (what == kOccluded)
        occluders.push_back(i);
      // A conflict is a region, not a pixel: an isolated outlier (a flying pixel, a speckle)
      // behind a right surface is noise, the model sticking out over the table is not.
      if ((what == kSeenThrough || what == kBelowSupport) &&
          sameVerdictNeighbours(verdict, footprint, u, v) < 2)
        ++count[kIsolatedConflict];
      else
        ++count[what];
    }
  const std::size_t supported = count[kSupported], seen_through = count[kSeenThrough],
                    below_support = count[kBelowSupport];
  if (supported > 0)
    e.residual = std::sqrt(squared_offsets / static_cast<double>(supported));
  if (tiles)
    e.local_misfit = tiles->largestMisfit(params, DepthVerificationParams::kMinTilePixels);
  const auto out_of_view = static_cast<std::size_t>(
      std::count_if(m.out_of_view_cosines.begin(), m.out_of_view_cosines.end(),
                    [&](float c) { return c >= params.min_view_cosine; }));
  e.model_pixels = supported + seen_through + below_support + count[kOccluded] +
                   count[kIsolatedConflict] + count[kMissing] + count[kOnBackground] + out_of_view;
  if (e.model_pixels == 0)
    return e;
  const double n = static_cast<double>(e.model_pixels);
  e.supported = static_cast<double>(supported) / n;
  e.seen_through = static_cast<double>(seen_through) / n;
  e.below_support = static_cast<double>(below_support) / n;
  e.occluded = static_cast<double>(count[kOccluded]) / n;
  e.isolated_conflicts = static_cast<double>(count[kIsolatedConflict]) / n;
  e.missing = static_cast<double>(count[kMissing]) / n;
  e.out_of_view = static_cast<double>(out_of_view) / n;
  e.on_background = static_cast<double>(count[kOnBackground]) / n;
  growSurface(footprint, image, seeds, params);
  e.silhouette_continuation =
      bandReached(footprint, m, image, diameter, margin, params, e.silhouette_pixels);
  std::size_t reached_occluders = 0;
  for (std::size_t i : occluders)
    reached_occluders += footprint.reached[i];
  if (reached_occluders > 0)
    e.occluded_by_support =
        occludedBySupport(footprint, verdict, image, occluders,
                          creaseWindowPixels(m, image.intrinsics(), diameter, params), params, n);
  e.occluder_continuation = occluders.empty() ? 0.0
                                              : static_cast<double>(reached_occluders) /
                                                    static_cast<double>(occluders.size());
  const PinholeIntrinsics& k = image.intrinsics();
  const double allowed = params.allowedEdgeOffset(m.nearest, std::max(k.fx, k.fy));
  // Far enough to find an edge twice the allowed offset out, where the confidence reaches 0.
  const int reach = std::clamp(static_cast<int>(std::ceil(2.0 * allowed)) + 1, 4, 16);
  double error = 0.0;
  e.silhouette_offset =
      silhouetteOffset(m, image, reach, diameter, params, e.silhouette_edges, error);
  // A mean of few, scattered edges is known only so well: two standard errors more allowed.
  e.allowed_offset = allowed + 2.0 * error;
  float deepest_z = m.nearest;
  e.sunk_into_support = sunkIntoSupport(m, image, deepest_z);
  e.support_tolerance = params.supportTolerance(deepest_z, diameter);
  const std::size_t conflicts = seen_through + below_support;
  e.visible_support = supported + conflicts > 0 ? static_cast<double>(supported) /
                                                      static_cast<double>(supported + conflicts)
                                                : 0.0;
  e.confidence =
      std::max(0.0, 1.0 - (1.0 - e.visible_support) / params.max_conflict) *
      std::max(0.0, 1.0 - e.silhouette_continuation / params.max_continuation) *
      params.evidenceFactor(e.supported, e.out_of_view) * params.residualFactor(e.residual) *
      params.edgeOffsetFactor(e.silhouette_offset, e.silhouette_edges, e.allowed_offset) *
      params.sinkFactor(e.sunk_into_support, e.support_tolerance) *
      params.supportOcclusionFactor(e.occluded_by_support) *
      params.localMisfitFactor(e.local_misfit);
  return e;
}

}  // namespace icf
}  // namespace pcl
