/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl/icf/tracking/tracker_fields.h>

#include <limits>

namespace pcl {
namespace icf {
namespace tracking {

namespace {

#define PCL_ICF_TRACKER(expr)      \
  [](TrackerParams & p) -> auto& { \
    return p.tuning().expr;        \
  }

FieldRegistry<TrackerParams> makeTrackerFields() {
  using P = TrackerParams;
  const double inf = std::numeric_limits<double>::infinity();
  return {
      numberField<P>("crop_margin", 0, inf,
                     "a tracked object is refined on the points in its box grown by this",
                     PCL_ICF_TRACKER(crop_margin)),
      numberField<P>("table_distance", 0, inf, "points this near the table are left out",
                     PCL_ICF_TRACKER(table_distance)),
      numberField<P>("velocity_gain", 0, 1, "share of the last motion the prediction repeats",
                     PCL_ICF_TRACKER(velocity_gain)),
      numberField<P>(
          "search_interval", 1, 1e6, "frames between two searches for an object not found",
          [](TrackerParams & p) -> auto& { return p.search_interval; }, false),
      numberField<P>("reacquire_margin", 0, inf,
                     "a lost object is first searched within this of its last pose",
                     PCL_ICF_TRACKER(reacquire_margin)),
      numberField<P>("reacquire_frames", 0, 1e6, "frames a lost object is searched there",
                     PCL_ICF_TRACKER(reacquire_frames)),
      numberField<P>("reacquire_shift", 0, 1,
                     "that search also starts from each hypothesis moved by this x the box extent",
                     PCL_ICF_TRACKER(reacquire_shift)),
      numberField<P>("reacquire_full_evidence", 0, 1,
                     "the verification's full_evidence for a re-acquisition",
                     PCL_ICF_TRACKER(reacquire_full_evidence)),
      numberField<P>("refine_max_points", 0, 1e7, "the refinement's points per frame",
                     PCL_ICF_TRACKER(refinement.max_points), false),
  };
}

#undef PCL_ICF_TRACKER

}  // namespace

const FieldRegistry<TrackerParams>& trackerFields() {
  static const FieldRegistry<TrackerParams> registry = makeTrackerFields();
  return registry;
}

}  // namespace tracking
}  // namespace icf
}  // namespace pcl
