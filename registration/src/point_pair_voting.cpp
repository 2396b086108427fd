/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Point pair voting is written here rather than taken from PCL or OpenCV. PCL 1.13's
 * PPFEstimation / PPFHashMapSearch / PPFRegistration keep a hash map of features without vote
 * spreading, one peak per reference point and no re-scoring, and register one cluster against
 * one model; OpenCV's ppf_match_3d (contrib) votes the same way, on a model read as a point
 * cloud, and found none of 11 objects on a real cluttered Kinect desk (PCL's ObjRecRANSAC none
 * of 8). What the BOP benchmark's best classical entry adds (spread
 * votes, one vote per feature and angle, edge-preserving sampling, view-dependent re-scoring)
 * is small once the table is a dense array, so it is built here on PCL's own kd-tree and
 * normal estimation.
 */
#include <pcl/features/normal_3d_omp.h>
#include <pcl/icf/registration/icf_model.h>
#include <pcl/icf/registration/point_pair_voting.h>
#include <pcl/icf/registration/usable_point.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl_icf_internal/parameter_check.h>
#include <pcl_icf_internal/place_quota.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace pcl {
namespace icf {

namespace {

constexpr float kPi = static_cast<float>(M_PI);

/** Angle between two unit-or-not vectors, radians in [0, pi] (atan2: stable near 0 and pi). */
float angleBetween(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/** Integer cell of \a p on a grid of \a step, packed into one key (21 bits a coordinate: a
 * scene of +-10 km at 1 cm, far beyond any depth camera). */
std::uint64_t cellKey(const Eigen::Vector3f& p, float step) {
  const auto c = [&](float x) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(x / step)) + (1 << 20)) &
           0x1fffff;
  };
  return (c(p.x()) << 42) | (c(p.y()) << 21) | c(p.z());
}

Eigen::Vector3f cellCentre(const Eigen::Vector3f& p, float step) {
  return ((p / step).array().floor() + 0.5f).matrix() * step;
}

}  // namespace

void PointPairModelParams::validate() const {
  const internal::ParameterCheck fail("PointPairModelParams");
  if (!(sampling_step >= 0.01f && sampling_step <= 0.5f))
    fail("sampling_step", sampling_step, "must lie in [0.01, 0.5] (a share of the diameter)");
  if (angle_bins < 4 || angle_bins > 32)
    fail("angle_bins", angle_bins, "must lie in [4, 32]");
  if (!(normal_split_deg > 0.f && normal_split_deg <= 180.f))
    fail("normal_split_deg", normal_split_deg, "must lie in (0, 180]");
  if (!(coplanar_deg >= 0.f && coplanar_deg < 45.f))
    fail("coplanar_deg", coplanar_deg, "must lie in [0, 45)");
  if (max_bin_pairs > 100000000)
    fail("max_bin_pairs", max_bin_pairs, "must be at most 1e8 (0: no cap)");
  if (dense_samples < 100 || dense_samples > 10000000)
    fail("dense_samples", dense_samples, "must lie in [100, 1e7]");
}

void PointPairVotingParams::validate() const {
  const internal::ParameterCheck fail("PointPairVotingParams");
  if (!(reference_share > 0.f && reference_share <= 1.f))
    fail("reference_share", reference_share, "must lie in (0, 1]");
  if (max_references < 1)
    fail("max_references", max_references, "must be >= 1");
  if (!(max_pairs_discs >= 1.f))
    fail("max_pairs_discs", max_pairs_discs, "must be >= 1 (discs of the model's diameter)");
  if (!(spread_margin >= 0.f && spread_margin <= 0.5f))
    fail("spread_margin", spread_margin, "must lie in [0, 0.5] (a share of a bin)");
  if (peaks_per_reference < 1 || peaks_per_reference > 16)
    fail("peaks_per_reference", peaks_per_reference, "must lie in [1, 16]");
  if (!(peak_share > 0.f && peak_share <= 1.f))
    fail("peak_share", peak_share, "must lie in (0, 1]");
  if (!(cluster_distance > 0.f && cluster_distance <= 1.f))
    fail("cluster_distance", cluster_distance, "must lie in (0, 1]");
  if (!(cluster_angle_deg > 0.f && cluster_angle_deg <= 180.f))
    fail("cluster_angle_deg", cluster_angle_deg, "must lie in (0, 180]");
  if (rescored < 1)
    fail("rescored", rescored, "must be >= 1");
  if (!(rescore_distance > 0.f && rescore_distance <= 10.f))
    fail("rescore_distance", rescore_distance, "must lie in (0, 10]");
  if (!(rescore_angle_deg > 0.f && rescore_angle_deg <= 180.f))
    fail("rescore_angle_deg", rescore_angle_deg, "must lie in (0, 180]");
  if (!(rescore_hidden_distance > 0.f && std::isfinite(rescore_hidden_distance)))
    fail("rescore_hidden_distance", rescore_hidden_distance, "must be positive and finite");
  if (!(rescore_min_share >= 0.f && rescore_min_share <= 1.f))
    fail("rescore_min_share", rescore_min_share, "must lie in [0, 1]");
  if (kept < 1)
    fail("kept", kept, "must be >= 1");
  if (kept_per_place < 1)
    fail("kept_per_place", kept_per_place, "must be >= 1");
  if (!(distinct_surface >= 0.f && distinct_surface <= 1.f))
    fail("distinct_surface", distinct_surface, "must lie in [0, 1]");
  if (!(normal_radius > 0.f && normal_radius <= 20.f))
    fail("normal_radius", normal_radius, "must lie in (0, 20]");
}

Eigen::Vector4f pointPairFeature(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1,
                                 const Eigen::Vector3f& p2, const Eigen::Vector3f& n2) {
  const Eigen::Vector3f d = p2 - p1;
  return {d.norm(), angleBetween(n1, d), angleBetween(n2, d), angleBetween(n1, n2)};
}

Eigen::Isometry3f pointPairFrame(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  // The turn about n x (+x) by the angle between them: exact to rounding also where n is nearly
  // -x (Eigen's FromTwoVectors falls back to an SVD there, 1e-4 off); a half turn about +y for
  // n along -x itself.
  const Eigen::Vector3f u = n.normalized();
  const Eigen::Vector3f axis = u.cross(Eigen::Vector3f::UnitX());
  const float sine = axis.norm();
  Eigen::Isometry3f frame = Eigen::Isometry3f::Identity();
  if (sine > 1e-12f)
    frame.linear() = Eigen::AngleAxisf(std::atan2(sine, u.x()), axis / sine).toRotationMatrix();
  else if (u.x() < 0.f)
    frame.linear() = Eigen::AngleAxisf(kPi, Eigen::Vector3f::UnitY()).toRotationMatrix();
  frame.translation() = -(frame.linear() * p);
  return frame;
}

float pointPairAngle(const Eigen::Isometry3f& frame, const Eigen::Vector3f& p2) {
  const Eigen::Vector3f q = frame * p2;
  return std::atan2(-q.z(), q.y());
}

namespace {

/** Area-weighted samples of \a mesh with outward face normals (the whole mesh flipped when
 * most normals point at its centroid). */
std::vector<SurfaceSample> outwardSamples(const FaceMesh& mesh, std::size_t count,
                                          std::uint64_t seed) {
  std::vector<SurfaceSample> samples = sampleSurface(mesh, count, seed);
  const Eigen::Vector3f& c = mesh.surfaceCentroid();
  double outward = 0.0;
  for (const SurfaceSample& s : samples)
    outward += s.normal.dot(s.point - c);
  if (outward < 0.0)
    for (SurfaceSample& s : samples)
      s.normal = -s.normal;
  return samples;
}

/** One sample per cell of \a step (the nearest to its centre), and more where normals differ by
 * more than \a split_cos's angle from every one kept in the cell. Cells in key order. */
void sampleCells(const std::vector<SurfaceSample>& samples, float step, float split_cos,
                 std::vector<Eigen::Vector3f>& points, std::vector<Eigen::Vector3f>& normals) {
  std::map<std::uint64_t, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < samples.size(); ++i)
    cells[cellKey(samples[i].point, step)].push_back(i);
  for (auto& [key, members] : cells) {
    const Eigen::Vector3f centre = cellCentre(samples[members.front()].point, step);
    std::stable_sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      return (samples[a].point - centre).squaredNorm() < (samples[b].point - centre).squaredNorm();
    });
    std::vector<Eigen::Vector3f> kept;
    for (std::size_t i : members) {
      const Eigen::Vector3f& n = samples[i].normal;
      if (std::any_of(kept.begin(), kept.end(),
                      [&](const Eigen::Vector3f& k) { return k.dot(n) >= split_cos; }))
        continue;
      kept.push_back(n);
      points.push_back(samples[i].point);
      normals.push_back(n);
    }
  }
}

float largestDistance(const std::vector<Eigen::Vector3f>& points) {
  float d2 = 0.f;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (std::size_t j = i + 1; j < points.size(); ++j)
      d2 = std::max(d2, (points[i] - points[j]).squaredNorm());
  return std::sqrt(d2);
}

/** Quantised coordinate \a q (a feature coordinate in bin widths) and, for spreading, the
 * neighbouring bin it lies nearer to. */
struct Quantised {
  int bin, neighbour;
  bool near_border;  ///< within the spread margin of the neighbour's border
};
Quantised quantise(float q, int bins, float margin = 0.f) {
  const int b = std::min(bins - 1, std::max(0, static_cast<int>(std::floor(q))));
  const float frac = q - static_cast<float>(b);
  return {b, frac < 0.5f ? b - 1 : b + 1, frac < margin || frac > 1.f - margin};
}

}  // namespace

long PointPairModel::binAt(int distance, int a1, int a2, int a3) const {
  const int a = feature_bins_;
  if (distance < 0 || distance >= distance_bins_ || a1 < 0 || a1 >= a || a2 < 0 || a2 >= a ||
      a3 < 0 || a3 >= a)
    return -1;
  return ((static_cast<long>(distance) * a + a1) * a + a2) * a + a3;
}

long PointPairModel::binOf(const Eigen::Vector4f& f) const {
  if (!(f.allFinite()) || f[0] / step_ >= static_cast<float>(distance_bins_))
    return -1;
  const float angle = kPi / static_cast<float>(feature_bins_);
  return binAt(static_cast<int>(f[0] / step_), quantise(f[1] / angle, feature_bins_).bin,
               quantise(f[2] / angle, feature_bins_).bin,
               quantise(f[3] / angle, feature_bins_).bin);
}

PointPairModel PointPairModel::build(const FaceMesh& mesh, const PointPairModelParams& params) {
  params.validate();
  PointPairModel m;
  const std::vector<SurfaceSample> dense = outwardSamples(mesh, params.dense_samples, params.seed);
  // The step from the diameter of a subset (the cells' own diameter is measured after).
  std::vector<Eigen::Vector3f> subset;
  const std::size_t stride = std::max<std::size_t>(1, dense.size() / 2000);
  for (std::size_t i = 0; i < dense.size(); i += stride)
    subset.push_back(dense[i].point);
  const float rough = largestDistance(subset);
  if (!(rough > 0.f) || !std::isfinite(rough))
    return m;
  m.step_ = params.sampling_step * rough;
  sampleCells(dense, m.step_, std::cos(params.normal_split_deg * kPi / 180.f), m.points_,
              m.normals_);
  m.diameter_ = largestDistance(m.points_);
  m.angle_bins_ = params.angle_bins;
  m.feature_bins_ = (params.angle_bins + 1) / 2;
  m.coplanar_ = params.coplanar_deg * kPi / 180.f;
  m.distance_bins_ = static_cast<int>(std::floor(m.diameter_ / m.step_)) + 1;
  const long bins =
      static_cast<long>(m.distance_bins_) * m.feature_bins_ * m.feature_bins_ * m.feature_bins_;
  // Two passes over every ordered pair: count per bin, then fill (a compressed table).
  const std::size_t n = m.points_.size();
  const auto binOfPair = [&](std::size_t i, std::size_t j) {
    if (i == j)
      return -1L;
    const Eigen::Vector4f f =
        pointPairFeature(m.points_[i], m.normals_[i], m.points_[j], m.normals_[j]);
    return m.isCoplanar(f) ? -1L : m.binOf(f);
  };
  std::vector<std::uint32_t> counts(static_cast<std::size_t>(bins) + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      if (const long b = binOfPair(i, j); b >= 0)
        ++counts[static_cast<std::size_t>(b) + 1];
  std::partial_sum(counts.begin(), counts.end(), counts.begin());
  m.offsets_ = counts;
  m.entries_.resize(m.offsets_.back());
  std::vector<std::uint32_t> fill(m.offsets_.begin(), m.offsets_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Isometry3f frame = pointPairFrame(m.points_[i], m.normals_[i]);
    for (std::size_t j = 0; j < n; ++j) {
      const long b = binOfPair(i, j);
      if (b < 0)
        continue;
      m.entries_[fill[static_cast<std::size_t>(b)]++] = {static_cast<std::uint32_t>(i),
                                                         pointPairAngle(frame, m.points_[j])};
    }
  }
  m.capBins(params.max_bin_pairs);
  return m;
}

void PointPairModel::capBins(std::size_t cap) {
  const std::size_t bins = offsets_.size() - 1;
  weights_.assign(bins, 1.f);
  if (cap == 0)
    return;
  std::vector<Entry> kept;
  kept.reserve(entries_.size());
  std::vector<std::uint32_t> offsets(offsets_.size(), 0);
  for (std::size_t b = 0; b < bins; ++b) {
    const std::size_t first = offsets_[b], count = offsets_[b + 1] - first;
    if (count <= cap) {
      kept.insert(kept.end(), entries_.begin() + first, entries_.begin() + first + count);
    } else {
      // An evenly strided share, each standing for count / cap pairs: the votes' total stays.
      for (std::size_t k = 0; k < cap; ++k)
        kept.push_back(entries_[first + k * count / cap]);
      weights_[b] = static_cast<float>(count) / static_cast<float>(cap);
    }
    offsets[b + 1] = static_cast<std::uint32_t>(kept.size());
  }
  entries_ = std::move(kept);
  offsets_ = std::move(offsets);
}

namespace {

/** At most \a cap of \a items, evenly strided from the first (which stays); order kept. */
void keepEvenlyStrided(std::vector<int>& items, std::size_t cap) {
  if (items.size() <= cap)
    return;
  const double stride = static_cast<double>(items.size()) / static_cast<double>(cap);
  for (std::size_t k = 0; k < cap; ++k)
    items[k] = items[static_cast<std::size_t>(std::floor(static_cast<double>(k) * stride))];
  items.resize(cap);
}

/** Of \a eligible (usable points only), one per cell of a grid of \a step: the nearest to the
 * cell's centre (ties: the lower index), cells in key order. One sort of (cell, distance,
 * index), a strict order, so the result does not depend on how it is sorted: in two halves in
 * parallel, then merged (a million points: 0.1 s, a fifth of what a hash map of the cells
 * took). */
std::vector<int> onePerCell(const std::vector<Eigen::Vector3f>& points,
                            const std::vector<int>& eligible, float step, int threads) {
  struct InCell {
    std::uint64_t key;
    float distance;
    int index;
  };
  std::vector<InCell> candidates;
  candidates.reserve(eligible.size());
  for (const int i : eligible) {
    const Eigen::Vector3f& p = points[static_cast<std::size_t>(i)];
    if (isUsablePoint(p))
      candidates.push_back({cellKey(p, step), (p - cellCentre(p, step)).squaredNorm(), i});
  }
  const auto before = [](const InCell& a, const InCell& b) {
    return std::tie(a.key, a.distance, a.index) < std::tie(b.key, b.distance, b.index);
  };
  const auto middle = candidates.begin() + static_cast<long>(candidates.size() / 2);
#pragma omp parallel sections num_threads(std::clamp(threads, 1, 2))
  {
#pragma omp section
    std::sort(candidates.begin(), middle, before);
#pragma omp section
    std::sort(middle, candidates.end(), before);
  }
  std::inplace_merge(candidates.begin(), middle, candidates.end(), before);
  std::vector<int> kept;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (k == 0 || candidates[k].key != candidates[k - 1].key)
      kept.push_back(candidates[k].index);
  return kept;
}

/** \a kept (one point per cell of a grid of \a step) regridded coarser until at most \a
 * max_points remain (0: no limit); returns the step of the last grid. A view of surfaces holds
 * cells in proportion to 1 / step^2, so the step grows by the square root of the excess (at
 * least 5%: near the budget a step barely larger merges nothing), again until the budget holds
 * (a volume of points shrinks faster than that); after 16 grids an evenly strided share, still
 * at most one point per cell. */
float coarsenToBudget(const std::vector<Eigen::Vector3f>& points, std::vector<int>& kept,
                      float step, std::size_t max_points, int threads) {
  if (max_points == 0)
    return step;
  for (int round = 0; kept.size() > max_points && round < 16; ++round) {
    step *= std::max(1.05f,
                     std::sqrt(static_cast<float>(kept.size()) / static_cast<float>(max_points)));
    kept = onePerCell(points, kept, step, threads);
  }
  keepEvenlyStrided(kept, max_points);
  return step;
}

/** Points a normal is fitted to per search radius: the search surface is the eligible points
 * on a grid fine enough to hold about this many in a disc of the radius. */
constexpr float kNormalSupport = 100.f;

}  // namespace

PointPairScene subsampleForVoting(const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<int>& eligible, float step, float normal_radius,
                                  int threads, std::size_t max_points) {
  PointPairScene scene;
  scene.step = step;
  if (!(step > 0.f) || eligible.empty())
    return scene;
  const std::vector<int> on_step = onePerCell(points, eligible, step, threads);
  std::vector<int> kept = on_step;
  scene.step = coarsenToBudget(points, kept, step, max_points, threads);
  const bool coarser = scene.step > step;
  normal_radius *= scene.step / step;
  // The surface the normals are fitted to: the eligible points on a grid of radius sqrt(pi /
  // kNormalSupport) (a full-resolution cloud holds thousands in the radius, and a plane through
  // a hundred is as good). On a coarser grid, drawn from the points on the model's step, at most
  // a quarter of what a view of surfaces holds per kept point: a plane through some 25 in the
  // radius, where a volume of points would put several hundred.
  const float support_step = normal_radius * std::sqrt(kPi / kNormalSupport);
  std::vector<int> support =
      onePerCell(points, coarser ? on_step : eligible, support_step, threads);
  if (coarser) {
    const auto per_kept = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::ceil(0.25f * std::pow(scene.step / support_step, 2.f))));
    coarsenToBudget(points, support, support_step, per_kept * kept.size(), threads);
  }
  std::vector<Eigen::Vector3f> estimated;
  {
    // PCL's NormalEstimationOMP on the kept points, the support as the search surface.
    pcl::PointCloud<pcl::PointXYZ>::Ptr surface(new pcl::PointCloud<pcl::PointXYZ>);
    for (const int i : support)
      surface->push_back(pcl::PointXYZ(points[static_cast<std::size_t>(i)].x(),
                                       points[static_cast<std::size_t>(i)].y(),
                                       points[static_cast<std::size_t>(i)].z()));
    pcl::PointCloud<pcl::PointXYZ>::Ptr input(new pcl::PointCloud<pcl::PointXYZ>);
    for (const int i : kept)
      input->push_back(pcl::PointXYZ(points[static_cast<std::size_t>(i)].x(),
                                     points[static_cast<std::size_t>(i)].y(),
                                     points[static_cast<std::size_t>(i)].z()));
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(std::max(1, threads));
    ne.setInputCloud(input);
    ne.setSearchSurface(surface);
    ne.setSearchMethod(
        pcl::search::KdTree<pcl::PointXYZ>::Ptr(new pcl::search::KdTree<pcl::PointXYZ>));
    ne.setRadiusSearch(normal_radius);
    ne.setViewPoint(0.f, 0.f, 0.f);
    pcl::PointCloud<pcl::Normal> out;
    ne.compute(out);
    for (const auto& n : out)
      estimated.push_back(n.getNormalVector3fMap());
  }
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const auto i = static_cast<std::size_t>(kept[k]);
    Eigen::Vector3f n = estimated[k];
    if (!n.allFinite() || !(n.norm() > 0.5f))
      continue;
    n.normalize();
    if (n.dot(points[i]) > 0.f)
      n = -n;
    scene.points.push_back(points[i]);
    scene.normals.push_back(n);
    scene.indices.push_back(kept[k]);
  }
  return scene;
}

namespace {

/** A pose one reference voted for. */
struct Vote {
  Eigen::Isometry3f pose;
  float votes;
};

/** The votes of one scene reference (Drost's voting scheme with Hinterstoisser's spreading and
 * one vote per feature bin and angle). Works in its own accumulator. */
class ReferenceVoter {
 public:
  ReferenceVoter(const PointPairModel& model, const PointPairVotingParams& params)
      : model_(model),
        params_(params),
        a_(model.angleBins()),
        accumulator_(model.points().size() * static_cast<std::size_t>(model.angleBins()), 0.f) {
    const std::size_t f = static_cast<std::size_t>(model.featureAngleBins());
    flags_.assign(static_cast<std::size_t>(model.distanceBins()) * f * f * f, 0);
    model_frames_.reserve(model.points().size());
    for (std::size_t i = 0; i < model.points().size(); ++i)
      model_frames_.push_back(pointPairFrame(model.points()[i], model.normals()[i]));
  }

  /** The peaks of reference \a r paired with \a neighbours (indices into \a scene). */
  void vote(const PointPairScene& scene, std::size_t r, const std::vector<int>& neighbours,
            std::vector<Vote>& out) {
    std::fill(accumulator_.begin(), accumulator_.end(), 0.f);
    for (const long b : touched_)
      flags_[static_cast<std::size_t>(b)] = 0;
    touched_.clear();
    const Eigen::Vector3f& sr = scene.points[r];
    const Eigen::Vector3f& nr = scene.normals[r];
    const Eigen::Isometry3f frame = pointPairFrame(sr, nr);
    const int fa = model_.featureAngleBins();
    const float angle = kPi / static_cast<float>(fa);
    const float turn = 2.f * kPi / static_cast<float>(a_);
    for (const int j : neighbours) {
      if (static_cast<std::size_t>(j) == r)
        continue;
      const Eigen::Vector3f& sj = scene.points[static_cast<std::size_t>(j)];
      const Eigen::Vector4f f =
          pointPairFeature(sr, nr, sj, scene.normals[static_cast<std::size_t>(j)]);
      if (!(f[0] > 0.f) || model_.isCoplanar(f))
        continue;
      const float alpha_scene = pointPairAngle(frame, sj);
      const float margin = params_.spread_margin;
      const Quantised d = quantise(f[0] / model_.step(), model_.distanceBins(), margin);
      const Quantised q1 = quantise(f[1] / angle, fa, margin),
                      q2 = quantise(f[2] / angle, fa, margin),
                      q3 = quantise(f[3] / angle, fa, margin);
      if (f[0] / model_.step() >= static_cast<float>(model_.distanceBins()))
        continue;
      // The scene angle's bin: a model pair and this one vote once per feature bin and angle.
      const int alpha_bin = angleBin(alpha_scene + kPi, turn);
      for (int id = 0; id < (d.near_border ? 2 : 1); ++id)
        for (int i1 = 0; i1 < (q1.near_border ? 2 : 1); ++i1)
          for (int i2 = 0; i2 < (q2.near_border ? 2 : 1); ++i2)
            for (int i3 = 0; i3 < (q3.near_border ? 2 : 1); ++i3) {
              const long bin = model_.binAt(id ? d.neighbour : d.bin, i1 ? q1.neighbour : q1.bin,
                                            i2 ? q2.neighbour : q2.bin, i3 ? q3.neighbour : q3.bin);
              if (bin < 0 || !firstVote(bin, alpha_bin))
                continue;
              const float weight = model_.binWeight(bin);
              for (const auto* e = model_.binBegin(bin); e != model_.binEnd(bin); ++e) {
                const int b = angleBin(e->alpha - alpha_scene, turn);
                accumulator_[static_cast<std::size_t>(e->reference) * a_ + b] += weight;
              }
            }
    }
    peaks(frame, out);
  }

 private:
  /** The bin of an angle in (-2 pi, 2 pi) (a difference of two pointPairAngle values) on
   * [0, 2 pi) in bins of \a turn. */
  int angleBin(float alpha, float turn) const {
    if (alpha < 0.f)
      alpha += 2.f * kPi;
    if (alpha >= 2.f * kPi)
      alpha -= 2.f * kPi;
    return std::max(0, std::min(a_ - 1, static_cast<int>(alpha / turn)));
  }

  /** True the first time this reference looks up (\a bin, \a alpha_bin): one bit per angle
   * bin in a word per feature bin (Hinterstoisser et al.), cleared after each reference. */
  bool firstVote(long bin, int alpha_bin) {
    std::uint32_t& word = flags_[static_cast<std::size_t>(bin)];
    const std::uint32_t bit = 1u << alpha_bin;
    if (word & bit)
      return false;
    if (word == 0)
      touched_.push_back(bin);
    word |= bit;
    return true;
  }

  /** The accumulator's best cells (at least peak_share of the highest, at most
   * peaks_per_reference, distinct model references) as poses. */
  void peaks(const Eigen::Isometry3f& frame, std::vector<Vote>& out) const {
    std::vector<std::pair<float, std::size_t>> best;  // (votes, cell)
    float top = 0.f;
    for (std::size_t c = 0; c < accumulator_.size(); ++c)
      top = std::max(top, accumulator_[c]);
    if (!(top > 0.f))
      return;
    const float floor_votes = params_.peak_share * top;
    for (std::size_t c = 0; c < accumulator_.size(); ++c)
      if (accumulator_[c] >= floor_votes)
        best.emplace_back(accumulator_[c], c);
    std::stable_sort(best.begin(), best.end(),
                     [](const auto& x, const auto& y) { return x.first > y.first; });
    const Eigen::Isometry3f to_scene = frame.inverse(Eigen::Isometry);
    const float turn = 2.f * kPi / static_cast<float>(a_);
    int taken = 0;
    for (const auto& [votes, cell] : best) {
      if (taken >= params_.peaks_per_reference)
        break;
      const std::size_t reference = cell / static_cast<std::size_t>(a_);
      const int b = static_cast<int>(cell % static_cast<std::size_t>(a_));
      const float alpha = (static_cast<float>(b) + 0.5f) * turn;
      Vote v;
      v.pose =
          to_scene * Eigen::AngleAxisf(alpha, Eigen::Vector3f::UnitX()) * model_frames_[reference];
      v.votes = votes;
      out.push_back(v);
      ++taken;
    }
  }

  const PointPairModel& model_;
  const PointPairVotingParams& params_;
  int a_;
  std::vector<Eigen::Isometry3f> model_frames_;
  std::vector<float> accumulator_;
  std::vector<std::uint32_t> flags_;  ///< per feature bin: the angle bins looked up
  std::vector<long> touched_;         ///< feature bins with a flag set
};

/** A cluster of votes: its best pose and the votes of all. */
struct PoseCluster {
  Eigen::Isometry3f pose;
  Eigen::Vector3f centre;
  double votes = 0.0;
};

/** Greedy pose clustering (Drost): votes by count, each joining the first cluster whose pose it
 * is close to (model centre within \a distance, rotation within \a angle_rad). */
std::vector<PoseCluster> clusterPoses(std::vector<Vote> votes, const Eigen::Vector3f& model_centre,
                                      float distance, float angle_rad) {
  std::stable_sort(votes.begin(), votes.end(),
                   [](const Vote& a, const Vote& b) { return a.votes > b.votes; });
  std::vector<PoseCluster> clusters;
  const float cos_half = std::cos(0.5f * angle_rad);
  for (const Vote& v : votes) {
    const Eigen::Vector3f centre = v.pose * model_centre;
    const Eigen::Quaternionf q(v.pose.linear());
    bool joined = false;
    for (PoseCluster& c : clusters) {
      if ((c.centre - centre).squaredNorm() > distance * distance)
        continue;
      // |<q1, q2>| = cos(angle / 2) of the relative rotation.
      if (std::abs(Eigen::Quaternionf(c.pose.linear()).dot(q)) < cos_half)
        continue;
      c.votes += v.votes;
      joined = true;
      break;
    }
    if (!joined)
      clusters.push_back({v.pose, centre, static_cast<double>(v.votes)});
  }
  std::stable_sort(clusters.begin(), clusters.end(),
                   [](const PoseCluster& a, const PoseCluster& b) { return a.votes > b.votes; });
  return clusters;
}

/** The scene's subsampled points on their grid, for the re-score's neighbour lookups. */
class SceneGrid {
 public:
  explicit SceneGrid(const PointPairScene& scene) : scene_(scene) {
    cells_.reserve(scene.points.size());
    for (std::size_t i = 0; i < scene.points.size(); ++i)
      cells_.emplace(cellKey(scene.points[i], scene.step), static_cast<int>(i));
  }

  /** True when a scene point lies within \a distance of \a p with a normal within \a cos_max
   * of \a n. */
  bool explains(const Eigen::Vector3f& p, const Eigen::Vector3f& n, float distance,
                float cos_max) const {
    const int reach = static_cast<int>(std::ceil(distance / scene_.step));
    const float step = scene_.step;
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) {
          const Eigen::Vector3f q =
              p + step * Eigen::Vector3f(static_cast<float>(dx), static_cast<float>(dy),
                                         static_cast<float>(dz));
          const auto it = cells_.find(cellKey(q, step));
          if (it == cells_.end())
            continue;
          const auto k = static_cast<std::size_t>(it->second);
          if ((scene_.points[k] - p).squaredNorm() <= distance * distance &&
              scene_.normals[k].dot(n) >= cos_max)
            return true;
        }
    return false;
  }

 private:
  const PointPairScene& scene_;
  std::unordered_map<std::uint64_t, int> cells_;
};

/** The model samples that face the camera at \a pose and that the scene explains (SceneGrid),
 * how many face it and, with \a image, how many of the unexplained ones the scene hides (its
 * depth at the sample's pixel more than \a hidden in front of it). */
std::size_t explainedSamples(const PointPairModel& model, const Eigen::Isometry3f& pose,
                             const SceneGrid& grid, float distance, float cos_max,
                             const DepthImage* image, float hidden, std::size_t& facing,
                             std::size_t& hidden_samples) {
  std::size_t explained = 0;
  facing = hidden_samples = 0;
  for (std::size_t i = 0; i < model.points().size(); ++i) {
    const Eigen::Vector3f p = pose * model.points()[i];
    const Eigen::Vector3f n = pose.linear() * model.normals()[i];
    if (!(n.dot(p) < 0.f))
      continue;
    ++facing;
    if (grid.explains(p, n, distance, cos_max)) {
      ++explained;
      continue;
    }
    int u = 0, v = 0;
    if (image && image->pixelOf(p, u, v) && image->depth(u, v) < p.z() - hidden)
      ++hidden_samples;
  }
  return explained;
}

}  // namespace

bool posesShareSurface(const IcfModel& model, const Eigen::Isometry3f& a,
                       const Eigen::Isometry3f& b, float tolerance) {
  const Eigen::Isometry3f a_to_b = b.inverse(Eigen::Isometry) * a;
  const std::size_t n = std::min<std::size_t>(64, model.samples().size());
  for (std::size_t i = 0; i < n; ++i)
    if (model.field().distance(a_to_b * model.samples()[i].point) > tolerance)
      return false;
  return true;
}

std::vector<VotedPose> voteForPoses(const IcfModel& model, const PointPairScene& scene,
                                    const PointPairVotingParams& params, int threads,
                                    const DepthImage* image) {
  params.validate();
  const PointPairModel& table = model.pointPairs();
  std::vector<VotedPose> result;
  if (table.empty() || scene.points.size() < 2)
    return result;
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(scene.points.size());
  for (std::size_t i = 0; i < scene.points.size(); ++i)
    (*cloud)[i].getVector3fMap() = scene.points[i];
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);

  // References evenly strided over the whole frame.
  const std::size_t wanted = std::min<std::size_t>(
      params.max_references,
      std::max<std::size_t>(
          1, static_cast<std::size_t>(std::ceil(params.reference_share * scene.points.size()))));
  const double stride = static_cast<double>(scene.points.size()) / static_cast<double>(wanted);
  std::vector<std::size_t> references;
  for (std::size_t k = 0; k < wanted; ++k)
    references.push_back(
        std::min(scene.points.size() - 1, static_cast<std::size_t>(std::floor(k * stride))));

  const auto bins = static_cast<double>(table.distanceBins());
  const auto max_pairs = static_cast<std::size_t>(
      std::ceil(static_cast<double>(params.max_pairs_discs) * M_PI * bins * bins));
  // Each reference votes into its own slot: the result does not depend on the thread count.
  std::vector<std::vector<Vote>> per_reference(references.size());
  const int n = static_cast<int>(references.size());
#pragma omp parallel num_threads(std::max(1, threads))
  {
    ReferenceVoter voter(table, params);
    std::vector<int> neighbours;
    std::vector<float> distances;
#pragma omp for schedule(dynamic, 16)
    for (int k = 0; k < n; ++k) {
      const std::size_t r = references[static_cast<std::size_t>(k)];
      tree.radiusSearch((*cloud)[r], table.diameter(), neighbours, distances);
      keepEvenlyStrided(neighbours, max_pairs);
      voter.vote(scene, r, neighbours, per_reference[static_cast<std::size_t>(k)]);
    }
  }
  std::vector<Vote> votes;
  for (auto& v : per_reference)
    votes.insert(votes.end(), v.begin(), v.end());

  const Eigen::Vector3f centre = 0.5f * (model.mesh().boundsMin() + model.mesh().boundsMax());
  std::vector<PoseCluster> clusters =
      clusterPoses(std::move(votes), centre, params.cluster_distance * table.diameter(),
                   params.cluster_angle_deg * kPi / 180.f);
  if (clusters.size() > params.rescored)
    clusters.resize(params.rescored);

  // View-dependent re-score of the best clusters, in parallel into fixed slots.
  const SceneGrid grid(scene);
  // Within the scene's own spacing where it was gridded coarser than the model's step
  // (subsampleForVoting's point budget): a sample then lies up to that far from a scene point.
  const float distance = params.rescore_distance * std::max(table.step(), scene.step);
  const float cos_max = std::cos(params.rescore_angle_deg * kPi / 180.f);
  const float hidden_distance = params.rescore_hidden_distance * table.step();
  // The hidden samples are counted only for the kept_visible ranking that reads them.
  const DepthImage* shown = params.kept_visible > 0 ? image : nullptr;
  std::vector<VotedPose> rescored(clusters.size());
  const int m = static_cast<int>(clusters.size());
#pragma omp parallel for schedule(dynamic, 4) num_threads(std::max(1, threads))
  for (int c = 0; c < m; ++c) {
    VotedPose& v = rescored[static_cast<std::size_t>(c)];
    v.model_to_camera = clusters[static_cast<std::size_t>(c)].pose;
    v.votes = clusters[static_cast<std::size_t>(c)].votes;
    std::size_t facing = 0, hidden = 0;
    v.explained_samples = explainedSamples(table, v.model_to_camera, grid, distance, cos_max, shown,
                                           hidden_distance, facing, hidden);
    v.explained = facing > 0 ? static_cast<double>(v.explained_samples) / facing : 0.0;
    if (shown && facing > hidden)
      v.explained_visible = static_cast<double>(v.explained_samples) / (facing - hidden);
  }
  std::stable_sort(rescored.begin(), rescored.end(), [](const VotedPose& a, const VotedPose& b) {
    return a.explained_samples > b.explained_samples;
  });
  const float tolerance = params.distinct_surface * table.diameter();
  // At most kept_per_place of one place (model centres within a quarter of the diameter of a
  // better one's), so that a second object, or a second copy, is voted for too.
  internal::PlaceQuota quota(0.25f * table.diameter(), params.kept_per_place);
  const auto keep = [&](const std::vector<VotedPose>& ranked, std::size_t limit) {
    for (const VotedPose& v : ranked) {
      if (result.size() >= limit)
        break;
      if (tolerance > 0.f && std::any_of(result.begin(), result.end(), [&](const VotedPose& k) {
            return posesShareSurface(model, v.model_to_camera, k.model_to_camera, tolerance);
          }))
        continue;
      if (quota.admit(v.model_to_camera * centre))
        result.push_back(v);
    }
  };
  keep(rescored, params.kept);
  if (shown) {
    // Then the poses that explain most of what they show: a target half hidden by others.
    std::vector<VotedPose> by_share;
    for (const VotedPose& v : rescored)
      if (v.explained >= params.rescore_min_share)
        by_share.push_back(v);
    std::stable_sort(by_share.begin(), by_share.end(), [](const VotedPose& a, const VotedPose& b) {
      return a.explained_visible > b.explained_visible;
    });
    keep(by_share, result.size() + params.kept_visible);
  }
  return result;
}

}  // namespace icf
}  // namespace pcl
