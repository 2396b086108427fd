/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/registration/rotation_sampling.h>

#include <cmath>

namespace pcl {
namespace icf {

Eigen::Quaternionf randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Vector4d q;
  do
    q = Eigen::Vector4d(g(rng), g(rng), g(rng), g(rng));
  while (q.norm() < 1e-9);
  q.normalize();
  return Eigen::Quaternionf(static_cast<float>(q[0]), static_cast<float>(q[1]),
                            static_cast<float>(q[2]), static_cast<float>(q[3]));
}

std::vector<Eigen::Quaternionf> uniformRotations(std::size_t count, std::uint64_t seed) {
  constexpr double kPhi = 1.4142135623730951;    // sqrt(2)
  constexpr double kPsi = 1.533751168755204288;  // root of psi^4 = psi + 4
  constexpr double kTwoPi = 6.283185307179586;
  std::mt19937_64 rng(seed);
  const Eigen::Quaterniond turn = randomRotation(rng).cast<double>();
  std::vector<Eigen::Quaternionf> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double s = static_cast<double>(i) + 0.5;
    const double t = s / static_cast<double>(count);
    const double r = std::sqrt(t), R = std::sqrt(1.0 - t);
    const double alpha = kTwoPi * s / kPhi, beta = kTwoPi * s / kPsi;
    const Eigen::Quaterniond q(r * std::sin(alpha), r * std::cos(alpha), R * std::sin(beta),
                               R * std::cos(beta));
    out.push_back((turn * q).normalized().cast<float>());
  }
  return out;
}

}  // namespace icf
}  // namespace pcl
