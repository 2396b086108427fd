/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "arguments.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace pcl_icf_tools {

ArgumentReader::ArgumentReader(int argc, const char* const* argv)
    : words_(argv + (argc > 0 ? 1 : 0), argv + argc) {}

std::string ArgumentReader::next() {
  std::string word = words_[next_++];
  attached_.clear();
  has_attached_ = false;
  const auto eq = word.find('=');
  if (word.rfind("--", 0) == 0 && eq != std::string::npos) {
    attached_ = word.substr(eq + 1);
    has_attached_ = true;
    word = word.substr(0, eq);
  }
  return word;
}

std::string ArgumentReader::value(const std::string& option) {
  if (has_attached_) {
    has_attached_ = false;
    return attached_;
  }
  if (done())
    throw UsageError(option + " needs a value");
  return words_[next_++];
}

void ArgumentReader::noValue(const std::string& option) const {
  if (has_attached_)
    throw UsageError(option + " takes no value");
}

bool isOption(const std::string& word) {
  return word.size() > 1 && word[0] == '-';
}

double parseNumber(const std::string& option, const std::string& text) {
  double v = 0.0;
  // std::from_chars takes no leading '+'.
  const char* begin = text.data() + (!text.empty() && text[0] == '+' ? 1 : 0);
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, v);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v))
    throw UsageError(option + ": '" + text + "' is not a number");
  return v;
}

double parsePositive(const std::string& option, const std::string& text) {
  const double v = parseNumber(option, text);
  if (!(v > 0.0))
    throw UsageError(option + ": " + text + " must be > 0");
  return v;
}

double parseFraction(const std::string& option, const std::string& text) {
  const double v = parseNumber(option, text);
  if (!(v >= 0.0 && v <= 1.0))
    throw UsageError(option + ": " + text + " must be in [0, 1]");
  return v;
}

long long parseInteger(const std::string& option, const std::string& text) {
  long long v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end)
    throw UsageError(option + ": '" + text + "' is not an integer");
  return v;
}

long long parseInteger(const std::string& option, const std::string& text, long long min,
                       long long max) {
  const long long v = parseInteger(option, text);
  if (v < min || v > max)
    throw UsageError(option + ": " + text + " must be in [" + std::to_string(min) + ", " +
                     std::to_string(max) + "]");
  return v;
}

std::uint64_t parseSeed(const std::string& option, const std::string& text) {
  std::uint64_t v = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end)
    throw UsageError(option + ": '" + text + "' is not a non-negative integer");
  return v;
}

std::vector<std::string> splitComma(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
    if (!part.empty())
      parts.push_back(part);
  return parts;
}

}  // namespace pcl_icf_tools
