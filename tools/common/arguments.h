/*
 * pcl_icf — Iterative Closest Face registration for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file
 * \brief The programs' command lines read one way: words in order, an option's value as the
 * next word or after '=' ("--out DIR", "--out=DIR"), typed values checked with a one-line
 * reason naming the option. Each program keeps its own options, defaults and usage text. */

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_icf_tools {

/** \brief Bad usage: an unknown option, a missing or nonsense value. The programs exit with
 * code 2 on it. */
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/** \brief Walks argv (argv[0], the program, skipped). A word "--name=value" is the option
 * "--name" with its value attached; any other word is returned whole.
 * \code
 * ArgumentReader args(argc, argv);
 * while (!args.done()) {
 *   const std::string a = args.next();
 *   if (a == "--limit")
 *     limit = parseInteger(a, args.value(a), 1, 100);
 *   else if (isOption(a))
 *     throw UsageError("unknown option " + a);
 * }
 * \endcode */
class ArgumentReader {
 public:
  ArgumentReader(int argc, const char* const* argv);

  /** True when every word has been read. */
  bool done() const { return next_ >= words_.size(); }
  /** The next word: an option's name or a positional argument. */
  std::string next();
  /** The value of \a option, just returned by next(): its "=value" or the following word.
   * \throws UsageError "OPTION needs a value" at the end of the line. */
  std::string value(const std::string& option);
  /** For a flag: \throws UsageError "OPTION takes no value" when it came as "--flag=...". */
  void noValue(const std::string& option) const;

 private:
  std::vector<std::string> words_;
  std::size_t next_ = 0;
  std::string attached_;  ///< the "=value" of the word last returned
  bool has_attached_ = false;
};

/** \brief True for an option's word: '-' followed by something ("-" alone is a positional,
 * conventionally standard input). */
bool isOption(const std::string& word);

/** \brief \a text as a finite number (an optional leading '+').
 * \throws UsageError "OPTION: 'TEXT' is not a number". */
double parseNumber(const std::string& option, const std::string& text);
/** \brief parseNumber and > 0. \throws UsageError "OPTION: TEXT must be > 0". */
double parsePositive(const std::string& option, const std::string& text);
/** \brief parseNumber and in [0, 1]. \throws UsageError "OPTION: TEXT must be in [0, 1]". */
double parseFraction(const std::string& option, const std::string& text);
/** \brief \a text as a whole integer, in decimal digits with an optional '-'.
 * \throws UsageError "OPTION: 'TEXT' is not an integer". */
long long parseInteger(const std::string& option, const std::string& text);
/** \brief parseInteger and in [min, max]. \throws UsageError "OPTION: TEXT must be in [MIN,
 * MAX]". */
long long parseInteger(const std::string& option, const std::string& text, long long min,
                       long long max);
/** \brief \a text as an unsigned 64-bit integer (a seed).
 * \throws UsageError "OPTION: 'TEXT' is not a non-negative integer". */
std::uint64_t parseSeed(const std::string& option, const std::string& text);

/** \brief The non-empty items of a comma-separated value: "a,,b" gives {"a", "b"}. */
std::vector<std::string> splitComma(const std::string& text);

}  // namespace pcl_icf_tools
