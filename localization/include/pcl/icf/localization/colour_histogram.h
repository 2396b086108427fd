/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PolygonMesh.h>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace pcl {
namespace icf {
namespace localization {

/** \brief A normalised colour histogram: \a bins hue bins for saturated colours plus \a bins
 * value (brightness) bins for greys, so white, grey and black objects have a colour too.
 * Colours in [0, 1] RGB. */
class ColourHistogram {
 public:
  explicit ColourHistogram(int bins = 8);
  void add(const Eigen::Vector3f& rgb, float weight = 1.f);
  /** \brief Histogram intersection with \a other, in [0, 1] (1: the same distribution). */
  double intersection(const ColourHistogram& other) const;
  /** \brief The histogram of one colour, spread over neighbouring hue bins so that lighting
   * shifts of a fraction of a bin still match. */
  static ColourHistogram ofColour(const Eigen::Vector3f& rgb, int bins = 8);
  bool empty() const { return total_ <= 0.f; }

 private:
  int bin(const Eigen::Vector3f& rgb) const;
  int bins_;
  std::vector<float> counts_;
  float total_ = 0.f;
};

/** \brief Mean vertex colour of a mesh with r, g, b (or rgb / rgba) vertex fields, in [0, 1];
 * empty when the mesh has none. */
std::optional<Eigen::Vector3f> meshColour(const pcl::PolygonMesh& mesh);

}  // namespace localization
}  // namespace icf
}  // namespace pcl
