#include "synthetic/synthetic_models.h"

#include "synthetic/mesh_geometry.h"

#include <cmath>
#include <stdexcept>

namespace pcl {
namespace icf {
namespace synthetic {

namespace {

constexpr double kPi = 3.14159265358979323846;

void requirePositive(double value, const char* what) {
  if (!(value > 0.0)) {
    throw std::invalid_argument(std::string("synthetic model: ") + what + " must be positive");
  }
}

/** Appends a quad (c - u - v, c + u - v, c + u + v, c - u + v), counter-clockwise seen from the
 *  side u x v points to. */
void addQuad(const Eigen::Vector3d& c, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
             std::vector<Eigen::Vector3d>& vertices, std::vector<Face>& faces) {
  const auto first = static_cast<pcl::index_t>(vertices.size());
  vertices.push_back(c - u - v);
  vertices.push_back(c + u - v);
  vertices.push_back(c + u + v);
  vertices.push_back(c - u + v);
  faces.push_back({first, first + 1, first + 2, first + 3});
}

/** Point on a regular polygon of radius r at corner k of n (corner 0 on +x), at height z. */
Eigen::Vector3d ringPoint(double r, int k, int n, double z) {
  const double angle = 2.0 * kPi * k / n;
  return Eigen::Vector3d(r * std::cos(angle), r * std::sin(angle), z);
}

/** Appends the two caps (bottom then top) as triangle fans: n ring vertices + 1 centre each. */
void addCapFans(double bottom_radius, double top_radius, double height, int n,
                std::vector<Eigen::Vector3d>& vertices, std::vector<Face>& faces) {
  const double z0 = -0.5 * height;
  const double z1 = 0.5 * height;
  const auto un = static_cast<pcl::index_t>(n);
  const auto bottom_ring = static_cast<pcl::index_t>(vertices.size());
  for (int k = 0; k < n; ++k) {
    vertices.push_back(ringPoint(bottom_radius, k, n, z0));
  }
  const auto top_ring = static_cast<pcl::index_t>(vertices.size());
  for (int k = 0; k < n; ++k) {
    vertices.push_back(ringPoint(top_radius, k, n, z1));
  }
  const auto bottom_centre = static_cast<pcl::index_t>(vertices.size());
  vertices.emplace_back(0.0, 0.0, z0);
  const auto top_centre = bottom_centre + 1;
  vertices.emplace_back(0.0, 0.0, z1);
  for (pcl::index_t k = 0; k < un; ++k) {  // bottom: clockwise seen from above = outward (-z)
    faces.push_back({bottom_centre, bottom_ring + (k + 1) % un, bottom_ring + k});
  }
  for (pcl::index_t k = 0; k < un; ++k) {  // top: counter-clockwise seen from above (+z)
    faces.push_back({top_centre, top_ring + k, top_ring + (k + 1) % un});
  }
}

/** Translates all vertices so that the bounding-box centre is the origin. */
pcl::PolygonMesh centred(const pcl::PolygonMesh& mesh) {
  const Eigen::AlignedBox3d box = boundingBox(mesh);
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.translation() = -box.center();
  return transformMesh(mesh, shift);
}

}  // namespace

pcl::PolygonMesh makeBox(double sx, double sy, double sz) {
  requirePositive(sx, "box size x");
  requirePositive(sy, "box size y");
  requirePositive(sz, "box size z");
  const Eigen::Vector3d ex(0.5 * sx, 0.0, 0.0);
  const Eigen::Vector3d ey(0.0, 0.5 * sy, 0.0);
  const Eigen::Vector3d ez(0.0, 0.0, 0.5 * sz);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Face> faces;
  addQuad(ex, ey, ez, vertices, faces);   // +x: y cross z = +x
  addQuad(-ex, ez, ey, vertices, faces);  // -x: z cross y = -x
  addQuad(ey, ez, ex, vertices, faces);   // +y: z cross x = +y
  addQuad(-ey, ex, ez, vertices, faces);  // -y: x cross z = -y
  addQuad(ez, ex, ey, vertices, faces);   // +z: x cross y = +z
  addQuad(-ez, ey, ex, vertices, faces);  // -z: y cross x = -z
  return makeMesh(vertices, faces);
}

pcl::PolygonMesh makeBox5() {
  return makeBox(0.14, 0.09, 0.05);
}

pcl::PolygonMesh makeFrustum(double bottom_radius, double top_radius, double height, int segments) {
  requirePositive(bottom_radius, "bottom radius");
  requirePositive(top_radius, "top radius");
  requirePositive(height, "height");
  if (segments < 3) {
    throw std::invalid_argument("makeFrustum: segments must be >= 3");
  }
  const auto n = static_cast<pcl::index_t>(segments);
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Face> faces;
  for (int k = 0; k < segments; ++k) {
    vertices.push_back(ringPoint(bottom_radius, k, segments, -0.5 * height));
  }
  for (int k = 0; k < segments; ++k) {
    vertices.push_back(ringPoint(top_radius, k, segments, 0.5 * height));
  }
  // Side quad k: tangent (bottom k -> bottom k+1) cross up = outward radial direction.
  for (pcl::index_t k = 0; k < n; ++k) {
    const pcl::index_t next = (k + 1) % n;
    faces.push_back({k, next, n + next, n + k});
  }
  addCapFans(bottom_radius, top_radius, height, segments, vertices, faces);
  return makeMesh(vertices, faces);
}

pcl::PolygonMesh makeCylinder(double radius, double height, int segments) {
  return makeFrustum(radius, radius, height, segments);
}

pcl::PolygonMesh makeYellowRoundSalt() {
  return makeCylinder(0.045, 0.13, 32);
}

pcl::PolygonMesh makeEisKaffe() {
  return makeCylinder(0.05, 0.15, 25);
}

pcl::PolygonMesh makeHexPrism(double circumradius, double height) {
  requirePositive(circumradius, "circumradius");
  requirePositive(height, "height");
  constexpr int n = 6;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Face> faces;
  for (int k = 0; k < n; ++k) {
    const auto first = static_cast<pcl::index_t>(vertices.size());
    vertices.push_back(ringPoint(circumradius, k, n, -0.5 * height));      // first + 0
    vertices.push_back(ringPoint(circumradius, k + 1, n, -0.5 * height));  // first + 1
    vertices.push_back(ringPoint(circumradius, k + 1, n, 0.5 * height));   // first + 2
    vertices.push_back(ringPoint(circumradius, k, n, 0.5 * height));       // first + 3
    faces.push_back({first, first + 1, first + 2});
    faces.push_back({first, first + 2, first + 3});
  }
  addCapFans(circumradius, circumradius, height, n, vertices, faces);
  return makeMesh(vertices, faces);
}

pcl::PolygonMesh makeAmicelly() {
  return makeHexPrism(0.04, 0.12);
}

pcl::PolygonMesh makeCup(double bottom_radius, double top_radius, double height, int segments) {
  return makeFrustum(bottom_radius, top_radius, height, segments);
}

pcl::PolygonMesh makeStatue() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pcl::PolygonMesh statue = makeBox(0.10, 0.07, 0.03);  // z in [-0.015, 0.015]

  pose.translation() = Eigen::Vector3d(0.02, -0.005, 0.015 + 0.045);
  appendMesh(statue, transformMesh(makeBox(0.04, 0.05, 0.09), pose));  // z in [0.015, 0.105]

  pose.linear() =
      Eigen::AngleAxisd(10.0 * kPi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.02, -0.005, 0.105 + 0.025);
  appendMesh(statue, transformMesh(makeHexPrism(0.02, 0.05), pose));  // z in [0.105, 0.155]
  return centred(statue);
}

pcl::PolygonMesh makePlane(double sx, double sy) {
  requirePositive(sx, "plane size x");
  requirePositive(sy, "plane size y");
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Face> faces;
  addQuad(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5 * sx, 0.0, 0.0),
          Eigen::Vector3d(0.0, 0.5 * sy, 0.0), vertices, faces);
  return makeMesh(vertices, faces);
}

SyntheticModel thesisModel(const std::string& name) {
  SyntheticModel model;
  model.name = name;
  if (name == "Box5") {
    model.mesh = makeBox5();
    model.symmetry = Symmetry::box(0.14, 0.09, 0.05);
    model.rgb = Eigen::Vector3f(0.10f, 0.25f, 0.80f);  // blue
  } else if (name == "EisKaffe") {
    model.mesh = makeEisKaffe();
    model.symmetry = Symmetry::cylinder(true);
    model.rgb = Eigen::Vector3f(0.15f, 0.35f, 0.75f);  // blue
  } else if (name == "YellowRoundSalt") {
    model.mesh = makeYellowRoundSalt();
    model.symmetry = Symmetry::cylinder(true);
    model.rgb = Eigen::Vector3f(0.95f, 0.85f, 0.10f);  // yellow
  } else if (name == "Amicelly") {
    model.mesh = makeAmicelly();
    model.symmetry = Symmetry::prism(6);
    model.rgb = Eigen::Vector3f(1.00f, 0.70f, 0.10f);  // yellow-orange
  } else if (name == "Cup") {
    model.mesh = makeCup();
    model.symmetry = Symmetry::cylinder(false);        // wider at the top: no flip symmetry
    model.rgb = Eigen::Vector3f(0.95f, 0.95f, 0.95f);  // white
  } else if (name == "Statue") {
    model.mesh = makeStatue();
    model.symmetry = Symmetry::none();
    model.rgb = Eigen::Vector3f(0.55f, 0.35f, 0.17f);  // brown
  } else {
    throw std::invalid_argument("thesisModel: unknown model '" + name + "'");
  }
  return model;
}

SyntheticModel suiteModel(const std::string& name) {
  const Eigen::Vector3f red(0.80f, 0.12f, 0.10f), blue(0.10f, 0.25f, 0.80f);
  SyntheticModel m;
  m.name = name;
  if (name == "LargeBox") {
    m.mesh = makeBox(0.20, 0.12, 0.08);
    m.symmetry = Symmetry::box(0.20, 0.12, 0.08);
  } else if (name == "TallCylinder" || name == "WideCylinder") {
    const bool tall = name == "TallCylinder";
    m.mesh = makeCylinder(tall ? 0.035 : 0.05, tall ? 0.16 : 0.10, 32);
    m.symmetry = Symmetry::cylinder(true);
    m.rgb = red;
  } else if (name == "OtherBox") {
    m.mesh = makeBox(0.16, 0.06, 0.10);
    m.symmetry = Symmetry::box(0.16, 0.06, 0.10);
    m.rgb = blue;
  } else {
    return thesisModel(name);
  }
  return m;
}

std::vector<std::string> thesisModelNames() {
  return {"Box5", "EisKaffe", "YellowRoundSalt", "Amicelly"};
}

std::vector<std::string> allModelNames() {
  return {"Box5", "EisKaffe", "YellowRoundSalt", "Amicelly", "Cup", "Statue"};
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
