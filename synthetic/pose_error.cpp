#include "synthetic/pose_error.h"

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

double radToDeg(double rad) {
  return rad * 180.0 / kPi;
}

bool nearlyEqual(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max({std::abs(a), std::abs(b), 1e-12});
}

}  // namespace

Symmetry Symmetry::none() {
  return Symmetry();
}

Symmetry Symmetry::box(double sx, double sy, double sz) {
  const double extent[3] = {sx, sy, sz};
  Symmetry symmetry;
  symmetry.kind = Kind::Discrete;
  // Enumerate the 48 signed permutation matrices; keep the proper rotations (det = +1) that map
  // each axis onto an axis of the same length.
  const int permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& perm : permutations) {
    bool same_lengths = true;
    for (int row = 0; row < 3; ++row) {
      same_lengths = same_lengths && nearlyEqual(extent[row], extent[perm[row]]);
    }
    if (!same_lengths) {
      continue;
    }
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      for (int row = 0; row < 3; ++row) {
        s(row, perm[row]) = ((signs >> row) & 1) ? -1.0 : 1.0;
      }
      if (s.determinant() > 0.0) {
        symmetry.group.push_back(s);
      }
    }
  }
  return symmetry;
}

Symmetry Symmetry::prism(int n) {
  if (n < 1) {
    throw std::invalid_argument("Symmetry::prism: n must be >= 1");
  }
  Symmetry symmetry;
  symmetry.kind = Kind::Discrete;
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d rz =
        Eigen::AngleAxisd(2.0 * kPi * k / n, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    symmetry.group.push_back(rz);
  }
  for (int k = 0; k < n; ++k) {
    symmetry.group.push_back(symmetry.group[static_cast<std::size_t>(k)] * flip);
  }
  return symmetry;
}

Symmetry Symmetry::cylinder(bool flip) {
  Symmetry symmetry;
  symmetry.kind = Kind::Axial;
  symmetry.axis = Eigen::Vector3d::UnitZ();
  symmetry.axial_flip = flip;
  return symmetry;
}

double rotationAngleDeg(const Eigen::Matrix3d& rotation) {
  const Eigen::Quaterniond q(rotation);
  return radToDeg(2.0 * std::atan2(q.vec().norm(), std::abs(q.w())));
}

double angleBetweenDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // atan2(|a x b|, a . b) is accurate for all angles, unlike acos of the normalised dot product.
  return radToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

PoseError poseError(const Eigen::Isometry3d& estimated_model_to_scene,
                    const Eigen::Isometry3d& true_model_to_scene, const Symmetry& symmetry) {
  PoseError error;
  error.translation =
      (estimated_model_to_scene.translation() - true_model_to_scene.translation()).norm();
  const Eigen::Matrix3d r_est = estimated_model_to_scene.linear();
  const Eigen::Matrix3d r_true = true_model_to_scene.linear();
  const Eigen::Matrix3d relative = r_true.transpose() * r_est;

  switch (symmetry.kind) {
    case Symmetry::Kind::None:
      error.rotation_deg = rotationAngleDeg(relative);
      break;
    case Symmetry::Kind::Discrete: {
      double best = rotationAngleDeg(relative);  // identity, also if the group is empty
      for (const auto& s : symmetry.group) {
        best = std::min(best, rotationAngleDeg(relative * s));
      }
      error.rotation_deg = best;
      break;
    }
    case Symmetry::Kind::Axial: {
      const double angle = angleBetweenDeg(r_est * symmetry.axis, r_true * symmetry.axis);
      error.rotation_deg = symmetry.axial_flip ? std::min(angle, 180.0 - angle) : angle;
      break;
    }
  }
  return error;
}

double addS(const pcl::PolygonMesh& mesh, const Eigen::Isometry3d& est,
            const Eigen::Isometry3d& truth) {
  const auto vertices = meshVertices(mesh);
  if (vertices.empty()) {
    return 0.0;
  }
  std::vector<Eigen::Vector3d> est_vertices;
  est_vertices.reserve(vertices.size());
  for (const auto& v : vertices) {
    est_vertices.push_back(est * v);
  }
  double sum = 0.0;
  for (const auto& v : vertices) {
    const Eigen::Vector3d p = truth * v;
    double best = std::numeric_limits<double>::infinity();
    for (const auto& q : est_vertices) {
      best = std::min(best, (p - q).squaredNorm());
    }
    sum += std::sqrt(best);
  }
  return sum / static_cast<double>(vertices.size());
}

double modelDiameter(const pcl::PolygonMesh& mesh) {
  const auto vertices = meshVertices(mesh);
  double best = 0.0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    for (std::size_t j = i + 1; j < vertices.size(); ++j) {
      best = std::max(best, (vertices[i] - vertices[j]).squaredNorm());
    }
  }
  return std::sqrt(best);
}

}  // namespace synthetic
}  // namespace icf
}  // namespace pcl
