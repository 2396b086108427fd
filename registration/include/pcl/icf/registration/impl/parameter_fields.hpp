/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/icf/registration/parameter_fields.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

namespace pcl {
namespace icf {

template <typename Params>
const ParameterField<Params>& findField(const FieldRegistry<Params>& registry,
                                        const std::string& name) {
  for (const auto& field : registry)
    if (field.name == name)
      return field;
  std::string known;
  for (const auto& field : registry)
    known += (known.empty() ? "" : ", ") + field.name;
  throw std::invalid_argument("unknown field '" + name + "' (known: " + known + ")");
}

namespace detail {

/** The shortest text that reads back as \a v (as a float when \a single): whole numbers
 * without an exponent. */
inline std::string shortestText(double v, bool single = false) {
  if (std::isinf(v))
    return v > 0 ? "inf" : "-inf";
  char buffer[40];
  if (v == std::floor(v) && std::abs(v) < 1e16) {
    std::snprintf(buffer, sizeof buffer, "%.0f", v);
    return buffer;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    const double back = std::strtod(buffer, nullptr);
    if (single ? static_cast<float>(back) == static_cast<float>(v) : back == v)
      break;
  }
  return buffer;
}

}  // namespace detail

template <typename Params>
void setFieldNumber(const ParameterField<Params>& field, Params& params, double value) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument(field.name + ": " + detail::shortestText(value) + " " + why);
  };
  switch (field.kind) {
    case FieldKind::Choice:
      fail("is not one of its names");
      break;
    case FieldKind::Flag:
      if (value != 0.0 && value != 1.0)
        fail("is not 0 or 1");
      break;
    case FieldKind::Count:
      if (!(value == std::floor(value)))
        fail("is not a whole number");
      [[fallthrough]];
    case FieldKind::Real:
      if (!(value >= field.min && value <= field.max))
        fail("is outside [" + detail::shortestText(field.min) + ", " +
             detail::shortestText(field.max) + "]");
      break;
  }
  field.set_number(params, value);
}

template <typename Params>
void setFieldText(const ParameterField<Params>& field, Params& params, const std::string& text) {
  if (field.kind == FieldKind::Choice) {
    try {
      field.set_choice(params, text);
    } catch (const std::invalid_argument&) {
      std::string names;
      for (const auto& c : field.choices)
        names += (names.empty() ? "" : ", ") + c;
      throw std::invalid_argument(field.name + ": '" + text + "' is not one of " + names);
    }
    return;
  }
  if (field.kind == FieldKind::Flag && (text == "true" || text == "false")) {
    setFieldNumber(field, params, text == "true" ? 1.0 : 0.0);
    return;
  }
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || std::isnan(value))
    throw std::invalid_argument(field.name + ": '" + text + "' is not a number");
  setFieldNumber(field, params, value);
}

template <typename Params>
std::string fieldText(const ParameterField<Params>& field, const Params& params) {
  return field.kind == FieldKind::Choice
             ? field.get_choice(params)
             : detail::shortestText(field.get_number(params), field.single);
}

template <typename Params>
std::string describeFields(const FieldRegistry<Params>& registry) {
  static const char* const kinds[] = {"flag", "count", "real", "choice"};
  const Params defaults{};
  std::ostringstream out;
  for (const auto& f : registry) {
    out << f.name << "  " << kinds[static_cast<int>(f.kind)];
    if (f.kind == FieldKind::Count || f.kind == FieldKind::Real)
      out << " [" << detail::shortestText(f.min) << ", " << detail::shortestText(f.max) << "]";
    if (f.kind == FieldKind::Choice) {
      out << " (";
      for (std::size_t i = 0; i < f.choices.size(); ++i)
        out << (i ? "|" : "") << f.choices[i];
      out << ")";
    }
    out << " = " << fieldText(f, defaults) << "  " << f.doc << "\n";
  }
  return out.str();
}

template <typename Params, typename Access>
ParameterField<Params> numberField(std::string name, double min, double max, std::string doc,
                                   Access access, bool tuning) {
  using T = std::remove_reference_t<decltype(access(std::declval<Params&>()))>;
  static_assert(std::is_arithmetic_v<T>, "a number field needs an arithmetic member");
  ParameterField<Params> f;
  f.name = std::move(name);
  f.kind = std::is_same_v<T, bool> ? FieldKind::Flag
           : std::is_integral_v<T> ? FieldKind::Count
                                   : FieldKind::Real;
  f.min = f.kind == FieldKind::Flag ? 0.0 : min;
  f.max = f.kind == FieldKind::Flag ? 1.0 : max;
  f.single = std::is_same_v<T, float>;
  f.tuning = tuning;
  f.doc = std::move(doc);
  f.set_number = [access](Params& p, double v) {
    if constexpr (std::is_same_v<T, bool>)
      access(p) = v != 0.0;
    else
      access(p) = static_cast<T>(v);
  };
  f.get_number = [access](const Params& p) {
    return static_cast<double>(access(const_cast<Params&>(p)));
  };
  return f;
}

template <typename Params, typename T, typename Access>
ParameterField<Params> choiceField(std::string name, std::vector<std::string> choices,
                                   std::string doc, Access access, T (*parse)(const std::string&),
                                   bool tuning) {
  ParameterField<Params> f;
  f.name = std::move(name);
  f.kind = FieldKind::Choice;
  f.choices = std::move(choices);
  f.tuning = tuning;
  f.doc = std::move(doc);
  f.set_choice = [access, parse](Params& p, const std::string& text) { access(p) = parse(text); };
  f.get_choice = [access](const Params& p) { return toString(access(const_cast<Params&>(p))); };
  return f;
}

template <typename Outer, typename Inner, typename Access>
FieldRegistry<Outer> liftFields(const FieldRegistry<Inner>& registry, Access access) {
  FieldRegistry<Outer> out;
  for (const auto& in : registry) {
    ParameterField<Outer> f;
    static_cast<FieldDescription&>(f) = in;
    if (in.set_number) {
      f.set_number = [set = in.set_number, access](Outer& o, double v) { set(access(o), v); };
      f.get_number = [get = in.get_number, access](const Outer& o) {
        return get(access(const_cast<Outer&>(o)));
      };
    }
    if (in.set_choice) {
      f.set_choice = [set = in.set_choice, access](Outer& o, const std::string& t) {
        set(access(o), t);
      };
      f.get_choice = [get = in.get_choice, access](const Outer& o) {
        return get(access(const_cast<Outer&>(o)));
      };
    }
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace icf
}  // namespace pcl
