/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_icf_internal/point_field.h>

#include <pcl/icf/registration/face_mesh.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <sstream>

namespace pcl {
namespace icf {
namespace {

/** In double: in float the cross products of tiny faces underflow to denormals (a "unit"
 * normal of norm 0.3 after normalized()) and those of huge ones overflow (fuzz/). */
Eigen::Vector3d newellNormal(const std::vector<Eigen::Vector3f>& v,
                             const std::vector<std::uint32_t>& poly) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Eigen::Vector3d a = v[poly[k]].cast<double>();
    const Eigen::Vector3d b = v[poly[(k + 1) % poly.size()]].cast<double>();
    n += a.cross(b);
  }
  return n;  // |n| = 2 * area for a planar polygon
}

bool isPlanar(const std::vector<Eigen::Vector3f>& v, const std::vector<std::uint32_t>& poly,
              const Eigen::Vector3f& unit_normal, float tolerance) {
  float extent = 0.f;
  for (std::size_t k = 1; k < poly.size(); ++k)
    extent = std::max(extent, (v[poly[k]] - v[poly[0]]).norm());
  const float offset = unit_normal.dot(v[poly[0]]);
  for (std::uint32_t i : poly)
    if (std::abs(unit_normal.dot(v[i]) - offset) > tolerance * extent)
      return false;
  return true;
}

bool isConvex(const std::vector<Eigen::Vector3f>& v, const std::vector<std::uint32_t>& poly,
              const Eigen::Vector3f& unit_normal) {
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
std::vector<std::vector<std::uint32_t>> earClip(const std::vector<Eigen::Vector3f>& v,
                                                std::vector<std::uint32_t> poly,
                                                const Eigen::Vector3f& unit_normal) {
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
std::vector<std::uint32_t> distinctLoop(const std::vector<std::uint32_t>& in) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t i : in)
    if (out.empty() || out.back() != i)
      out.push_back(i);
  while (out.size() > 1 && out.front() == out.back())
    out.pop_back();
  return out;
}

/** The vertices of any x, y, z field layout (float, double or integer: PLY files carry all of
 * them; pcl::fromPCLPointCloud2 would silently leave non-float coordinates at zero), checked
 * against the data actually present. */
std::vector<Eigen::Vector3f> readVertices(const pcl::PolygonMesh& mesh, float scale) {
  const pcl::PCLPointCloud2& cloud = mesh.cloud;
  const pcl::PCLPointField* axes[3];
  const std::string unusable = internal::findVertexFields(cloud, axes);
  if (!unusable.empty())
    throw InvalidMeshError(unusable);
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  const std::size_t row_step = cloud.height > 1 ? cloud.row_step : n * cloud.point_step;
  if (n > 0 && (row_step < static_cast<std::size_t>(cloud.width) * cloud.point_step ||
                cloud.data.size() < (cloud.height - 1) * row_step +
                                        static_cast<std::size_t>(cloud.width) * cloud.point_step))
    throw InvalidMeshError("mesh vertex data is shorter than its " + std::to_string(n) +
                           " vertices need");
  std::vector<Eigen::Vector3f> vertices;
  vertices.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* point =
        cloud.data.data() + (i / cloud.width) * row_step + (i % cloud.width) * cloud.point_step;
    Eigen::Vector3f v;
    for (int k = 0; k < 3; ++k) {
      const double c = internal::readFieldValue(point + axes[k]->offset, axes[k]->datatype);
      v[k] = static_cast<float>(c * scale);
    }
    vertices.push_back(v);
  }
  return vertices;
}

/** The diagonal of the bounding box of the finite vertices the faces use: the scale of the area
 * tolerance. In double, and without unreferenced vertices: one stray vertex at 1e30 made the
 * float square infinite and every face "degenerate". 0 when no face uses a finite vertex. */
double usedBoundsDiagonal(const pcl::PolygonMesh& mesh,
                          const std::vector<Eigen::Vector3f>& vertices) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector3d hi = -lo;
  for (const auto& polygon : mesh.polygons)
    for (const auto i : polygon.vertices)
      if (i >= 0 && static_cast<std::size_t>(i) < vertices.size() &&
          vertices[static_cast<std::size_t>(i)].allFinite()) {
        lo = lo.cwiseMin(vertices[static_cast<std::size_t>(i)].cast<double>());
        hi = hi.cwiseMax(vertices[static_cast<std::size_t>(i)].cast<double>());
      }
  return (hi.array() >= lo.array()).all() ? (hi - lo).norm() : 0.0;
}

/** The polygon's vertex indices; \throws InvalidMeshError for one outside the mesh. */
std::vector<std::uint32_t> polygonIndices(const pcl::Vertices& polygon, std::size_t vertex_count) {
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
  return raw;
}

/** Why a polygon (its distinct loop) is dropped before its area is known, or Usable. */
enum class LoopCheck { Usable, NonFinite, Degenerate, Duplicate };

/** Checks \a loop in order: a non-finite vertex, fewer than 3 distinct vertices (or a vertex
 * repeated), the same vertex set as an earlier polygon (\a seen, which gains it). */
LoopCheck checkLoop(const std::vector<std::uint32_t>& loop,
                    const std::vector<Eigen::Vector3f>& vertices,
                    std::set<std::vector<std::uint32_t>>& seen) {
  if (std::any_of(loop.begin(), loop.end(),
                  [&](std::uint32_t i) { return !vertices[i].allFinite(); }))
    return LoopCheck::NonFinite;
  std::vector<std::uint32_t> key = loop;
  std::sort(key.begin(), key.end());
  if (loop.size() < 3 || std::adjacent_find(key.begin(), key.end()) != key.end())
    return LoopCheck::Degenerate;
  if (!seen.insert(key).second)
    return LoopCheck::Duplicate;
  return LoopCheck::Usable;
}

/** The report's count of polygons dropped for \a why (not Usable). */
std::size_t& droppedCount(FaceMeshReport& report, LoopCheck why) {
  if (why == LoopCheck::NonFinite)
    return report.nonfinite_dropped;
  return why == LoopCheck::Degenerate ? report.degenerate_dropped : report.duplicate_dropped;
}

/** \throws InvalidMeshError saying why no face was kept. */
[[noreturn]] void throwNoUsableFace(const FaceMeshReport& report, float area_tolerance,
                                    double diagonal) {
  std::ostringstream msg;
  msg << "mesh has no usable face: " << report.degenerate_dropped << " degenerate, "
      << report.duplicate_dropped << " duplicate, " << report.nonfinite_dropped
      << " with non-finite vertices out of " << report.input_polygons << " (degenerate: area below "
      << area_tolerance << " x the squared bounding-box diagonal, " << diagonal << ")";
  throw InvalidMeshError(msg.str());
}

}  // namespace

std::size_t FaceMesh::countFacesWithVertices(std::uint32_t count) const {
  return static_cast<std::size_t>(std::count_if(
      faces_.begin(), faces_.end(), [count](const Face& f) { return f.count == count; }));
}

void FaceMesh::addFace(const std::vector<std::uint32_t>& polygon, const Eigen::Vector3f& normal,
                       float area) {
  Face face;
  face.first = static_cast<std::uint32_t>(indices_.size());
  face.count = static_cast<std::uint32_t>(polygon.size());
  face.normal = normal;
  face.area = area;
  indices_.insert(indices_.end(), polygon.begin(), polygon.end());
  faces_.push_back(face);
}

FaceMesh FaceMesh::build(const pcl::PolygonMesh& mesh, const FaceMeshOptions& options) {
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
  const double diagonal = usedBoundsDiagonal(mesh, out.vertices_);
  const double min_area = options.area_tolerance * diagonal * diagonal;

  std::set<std::vector<std::uint32_t>> seen;
  for (const auto& polygon : mesh.polygons) {
    const std::vector<std::uint32_t> loop =
        distinctLoop(polygonIndices(polygon, out.vertices_.size()));
    const LoopCheck check = checkLoop(loop, out.vertices_, seen);
    if (check != LoopCheck::Usable) {
      ++droppedCount(out.report_, check);
      continue;
    }
    const Eigen::Vector3d newell = newellNormal(out.vertices_, loop);
    const float area = static_cast<float>(0.5 * newell.norm());  // beyond float: inf, dropped
    if (!(area > min_area) || !std::isfinite(area)) {
      ++out.report_.degenerate_dropped;
      continue;
    }
    const Eigen::Vector3f normal = newell.normalized().cast<float>();
    if (loop.size() == 3 || (isPlanar(out.vertices_, loop, normal, options.planarity_tolerance) &&
                             isConvex(out.vertices_, loop, normal))) {
      out.addFace(loop, normal, area);
      ++out.report_.kept_faces;
      continue;
    }
    ++out.report_.triangulated_polygons;
    for (const auto& tri : earClip(out.vertices_, loop, normal)) {
      const Eigen::Vector3d n = newellNormal(out.vertices_, tri);
      const float a = static_cast<float>(0.5 * n.norm());
      if (a > min_area && std::isfinite(a))
        out.addFace(tri, n.normalized().cast<float>(), a);
    }
  }
  if (out.faces_.empty())
    throwNoUsableFace(out.report_, options.area_tolerance, diagonal);
  out.finish();
  return out;
}

void FaceMesh::finish() {
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

std::vector<SurfaceSample> sampleSurface(const FaceMesh& mesh, std::size_t count,
                                         std::uint64_t seed) {
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
    const std::size_t f =
        std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), mesh.size() - 1);
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
