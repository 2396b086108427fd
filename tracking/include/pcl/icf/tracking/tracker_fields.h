/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief TrackerParams' own fields in the field registry (parameter_fields.h); its localizer's
 * are localization::localizerFields(). */

#include <pcl/icf/registration/parameter_fields.h>
#include <pcl/icf/tracking/object_tracker.h>

namespace pcl {
namespace icf {
namespace tracking {

/** The fields TrackerParams has itself (the localizer's are localizerFields()). */
const FieldRegistry<TrackerParams>& trackerFields();

}  // namespace tracking
}  // namespace icf
}  // namespace pcl
