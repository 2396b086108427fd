/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/localization/objects_localizer.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl {
namespace icf {
namespace localization {

namespace {

/** How many points the sorted index lists \a a and \a b have in common. */
std::size_t sharedPoints(const std::vector<pcl::index_t>& a, const std::vector<pcl::index_t>& b) {
  std::size_t shared = 0;
  for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();)
    if (*i < *j)
      ++i;
    else if (*j < *i)
      ++j;
    else {
      ++shared;
      ++i;
      ++j;
    }
  return shared;
}

std::vector<pcl::index_t> sortedIndices(pcl::Indices s) {
  std::sort(s.begin(), s.end());
  return s;
}

/** An accepted hypothesis: objects[object].clusters[index]. */
struct Claimant {
  int object = 0;
  int index = 0;
  double score = 0.0;
};

/** The greedy choice of rankInstances and selectInstances: \a claimants by score (ties: the
 * lower object, then the lower index), each kept unless more than \a max_shared of its
 * \a explained points are claimed by a kept one, or its object has \a caps of them already.
 * \a lost(claimant, winner object, winner's rank in its object) is told of a claimant whose
 * points another object's instance holds. */
template <typename Explained, typename Lost>
std::vector<std::vector<int>> chooseInstances(std::vector<Claimant> claimants,
                                              const std::vector<int>& caps, double max_shared,
                                              Explained explained, Lost lost) {
  std::stable_sort(claimants.begin(), claimants.end(), [](const Claimant& a, const Claimant& b) {
    if (a.score != b.score)
      return a.score > b.score;
    return a.object != b.object ? a.object < b.object : a.index < b.index;
  });
  std::vector<std::vector<int>> kept(caps.size());
  struct Claim {
    std::vector<pcl::index_t> points;
    int object, rank;
  };
  std::vector<Claim> claims;
  for (const Claimant& c : claimants) {
    auto& mine = kept[static_cast<std::size_t>(c.object)];
    if (static_cast<int>(mine.size()) >= caps[static_cast<std::size_t>(c.object)])
      continue;
    std::vector<pcl::index_t> points = sortedIndices(explained(c));
    // Each scene point explains one instance: a pose that explains the points of a better one
    // is the same object found again (in a merged cluster and in its convexity segment) or,
    // for another model, a worse explanation of that object.
    const double limit = max_shared * static_cast<double>(points.size());
    const auto holder = std::find_if(claims.begin(), claims.end(), [&](const Claim& other) {
      return static_cast<double>(sharedPoints(points, other.points)) > limit;
    });
    if (holder != claims.end()) {
      if (holder->object != c.object)
        lost(c, holder->object, holder->rank);
      continue;
    }
    claims.push_back({std::move(points), c.object, static_cast<int>(mine.size())});
    mine.push_back(c.index);
  }
  return kept;
}

}  // namespace

std::vector<int> rankInstances(const std::vector<ClusterLocalization>& clusters, int max_instances,
                               double max_shared) {
  std::vector<Claimant> claimants;
  for (std::size_t k = 0; k < clusters.size(); ++k)
    if (clusters[k].accepted)
      claimants.push_back({0, static_cast<int>(k), clusters[k].score});
  const auto explained = [&](const Claimant& c) {
    return clusters[static_cast<std::size_t>(c.index)].explained;
  };
  return chooseInstances(std::move(claimants), {max_instances}, max_shared, explained,
                         [](const Claimant&, int, int) {})
      .front();
}

std::vector<std::vector<int>> selectInstances(std::vector<Localization>& objects,
                                              const std::vector<int>& max_instances,
                                              const std::vector<std::string>& names,
                                              double max_shared) {
  if (max_instances.size() != objects.size() || names.size() != objects.size())
    throw std::invalid_argument(
        "[pcl::icf::localization::selectInstances] one instance count and one name per object");
  std::vector<Claimant> claimants;
  for (std::size_t o = 0; o < objects.size(); ++o)
    for (std::size_t k = 0; k < objects[o].clusters.size(); ++k)
      if (objects[o].clusters[k].accepted)
        claimants.push_back(
            {static_cast<int>(o), static_cast<int>(k), objects[o].clusters[k].score});
  const auto cluster = [&](const Claimant& c) -> ClusterLocalization& {
    return objects[static_cast<std::size_t>(c.object)].clusters[static_cast<std::size_t>(c.index)];
  };
  const auto explained = [&](const Claimant& c) { return cluster(c).explained; };
  const auto lost = [&](const Claimant& c, int winner, int rank) {
    ClusterLocalization& loser = cluster(c);
    loser.accepted = false;
    loser.reason = "explained better by " + names[static_cast<std::size_t>(winner)] + " instance " +
                   std::to_string(rank);
  };
  return chooseInstances(std::move(claimants), max_instances, max_shared, explained, lost);
}

}  // namespace localization
}  // namespace icf
}  // namespace pcl
