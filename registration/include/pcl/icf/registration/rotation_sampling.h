/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <random>
#include <vector>

namespace pcl {
namespace icf {

/** \brief \a count rotations spread uniformly over SO(3): super-Fibonacci spirals (M. Alexa,
 * "Super-Fibonacci Spirals: Fast, Low-Discrepancy Sampling of SO(3)", CVPR 2022), all turned
 * by one random rotation drawn from \a seed so different seeds give different, equally
 * uniform sets. The covering radius is about 4.2 / cbrt(count) radians of turning
 * (2.1 / cbrt(count) on the unit quaternions' sphere; doc/icf.md). */
std::vector<Eigen::Quaternionf> uniformRotations(std::size_t count, std::uint64_t seed);

/** \brief One rotation uniform on SO(3) (a normalised 4D Gaussian). */
Eigen::Quaternionf randomRotation(std::mt19937_64& rng);

}  // namespace icf
}  // namespace pcl
