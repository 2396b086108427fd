/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The model is rendered by a small z-buffer rasteriser written here: PCL's own renderer
 * (pcl::simulation) is not in Debian's PCL, and VTK renders only through an X display, which a
 * library called from a robot's process cannot require. Convex planar faces (FaceMesh) make
 * it short: an edge-function test per pixel and the exact ray-plane depth.
 */
#include <pcl/icf/depth_verification.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

void DepthVerificationParams::validate() const {
  noise.validate();
  auto fail = [](const char* field, double value, const char* rule) {
    std::ostringstream msg;
    msg << "[pcl::icf::DepthVerificationParams::validate] " << field << " = " << value << ": "
        << rule;
    throw std::invalid_argument(msg.str());
  };
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
  if (!(min_view_cosine >= 0.f && min_view_cosine < 1.f))
    fail("min_view_cosine", min_view_cosine, "must lie in [0, 1)");
  if (!(max_seen_through > 0.0 && max_seen_through <= 1.0))
    fail("max_seen_through", max_seen_through, "must lie in (0, 1]");
  if (!(full_evidence > 0.0 && full_evidence <= 1.0))
    fail("full_evidence", full_evidence, "must lie in (0, 1]");
}

namespace {

/** One face in the camera's frame, projected. */
struct ProjectedFace {
  std::vector<Eigen::Vector2f> pixels;
  Eigen::Vector3f normal;
  float offset = 0.f;  // normal . x = offset on the face's plane
};

/** Draws one convex face into \a out (z-buffer). */
void rasterFace(const ProjectedFace& f, const PinholeIntrinsics& k, ModelDepth& out) {
  Eigen::Vector2f lo = f.pixels[0], hi = f.pixels[0];
  for (const auto& p : f.pixels) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Clamped as floats first: a vertex just in front of the camera projects far outside.
  const float w = static_cast<float>(k.width), h = static_cast<float>(k.height);
  const int u0 = static_cast<int>(std::ceil(std::clamp(lo.x(), 0.f, w)));
  const int v0 = static_cast<int>(std::ceil(std::clamp(lo.y(), 0.f, h)));
  const int u1 = static_cast<int>(std::floor(std::clamp(hi.x(), -1.f, w - 1.f)));
  const int v1 = static_cast<int>(std::floor(std::clamp(hi.y(), -1.f, h - 1.f)));
  if (!(lo.allFinite() && hi.allFinite()))
    return;
  const std::size_t n = f.pixels.size();
  float area = 0.f;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = f.pixels[i];
    const auto& b = f.pixels[(i + 1) % n];
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
        const Eigen::Vector2f e = f.pixels[(i + 1) % n] - f.pixels[i];
        const Eigen::Vector2f w = q - f.pixels[i];
        inside = sign * (e.x() * w.y() - e.y() * w.x()) >= 0.f;
      }
      if (!inside)
        continue;
      const Eigen::Vector3f ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.f);
      const float along = f.normal.dot(ray);
      if (!(std::abs(along) > 1e-9f))
        continue;
      const float z = f.offset / along;
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
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

/** Nearest model depth among the pixels within \a r of (u, v); kEmpty when none is covered. */
float nearbyModelDepth(const ModelDepth& m, int u, int v, int r) {
  float z = DepthImage::kEmpty;
  for (int dv = -r; dv <= r; ++dv)
    for (int du = -r; du <= r; ++du)
      if (m.covers(u + du, v + dv))
        z = std::min(z, m.depth[static_cast<std::size_t>(v + dv) * m.width + (u + du)]);
  return z;
}

/** Share of the judged ring pixels (r + 1 outside the silhouette) where the scene surface
 * carries on at the model's depth. */
double silhouetteContinuation(const ModelDepth& m, const DepthImage& image, float diameter,
                              const DepthVerificationParams& params, int margin,
                              std::size_t& judged) {
  const int ring = margin + 1;
  std::size_t continuing = 0;
  judged = 0;
  for (int v = std::max(0, m.v_min - ring); v <= std::min(m.height - 1, m.v_max + ring); ++v)
    for (int u = std::max(0, m.u_min - ring); u <= std::min(m.width - 1, m.u_max + ring); ++u) {
      if (m.covers(u, v))
        continue;
      // On the ring: exactly `ring` steps from a covered pixel along u or v.
      if (!(m.covers(u + ring, v) || m.covers(u - ring, v) || m.covers(u, v + ring) ||
            m.covers(u, v - ring)))
        continue;
      if (nearbyModelDepth(m, u, v, ring - 1) < DepthImage::kEmpty)
        continue;  // nearer to the silhouette than the ring
      const float scene = image.depth(u, v);
      if (scene == DepthImage::kEmpty || image.background(u, v))
        continue;
      const float model = nearbyModelDepth(m, u, v, ring);
      const float tolerance =
          params.edge_sigmas * params.noise.sigma(model) + params.size_tolerance * diameter;
      if (model - scene > tolerance)
        continue;  // an occluder in front: says nothing about where the object ends
      ++judged;
      if (std::abs(scene - model) <= tolerance)
        ++continuing;
    }
  return judged > 0 ? static_cast<double>(continuing) / static_cast<double>(judged) : 0.0;
}

}  // namespace

int silhouetteMarginPixels(const ModelDepth& m, const PinholeIntrinsics& k, float diameter,
                           const DepthVerificationParams& params) {
  if (m.u_max < m.u_min)
    return params.border_pixels;
  // At the model's nearest depth, where a length spans the most pixels.
  const float pixels = params.silhouette_margin * diameter * std::max(k.fx, k.fy) / m.nearest;
  const float bounded = std::isfinite(pixels) ? std::clamp(pixels, 0.f, 16.f) : 16.f;
  return std::clamp(static_cast<int>(std::ceil(bounded)), params.border_pixels, 16);
}

ModelDepth renderModelDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                            const PinholeIntrinsics& k) {
  k.validate();
  ModelDepth out;
  out.width = k.width;
  out.height = k.height;
  out.depth.assign(static_cast<std::size_t>(k.width) * k.height, DepthImage::kEmpty);
  out.cosine.assign(out.depth.size(), 0.f);
  out.u_min = k.width;
  out.v_min = k.height;
  const FaceMesh& mesh = model.mesh();
  ProjectedFace f;
  for (std::size_t i = 0; i < mesh.size(); ++i) {
    const Face& face = mesh.faces()[i];
    f.normal = model_to_camera.linear() * face.normal;
    const Eigen::Vector3f first = model_to_camera * mesh.faceVertex(i, 0);
    f.offset = f.normal.dot(first);
    if (!(f.offset < 0.f))
      continue;  // facing away from the camera (or seen edge-on)
    f.pixels.clear();
    bool in_front = true;
    for (std::size_t j = 0; j < face.count && in_front; ++j) {
      const Eigen::Vector3f p = model_to_camera * mesh.faceVertex(i, j);
      in_front = p.z() > 1e-3f;
      f.pixels.emplace_back(k.fx * p.x() / p.z() + k.cx, k.fy * p.y() / p.z() + k.cy);
    }
    if (in_front)
      rasterFace(f, k, out);
  }
  out.pixels = static_cast<std::size_t>(std::count_if(
      out.depth.begin(), out.depth.end(), [](float z) { return z < DepthImage::kEmpty; }));
  return out;
}

DepthExplanation explainDepth(const IcfModel& model, const Eigen::Isometry3f& model_to_camera,
                              const DepthImage& image, const DepthVerificationParams& params) {
  if (image.empty())
    return {};
  return explainDepth(renderModelDepth(model, model_to_camera, image.intrinsics()), image,
                      2.f * model.radius(), params);
}

DepthExplanation explainDepth(const ModelDepth& m, const DepthImage& image, float diameter,
                              const DepthVerificationParams& params) {
  params.validate();
  DepthExplanation e;
  if (image.empty() || m.width != image.width() || m.height != image.height())
    return e;
  const int margin = silhouetteMarginPixels(m, image.intrinsics(), diameter, params);
  std::size_t supported = 0, seen_through = 0, occluded = 0, missing = 0, on_background = 0;
  for (int v = m.v_min; v <= m.v_max; ++v)
    for (int u = m.u_min; u <= m.u_max; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * m.width + u;
      if (!m.covers(u, v) || m.cosine[i] < params.min_view_cosine ||
          !awayFromSilhouette(m, u, v, margin))
        continue;
      const float scene = image.depth(u, v);
      if (scene == DepthImage::kEmpty) {
        ++missing;
        continue;
      }
      const float tolerance =
          params.noise_sigmas * params.noise.sigma(m.depth[i]) + params.size_tolerance * diameter;
      // Distance along the surface normal: a depth offset on an oblique face is larger.
      const float off = (scene - m.depth[i]) * m.cosine[i];
      if (off > tolerance)
        ++seen_through;
      else if (off < -tolerance)
        ++occluded;
      else if (image.background(u, v))
        ++on_background;
      else
        ++supported;
    }
  e.model_pixels = supported + seen_through + occluded + missing + on_background;
  if (e.model_pixels == 0)
    return e;
  const double n = static_cast<double>(e.model_pixels);
  e.supported = static_cast<double>(supported) / n;
  e.seen_through = static_cast<double>(seen_through) / n;
  e.occluded = static_cast<double>(occluded) / n;
  e.missing = static_cast<double>(missing) / n;
  e.on_background = static_cast<double>(on_background) / n;
  e.visible_support =
      supported + seen_through > 0
          ? static_cast<double>(supported) / static_cast<double>(supported + seen_through)
          : 0.0;
  e.silhouette_continuation =
      silhouetteContinuation(m, image, diameter, params, margin, e.silhouette_pixels);
  e.confidence = std::max(0.0, 1.0 - (1.0 - e.visible_support) / params.max_seen_through) *
                 (1.0 - e.silhouette_continuation) *
                 std::min(1.0, e.supported / params.full_evidence);
  return e;
}

}  // namespace icf
}  // namespace pcl
