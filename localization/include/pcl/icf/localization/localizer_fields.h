/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief LocalizerParams' field registry (parameter_fields.h): its own knobs and the
 * calibration constants under tuning(), by the names the Python keywords, pcl_icf_tool's --set
 * and pcl_icf_bench's --icf, --verification and --tuning use. */

#include <pcl/icf/localization/object_localizer.h>
#include <pcl/icf/registration/parameter_fields.h>

namespace pcl {
namespace icf {
namespace localization {

/** Every registered field of LocalizerParams: first its own (tuning false), then the
 * registration's (icfFields() under tuning().icf, its strategy, fallback, seed and threads
 * being LocalizerParams' own), the verification's, the turns' and the hypotheses'. The colour,
 * the camera and the explained points are not numbers and are set by their own options. */
const FieldRegistry<LocalizerParams>& localizerFields();

}  // namespace localization
}  // namespace icf
}  // namespace pcl
