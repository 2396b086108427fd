/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/console/print.h>
#include <pcl/icf/segmentation/euclidean_clusters.h>
#include <pcl/search/kdtree.h>
#include <pcl/search/organized.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/icf/segmentation/impl/segmentation_common.hpp>

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

/** Connected components of cloud[indices] (finite points) under "distance <= tolerance", by the
 * grid algorithm described at ClusterMethod::Grid. Returns false (and leaves \a components
 * empty) when the grid would need more than 2^20 cells along an axis. */
template <typename PointT>
bool gridComponents(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices,
                    float tolerance, std::vector<pcl::Indices>& components) {
  components.clear();
  if (indices.empty())
    return true;
  constexpr int kBits = 21;
  constexpr std::int64_t kMask = (std::int64_t{1} << kBits) - 1;
  // Cells of edge a little under tolerance / sqrt(3): two points of one cell are closer than
  // tolerance even after float rounding of the binning.
  const float cell = tolerance / std::sqrt(3.0f) * (1.0f - 1e-5f);
  const float squared_tolerance = tolerance * tolerance;

  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
  Eigen::Array3f hi = Eigen::Array3f::Constant(std::numeric_limits<float>::lowest());
  for (const pcl::index_t i : indices) {
    lo = lo.min(cloud[i].getArray3fMap());
    hi = hi.max(cloud[i].getArray3fMap());
  }
  // Start the grid three cells below the lowest point: float rounding may put that point in
  // cell 2 instead of 3, and neighbour offsets reach 2 cells down, so no coordinate goes
  // negative; the span limit keeps them below 2^21 (kBits) at the top.
  const Eigen::Array3f span = (hi - lo) / cell;
  if (!(span.maxCoeff() < static_cast<float>(1 << 20)))
    return false;
  lo -= 3.0f * cell;

  const auto cellOf = [&](const Eigen::Array3f& p) {
    const Eigen::Array3f c = ((p - lo) / cell).floor();
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(c[0]),
                                       static_cast<std::int64_t>(c[1]),
                                       static_cast<std::int64_t>(c[2])};
  };
  const auto keyOf = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::uint64_t>((x << (2 * kBits)) | (y << kBits) | z);
  };

  // Points sorted by cell key: each cell is a contiguous run.
  const std::size_t n = indices.size();
  std::vector<std::pair<std::uint64_t, pcl::index_t>> keyed(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto c = cellOf(cloud[indices[k]].getArray3fMap());
    keyed[k] = {keyOf(c[0], c[1], c[2]), indices[k]};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Vector3f> position(n);
  for (std::size_t k = 0; k < n; ++k)
    position[k] = cloud[keyed[k].second].getVector3fMap();

  std::vector<std::size_t> begin;  // cell c holds sorted points [begin[c], begin[c + 1])
  std::unordered_map<std::uint64_t, std::size_t> cell_of_key;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) {
      cell_of_key.emplace(keyed[k].first, begin.size());
      begin.push_back(k);
    }
  }
  const std::size_t cells = begin.size();
  begin.push_back(n);

  // Neighbour offsets in [-2, 2]^3, half of them (the other half is seen from the other cell),
  // keeping those whose cells can hold points within tolerance.
  std::vector<std::array<std::int64_t, 3>> offsets;
  for (std::int64_t dx = -2; dx <= 2; ++dx)
    for (std::int64_t dy = -2; dy <= 2; ++dy)
      for (std::int64_t dz = -2; dz <= 2; ++dz) {
        if (std::make_tuple(dx, dy, dz) <=
            std::make_tuple(std::int64_t{0}, std::int64_t{0}, std::int64_t{0}))
          continue;
        const auto gap = [&](std::int64_t d) {
          const float g = static_cast<float>(std::max<std::int64_t>(std::abs(d) - 1, 0)) * cell;
          return g * g;
        };
        if (gap(dx) + gap(dy) + gap(dz) <= squared_tolerance)
          offsets.push_back({dx, dy, dz});
      }

  DisjointSets sets(cells);
  for (std::size_t a = 0; a < cells; ++a) {
    const std::uint64_t key = keyed[begin[a]].first;
    const auto ax = static_cast<std::int64_t>(key >> (2 * kBits));
    const auto ay = static_cast<std::int64_t>((key >> kBits) & kMask);
    const auto az = static_cast<std::int64_t>(key & kMask);
    for (const auto& o : offsets) {
      const auto it = cell_of_key.find(keyOf(ax + o[0], ay + o[1], az + o[2]));
      if (it == cell_of_key.end())
        continue;
      const std::size_t b = it->second;
      if (sets.find(a) == sets.find(b))
        continue;
      bool linked = false;
      for (std::size_t i = begin[a]; i < begin[a + 1] && !linked; ++i)
        for (std::size_t j = begin[b]; j < begin[b + 1]; ++j)
          if ((position[i] - position[j]).squaredNorm() <= squared_tolerance) {
            linked = true;
            break;
          }
      if (linked)
        sets.unite(a, b);
    }
  }

  std::unordered_map<std::size_t, std::size_t> component_of_root;
  for (std::size_t c = 0; c < cells; ++c) {
    const std::size_t root = sets.find(c);
    auto it = component_of_root.find(root);
    if (it == component_of_root.end()) {
      it = component_of_root.emplace(root, components.size()).first;
      components.emplace_back();
    }
    pcl::Indices& members = components[it->second];
    for (std::size_t k = begin[c]; k < begin[c + 1]; ++k)
      members.push_back(keyed[k].second);
  }
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
