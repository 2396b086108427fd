#include "synthetic/depth_camera.h"

#include "synthetic/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace synthetic {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNearDepth = 1e-4;         ///< metres; hits closer than this are ignored
constexpr double kParallelEpsilon = 1e-12;  ///< determinant below which a ray is parallel
constexpr double kNoiseTruncation = 4.0;    ///< Gaussian noise is resampled beyond this many sigma

/** Nearest hit per pixel: depth (z, metres) and index of the object (-1 for none). */
struct DepthBuffer {
  int width = 0;
  int height = 0;
  std::vector<double> depth;
  std::vector<int> object;
};

/** Inclusive pixel rectangle. */
struct PixelRect {
  int u_min = 0;
  int u_max = -1;
  int v_min = 0;
  int v_max = -1;
  bool empty() const { return u_min > u_max || v_min > v_max; }
};

void validate(const CameraIntrinsics& intrinsics, const ScanNoise& noise) {
  if (intrinsics.width <= 0 || intrinsics.height <= 0) {
    throw std::invalid_argument("depth camera: image size must be positive");
  }
  if (!(intrinsics.fx > 0.0) || !(intrinsics.fy > 0.0)) {
    throw std::invalid_argument("depth camera: focal lengths must be positive");
  }
  if (!(noise.sigma_at_1m >= 0.0) || !(noise.outlier_range >= 0.0) ||
      !(noise.outlier_ratio >= 0.0 && noise.outlier_ratio <= 1.0) ||
      !(noise.focal_baseline >= 0.0 && std::isfinite(noise.focal_baseline)) ||
      !(noise.disparity_step > 0.0 && std::isfinite(noise.disparity_step))) {
    throw std::invalid_argument("depth camera: invalid noise parameters");
  }
}

/** Pixels whose centres may see the given points (all in front of the camera): the bounding box of
 *  their projections, widened by one pixel and clipped to the image. */
PixelRect projectedRect(const CameraIntrinsics& in, const Eigen::Vector3d* const* points,
                        std::size_t count) {
  double u_lo = std::numeric_limits<double>::infinity();
  double v_lo = u_lo;
  double u_hi = -u_lo;
  double v_hi = -u_lo;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d& p = *points[i];
    const double u = in.fx * p.x() / p.z() + in.cx;
    const double v = in.fy * p.y() / p.z() + in.cy;
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
    v_lo = std::min(v_lo, v);
    v_hi = std::max(v_hi, v);
  }
  PixelRect rect;
  // Clamp in double before converting so that huge projections cannot overflow int.
  const double w = in.width;
  const double h = in.height;
  rect.u_min = static_cast<int>(std::max(0.0, std::floor(u_lo) - 1.0));
  rect.u_max = static_cast<int>(std::min(w - 1.0, std::ceil(u_hi) + 1.0));
  rect.v_min = static_cast<int>(std::max(0.0, std::floor(v_lo) - 1.0));
  rect.v_max = static_cast<int>(std::min(h - 1.0, std::ceil(v_hi) + 1.0));
  if (u_hi < -1.0 || v_hi < -1.0 || u_lo > w || v_lo > h) {
    rect = PixelRect();  // empty
  }
  return rect;
}

PixelRect fullImage(const CameraIntrinsics& in) {
  PixelRect rect;
  rect.u_max = in.width - 1;
  rect.v_max = in.height - 1;
  return rect;
}

/** Ray-casts one triangle (camera frame) into the depth buffer (Moeller-Trumbore, two-sided). */
void castTriangle(const CameraIntrinsics& in, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                  const Eigen::Vector3d& p2, int object_index, DepthBuffer& buffer) {
  PixelRect rect;
  if (p0.z() > kNearDepth && p1.z() > kNearDepth && p2.z() > kNearDepth) {
    const Eigen::Vector3d* points[3] = {&p0, &p1, &p2};
    rect = projectedRect(in, points, 3);
  } else if (p0.z() > kNearDepth || p1.z() > kNearDepth || p2.z() > kNearDepth) {
    rect = fullImage(in);  // crosses the camera plane: no projected bound, test every pixel
  }
  if (rect.empty()) {
    return;
  }
  // Moeller-Trumbore with the ray d = (x, y, 1) from the origin. All terms are linear in d, so
  // they reduce to dot products with vectors precomputed per triangle (plain doubles keep the inner
  // loop fast in unoptimised builds as well):
  //   det = e1 . (d x e2) = d . (e2 x e1),   a = s . (d x e2) / det = d . (e2 x s) / det,
  //   b = d . (s x e1) / det,                t = e2 . (s x e1) / det,   with s = -p0.
  const Eigen::Vector3d e1 = p1 - p0;
  const Eigen::Vector3d e2 = p2 - p0;
  const Eigen::Vector3d s = -p0;
  const Eigen::Vector3d q = s.cross(e1);
  const Eigen::Vector3d det_vector = e2.cross(e1);
  const Eigen::Vector3d a_vector = e2.cross(s);
  const double t_numerator = e2.dot(q);
  const double dx = det_vector.x(), dy = det_vector.y(), dz = det_vector.z();
  const double ax = a_vector.x(), ay = a_vector.y(), az = a_vector.z();
  const double bx = q.x(), by = q.y(), bz = q.z();
  for (int v = rect.v_min; v <= rect.v_max; ++v) {
    const double y = (v - in.cy) / in.fy;
    const std::size_t row = static_cast<std::size_t>(v) * static_cast<std::size_t>(in.width);
    for (int u = rect.u_min; u <= rect.u_max; ++u) {
      const double x = (u - in.cx) / in.fx;
      const double det = dx * x + dy * y + dz;
      if (std::abs(det) < kParallelEpsilon) {
        continue;
      }
      const double inv_det = 1.0 / det;
      const double a = (ax * x + ay * y + az) * inv_det;
      if (a < 0.0 || a > 1.0) {
        continue;
      }
      const double b = (bx * x + by * y + bz) * inv_det;
      if (b < 0.0 || a + b > 1.0) {
        continue;
      }
      const double t = t_numerator * inv_det;  // = depth z, since d.z() == 1
      const std::size_t index = row + static_cast<std::size_t>(u);
      if (t > kNearDepth && t < buffer.depth[index]) {
        buffer.depth[index] = t;
        buffer.object[index] = object_index;
      }
    }
  }
}

/** Ray-casts all objects and returns the nearest hit per pixel. */
DepthBuffer rayCast(const std::vector<SceneObject>& objects, const CameraIntrinsics& in) {
  DepthBuffer buffer;
  buffer.width = in.width;
  buffer.height = in.height;
  const std::size_t pixels = static_cast<std::size_t>(in.width) * in.height;
  buffer.depth.assign(pixels, std::numeric_limits<double>::infinity());
  buffer.object.assign(pixels, -1);

  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].mesh == nullptr) {
      throw std::invalid_argument("renderScan: SceneObject without mesh");
    }
    std::vector<Eigen::Vector3d> vertices = meshVertices(*objects[i].mesh);
    if (vertices.empty()) {
      continue;
    }
    Eigen::AlignedBox3d box;
    for (auto& vertex : vertices) {
      vertex = objects[i].pose * vertex;
      box.extend(vertex);
    }
    // Object-level rejection: bounding sphere behind the camera, or projection outside the image.
    const Eigen::Vector3d centre = box.center();
    const double radius = 0.5 * box.diagonal().norm();
    if (centre.z() + radius <= kNearDepth) {
      continue;
    }
    if (box.min().z() > kNearDepth) {
      std::vector<const Eigen::Vector3d*> pointers;
      pointers.reserve(vertices.size());
      for (const auto& vertex : vertices) {
        pointers.push_back(&vertex);
      }
      if (projectedRect(in, pointers.data(), pointers.size()).empty()) {
        continue;
      }
    }
    for (const auto& t : triangulateFaces(*objects[i].mesh)) {
      castTriangle(in, vertices[t[0]], vertices[t[1]], vertices[t[2]], static_cast<int>(i), buffer);
    }
  }
  return buffer;
}

/** Noisy camera-frame points per pixel (row-major), NaN where nothing was hit. */
std::vector<Eigen::Vector3f> noisyPoints(const DepthBuffer& buffer, const CameraIntrinsics& in,
                                         const ScanNoise& noise) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<Eigen::Vector3f> points(buffer.depth.size(), Eigen::Vector3f::Constant(nan));
  std::mt19937_64 rng(noise.seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> outlier(-noise.outlier_range, noise.outlier_range);
  for (int v = 0; v < in.height; ++v) {
    for (int u = 0; u < in.width; ++u) {
      const std::size_t index = static_cast<std::size_t>(v) * in.width + u;
      if (buffer.object[index] < 0) {
        continue;
      }
      const double z = buffer.depth[index];
      const double x = (u - in.cx) / in.fx;  // ray (x, y, 1)
      const double y = (v - in.cy) / in.fy;
      double offset = 0.0;  // metres along the unit ray direction
      const double sigma = noise.sigma_at_1m * z * z;
      if (sigma > 0.0) {
        double n = gaussian(rng);
        while (std::abs(n) > kNoiseTruncation) {
          n = gaussian(rng);
        }
        offset += sigma * n;
      }
      if (noise.outlier_ratio > 0.0 && unit(rng) < noise.outlier_ratio) {
        offset += outlier(rng);
      }
      double scale = z + offset / std::sqrt(x * x + y * y + 1.0);
      if (noise.focal_baseline > 0.0 && scale > 0.0) {
        const double steps = std::round(noise.focal_baseline / scale / noise.disparity_step);
        if (steps < 1.0)
          continue;  // beyond the sensor's range: no depth
        scale = noise.focal_baseline / (steps * noise.disparity_step);
      }
      points[index] = Eigen::Vector3f(static_cast<float>(scale * x), static_cast<float>(scale * y),
                                      static_cast<float>(scale));
    }
  }
  return points;
}

std::uint8_t toByte(float channel) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(channel, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

ScanNoise ScanNoise::structuredLight() {
  ScanNoise noise;
  noise.sigma_at_1m = 0.001;
  noise.outlier_ratio = 0.02;
  noise.outlier_range = 0.05;
  noise.focal_baseline = 580.0 * 0.075;
  noise.disparity_step = 0.125;
  return noise;
}

ScanNoise ScanNoise::none() {
  ScanNoise noise;
  noise.sigma_at_1m = 0.0;
  noise.outlier_ratio = 0.0;
  noise.outlier_range = 0.0;
  return noise;
}

Scan renderScan(const std::vector<SceneObject>& objects, const CameraIntrinsics& intrinsics,
                const ScanNoise& noise) {
  validate(intrinsics, noise);
  const DepthBuffer buffer = rayCast(objects, intrinsics);
  const std::vector<Eigen::Vector3f> points = noisyPoints(buffer, intrinsics, noise);

  Scan scan;
  scan.cloud.reset(new pcl::PointCloud<pcl::PointXYZRGB>(
      static_cast<std::uint32_t>(intrinsics.width), static_cast<std::uint32_t>(intrinsics.height)));
  scan.cloud->is_dense = false;
  scan.cloud->sensor_origin_ = Eigen::Vector4f(0.0f, 0.0f, 0.0f, 0.0f);
  scan.cloud->sensor_orientation_ = Eigen::Quaternionf::Identity();
  scan.labels.assign(points.size(), -1);
  for (std::size_t index = 0; index < points.size(); ++index) {
    pcl::PointXYZRGB& point = (*scan.cloud)[index];
    point.x = points[index].x();
    point.y = points[index].y();
    point.z = points[index].z();
    const int object = buffer.object[index];
    if (object < 0) {
      point.r = point.g = point.b = 0;
      continue;
    }
    const auto& rgb = objects[static_cast<std::size_t>(object)].rgb;
    point.r = toByte(rgb.x());
    point.g = toByte(rgb.y());
    point.b = toByte(rgb.z());
    scan.labels[index] = objects[static_cast<std::size_t>(object)].label;
  }
  return scan;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr renderCluster(const pcl::PolygonMesh& mesh,
                                                  const Eigen::Isometry3d& model_to_camera,
                                                  const CameraIntrinsics& intrinsics,
                                                  const ScanNoise& noise) {
  validate(intrinsics, noise);
  SceneObject object;
  object.mesh = &mesh;
  object.pose = model_to_camera;
  const DepthBuffer buffer = rayCast({object}, intrinsics);
  const std::vector<Eigen::Vector3f> points = noisyPoints(buffer, intrinsics, noise);

  pcl::PointCloud<pcl::PointXYZ>::Ptr cluster(new pcl::PointCloud<pcl::PointXYZ>);
  for (std::size_t index = 0; index < points.size(); ++index) {
    if (buffer.object[index] >= 0) {
      cluster->push_back(pcl::PointXYZ(points[index].x(), points[index].y(), points[index].z()));
    }
  }
  cluster->is_dense = true;
  return cluster;
}

std::vector<Eigen::Vector3f> scanPoints(const Scan& scan) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(scan.cloud->size());
  for (const auto& p : *scan.cloud)
    points.emplace_back(p.x, p.y, p.z);
  return points;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr extractLabelCloud(const Scan& scan, int label) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cluster(new pcl::PointCloud<pcl::PointXYZ>);
  for (std::size_t index = 0; index < scan.labels.size(); ++index) {
    const auto& p = (*scan.cloud)[index];
    if (scan.labels[index] == label && std::isfinite(p.z)) {
      cluster->push_back(pcl::PointXYZ(p.x, p.y, p.z));
    }
  }
  cluster->is_dense = true;
  return cluster;
}

Eigen::Matrix3d randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> gaussian(0.0, 1.0);
  Eigen::Quaterniond q;
  do {
    const double w = gaussian(rng);
    const double x = gaussian(rng);
    const double y = gaussian(rng);
    const double z = gaussian(rng);
    q = Eigen::Quaterniond(w, x, y, z);
  } while (q.norm() < 1e-9);
  return q.normalized().toRotationMatrix();
}

Eigen::Isometry3d randomTabletopPose(std::mt19937_64& rng, double distance_min,
                                     double distance_max) {
  if (!(distance_min > 0.0) || !(distance_max >= distance_min)) {
    throw std::invalid_argument("randomTabletopPose: need 0 < distance_min <= distance_max");
  }
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = randomRotation(rng);
  std::uniform_real_distribution<double> lateral(-0.15, 0.15);
  std::uniform_real_distribution<double> depth(distance_min, distance_max);
  const double x = lateral(rng);
  const double y = lateral(rng);
  const double z = depth(rng);
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
}

RandomView randomView(const pcl::PolygonMesh& mesh, std::uint64_t seed, std::size_t min_points) {
  std::mt19937_64 rng(seed);
  RandomView v;
  do {
    v.truth = randomTabletopPose(rng);
    ScanNoise noise;
    noise.seed = seed;
    v.cluster = renderCluster(mesh, v.truth, CameraIntrinsics(), noise);
  } while (v.cluster->size() < min_points);
  return v;
}

Eigen::Isometry3d standOnTable(const pcl::PolygonMesh& mesh, const Eigen::Vector3d& xy_yaw) {
  Eigen::Isometry3d model_to_table = Eigen::Isometry3d::Identity();
  model_to_table.linear() =
      Eigen::AngleAxisd(xy_yaw.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  model_to_table.translation() =
      Eigen::Vector3d(xy_yaw.x(), xy_yaw.y(), -boundingBox(mesh).min().z());
  return model_to_table;
}

Eigen::Isometry3d tableToCamera(double camera_height, double camera_tilt_deg) {
  if (!(camera_height > 0.0) || !(camera_tilt_deg > 0.0 && camera_tilt_deg <= 90.0)) {
    throw std::invalid_argument("makeTabletopScene: need height > 0 and tilt in (0, 90]");
  }
  // Camera in the table frame: looking at the table centre, tilted below the horizontal.
  const double tilt = camera_tilt_deg * kPi / 180.0;
  const Eigen::Vector3d forward(0.0, std::cos(tilt), -std::sin(tilt));
  const Eigen::Vector3d right = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d down = forward.cross(right);  // camera y = z cross x
  Eigen::Isometry3d camera_to_table = Eigen::Isometry3d::Identity();
  camera_to_table.linear().col(0) = right;
  camera_to_table.linear().col(1) = down;
  camera_to_table.linear().col(2) = forward;
  camera_to_table.translation() = -(camera_height / std::sin(tilt)) * forward;
  return camera_to_table.inverse();
}

double visibleShare(const Scan& scene, int label, const SceneObject& object,
                    const CameraIntrinsics& intrinsics) {
  SceneObject alone = object;
  alone.label = 0;
  const Scan own = renderScan({alone}, intrinsics, ScanNoise::none());
  const auto covered = std::count(own.labels.begin(), own.labels.end(), 0);
  const auto seen = std::count(scene.labels.begin(), scene.labels.end(), label);
  return covered > 0 ? std::min(1.0, static_cast<double>(seen) / static_cast<double>(covered))
                     : 0.0;
}

double inViewShare(const SceneObject& object, const CameraIntrinsics& intrinsics, int pad) {
  if (pad < 0)
    throw std::invalid_argument("inViewShare: negative pad");
  validate(intrinsics, ScanNoise::none());
  if (object.mesh == nullptr)
    throw std::invalid_argument("inViewShare: SceneObject without mesh");
  // No pixel beyond the object's projected bounding box can be covered: pad only that far
  // (an object wholly in view costs one image, not one padded by 640 pixels on every side).
  double beyond = 0.0;
  bool in_front = true;
  for (const Eigen::Vector3d& vertex : meshVertices(*object.mesh)) {
    const Eigen::Vector3d p = object.pose * vertex;
    in_front = in_front && p.z() > kNearDepth;
    if (!in_front)
      break;
    const double u = intrinsics.fx * p.x() / p.z() + intrinsics.cx;
    const double v = intrinsics.fy * p.y() / p.z() + intrinsics.cy;
    beyond =
        std::max({beyond, -u, u - (intrinsics.width - 1.0), -v, v - (intrinsics.height - 1.0)});
  }
  if (in_front)
    pad = static_cast<int>(std::min<double>(pad, std::ceil(beyond) + 1.0));
  CameraIntrinsics wide = intrinsics;
  wide.width += 2 * pad;
  wide.height += 2 * pad;
  wide.cx += pad;
  wide.cy += pad;
  const DepthBuffer own = rayCast({object}, wide);  // the depths only: no noise, no cloud
  std::size_t whole = 0, in_view = 0;
  for (int v = 0; v < wide.height; ++v)
    for (int u = 0; u < wide.width; ++u)
      if (own.object[static_cast<std::size_t>(v) * wide.width + u] == 0) {
        ++whole;
        in_view +=
            u >= pad && v >= pad && u < pad + intrinsics.width && v < pad + intrinsics.height;
      }
  return whole > 0 ? static_cast<double>(in_view) / static_cast<double>(whole) : 0.0;
}

void addEdgeArtefacts(Scan& scan, const EdgeArtefacts& artefacts) {
  if (!(artefacts.edge_step > 0.0) || !(artefacts.dropout >= 0.0 && artefacts.dropout <= 1.0) ||
      !(artefacts.flying >= 0.0 && artefacts.flying <= 1.0))
    throw std::invalid_argument("addEdgeArtefacts: invalid parameters");
  auto& cloud = *scan.cloud;
  const int width = static_cast<int>(cloud.width), height = static_cast<int>(cloud.height);
  const std::vector<pcl::PointXYZRGB> measured(cloud.points.begin(), cloud.points.end());
  std::mt19937_64 rng(artefacts.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      const float z = measured[i].z;
      if (!std::isfinite(z))
        continue;
      float other = z;  // the neighbour across the largest step
      const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
      for (int k = 0; k < 4; ++k) {
        const int nu = u + du[k], nv = v + dv[k];
        if (nu < 0 || nv < 0 || nu >= width || nv >= height)
          continue;
        const float zn = measured[static_cast<std::size_t>(nv) * width + nu].z;
        if (std::isfinite(zn) && std::abs(zn - z) > std::abs(other - z))
          other = zn;
      }
      if (!(std::abs(other - z) > artefacts.edge_step))
        continue;
      if (unit(rng) < artefacts.dropout) {
        cloud[i].x = cloud[i].y = cloud[i].z = nan;
      } else if (unit(rng) < artefacts.flying) {
        const float scale = (z + static_cast<float>(unit(rng)) * (other - z)) / z;
        cloud[i].x *= scale;
        cloud[i].y *= scale;
        cloud[i].z *= scale;
      }
    }
}

TabletopScene makeTabletopScene(const std::vector<SyntheticModel>& objects,
                                const std::vector<Eigen::Vector3d>& table_xy_yaw,
                                const CameraIntrinsics& intrinsics, const ScanNoise& noise,
                                double camera_height, double camera_tilt_deg) {
  if (objects.size() != table_xy_yaw.size()) {
    throw std::invalid_argument("makeTabletopScene: one (x, y, yaw) per object is required");
  }
  TabletopScene scene;
  scene.table_to_camera = tableToCamera(camera_height, camera_tilt_deg);
  const Eigen::Vector3d normal = scene.table_to_camera.linear() * Eigen::Vector3d::UnitZ();
  const double d = -normal.dot(scene.table_to_camera.translation());
  scene.table_plane = Eigen::Vector4d(normal.x(), normal.y(), normal.z(), d).cast<float>();

  const pcl::PolygonMesh table = makePlane(1.2, 0.8);
  std::vector<SceneObject> scene_objects;
  SceneObject table_object;
  table_object.mesh = &table;
  table_object.pose = scene.table_to_camera;
  table_object.rgb = Eigen::Vector3f(0.60f, 0.55f, 0.50f);
  table_object.label = 0;
  scene_objects.push_back(table_object);

  for (std::size_t i = 0; i < objects.size(); ++i) {
    SceneObject object;
    object.mesh = &objects[i].mesh;
    object.pose = scene.table_to_camera * standOnTable(objects[i].mesh, table_xy_yaw[i]);
    object.rgb = objects[i].rgb;
    object.label = static_cast<int>(i) + 1;
    scene_objects.push_back(object);
    scene.poses.push_back(object.pose);
    scene.names.push_back(objects[i].name);
  }
  scene.scan = renderScan(scene_objects, intrinsics, noise);
  return scene;
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
