// The refinement's step (pcl_icf_internal/damped_step.h; doc/icf.md eq. 6-7) on its own:
// solveDampedDegeneracyAware against an independent solver (Eigen's LDLT) on random full-rank
// symmetric positive definite H, with and without the Levenberg-Marquardt damping, and on the
// normal equations of a plane, whose point-to-plane residuals say nothing about the in-plane
// translations and the turn about the normal: those frozen directions must get no step at all,
// and the constrained ones the exact step of the reduced problem.
#include <pcl_icf_internal/damped_step.h>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <cmath>
#include <cstdint>
#include <random>

namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using pcl::icf::internal::solveDampedDegeneracyAware;

Vector6d gaussian6(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  Vector6d v;
  for (int i = 0; i < 6; ++i)
    v[i] = n(rng);
  return v;
}

/** A random symmetric positive definite H = Q diag(l) Q^T with a uniformly random orthonormal Q
 * and eigenvalues l log-uniform in [1, \a condition]: full rank, condition number at most
 * \a condition. */
Matrix6d randomSpd(std::mt19937_64& rng, double condition) {
  Matrix6d a;
  for (int c = 0; c < 6; ++c)
    a.col(c) = gaussian6(rng);
  const Matrix6d q = Eigen::HouseholderQR<Matrix6d>(a).householderQ();
  std::uniform_real_distribution<double> u(0.0, std::log(condition));
  Vector6d l;
  for (int i = 0; i < 6; ++i)
    l[i] = std::exp(u(rng));
  const Matrix6d h = q * l.asDiagonal() * q.transpose();
  return 0.5 * (h + h.transpose());
}

// Tolerance of the full-rank comparisons: both solvers are backward stable, so each is within
// about condition x n x eps of the exact solution; with condition <= 100, n = 6 and
// eps = 2.2e-16 that is 1.3e-13 relative. 1e-11 leaves the eigensolver's larger constant room
// and still catches any wrong term (a missing or doubled damping, a sign, a dropped direction:
// all of order 1e-4 relative or more).
constexpr double kRelative = 1e-11;

TEST(DampedStep, UndampedIsMinusHInverseGOnFullRankH) {
  std::mt19937_64 rng(31);
  for (int trial = 0; trial < 50; ++trial) {
    const Matrix6d h = randomSpd(rng, 100.0);
    const Vector6d g = gaussian6(rng);
    Vector6d x;
    // ratio 1e-3 (the default): no eigenvalue of a condition-100 H is below it.
    EXPECT_EQ(solveDampedDegeneracyAware(h, g, 0.0, 1e-3, x), 0) << "trial " << trial;
    const Vector6d oracle = -h.ldlt().solve(g);
    EXPECT_LE((x - oracle).norm(), kRelative * oracle.norm()) << "trial " << trial;
  }
}

TEST(DampedStep, DampedIsMinusHPlusLambdaIInverseG) {
  // Levenberg-Marquardt with lambda = damping x mean diagonal of H (trace / 6): the default
  // 1e-4 of RefinementParams and a large 0.5, where the damping dominates the weak directions.
  std::mt19937_64 rng(32);
  for (const double damping : {1e-4, 0.5})
    for (int trial = 0; trial < 20; ++trial) {
      const Matrix6d h = randomSpd(rng, 100.0);
      const Vector6d g = gaussian6(rng);
      Vector6d x;
      EXPECT_EQ(solveDampedDegeneracyAware(h, g, damping, 1e-3, x), 0);
      const double lambda = damping * h.trace() / 6.0;
      const Vector6d oracle = -(h + lambda * Matrix6d::Identity()).ldlt().solve(g);
      EXPECT_LE((x - oracle).norm(), kRelative * oracle.norm())
          << "damping " << damping << ", trial " << trial;
    }
}

/** The normal equations the refinement builds (registration/src/refinement.cpp) for points
 * on a plane with normal \a n through \a origin, unit weights: per point the Jacobian of the
 * point-to-plane residual with respect to (turn omega, scaled by \a scale; translation v) about
 * \a pivot is J = ((y - pivot) x n / scale, n). */
Matrix6d planeNormalEquations(const Eigen::Vector3d& n, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& pivot, double scale) {
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  Matrix6d h = Matrix6d::Zero();
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) {
      const Eigen::Vector3d y = origin + 0.01 * i * e1 + 0.01 * j * e2;  // 20 x 20 cm, 1 cm grid
      Vector6d jac;
      jac.head<3>() = (y - pivot).cross(n) / scale;
      jac.tail<3>() = n;
      h += jac * jac.transpose();
    }
  return h;
}

/** The directions a plane with normal \a n leaves free, in the step's coordinates (omega x
 * scale, v), orthonormal, as columns: the translations along the plane, (0, e1) and (0, e2),
 * and the turn about the normal, (n, 0): a turn omega = n about the pivot moves a point y by
 * n x (y - pivot), and the residual by n . (n x (y - pivot)) = 0, wherever the plane and the
 * pivot lie. */
Eigen::Matrix<double, 6, 3> planeNullSpace(const Eigen::Vector3d& n) {
  const Eigen::Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  Eigen::Matrix<double, 6, 3> basis = Eigen::Matrix<double, 6, 3>::Zero();
  basis.col(0).head<3>() = n;
  basis.col(1).tail<3>() = e1;
  basis.col(2).tail<3>() = e2;
  return basis;  // orthonormal already: n, e1, e2 are unit and the blocks do not overlap
}

TEST(DampedStep, APlaneGetsNoStepAlongWhatItCannotSee) {
  // Two planes: the refinement's own frame (normal z through the pivot) and a tilted plane off
  // the pivot, whose free directions mix every coordinate. g is random in all six coordinates:
  // noise and a bad start push along the free directions too, and the step must ignore them.
  struct Case {
    Eigen::Vector3d n, origin, pivot;
    double scale;
  };
  const Case cases[] = {
      {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.1},
      {Eigen::Vector3d(0.3, -0.5, 0.8).normalized(), Eigen::Vector3d(0.05, 0.02, 0.9),
       Eigen::Vector3d(0.0, 0.01, 0.95), 0.08},
  };
  std::mt19937_64 rng(33);
  for (const Case& c : cases) {
    const Matrix6d h = planeNormalEquations(c.n, c.origin, c.pivot, c.scale);
    const Eigen::Matrix<double, 6, 3> frozen = planeNullSpace(c.n);
    // The oracle's premise: H really is blind along those directions (up to rounding).
    ASSERT_LE((h * frozen).norm(), 1e-12 * h.norm());
    // The constrained directions: the orthonormal complement of the frozen ones.
    const Matrix6d q = Eigen::HouseholderQR<Eigen::Matrix<double, 6, 3>>(frozen).householderQ();
    const Eigen::Matrix<double, 6, 3> seen = q.rightCols<3>();
    for (const double damping : {0.0, 1e-4}) {
      const Vector6d g = gaussian6(rng);
      Vector6d x;
      EXPECT_EQ(solveDampedDegeneracyAware(h, g, damping, 1e-3, x), 3);
      // No step along the frozen directions: only rounding of the eigenvectors (eps x the
      // step) may leak into them.
      EXPECT_LE((frozen.transpose() * x).norm(), 1e-12 * x.norm()) << "damping " << damping;
      // Along the seen ones, the exact damped step of the reduced 3x3 problem.
      const double lambda = damping * h.trace() / 6.0;
      const Eigen::Matrix3d reduced =
          seen.transpose() * h * seen + lambda * Eigen::Matrix3d::Identity();
      const Vector6d oracle = -seen * reduced.ldlt().solve(seen.transpose() * g);
      EXPECT_LE((x - oracle).norm(), kRelative * oracle.norm()) << "damping " << damping;
    }
  }
}

TEST(DampedStep, NothingToSolveGivesNoStep) {
  // No constraint at all (no inlier, H = 0) or a broken sum (NaN): all six directions frozen.
  const Vector6d g = Vector6d::Ones();
  Vector6d x = Vector6d::Constant(7.0);
  EXPECT_EQ(solveDampedDegeneracyAware(Matrix6d::Zero(), g, 1e-4, 1e-3, x), 6);
  EXPECT_TRUE(x.isZero(0.0));
  Matrix6d nan = Matrix6d::Identity();
  nan(2, 2) = std::nan("");
  x.setConstant(7.0);
  EXPECT_EQ(solveDampedDegeneracyAware(nan, g, 1e-4, 1e-3, x), 6);
  EXPECT_TRUE(x.isZero(0.0));
}

}  // namespace
