/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief Internal to the libraries' sources (not installed): the one reader and writer of a
 * single value of a pcl::PCLPointField, whatever its datatype. PCL converts a PCLPointCloud2 to
 * a typed cloud only when the field types match the point type's (pcl::fromPCLPointCloud2 leaves
 * an x of type double or int at zero); files carry every type (PLY declares any, PCD writes
 * F 8 and I 2), so the readers and the mesh code read each value through these. Find the field
 * with pcl::getFieldIndex and its size with pcl::getFieldSize. */

#include <pcl/PCLPointCloud2.h>
#include <pcl/PCLPointField.h>
#include <pcl/common/io.h>
#include <pcl/type_traits.h>

#include <cstdint>
#include <cstring>
#include <string>

namespace pcl {
namespace icf {
namespace internal {

/** The field types a PCLPointField value is read as, besides FLOAT32. */
template <typename... T>
struct FieldTypes {};

/** visitFieldType over the types \a T, Rest...: the first whose PCL datatype is \a datatype. */
template <typename F, typename T, typename... Rest>
auto visitFieldTypeIn(std::uint8_t datatype, F&& f, FieldTypes<T, Rest...>) {
  if (datatype == pcl::traits::asEnum_v<T>)
    return f(T());
  if constexpr (sizeof...(Rest) > 0)
    return visitFieldTypeIn(datatype, f, FieldTypes<Rest...>());
  else
    return f(float());
}

/** \brief Calls \a f with a value of the C++ type of a field of type \a datatype (a
 * pcl::PCLPointField::PointFieldTypes) and returns what it returns. Types of 32 bits or fewer
 * and FLOAT64 are themselves; any other datatype (BOOL, INT64, UINT64, unknown) is taken as
 * FLOAT32, the type of most clouds: callers check the datatype first where that matters. */
template <typename F>
auto visitFieldType(std::uint8_t datatype, F&& f) {
  return visitFieldTypeIn(datatype, f,
                          FieldTypes<std::int8_t, std::uint8_t, std::int16_t, std::uint16_t,
                                     std::int32_t, std::uint32_t, double>());
}

/** \brief The value at \a p of a field of type \a datatype (in the machine's byte order; \a p
 * need not be aligned) as a double: exact for every type visitFieldType knows. */
inline double readFieldValue(const std::uint8_t* p, std::uint8_t datatype) {
  return visitFieldType(datatype, [p](auto type) {
    decltype(type) v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  });
}

/** \brief True for the datatypes readFieldValue reads exactly: the integers of 8 to 32 bits,
 * FLOAT32 and FLOAT64. BOOL, INT64, UINT64 and unknown types are not (it would take them as
 * FLOAT32): a coordinate field of such a type is refused, not read as zeros. */
inline bool isExactNumberField(std::uint8_t datatype) {
  switch (datatype) {
    case pcl::PCLPointField::INT8:
    case pcl::PCLPointField::UINT8:
    case pcl::PCLPointField::INT16:
    case pcl::PCLPointField::UINT16:
    case pcl::PCLPointField::INT32:
    case pcl::PCLPointField::UINT32:
    case pcl::PCLPointField::FLOAT32:
    case pcl::PCLPointField::FLOAT64:
      return true;
    default:
      return false;
  }
}

/** \brief Writes \a v at \a out (need not be aligned) as a field of type \a datatype: a C++
 * conversion (integers: \a v must lie in the type's range, fractions are cut; FLOAT32:
 * rounded, beyond float's range +-inf). */
inline void writeFieldValue(double v, std::uint8_t datatype, std::uint8_t* out) {
  visitFieldType(datatype, [v, out](auto type) {
    const auto x = static_cast<decltype(type)>(v);
    std::memcpy(out, &x, sizeof x);
  });
}

/** \brief Finds the x, y and z fields of a mesh's vertex cloud (pcl::getFieldIndex), each of a
 * type readFieldValue reads exactly and lying inside the point. Fills \a axes and returns an
 * empty string, or returns why not: a missing field first (x, y, z in turn), then an unusable
 * one. Used by FaceMesh and by the tool's posed mesh, so both accept the same vertices. */
inline std::string findVertexFields(const pcl::PCLPointCloud2& cloud,
                                    const pcl::PCLPointField* (&axes)[3]) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const int index = pcl::getFieldIndex(cloud, names[k]);
    if (index < 0)
      return std::string("mesh vertices have no '") + names[k] + "' field";
    axes[k] = &cloud.fields[static_cast<std::size_t>(index)];
  }
  for (const pcl::PCLPointField* f : axes)
    if (!isExactNumberField(f->datatype) ||
        f->offset + pcl::getFieldSize(f->datatype) > cloud.point_step)
      return "mesh vertex field '" + f->name + "' (PCL datatype " + std::to_string(f->datatype) +
             ") is not an integer of 8 to 32 bits or a float, or lies outside the point";
  return {};
}

}  // namespace internal
}  // namespace icf
}  // namespace pcl
