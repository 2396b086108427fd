/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/common/io.h>
#include <pcl/conversions.h>
#include <pcl/icf/face_mesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <sstream>

namespace pcl {
namespace icf {
namespace {

Eigen::Vector3f
newellNormal(const std::vector<Eigen::Vector3f>& v, const std::vector<std::uint32_t>& poly)
{
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Eigen::Vector3f& a = v[poly[k]];
    const Eigen::Vector3f& b = v[poly[(k + 1) % poly.size()]];
    n += a.cross(b);
  }
  return n;  // |n| = 2 * area for a planar polygon
}

bool
isPlanar(const std::vector<Eigen::Vector3f>& v, const std::vector<std::uint32_t>& poly,
         const Eigen::Vector3f& unit_normal, float tolerance)
{
  float extent = 0.f;
  for (std::size_t k = 1; k < poly.size(); ++k)
    extent = std::max(extent, (v[poly[k]] - v[poly[0]]).norm());
  const float offset = unit_normal.dot(v[poly[0]]);
  for (std::uint32_t i : poly)
    if (std::abs(unit_normal.dot(v[i]) - offset) > tolerance * extent)
      return false;
  return true;
}

bool
isConvex(const std::vector<Eigen::Vector3f>& v, const std::vector<std::uint32_t>& poly,
         const Eigen::Vector3f& unit_normal)
{
  const std::size_t n = poly.size();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3f& a = v[poly[k]];
    const Eigen::Vector3f& b = v[poly[(k + 1) % n]];
    const Eigen::Vector3f& c = v[poly[(k + 2) % n]];
    if ((b - a).cross(c - b).dot(unit_normal) < 0.f)
      return false;
  }
  return true;
}

/** Ear clipping in the polygon's Newell plane; returns triangles as index triples. Works for
 * simple (possibly concave) polygons; falls back to a fan if no ear is found (self-intersecting
 * input), so every vertex is still covered. */
std::vector<std::vector<std::uint32_t>>
earClip(const std::vector<Eigen::Vector3f>& v, std::vector<std::uint32_t> poly,
        const Eigen::Vector3f& unit_normal)
{
  std::vector<std::vector<std::uint32_t>> triangles;
  auto cross = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return (v[b] - v[a]).cross(v[c] - v[b]).dot(unit_normal);
  };
  auto inside = [&](std::uint32_t p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return (v[b] - v[a]).cross(v[p] - v[a]).dot(unit_normal) >= 0.f &&
           (v[c] - v[b]).cross(v[p] - v[b]).dot(unit_normal) >= 0.f &&
           (v[a] - v[c]).cross(v[p] - v[c]).dot(unit_normal) >= 0.f;
  };
  while (poly.size() > 3) {
    const std::size_t n = poly.size();
    bool clipped = false;
    for (std::size_t k = 0; k < n && !clipped; ++k) {
      const std::uint32_t a = poly[(k + n - 1) % n], b = poly[k], c = poly[(k + 1) % n];
      if (cross(a, b, c) <= 0.f)
        continue;
      bool ear = true;
      for (std::uint32_t p : poly)
        if (p != a && p != b && p != c && inside(p, a, b, c)) {
          ear = false;
          break;
        }
      if (!ear)
        continue;
      triangles.push_back({a, b, c});
      poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) {
      for (std::size_t k = 1; k + 1 < poly.size(); ++k)
        triangles.push_back({poly[0], poly[k], poly[k + 1]});
      return triangles;
    }
  }
  triangles.push_back(poly);
  return triangles;
}

/** The polygon's vertex indices with consecutive repeats removed. */
std::vector<std::uint32_t>
distinctLoop(const std::vector<std::uint32_t>& in)
{
  std::vector<std::uint32_t> out;
  for (std::uint32_t i : in)
    if (out.empty() || out.back() != i)
      out.push_back(i);
  while (out.size() > 1 && out.front() == out.back())
    out.pop_back();
  return out;
}

std::vector<Eigen::Vector3f>
readVertices(const pcl::PolygonMesh& mesh, float scale)
{
  for (const char* name : {"x", "y", "z"})
    if (pcl::getFieldIndex(mesh.cloud, name) < 0)
      throw InvalidMeshError(std::string("mesh vertices have no '") + name + "' field");
  pcl::PointCloud<pcl::PointXYZ> cloud;
  pcl::fromPCLPointCloud2(mesh.cloud, cloud);
  std::vector<Eigen::Vector3f> vertices;
  vertices.reserve(cloud.size());
  for (const auto& p : cloud.points)
    vertices.emplace_back(p.getVector3fMap() * scale);
  return vertices;
}

}  // namespace

std::size_t
FaceMesh::countFacesWithVertices(std::uint32_t count) const
{
  return static_cast<std::size_t>(std::count_if(
      faces_.begin(), faces_.end(), [count](const Face& f) { return f.count == count; }));
}

void
FaceMesh::addFace(const std::vector<std::uint32_t>& polygon, const Eigen::Vector3f& normal,
                  float area)
{
  Face face;
  face.first = static_cast<std::uint32_t>(indices_.size());
  face.count = static_cast<std::uint32_t>(polygon.size());
  face.normal = normal;
  face.area = area;
  indices_.insert(indices_.end(), polygon.begin(), polygon.end());
  faces_.push_back(face);
}

FaceMesh
FaceMesh::build(const pcl::PolygonMesh& mesh, const FaceMeshOptions& options)
{
  if (!(options.scale > 0.f) || !std::isfinite(options.scale))
    throw std::invalid_argument("FaceMeshOptions::scale must be a positive finite number");
  if (!(options.planarity_tolerance >= 0.f) || !(options.area_tolerance >= 0.f))
    throw std::invalid_argument("FaceMeshOptions tolerances must be non-negative");

  FaceMesh out;
  out.vertices_ = readVertices(mesh, options.scale);
  out.report_.input_polygons = mesh.polygons.size();
  if (out.vertices_.empty())
    throw InvalidMeshError("mesh has no vertices");
  if (mesh.polygons.empty())
    throw InvalidMeshError("mesh has no faces (" + std::to_string(out.vertices_.size()) +
                           " vertices, 0 polygons): a point cloud is not a model");

  // Bounds of the finite vertices give the scale of the area tolerance.
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (const auto& p : out.vertices_)
    if (p.allFinite()) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  const float diagonal = (hi - lo).allFinite() ? (hi - lo).norm() : 0.f;
  const float min_area = options.area_tolerance * diagonal * diagonal;

  std::set<std::vector<std::uint32_t>> seen;
  const auto vertex_count = out.vertices_.size();
  for (const auto& polygon : mesh.polygons) {
    std::vector<std::uint32_t> raw;
    raw.reserve(polygon.vertices.size());
    for (const auto i : polygon.vertices) {
      if (i < 0 || static_cast<std::size_t>(i) >= vertex_count) {
        std::ostringstream msg;
        msg << "mesh face refers to vertex " << i << " but the mesh has only " << vertex_count
            << " vertices";
        throw InvalidMeshError(msg.str());
      }
      raw.push_back(static_cast<std::uint32_t>(i));
    }
    const std::vector<std::uint32_t> loop = distinctLoop(raw);
    if (std::any_of(loop.begin(), loop.end(),
                    [&](std::uint32_t i) { return !out.vertices_[i].allFinite(); })) {
      ++out.report_.nonfinite_dropped;
      continue;
    }
    std::vector<std::uint32_t> key = loop;
    std::sort(key.begin(), key.end());
    if (loop.size() < 3 || std::adjacent_find(key.begin(), key.end()) != key.end()) {
      ++out.report_.degenerate_dropped;
      continue;
    }
    if (!seen.insert(key).second) {
      ++out.report_.duplicate_dropped;
      continue;
    }
    const Eigen::Vector3f newell = newellNormal(out.vertices_, loop);
    const float area = 0.5f * newell.norm();
    if (!(area > min_area) || !std::isfinite(area)) {
      ++out.report_.degenerate_dropped;
      continue;
    }
    const Eigen::Vector3f normal = newell.normalized();
    if (loop.size() == 3 || (isPlanar(out.vertices_, loop, normal, options.planarity_tolerance) &&
                             isConvex(out.vertices_, loop, normal))) {
      out.addFace(loop, normal, area);
      ++out.report_.kept_faces;
      continue;
    }
    ++out.report_.triangulated_polygons;
    for (const auto& tri : earClip(out.vertices_, loop, normal)) {
      const Eigen::Vector3f n = newellNormal(out.vertices_, tri);
      const float a = 0.5f * n.norm();
      if (a > min_area)
        out.addFace(tri, n.normalized(), a);
    }
  }
  if (out.faces_.empty()) {
    std::ostringstream msg;
    msg << "mesh has no usable face: " << out.report_.degenerate_dropped << " degenerate, "
        << out.report_.duplicate_dropped << " duplicate, " << out.report_.nonfinite_dropped
        << " with non-finite vertices out of " << out.report_.input_polygons;
    throw InvalidMeshError(msg.str());
  }
  out.finish();
  return out;
}

void
FaceMesh::finish()
{
  min_ = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  max_ = -min_;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
  total_area_ = 0.0;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    Eigen::Vector3f centre = Eigen::Vector3f::Zero();
    for (std::uint32_t k = 0; k < faces_[f].count; ++k) {
      const Eigen::Vector3f& v = faceVertex(f, k);
      min_ = min_.cwiseMin(v);
      max_ = max_.cwiseMax(v);
      centre += v;
    }
    centre /= static_cast<float>(faces_[f].count);
    weighted += centre.cast<double>() * faces_[f].area;
    total_area_ += faces_[f].area;
  }
  centroid_ = (weighted / total_area_).cast<float>();
}

std::vector<SurfaceSample>
sampleSurface(const FaceMesh& mesh, std::size_t count, std::uint64_t seed)
{
  std::vector<double> cumulative(mesh.size());
  double sum = 0.0;
  for (std::size_t f = 0; f < mesh.size(); ++f)
    cumulative[f] = (sum += mesh.faces()[f].area);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<SurfaceSample> samples;
  samples.reserve(count);
  for (std::size_t s = 0; s < count; ++s) {
    const double pick = uniform(rng) * sum;
    const auto it = std::lower_bound(cumulative.begin(), cumulative.end(), pick);
    const std::size_t f = std::min<std::size_t>(
        static_cast<std::size_t>(it - cumulative.begin()), mesh.size() - 1);
    const Face& face = mesh.faces()[f];
    // Pick a fan triangle of the convex face by area, then a uniform point in it.
    std::vector<double> fan(face.count - 2);
    double fan_sum = 0.0;
    for (std::uint32_t k = 0; k + 2 < face.count; ++k)
      fan[k] = (fan_sum += 0.5 * (mesh.faceVertex(f, k + 1) - mesh.faceVertex(f, 0))
                                     .cross(mesh.faceVertex(f, k + 2) - mesh.faceVertex(f, 0))
                                     .norm());
    const double fan_pick = uniform(rng) * fan_sum;
    std::uint32_t k = 0;
    while (k + 1 < fan.size() && fan[k] < fan_pick)
      ++k;
    double u = uniform(rng), v = uniform(rng);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const Eigen::Vector3f& a = mesh.faceVertex(f, 0);
    const Eigen::Vector3f& b = mesh.faceVertex(f, k + 1);
    const Eigen::Vector3f& c = mesh.faceVertex(f, k + 2);
    samples.push_back({a + static_cast<float>(u) * (b - a) + static_cast<float>(v) * (c - a),
                       face.normal, static_cast<std::uint32_t>(f)});
  }
  return samples;
}

}  // namespace icf
}  // namespace pcl
