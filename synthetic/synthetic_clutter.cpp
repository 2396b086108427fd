#include "synthetic/synthetic_clutter.h"

#include "synthetic/mesh_geometry.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

namespace pcl {
namespace icf {
namespace synthetic {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeskX = 0.6, kDeskY = 0.4;  ///< half sides of the 1.2 x 0.8 m desk
/** The shelf behind the desk's far edge: 1.2 x 0.3 m, its surface this high above the desk. */
constexpr double kShelfY = 0.6, kShelfHalfDepth = 0.15, kShelfHeight = 0.15;

/** An object's place in the desk frame and what the placement rules need of it. */
struct Placed {
  const SyntheticModel* model = nullptr;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  double radius = 0.0;    ///< footprint's bounding circle
  double base = 0.0;      ///< height of the surface it stands on
  double height = 0.0;    ///< its own height
  bool flat_top = false;  ///< another object can stand on it
  bool carries = false;   ///< one already does
  bool stacked = false, background = false;
  double yaw = 0.0;
};

double footprintRadius(const pcl::PolygonMesh& mesh) {
  const Eigen::AlignedBox3d box = boundingBox(mesh);
  return 0.5 * (box.max() - box.min()).head<2>().norm();
}

/** True when the vertices at the mesh's top span at least 60% of its footprint along x and y
 * (a box's lid, a can's cap): something can stand on it. */
bool hasFlatTop(const pcl::PolygonMesh& mesh) {
  const Eigen::AlignedBox3d box = boundingBox(mesh);
  Eigen::AlignedBox2d top;
  for (const auto& v : meshVertices(mesh))
    if (v.z() > box.max().z() - 1e-6)
      top.extend(v.head<2>());
  if (top.isEmpty())
    return false;
  const Eigen::Vector2d span = top.sizes(), full = (box.max() - box.min()).head<2>();
  return span.x() >= 0.6 * full.x() && span.y() >= 0.6 * full.y();
}

Placed describe(const SyntheticModel& model) {
  Placed p;
  p.model = &model;
  p.radius = footprintRadius(model.mesh);
  const Eigen::AlignedBox3d box = boundingBox(model.mesh);
  p.height = box.max().z() - box.min().z();
  p.flat_top = hasFlatTop(model.mesh);
  return p;
}

/** Free of the desk objects already placed (bounding circles apart) and on the desk. */
bool freeOnDesk(const Placed& p, const std::vector<Placed>& placed) {
  if (std::abs(p.xy.x()) > kDeskX - p.radius || std::abs(p.xy.y()) > kDeskY - p.radius)
    return false;
  for (const auto& q : placed)
    if (!q.stacked && !q.background && (p.xy - q.xy).norm() < p.radius + q.radius)
      return false;
  return true;
}

/** Puts \a p on the desk: against a desk object already there (touch_probability), else
 * anywhere free. False when no place is found. */
bool placeOnDesk(Placed& p, const std::vector<Placed>& placed, const ClutterSpec& spec,
                 std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0), angle(-kPi, kPi);
  std::vector<const Placed*> neighbours;
  for (const auto& q : placed)
    if (!q.stacked && !q.background)
      neighbours.push_back(&q);
  if (!neighbours.empty() && unit(rng) < spec.touch_probability)
    for (int attempt = 0; attempt < 50; ++attempt) {
      const Placed& q =
          *neighbours[static_cast<std::size_t>(unit(rng) * neighbours.size()) % neighbours.size()];
      const double a = angle(rng), gap = spec.gap_max * unit(rng);
      p.xy = q.xy + (p.radius + q.radius + gap) * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (freeOnDesk(p, placed))
        return true;
    }
  for (int attempt = 0; attempt < 200; ++attempt) {
    p.xy = Eigen::Vector2d((2.0 * unit(rng) - 1.0) * kDeskX, (2.0 * unit(rng) - 1.0) * kDeskY);
    if (freeOnDesk(p, placed))
      return true;
  }
  return false;
}

/** Puts \a p on the flat top of a desk object that carries nothing yet and is at least as wide
 * as \a p (bounding circles), so it does not overhang into the neighbours. False when there is
 * none. */
bool placeOnTop(Placed& p, std::vector<Placed>& placed, std::mt19937_64& rng) {
  std::vector<std::size_t> carriers;
  for (std::size_t i = 0; i < placed.size(); ++i)
    if (placed[i].flat_top && !placed[i].carries && !placed[i].stacked && !placed[i].background &&
        placed[i].radius >= p.radius)
      carriers.push_back(i);
  if (carriers.empty())
    return false;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Placed& carrier =
      placed[carriers[static_cast<std::size_t>(unit(rng) * carriers.size()) % carriers.size()]];
  carrier.carries = true;
  p.xy = carrier.xy + 0.01 * Eigen::Vector2d(2.0 * unit(rng) - 1.0, 2.0 * unit(rng) - 1.0);
  p.base = carrier.base + carrier.height;
  p.stacked = true;
  return true;
}

/** Puts \a p on the shelf behind the desk, free of the shelf's other objects. */
bool placeOnShelf(Placed& p, const std::vector<Placed>& placed, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int attempt = 0; attempt < 200; ++attempt) {
    p.xy = Eigen::Vector2d((2.0 * unit(rng) - 1.0) * (kDeskX - p.radius),
                           kShelfY + (2.0 * unit(rng) - 1.0) * (kShelfHalfDepth - p.radius));
    bool free = p.radius < kShelfHalfDepth;
    for (const auto& q : placed)
      free = free && !(q.background && (p.xy - q.xy).norm() < p.radius + q.radius);
    if (free) {
      p.base = kShelfHeight;
      p.background = true;
      return true;
    }
  }
  return false;
}

/** A layout: the target first, then what found a place. */
std::vector<Placed> drawLayout(const SyntheticModel& target,
                               const std::vector<SyntheticModel>& distractors,
                               const ClutterSpec& spec, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> on_desk(spec.min_objects - 1, spec.max_objects - 1);
  std::uniform_int_distribution<int> on_shelf(spec.min_background, spec.max_background);
  std::uniform_int_distribution<std::size_t> pick(0, distractors.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0), yaw(-kPi, kPi);
  std::vector<Placed> placed;
  const int desk_count = on_desk(rng), shelf_count = on_shelf(rng);
  for (int i = 0; i < desk_count; ++i) {
    Placed p = describe(distractors[pick(rng)]);
    p.yaw = yaw(rng);
    const bool stack = i > 0 && unit(rng) < spec.stack_probability;
    if ((stack && placeOnTop(p, placed, rng)) || placeOnDesk(p, placed, spec, rng))
      placed.push_back(p);
  }
  for (int i = 0; i < shelf_count; ++i) {
    Placed p = describe(distractors[pick(rng)]);
    p.yaw = yaw(rng);
    if (placeOnShelf(p, placed, rng))
      placed.push_back(p);
  }
  Placed t = describe(target);
  t.yaw = yaw(rng);
  const bool stack = unit(rng) < spec.stack_probability;
  if (!(stack && placeOnTop(t, placed, rng)) && !placeOnDesk(t, placed, spec, rng))
    return {};  // a desk too full for the target: draw again
  placed.insert(placed.begin(), t);
  return placed;
}

DeskObject deskObject(const Placed& p) {
  return {p.model, p.xy.x(), p.xy.y(), p.yaw, p.base, p.stacked, p.background};
}

Eigen::Isometry3d modelToDesk(const DeskObject& o) {
  Eigen::Isometry3d pose = standOnTable(o.model->mesh, Eigen::Vector3d(o.x, o.y, o.yaw));
  pose.translation().z() += o.base;
  return pose;
}

/** The desk and the shelf behind its far edge. */
struct Furniture {
  pcl::PolygonMesh desk = makePlane(2 * kDeskX, 2 * kDeskY);
  pcl::PolygonMesh shelf = makePlane(2 * kDeskX, 2 * kShelfHalfDepth);
};

/** Renders scene.layout seen from scene.view into scene.present and measures the target's
 * visible share. Returns what was rendered: the desk, the shelf, then the layout's objects. */
std::vector<SceneObject> renderPresent(ClutterScene& scene, const Furniture& furniture,
                                       const CameraIntrinsics& intrinsics) {
  const Eigen::Isometry3d desk_to_camera =
      tableToCamera(scene.view.camera_height, scene.view.camera_tilt);
  const Eigen::Vector3d normal = desk_to_camera.linear() * Eigen::Vector3d::UnitZ();
  scene.desk_plane =
      Eigen::Vector4d(normal.x(), normal.y(), normal.z(), -normal.dot(desk_to_camera.translation()))
          .cast<float>();
  std::vector<SceneObject> objects(2);
  objects[0].mesh = &furniture.desk;
  objects[0].pose = desk_to_camera;
  objects[0].rgb = Eigen::Vector3f(0.60f, 0.55f, 0.50f);
  objects[0].label = 0;
  objects[1].mesh = &furniture.shelf;
  objects[1].pose = desk_to_camera * Eigen::Translation3d(0.0, kShelfY, kShelfHeight);
  objects[1].rgb = Eigen::Vector3f(0.45f, 0.40f, 0.35f);
  objects[1].label = -2;
  for (std::size_t i = 0; i < scene.layout.size(); ++i) {
    const DeskObject& d = scene.layout[i];
    SceneObject o;
    o.mesh = &d.model->mesh;
    o.pose = desk_to_camera * modelToDesk(d);
    o.rgb = d.model->rgb;
    o.label = static_cast<int>(i) + 1;
    objects.push_back(o);
    scene.names.push_back(d.model->name);
    scene.poses.push_back(o.pose);
    scene.stacked.push_back(d.stacked);
    scene.background.push_back(d.background);
  }
  scene.present = renderScan(objects, intrinsics, scene.view.noise);
  scene.target_visible = visibleShare(scene.present, 1, objects[2], intrinsics);
  return objects;
}

/** The rest of the frame after renderPresent: the target's share in view, the twin without the
 * target (\a objects as renderPresent returned them) and both frames' edge artefacts. */
void renderAbsent(ClutterScene& scene, std::vector<SceneObject> objects,
                  const CameraIntrinsics& intrinsics) {
  scene.target_in_view = inViewShare(objects[2], intrinsics);
  objects.erase(objects.begin() + 2);
  scene.absent = renderScan(objects, intrinsics, scene.view.noise);
  addEdgeArtefacts(scene.present, scene.view.edges);
  addEdgeArtefacts(scene.absent, scene.view.edges);
}

void validate(const ClutterSpec& spec, const std::vector<SyntheticModel>& distractors) {
  if (distractors.empty())
    throw std::invalid_argument("makeClutterScene: no distractors");
  if (spec.min_objects < 1 || spec.max_objects < spec.min_objects || spec.min_background < 0 ||
      spec.max_background < spec.min_background ||
      !(spec.min_target_visible >= 0.0 && spec.min_target_visible < spec.max_target_visible) ||
      !(spec.max_target_visible <= 1.0) ||
      !(spec.touch_probability >= 0.0 && spec.touch_probability <= 1.0) ||
      !(spec.stack_probability >= 0.0 && spec.stack_probability <= 1.0) || !(spec.gap_max >= 0.0))
    throw std::invalid_argument("makeClutterScene: spec out of range");
}

}  // namespace

ClutterScene makeClutterScene(const SyntheticModel& target,
                              const std::vector<SyntheticModel>& distractors, std::uint64_t seed,
                              const ClutterSpec& spec, const CameraIntrinsics& intrinsics) {
  validate(spec, distractors);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> height(spec.camera_min_height, spec.camera_max_height),
      tilt(spec.camera_min_tilt, spec.camera_max_tilt);
  const Furniture furniture;
  for (int draw = 0; draw < 5000; ++draw) {
    const std::vector<Placed> layout = drawLayout(target, distractors, spec, rng);
    ClutterScene scene;
    scene.view.camera_height = height(rng);
    scene.view.camera_tilt = tilt(rng);
    scene.view.noise = spec.noise;
    scene.view.noise.seed = rng();
    scene.view.edges = spec.edges;
    scene.view.edges.seed = rng();
    if (layout.empty())
      continue;
    std::transform(layout.begin(), layout.end(), std::back_inserter(scene.layout), deskObject);
    std::vector<SceneObject> objects = renderPresent(scene, furniture, intrinsics);
    if (scene.target_visible < spec.min_target_visible ||
        scene.target_visible > spec.max_target_visible)
      continue;
    renderAbsent(scene, std::move(objects), intrinsics);
    return scene;
  }
  throw std::runtime_error("makeClutterScene: 5000 draws missed the target's visible share [" +
                           std::to_string(spec.min_target_visible) + ", " +
                           std::to_string(spec.max_target_visible) + "]");
}

ClutterScene renderClutterDesk(const std::vector<DeskObject>& layout, const DeskView& view,
                               const CameraIntrinsics& intrinsics) {
  if (layout.empty())
    throw std::invalid_argument("renderClutterDesk: an empty layout (layout[0] is the target)");
  for (std::size_t i = 0; i < layout.size(); ++i)
    if (!layout[i].model)
      throw std::invalid_argument("renderClutterDesk: object " + std::to_string(i) +
                                  " has no model");
  ClutterScene scene;
  scene.layout = layout;
  scene.view = view;
  const Furniture furniture;
  renderAbsent(scene, renderPresent(scene, furniture, intrinsics), intrinsics);
  return scene;
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
