/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Private to pcl_icf_segmentation's sources (not installed): the body of
 * euclidean_clusters.h's templates, instantiated in src/euclidean_clusters.cpp for
 * PCL_ICF_SEGMENTATION_POINT_TYPES. */

#include <pcl/console/print.h>
#include <pcl/icf/segmentation/euclidean_clusters.h>
#include <pcl/search/kdtree.h>
#include <pcl/search/organized.h>
#include <pcl/segmentation/extract_clusters.h>
#include "segmentation_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pcl {
namespace icf {
namespace segmentation {
namespace detail {

/** Union-find with path halving and union by size. */
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }

  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b)
      return;
    if (size_[a] < size_[b])
      std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<std::size_t> parent_;
  std::vector<std::size_t> size_;
};

/** The grid of ClusterMethod::Grid over a set of points: cubic cells of edge a little under
 * tolerance / sqrt(3), so each cell is a clique, keyed by their integer coordinates (21 bits
 * each) from a corner three cells below the lowest point, and the points sorted by cell key so
 * that each cell is a contiguous run. */
struct CellGrid {
  static constexpr int kBits = 21;
  static constexpr std::int64_t kMask = (std::int64_t{1} << kBits) - 1;

  float cell = 0.f;                                           ///< edge length
  Eigen::Array3f corner = Eigen::Array3f::Zero();             ///< cell (0, 0, 0)'s lowest corner
  std::vector<std::pair<std::uint64_t, pcl::index_t>> keyed;  ///< (cell key, point), sorted
  std::vector<Eigen::Vector3f> position;                      ///< the points in keyed's order
  std::vector<std::size_t> begin;  ///< cell c holds keyed[begin[c], begin[c + 1])
  std::unordered_map<std::uint64_t, std::size_t> cell_of_key;

  std::size_t cells() const { return begin.size() - 1; }

  static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>((x << (2 * kBits)) | (y << kBits) | z);
  }

  std::uint64_t keyOf(const Eigen::Array3f& p) const {
    const Eigen::Array3f c = ((p - corner) / cell).floor();
    return key(static_cast<std::int64_t>(c[0]), static_cast<std::int64_t>(c[1]),
               static_cast<std::int64_t>(c[2]));
  }
};

/** Places \a grid's corner three cells below the lowest of cloud[indices]: float rounding may
 * put that point in cell 2 instead of 3, and neighbour offsets reach 2 cells down, so no
 * coordinate goes negative. False when the points span 2^20 cells or more along an axis (the
 * coordinates would not stay below 2^21 at the top). */
template <typename PointT>
bool placeGrid(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, CellGrid& grid) {
  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
  Eigen::Array3f hi = Eigen::Array3f::Constant(std::numeric_limits<float>::lowest());
  for (const pcl::index_t i : indices) {
    lo = lo.min(cloud[i].getArray3fMap());
    hi = hi.max(cloud[i].getArray3fMap());
  }
  const Eigen::Array3f span = (hi - lo) / grid.cell;
  if (!(span.maxCoeff() < static_cast<float>(1 << 20)))
    return false;
  lo -= 3.0f * grid.cell;
  grid.corner = lo;
  return true;
}

/** Fills grid.begin and grid.cell_of_key from the sorted grid.keyed. */
void indexCells(CellGrid& grid);

/** Bins cloud[indices] into \a grid (placed by placeGrid): keys, sort, positions, cells. */
template <typename PointT>
void binPoints(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices, CellGrid& grid) {
  const std::size_t n = indices.size();
  grid.keyed.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    grid.keyed[k] = {grid.keyOf(cloud[indices[k]].getArray3fMap()), indices[k]};
  std::sort(grid.keyed.begin(), grid.keyed.end());
  grid.position.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    grid.position[k] = cloud[grid.keyed[k].second].getVector3fMap();
  indexCells(grid);
}

/** Neighbour offsets in [-2, 2]^3, half of them (the other half is seen from the other cell),
 * keeping those whose cells can hold points within tolerance (squared: \a squared_tolerance)
 * of each other. */
std::vector<std::array<std::int64_t, 3>> neighbourOffsets(float cell, float squared_tolerance);

/** Joins in \a sets every two cells of \a grid, \a offsets apart, that hold a pair of points
 * within tolerance of each other. */
void linkNeighbourCells(const CellGrid& grid,
                        const std::vector<std::array<std::int64_t, 3>>& offsets,
                        float squared_tolerance, DisjointSets& sets);

/** The points of each set of \a sets' cells, sets in the order of their first cell, points in
 * grid order. */
std::vector<pcl::Indices> cellComponents(const CellGrid& grid, DisjointSets& sets);

/** Connected components of cloud[indices] (finite points) under "distance <= tolerance", by the
 * grid algorithm described at ClusterMethod::Grid. Returns false (and leaves \a components
 * empty) when the grid would need more than 2^20 cells along an axis. */
template <typename PointT>
bool gridComponents(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                    float tolerance, std::vector<pcl::Indices>& components) {
  components.clear();
  if (indices.empty())
    return true;
  CellGrid grid;
  // Cells of edge a little under tolerance / sqrt(3): two points of one cell are closer than
  // tolerance even after float rounding of the binning.
  grid.cell = tolerance / std::sqrt(3.0f) * (1.0f - 1e-5f);
  const float squared_tolerance = tolerance * tolerance;
  if (!placeGrid(cloud, indices, grid))
    return false;
  binPoints(cloud, indices, grid);
  DisjointSets sets(grid.cells());
  linkNeighbourCells(grid, neighbourOffsets(grid.cell, squared_tolerance), squared_tolerance, sets);
  components = cellComponents(grid, sets);
  return true;
}

}  // namespace detail
}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

template <typename PointT>
std::vector<pcl::PointIndices> pcl::icf::segmentation::extractClusters(
    const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
    const ClusterParams& params) {
  params.validate();
  detail::requireIndicesInRange(cloud, indices, "segmentation::extractClusters");

  std::vector<pcl::PointIndices> clusters;
  auto candidates = std::make_shared<pcl::Indices>(detail::finiteSubset(cloud, indices));
  if (candidates->size() < params.min_size)
    return clusters;
  const auto tolerance = static_cast<float>(params.tolerance);

  if (params.method == ClusterMethod::Grid) {
    std::vector<pcl::Indices> components;
    if (detail::gridComponents(cloud, *candidates, tolerance, components)) {
      for (pcl::Indices& members : components) {
        if (members.size() < params.min_size || members.size() > params.max_size)
          continue;
        clusters.emplace_back();
        clusters.back().header = cloud.header;
        clusters.back().indices = std::move(members);
      }
      sortClusters(clusters);
      return clusters;
    }
    PCL_DEBUG(
        "[pcl::icf::segmentation::extractClusters] the points span too many grid cells; using a "
        "kd-tree\n");
  }

  typename pcl::search::Search<PointT>::Ptr search;
  if (params.method == ClusterMethod::PclOrganized && cloud.isOrganized())
    search = std::make_shared<pcl::search::OrganizedNeighbor<PointT>>();
  else
    search = std::make_shared<pcl::search::KdTree<PointT>>(false);

  pcl::EuclideanClusterExtraction<PointT> ece;
  ece.setInputCloud(detail::nonOwning(cloud));
  ece.setIndices(candidates);
  ece.setSearchMethod(search);
  ece.setClusterTolerance(tolerance);
  ece.setMinClusterSize(static_cast<pcl::uindex_t>(params.min_size));
  ece.setMaxClusterSize(static_cast<pcl::uindex_t>(params.max_size));
  ece.extract(clusters);
  sortClusters(clusters);
  return clusters;
}

#define PCL_INSTANTIATE_IcfExtractClusters(T)                                         \
  template std::vector<pcl::PointIndices> pcl::icf::segmentation::extractClusters<T>( \
      const pcl::PointCloud<T>&, const pcl::Indices&,                                 \
      const pcl::icf::segmentation::ClusterParams&);
