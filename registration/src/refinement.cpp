/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/distance_field.h>
#include <pcl/icf/registration/refinement.h>
#include <pcl_icf_internal/damped_step.h>
#include <pcl_icf_internal/parameter_check.h>

#include <Eigen/Eigenvalues>

#include <omp.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pcl {
namespace icf {

void RefinementParams::validate() const {
  const internal::ParameterCheck fail("RefinementParams");
  if (max_iterations < 0 || max_iterations > 100000)
    fail("max_iterations", max_iterations, "must lie in [0, 100000]");
  if (!(initial_inlier_distance > 0.f) || !std::isfinite(initial_inlier_distance))
    fail("initial_inlier_distance", initial_inlier_distance, "must be positive and finite");
  if (!(final_inlier_distance > 0.f) || final_inlier_distance > initial_inlier_distance)
    fail("final_inlier_distance", final_inlier_distance,
         "must be positive and at most initial_inlier_distance");
  if (!(inlier_shrink > 0.f && inlier_shrink <= 1.f))
    fail("inlier_shrink", inlier_shrink, "must lie in (0, 1]");
  if (!(damping >= 0.f) || !std::isfinite(damping))
    fail("damping", damping, "must be finite and >= 0");
  if (!(degeneracy_ratio >= 0.f && degeneracy_ratio < 1.f))
    fail("degeneracy_ratio", degeneracy_ratio, "must lie in [0, 1)");
  if (!(transformation_epsilon >= 0.0) || !(rotation_epsilon >= 0.0) ||
      !(euclidean_fitness_epsilon >= 0.0))
    fail("*_epsilon", -1, "must be >= 0");
}

namespace internal {

int solveDampedDegeneracyAware(const Eigen::Matrix<double, 6, 6>& H,
                               const Eigen::Matrix<double, 6, 1>& g, double damping, double ratio,
                               Eigen::Matrix<double, 6, 1>& x) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(H);
  const auto& values = eig.eigenvalues();  // ascending
  const double largest = values[5];
  x.setZero();
  if (!(largest > 0.0) || !std::isfinite(largest))
    return 6;
  const double lm = damping * H.trace() / 6.0;
  int degenerate = 0;
  for (int k = 0; k < 6; ++k) {
    if (values[k] < ratio * largest) {
      ++degenerate;
      continue;
    }
    const Eigen::Matrix<double, 6, 1> v = eig.eigenvectors().col(k);
    x -= v * (v.dot(g) / (values[k] + lm));
  }
  return degenerate;
}

}  // namespace internal

namespace {

struct NormalEquations {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double weighted_sq = 0.0, weight = 0.0;

  void add(const NormalEquations& o) {
    H += o.H;
    g += o.g;
    weighted_sq += o.weighted_sq;
    weight += o.weight;
  }
};

/** One point's contribution, given its closest point \a c and residual direction \a u in the
 * model frame; the rotation is about \a pivot. */
void accumulate(const Eigen::Vector3f& y, const Eigen::Vector3f& c, const Eigen::Vector3f& u,
                const Eigen::Vector3f& pivot, float radius, double scale, NormalEquations& ne) {
  const double r = u.dot(y - c);
  const double t = r / radius;
  if (!(std::abs(t) < 1.0))
    return;
  const double w = (1.0 - t * t) * (1.0 - t * t);  // Tukey biweight
  // d r / d(omega, v) for y' = pivot + (I + [omega]x)(y - pivot) + v; rotation columns scaled
  // by 1/scale so both blocks are in length units (conditioning of the degeneracy test).
  Eigen::Matrix<double, 6, 1> J;
  J.head<3>() = (y - pivot).cross(u).cast<double>() / scale;
  J.tail<3>() = u.cast<double>();
  ne.H.noalias() += w * J * J.transpose();
  ne.g.noalias() += w * r * J;
  ne.weighted_sq += w * r * r;
  ne.weight += w;
}

/** The iteration shared by the exact and the field refinement. \a correspond(i, y, radius, c, u)
 * fills the closest point and residual direction of the model-frame point y of the i-th used
 * scene point (the same i in every iteration), or returns false. */
template <typename Correspond>
RefinementResult iterate(const Correspond& correspond, const Eigen::Vector3f& pivot, double scale,
                         const std::vector<Eigen::Vector3f>& scene_points,
                         const Eigen::Isometry3f& initial, const RefinementParams& params,
                         int threads, const IterationCallback& callback) {
  params.validate();
  RefinementResult result;
  result.scene_to_model = initial;
  if (scene_points.empty())
    return result;
  const std::size_t stride =
      params.max_points > 0 ? std::max<std::size_t>(1, scene_points.size() / params.max_points) : 1;
  const int n = static_cast<int>((scene_points.size() + stride - 1) / stride);
  float radius = params.initial_inlier_distance;
  double previous_fitness = std::numeric_limits<double>::infinity();
  threads = std::max(1, threads);
  // Fixed chunks reduced in order: the same sums for any thread count, one thread included.
  const int chunks = 64;
  std::vector<NormalEquations> partial(static_cast<std::size_t>(chunks));

  for (int it = 0; it < params.max_iterations; ++it) {
    const Eigen::Isometry3f T = result.scene_to_model;
    std::fill(partial.begin(), partial.end(), NormalEquations());
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (int chunk = 0; chunk < chunks; ++chunk)
      for (int i = chunk; i < n; i += chunks) {
        const Eigen::Vector3f y = T * scene_points[static_cast<std::size_t>(i) * stride];
        Eigen::Vector3f c, u;
        if (correspond(i, y, radius, c, u))
          accumulate(y, c, u, pivot, radius, scale, partial[static_cast<std::size_t>(chunk)]);
      }
    NormalEquations ne;
    for (const auto& p : partial)
      ne.add(p);
    result.iterations = it + 1;
    if (ne.weight < 6.0)  // fewer than ~6 full-weight constraints: nothing reliable to solve
      break;
    Eigen::Matrix<double, 6, 1> x;
    result.degenerate_directions = internal::solveDampedDegeneracyAware(ne.H, ne.g, params.damping,
                                                                        params.degeneracy_ratio, x);
    const Eigen::Vector3d omega = x.head<3>() / scale;
    const Eigen::Vector3d v = x.tail<3>();
    const double angle = omega.norm();
    Eigen::Isometry3f step = Eigen::Isometry3f::Identity();
    if (angle > 0.0)
      step.linear() = Eigen::AngleAxisf(static_cast<float>(angle), (omega / angle).cast<float>())
                          .toRotationMatrix();
    step.translation() = pivot + v.cast<float>() - step.linear() * pivot;
    result.scene_to_model = step * T;
    const double fitness = ne.weighted_sq / ne.weight;
    result.weighted_rmse = std::sqrt(fitness);
    if (callback)
      callback(result.scene_to_model, it + 1);

    const bool small_step =
        v.squaredNorm() < params.transformation_epsilon && angle < params.rotation_epsilon;
    const bool flat_fitness =
        std::isfinite(previous_fitness) &&
        std::abs(previous_fitness - fitness) < params.euclidean_fitness_epsilon * previous_fitness;
    previous_fitness = fitness;
    if (radius <= params.final_inlier_distance * 1.0001f && (small_step || flat_fitness)) {
      result.converged = true;
      break;
    }
    radius = std::max(params.final_inlier_distance, radius * params.inlier_shrink);
  }
  return result;
}

/** The query radius for \a y: \a radius, or less when \a face (-1: none) is closer than
 * that. Slightly widened so that rounding cannot leave the face itself outside. */
float withinPreviousFace(const FaceMesh& mesh, int face, const Eigen::Vector3f& y, float radius) {
  if (face < 0)
    return radius;
  const float d =
      std::sqrt(closestPointOnMeshFace(mesh, static_cast<std::size_t>(face), y).squared_distance);
  return std::min(radius, d * (1.f + 1e-5f) + 1e-9f);
}

double modelScale(const FaceMesh& mesh) {
  return std::max(1e-3, 0.5 * static_cast<double>((mesh.boundsMax() - mesh.boundsMin()).norm()));
}

}  // namespace

RefinementResult refinePose(const ClosestFaceQuery& index,
                            const std::vector<Eigen::Vector3f>& scene_points,
                            const Eigen::Isometry3f& initial, const RefinementParams& params,
                            int threads, const IterationCallback& callback) {
  // Each point's closest face of the previous iteration bounds its closest distance now (a
  // step moves a point by little): querying within that bound instead of the Tukey radius
  // lets the BVH skip most faces. Exact all the same: the closest face lies within the bound.
  std::vector<int> previous_face(scene_points.size(), -1);
  const auto correspond = [&index, &previous_face](int i, const Eigen::Vector3f& y, float radius,
                                                   Eigen::Vector3f& c, Eigen::Vector3f& u) {
    int& previous = previous_face[static_cast<std::size_t>(i)];
    ClosestFace hit = index.closestFace(y, withinPreviousFace(index.mesh(), previous, y, radius));
    if (!hit.found()) {
      previous = -1;
      return false;
    }
    previous = hit.face;
    c = hit.point;
    u = residualDirection(index.mesh(), y, hit);
    return true;
  };
  return iterate(correspond, index.mesh().surfaceCentroid(), modelScale(index.mesh()), scene_points,
                 initial, params, threads, callback);
}

RefinementResult refinePoseOnField(const ClosestPointField& field, const Eigen::Vector3f& pivot,
                                   double scale, const std::vector<Eigen::Vector3f>& scene_points,
                                   const Eigen::Isometry3f& initial,
                                   const RefinementParams& params) {
  const auto correspond = [&field](int, const Eigen::Vector3f& y, float radius, Eigen::Vector3f& c,
                                   Eigen::Vector3f& u) {
    c = field.closestPoint(y);
    const Eigen::Vector3f offset = y - c;
    const float d = offset.norm();
    if (!(d < radius) || !(d > 1e-7f))
      return false;
    u = offset / d;
    return true;
  };
  return iterate(correspond, pivot, scale, scene_points, initial, params, 1, {});
}

}  // namespace icf
}  // namespace pcl
