/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
// Explicit instantiation for PCL_ICF_SEGMENTATION_POINT_TYPES (PCL's PCL_INSTANTIATE pattern),
// and the point-type-independent steps of the grid clustering (impl/euclidean_clusters.hpp).
#include <pcl/icf/segmentation/euclidean_clusters.h>

#include <pcl/point_types.h>
#include <pcl/impl/instantiate.hpp>

#include "impl/euclidean_clusters.hpp"

namespace pcl {
namespace icf {
namespace segmentation {
namespace detail {

void indexCells(CellGrid& grid) {
  const std::size_t n = grid.keyed.size();
  grid.begin.clear();
  grid.cell_of_key.clear();
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || grid.keyed[k].first != grid.keyed[k - 1].first) {
      grid.cell_of_key.emplace(grid.keyed[k].first, grid.begin.size());
      grid.begin.push_back(k);
    }
  }
  grid.begin.push_back(n);
}

std::vector<std::array<std::int64_t, 3>> neighbourOffsets(float cell, float squared_tolerance) {
  const auto gap = [cell](std::int64_t d) {
    const float g = static_cast<float>(std::max<std::int64_t>(std::abs(d) - 1, 0)) * cell;
    return g * g;
  };
  std::vector<std::array<std::int64_t, 3>> offsets;
  for (std::int64_t dx = -2; dx <= 2; ++dx)
    for (std::int64_t dy = -2; dy <= 2; ++dy)
      for (std::int64_t dz = -2; dz <= 2; ++dz) {
        if (std::make_tuple(dx, dy, dz) <=
            std::make_tuple(std::int64_t{0}, std::int64_t{0}, std::int64_t{0}))
          continue;
        if (gap(dx) + gap(dy) + gap(dz) <= squared_tolerance)
          offsets.push_back({dx, dy, dz});
      }
  return offsets;
}

namespace {

/** True when a point of cell \a a and a point of cell \a b are within tolerance. */
bool cellsTouch(const CellGrid& grid, std::size_t a, std::size_t b, float squared_tolerance) {
  for (std::size_t i = grid.begin[a]; i < grid.begin[a + 1]; ++i)
    for (std::size_t j = grid.begin[b]; j < grid.begin[b + 1]; ++j)
      if ((grid.position[i] - grid.position[j]).squaredNorm() <= squared_tolerance)
        return true;
  return false;
}

}  // namespace

void linkNeighbourCells(const CellGrid& grid,
                        const std::vector<std::array<std::int64_t, 3>>& offsets,
                        float squared_tolerance, DisjointSets& sets) {
  for (std::size_t a = 0; a < grid.cells(); ++a) {
    const std::uint64_t key = grid.keyed[grid.begin[a]].first;
    const auto ax = static_cast<std::int64_t>(key >> (2 * CellGrid::kBits));
    const auto ay = static_cast<std::int64_t>((key >> CellGrid::kBits) & CellGrid::kMask);
    const auto az = static_cast<std::int64_t>(key & CellGrid::kMask);
    for (const auto& o : offsets) {
      const auto it = grid.cell_of_key.find(CellGrid::key(ax + o[0], ay + o[1], az + o[2]));
      if (it == grid.cell_of_key.end())
        continue;
      const std::size_t b = it->second;
      if (sets.find(a) == sets.find(b))
        continue;
      if (cellsTouch(grid, a, b, squared_tolerance))
        sets.unite(a, b);
    }
  }
}

std::vector<pcl::Indices> cellComponents(const CellGrid& grid, DisjointSets& sets) {
  std::vector<pcl::Indices> components;
  std::unordered_map<std::size_t, std::size_t> component_of_root;
  for (std::size_t c = 0; c < grid.cells(); ++c) {
    const std::size_t root = sets.find(c);
    auto it = component_of_root.find(root);
    if (it == component_of_root.end()) {
      it = component_of_root.emplace(root, components.size()).first;
      components.emplace_back();
    }
    pcl::Indices& members = components[it->second];
    for (std::size_t k = grid.begin[c]; k < grid.begin[c + 1]; ++k)
      members.push_back(grid.keyed[k].second);
  }
  return components;
}

}  // namespace detail
}  // namespace segmentation
}  // namespace icf
}  // namespace pcl

PCL_INSTANTIATE(IcfExtractClusters, PCL_ICF_SEGMENTATION_POINT_TYPES)
