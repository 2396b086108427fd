/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Pose hypotheses of a model anywhere in a scene by point pair feature voting (Drost,
 * Ulrich, Navab and Ilic, "Model globally, match locally", CVPR 2010), with the refinements
 * that made it the best classical method on the BOP benchmark (Hinterstoisser, Lepetit, Rajkumar
 * and Konolige, "Going further with point pair features", ECCV 2016; Vidal, Lin and Marti, "6D
 * pose estimation using an improved method based on point pair features", ICCAR 2018): votes
 * spread to the neighbouring feature bins, a model sampled so that both sides of an edge keep a
 * point, pose clustering, and view-dependent re-scoring of the clusters.
 *
 * It needs no segmentation: every scene point may be a reference. The model's table
 * (PointPairModel) is built once per model (IcfModel holds it); voting runs once per scene.
 *
 * Frames: the scene is in the camera's frame (camera at the origin, looking along +z); poses are
 * model -> camera. Lengths in the scene's units (metres). */

#include <pcl/icf/registration/face_mesh.h>
#include <pcl/icf/verification/depth_image.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace pcl {
namespace icf {

class IcfModel;

/** \brief How a model is sampled and its pairs quantised. Calibration constants (the
 * localizer's tuning), not a user's knobs. */
struct PointPairModelParams {
  /** Sampling step of the model's surface and of the pair distance, as a share of the model's
   * diameter (Drost's tau_d). */
  float sampling_step = 0.05f;
  /** Bins of the rotation about the reference normal over [0, 2 pi); the feature's three
   * angles over [0, pi] are binned at the same width (half as many bins): 30 is Drost's 12
   * degrees. */
  int angle_bins = 30;
  /** Two samples of one sampling cell are both kept when their normals differ by more than this
   * (degrees): a box's edge keeps a point of each face (Vidal et al.). */
  float normal_split_deg = 30.f;
  /** Pairs of one plane (normals within this many degrees of each other and of perpendicular
   * to the pair's direction) are left out of the table, and scene pairs like them vote for
   * nothing: they fix the plane but not where on it the model lies, so a large flat face of
   * another object would vote for every place on it (0: keep them). */
  float coplanar_deg = 10.f;
  /** A bin holding more pairs keeps this many of them, evenly strided, each voting for the
   * pairs it stands for (0: every pair). A feature seen at thousands of places on the model (the
   * pairs around a cylinder, across a box's edge) costs a vote per place and tells little; the
   * cap bounds the cost of one lookup. */
  std::size_t max_bin_pairs = 256;
  /** Dense area-weighted surface samples the cells are filled from. */
  std::size_t dense_samples = 20000;
  std::uint64_t seed = 1;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief The four numbers of an oriented point pair (Drost eq. 1): the distance |d| and the
 * angles (radians, [0, pi]) between n1 and d, n2 and d, n1 and n2, with d = p2 - p1. */
Eigen::Vector4f pointPairFeature(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1,
                                 const Eigen::Vector3f& p2, const Eigen::Vector3f& n2);

/** \brief The rigid motion that takes the oriented point (\a p, unit \a n) to the origin with
 * its normal along +x (Drost's T_{s->g}). */
Eigen::Isometry3f pointPairFrame(const Eigen::Vector3f& p, const Eigen::Vector3f& n);

/** \brief The angle (radians, (-pi, pi]) of the turn about +x that brings \a frame * \a p2 into
 * the half plane z = 0, y >= 0 (Drost's alpha). A model pair and a scene pair with the same
 * feature are aligned by the reference frames and a turn of alpha_model - alpha_scene. */
float pointPairAngle(const Eigen::Isometry3f& frame, const Eigen::Vector3f& p2);

/** \brief A model's oriented samples and the table of all their pairs, indexed by the
 * quantised feature: what the scene's pairs vote with. Built once per model; immutable and
 * safe to share between threads. */
struct ModelFileAccess;  // model_file.cpp: writes and reads the prepared table

class PointPairModel {
 public:
  /** One model pair in the table: its reference sample and its angle (pointPairAngle). */
  struct Entry {
    std::uint32_t reference = 0;
    float alpha = 0.f;
  };

  PointPairModel() = default;
  /** \brief Samples \a mesh (area-weighted, then one sample per cell of sampling_step x the
   * diameter, two where the normals differ by more than normal_split_deg) and tables every
   * ordered pair. Face normals point out of the mesh when its winding is consistent; a mesh
   * whose normals mostly point inwards (area-weighted, seen from its centroid) is flipped as
   * a whole. \throws std::invalid_argument for invalid \a params. */
  static PointPairModel build(const FaceMesh& mesh, const PointPairModelParams& params = {});

  bool empty() const { return points_.empty(); }
  const std::vector<Eigen::Vector3f>& points() const { return points_; }
  const std::vector<Eigen::Vector3f>& normals() const { return normals_; }
  /** Largest distance between two samples (the model's diameter as the table sees it). */
  float diameter() const { return diameter_; }
  /** The sampling step and the distance bin's width, in mesh units. */
  float step() const { return step_; }
  /** Bins of the rotation about the reference normal (the vote's angle) over [0, 2 pi). */
  int angleBins() const { return angle_bins_; }
  /** Bins of each of the feature's three angles over [0, pi] (the same width). */
  int featureAngleBins() const { return feature_bins_; }
  int distanceBins() const { return distance_bins_; }
  /** Pairs tabled (a capped bin counts the ones it keeps). */
  std::size_t pairs() const { return entries_.size(); }
  /** \brief True for a feature the table leaves out (PointPairModelParams::coplanar_deg). */
  bool isCoplanar(const Eigen::Vector4f& feature) const {
    return coplanar_ > 0.f && feature[3] < coplanar_ &&
           std::abs(feature[1] - 1.5707964f) < coplanar_ &&
           std::abs(feature[2] - 1.5707964f) < coplanar_;
  }

  /** \brief The quantised feature's bin index, or -1 when it lies outside the table (a pair
   * farther apart than the diameter). */
  long binOf(const Eigen::Vector4f& feature) const;
  /** \brief The entries of one bin. */
  const Entry* binBegin(long bin) const { return entries_.data() + offsets_[bin]; }
  const Entry* binEnd(long bin) const { return entries_.data() + offsets_[bin + 1]; }
  /** \brief The votes each entry of \a bin casts: 1, or the pairs it stands for in a capped bin
   * (PointPairModelParams::max_bin_pairs). */
  float binWeight(long bin) const { return weights_[static_cast<std::size_t>(bin)]; }
  /** \brief The bin of the feature's quantised coordinates (distance, three angles), -1 when
   * one lies outside the table. */
  long binAt(int distance, int a1, int a2, int a3) const;

 private:
  std::vector<Eigen::Vector3f> points_, normals_;
  float diameter_ = 0.f, step_ = 0.f, coplanar_ = 0.f;
  int angle_bins_ = 0, feature_bins_ = 0, distance_bins_ = 0;
  std::vector<std::uint32_t> offsets_;  ///< per bin, into entries_ (one more than the bins)
  std::vector<Entry> entries_;
  std::vector<float> weights_;  ///< per bin
  void capBins(std::size_t cap);
  friend struct ModelFileAccess;
};

/** \brief How the scene votes. Calibration constants (the localizer's tuning). */
struct PointPairVotingParams {
  /** Share of the subsampled scene points used as references, evenly strided (Drost: 1/5). */
  float reference_share = 0.2f;
  /** At most this many references (strided further over the whole frame). */
  std::size_t max_references = 300;
  /** A reference pairs with at most this many times the points a flat disc of the model's
   * diameter holds on the voting grid (pi x distance bins squared); beyond it an evenly
   * strided subset of its neighbours, nearest first. A camera sees a surface, a layer or two
   * deep within the diameter; only a volume full of points (no view of anything) reaches it. */
  float max_pairs_discs = 4.f;
  /** A feature coordinate within this share of a bin from its border also looks up the
   * neighbouring bin across it, so that noise across the border does not lose the vote
   * (Hinterstoisser et al. spread to every neighbour: 0.5, 16 bins a pair; 0: none). */
  float spread_margin = 0.25f;
  /** Hypotheses taken from each reference's accumulator: its best peaks, at least
   * peak_share of its highest. */
  int peaks_per_reference = 2;
  float peak_share = 0.8f;
  /** Poses whose model centres lie within cluster_distance x the diameter and whose rotations
   * differ by at most cluster_angle_deg are one cluster; its votes add up. */
  float cluster_distance = 0.1f;
  float cluster_angle_deg = 30.f;
  /** The best clusters by votes are re-scored by the model samples they explain as the camera
   * sees them: a visible sample (its normal facing the camera) with a scene point within
   * rescore_distance x the sampling step whose normal lies within rescore_angle_deg
   * (Vidal et al.). */
  std::size_t rescored = 300;
  float rescore_distance = 1.f;
  float rescore_angle_deg = 45.f;
  /** Hypotheses returned, best re-score first, no two putting the model's surface in the same
   * place (every one of 64 samples within distinct_surface x the diameter of the other's
   * surface: a can's spins are one hypothesis). */
  std::size_t kept = 12;
  /** With the scene's depth image (voteForPoses' \a image), up to this many more hypotheses,
   * best first by the share of the facing samples the scene explains among those it does not
   * hide (samples whose pixel shows something more than rescore_hidden_distance x the sampling
   * step in front): a target half hidden behind its neighbours explains few samples and is
   * outranked by poses on larger, wholly visible objects, but explains most of what it shows.
   * Poses that explain fewer than rescore_min_share of their facing samples are not taken. */
  std::size_t kept_visible = 0;
  float rescore_hidden_distance = 2.f;
  float rescore_min_share = 0.2f;
  float distinct_surface = 0.05f;
  /** At most this many of the hypotheses returned put the model's centre at one place (within
   * a quarter of the diameter of a better one's): a second object is hypothesised too. */
  std::size_t kept_per_place = 40;
  /** The scene's normals are estimated over this radius, in sampling steps
   * (subsampleForVoting). */
  float normal_radius = 2.f;

  /** \throws std::invalid_argument naming the field. */
  void validate() const;
};

/** \brief A pose the scene voted for. */
struct VotedPose {
  Eigen::Isometry3f model_to_camera = Eigen::Isometry3f::Identity();
  double votes = 0.0;  ///< the cluster's summed votes
  /** Share of the model's samples that face the camera at this pose and have a scene point
   * on them (the re-score), in [0, 1]. */
  double explained = 0.0;
  std::size_t explained_samples = 0;  ///< their number (what hypotheses are ranked by)
  /** With a depth image and kept_visible > 0: explained_samples over the facing samples the
   * scene does not hide (the kept_visible ranking); 0 otherwise. */
  double explained_visible = 0.0;
};

/** \brief The scene as the voting reads it: subsampled points with unit normals facing the
 * camera, and the index of each in the scene. */
struct PointPairScene {
  std::vector<Eigen::Vector3f> points, normals;
  std::vector<int> indices;
  float step = 0.f;  ///< the grid's step: the one asked for, or coarser to keep a point budget
};

/** \brief The scene points \a eligible (indices into \a points; usable points only) on a grid of
 * \a step, one per cell (the one nearest the cell's centre), each with its normal estimated over
 * \a normal_radius from the eligible points (PCL's NormalEstimationOMP, a plane through the
 * neighbours), oriented towards the camera. The radius follows the model's sampling step rather
 * than the image's pixels, so the normals are as smooth at 1.5 m as at 0.5 m and a structured-
 * light sensor's depth steps (a few millimetres at 1 m) do not tilt them. Points without a
 * normal are left out. With \a max_points > 0, a scene that would keep more (a volume of points
 * rather than a view of surfaces, a wide high-resolution frame for a small model) is gridded
 * coarser, step and radius by one factor, until at most \a max_points are kept
 * (PointPairScene::step says which). Deterministic and independent of \a threads. */
PointPairScene subsampleForVoting(const std::vector<Eigen::Vector3f>& points,
                                  const std::vector<int>& eligible, float step, float normal_radius,
                                  int threads = 1, std::size_t max_points = 0);

/** \brief True when \a a and \a b (model -> camera) put the model's surface in the same place:
 * each of the first 64 of the model's surface samples moved from \a a to \a b lies within \a
 * tolerance of the model's surface (a can's spins, a box's half turns are one place). */
bool posesShareSurface(const IcfModel& model, const Eigen::Isometry3f& a,
                       const Eigen::Isometry3f& b, float tolerance);

/** \brief Votes for poses of \a model in \a scene (subsampleForVoting at the model table's
 * step): every reference pairs with each scene point within the model's diameter, looks its
 * feature up in the model's table and votes for (model reference, angle); each reference's
 * peaks become poses, which are clustered, re-scored as the camera sees them and returned best
 * first (at most params.kept), then, with \a image (the scene's depth image, the same camera
 * frame), up to params.kept_visible more, best first by the share of what they show that the
 * scene explains. Deterministic and independent of \a threads. Empty when the model has no
 * table or the scene no point. */
std::vector<VotedPose> voteForPoses(const IcfModel& model, const PointPairScene& scene,
                                    const PointPairVotingParams& params = {}, int threads = 1,
                                    const DepthImage* image = nullptr);

}  // namespace icf
}  // namespace pcl
