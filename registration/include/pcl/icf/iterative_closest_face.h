/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * The PCL-facing include of pcl::IterativeClosestFace, beside PCL's
 * <pcl/registration/icp.h>: the class lives in the registration room. */
#include <pcl/icf/registration/iterative_closest_face.h>
